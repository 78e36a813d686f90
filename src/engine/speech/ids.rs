//! Ids, landmarks and positions in what the robot says: spoken only where the answer needs them
//! to tell its objects apart.
//!
//! Owns: which ids an utterance leaves out. Must not: change a reading's description or
//! reasons, which the contract describes against the whole scene.

use super::{Describer, Interpretation, Plan, Style, utterance};
use crate::engine::scene::Scene;
use crate::engine::term::{Sym, Term};

/// The utterance of `plan`. An object whose description needs its id among the scene's objects
/// of its type ("the cup (cup1)") is spoken without it when it is the only object of its type
/// the answer's readings name: there, "the cup" tells it apart. The readings' descriptions and
/// reasons keep the id, as the contract describes them against the whole scene.
pub fn answer_utterance(
    plan: &Plan,
    interpretations: &mut [Interpretation],
    style: Style,
    describer: &mut Describer<'_>,
) -> String {
    let alone = alone(interpretations, describer.scene(), describer.told_apart());
    if alone.is_empty() {
        return utterance(plan, interpretations, style, describer);
    }
    let kept: Vec<String> = interpretations.iter().map(|i| i.description.clone()).collect();
    // Each alone object's words, and the words of its type and features only.
    let plain: Vec<(String, String)> = (alone.iter())
        .filter_map(|id| {
            let full = describer.argument(&Term::Const(id.clone()));
            let plain = describer.plain(id)?;
            (full != plain).then_some((full, plain))
        })
        .collect();
    for i in interpretations.iter_mut() {
        for (full, plain) in &plain {
            i.description = i.description.replace(full.as_str(), plain);
        }
    }
    describer.without_ids(alone);
    let utterance = utterance(plan, interpretations, style, describer);
    describer.without_ids(Vec::new());
    for (i, description) in interpretations.iter_mut().zip(kept) {
        i.description = description;
    }
    utterance
}

/// The objects the readings name with an id in their words (or, where a landmark or a position
/// told some apart, any) that are the only objects of their type among all the objects the
/// readings name.
fn alone(interpretations: &[Interpretation], scene: &Scene, told: bool) -> Vec<Sym> {
    if !told && !interpretations.iter().any(|i| i.description.contains(')')) {
        return Vec::new();
    }
    let mut named: Vec<&crate::engine::scene::Object> = Vec::new();
    for i in interpretations {
        for value in &i.values {
            if let Some(object) = value.name().and_then(|id| scene.object(id))
                && !named.iter().any(|o| o.id == object.id)
            {
                named.push(object);
            }
        }
    }
    (named.iter())
        .filter(|o| named.iter().filter(|p| p.kind == o.kind).count() == 1)
        .filter(|o| {
            told || interpretations
                .iter()
                .any(|i| i.description.contains(&format!(" ({})", o.id)))
        })
        .map(|o| o.id.clone())
        .collect()
}
