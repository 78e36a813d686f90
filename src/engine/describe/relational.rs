//! Descriptions that tell apart objects their type and features do not (Dale & Haddock's
//! relational descriptions, as the contract orders them): one relation to a landmark, then a
//! position ("the left cup"); the caller speaks an id only when neither does.
//!
//! Owns: which landmark and which position are said. Must not: depend on hash order, or say
//! words the service's own words path would read as another object.

use super::{Feature, after_the_noun};
use crate::engine::scene::relate::{self, Relation, Superlative};
use crate::engine::scene::{Object, Scene, spoken};

/// Scenes up to this many objects are described with landmarks and positions; in a larger one
/// an object its features do not tell apart keeps its id (a landmark search per object, over
/// thousands of look-alikes, would cost more than the decision).
pub(super) const UP_TO: usize = 64;

/// What tells the object apart: a position said after "the", a relation said after the noun.
pub(super) struct Told {
    pub(super) position: Option<&'static str>,
    pub(super) relation: Option<String>,
}

/// The words that leave `object` alone among `distractors` (the other objects its type and
/// features so far match), or `None` when no landmark and no position does.
pub(super) fn tell_apart(scene: &Scene, object: &Object, distractors: &[&Object]) -> Option<Told> {
    let index = scene.index_of(&object.id)?;
    let mut left: Vec<usize> = distractors.iter().filter_map(|d| scene.index_of(&d.id)).collect();
    left.sort_unstable();
    let layout = scene.layout();
    let never = || false;
    // The first landmark that rules every distractor out; else each that rules some out, in
    // order, to be tried with a position.
    let mut partial: Vec<(String, Vec<usize>)> = Vec::new();
    // In the contract's order; "from" is a source, not a place.
    for &relation in Relation::PLACES {
        // A landmark of the object's own type ("the mug to the left of the mug") reads as
        // one of the look-alikes: the position says it better.
        let landmarks = layout.landmarks_of(scene, index, relation);
        for landmark in landmarks.into_iter().filter(|&l| scene.objects[l].kind != object.kind) {
            for (words, landmarks) in landmark_words(scene, &scene.objects[landmark]) {
                let kept = layout
                    .related(scene, &left, relation, &landmarks, &never)
                    .unwrap_or_else(|| left.clone());
                let said = format!("{} {words}", relation.spoken());
                if kept.is_empty() {
                    return Some(Told {
                        position: None,
                        relation: Some(said),
                    });
                }
                if kept.len() < left.len() && !partial.iter().any(|(_, k)| *k == kept) {
                    partial.push((said, kept));
                }
            }
        }
    }
    // "the left cup" is the leftmost of those the rest of the words match, alone: with a
    // landmark that narrowed them first, else with none.
    let tries = (partial.into_iter().map(|(said, kept)| (Some(said), kept))).chain([(None, left)]);
    for (relation, mut among) in tries {
        among.push(index);
        among.sort_unstable();
        for (word, most) in [("left", true), ("right", false)] {
            if relate::superlative(scene, &among, Superlative::Left { most }).is_ok_and(|picked| picked == [index]) {
                return Some(Told {
                    position: Some(word),
                    relation,
                });
            }
        }
    }
    None
}

/// The ways to say a landmark, shortest first: its type, then its type with each of its own
/// features that narrows the objects of that type (as the Incremental Algorithm adds them);
/// each with the objects (indices, ascending) the words match.
fn landmark_words(scene: &Scene, landmark: &Object) -> Vec<(String, Vec<usize>)> {
    let mut matching: Vec<usize> = (scene.objects.iter().enumerate())
        .filter(|(_, o)| o.kind == landmark.kind)
        .map(|(i, _)| i)
        .collect();
    let (mut before, mut after) = (Vec::new(), Vec::new());
    let say = |before: &[String], after: &[String]| {
        let mut words = vec!["the".to_owned()];
        words.extend(before.iter().cloned());
        words.push(spoken(&landmark.kind));
        words.extend(after.iter().cloned());
        words.join(" ")
    };
    let mut out = vec![(say(&before, &after), matching.clone())];
    let features = (landmark.properties.iter().map(|p| Feature::Property(p)))
        .chain(landmark.attributes.iter().map(|(k, v)| Feature::Attribute(k, v)));
    for feature in features {
        let count = matching.len();
        matching.retain(|&i| feature.holds_for(&scene.objects[i]));
        if matching.len() < count {
            let word = feature.word();
            match after_the_noun(&word) {
                true => after.push(word),
                false => before.push(word),
            }
            out.push((say(&before, &after), matching.clone()));
        }
    }
    out
}
