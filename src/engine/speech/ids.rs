//! Ids, landmarks and positions in what the robot says: spoken only where the answer needs them
//! to tell its objects apart.
//!
//! Owns: which ids an utterance leaves out. Must not: change a reading's description or
//! reasons, which the contract describes against the whole scene.

use super::{Describer, Interpretation, Plan, Style, utterance};
use crate::engine::scene::Scene;
use crate::engine::term::{Sym, Term};
use rustc_hash::{FxHashMap, FxHashSet};

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
    let plain: FxHashMap<&Sym, (String, String)> = (alone.iter())
        .filter_map(|id| {
            let full = describer.argument(&Term::Const(id.clone()));
            let plain = describer.plain(id)?;
            (full != plain).then_some((id, (full, plain)))
        })
        .collect();
    // A reading's words name only its own values: each is mended for those, so ten thousand
    // readings of ten thousand objects cost a pass, not a product.
    for i in interpretations.iter_mut() {
        for id in i.values.iter().filter_map(Term::name) {
            if let Some((full, plain)) = plain.get(id) {
                i.description = i.description.replace(full.as_str(), plain);
            }
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
    // The objects named, in the readings' order, and how many of each type: one pass over the
    // readings, as an answer may hold ten thousand of them.
    let mut seen: FxHashSet<&Sym> = FxHashSet::default();
    let mut named: Vec<&crate::engine::scene::Object> = Vec::new();
    let mut of_kind: FxHashMap<&str, usize> = FxHashMap::default();
    for i in interpretations {
        for value in &i.values {
            if let Some(object) = value.name().and_then(|id| scene.object(id))
                && seen.insert(&object.id)
            {
                named.push(object);
                *of_kind.entry(object.kind.as_str()).or_default() += 1;
            }
        }
    }
    // The ids the readings' words speak: an id is a constant's name (no space, no parenthesis),
    // spoken as " (id)", so the words between " (" and the next ")" are exactly the ids spoken.
    let spoken: FxHashSet<&str> = if told {
        FxHashSet::default()
    } else {
        (interpretations.iter())
            .flat_map(|i| i.description.split(" (").skip(1))
            .filter_map(|after| after.split_once(')').map(|(id, _)| id))
            .collect()
    };
    (named.iter())
        .filter(|o| of_kind[o.kind.as_str()] == 1)
        .filter(|o| told || spoken.contains(o.id.as_str()))
        .map(|o| o.id.clone())
        .collect()
}
