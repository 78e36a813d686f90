//! Which objects a reference selects, as a set: relations, superlatives and ordinals are said of
//! objects among others, so they are decided over the scene, not object by object.
//!
//! Owns: the set each kind of reference selects, and what the scene could not tell. Must not:
//! guess: a reference whose words name nothing, or whose measure the scene lacks, selects
//! nothing.

use super::Reference;
use crate::engine::scene::Scene;
use crate::engine::scene::relate::{self, Superlative};

/// The objects a reference selects, by index in the scene's list, ascending; with nothing
/// selected, what the scene could not tell, when that is why.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Selected {
    pub objects: Vec<usize>,
    pub untold: Option<String>,
}

impl Selected {
    fn of(objects: Vec<usize>) -> Selected {
        Selected { objects, untold: None }
    }
}

/// The indices in both ascending lists.
fn both(a: &[usize], b: &[usize]) -> Vec<usize> {
    let mut b = b.iter().peekable();
    a.iter()
        .copied()
        .filter(|x| {
            while b.next_if(|y| *y < x).is_some() {}
            b.peek().is_some_and(|y| *y == x)
        })
        .collect()
}

/// The indices of ascending `a` not in ascending `b`.
fn less(a: &[usize], b: &[usize]) -> Vec<usize> {
    let mut b = b.iter().peekable();
    a.iter()
        .copied()
        .filter(|x| {
            while b.next_if(|y| *y < x).is_some() {}
            b.peek().is_none_or(|y| *y != x)
        })
        .collect()
}

/// The indices in any of the lists, ascending, once each.
fn any(lists: impl Iterator<Item = Vec<usize>>) -> Vec<usize> {
    let mut all: Vec<usize> = lists.flatten().collect();
    all.sort_unstable();
    all.dedup();
    all
}

impl Reference {
    /// [`Reference::select`], once per request for a reference that relations, a superlative
    /// or an ordinal make costly: the parse shows what resolving it found.
    pub fn select_once(&self, scene: &Scene, expired: &dyn Fn() -> bool) -> Option<Selected> {
        if !self.placed_among_others() {
            return self.select(scene, expired);
        }
        let key = format!("{self:?}");
        if let Some((objects, untold)) = scene.layout().selected(&key) {
            return Some(Selected { objects, untold });
        }
        let selected = self.select(scene, expired)?;
        scene.layout().remember(key, &selected.objects, selected.untold.clone());
        Some(selected)
    }

    /// Whether what the reference selects depends on other objects than each one alone.
    fn placed_among_others(&self) -> bool {
        match self {
            Reference::Related { .. } | Reference::Most { .. } | Reference::Nth { .. } | Reference::Union { .. } => {
                true
            }
            Reference::Narrowed { base, by, .. } => base.placed_among_others() || by.placed_among_others(),
            Reference::Plural { base, .. } => base.placed_among_others(),
            Reference::Either { options, .. } => options.iter().any(Reference::placed_among_others),
            Reference::Id(_)
            | Reference::Described { .. }
            | Reference::Spoken { .. }
            | Reference::Pronoun { .. }
            | Reference::Nothing { .. }
            | Reference::Implied { .. }
            | Reference::Speaker(_) => false,
        }
    }

    /// The objects the reference selects; `None` when the deadline passed on the way.
    pub fn select(&self, scene: &Scene, expired: &dyn Fn() -> bool) -> Option<Selected> {
        if self.names_nothing() {
            return Some(Selected::default());
        }
        Some(match self {
            Reference::Id(_) | Reference::Described { .. } | Reference::Spoken { .. } => Selected::of(
                (scene.objects.iter().enumerate())
                    .filter(|(_, o)| self.head_matches(o))
                    .map(|(i, _)| i)
                    .collect(),
            ),
            Reference::Pronoun { .. } | Reference::Nothing { .. } => Selected::default(),
            Reference::Speaker(id) => match scene.index_of(id) {
                Some(i) => Selected::of(vec![i]),
                None => Selected {
                    objects: Vec::new(),
                    untold: Some("I do not know where you are.".to_owned()),
                },
            },
            Reference::Implied {
                param, facts, untold, ..
            } => {
                let objects = super::unsaid::meeting(scene, param, facts, expired)?;
                Selected {
                    untold: objects.is_empty().then(|| untold.clone()),
                    objects,
                }
            }
            Reference::Narrowed { base, by, keep, .. } => {
                let (base, by) = (base.select(scene, expired)?, by.select(scene, expired)?);
                let objects = match keep {
                    true => both(&base.objects, &by.objects),
                    false => less(&base.objects, &by.objects),
                };
                Selected {
                    untold: base.untold.or(by.untold).filter(|_| objects.is_empty()),
                    objects,
                }
            }
            // Any option, or any reading of words that read more than one way: the union.
            Reference::Either { options: parts, .. } | Reference::Union { readings: parts, .. } => {
                let mut selected = Vec::with_capacity(parts.len());
                for part in parts {
                    selected.push(part.select(scene, expired)?);
                }
                let untold = selected.iter().find_map(|s| s.untold.clone());
                let objects = any(selected.into_iter().map(|s| s.objects));
                Selected {
                    untold: untold.filter(|_| objects.is_empty()),
                    objects,
                }
            }
            Reference::Related { base, relation, to, .. } => {
                let base = base.select(scene, expired)?;
                if base.objects.is_empty() {
                    return Some(base);
                }
                let to = to.select(scene, expired)?;
                if to.objects.is_empty() {
                    return Some(to);
                }
                let objects = scene
                    .layout()
                    .related(scene, &base.objects, *relation, &to.objects, expired)?;
                Selected::of(objects)
            }
            Reference::Most {
                base,
                superlative,
                said,
                ..
            } => {
                let base = base.select(scene, expired)?;
                match relate::superlative(scene, &base.objects, *superlative) {
                    Ok(objects) => Selected::of(objects),
                    Err(relate::Unmeasured) => Selected {
                        objects: Vec::new(),
                        untold: Some(untold_measure(self, *superlative, said)),
                    },
                }
            }
            // Which of the matches are meant together is the slot's to say (`number`).
            Reference::Plural { base, .. } => base.select(scene, expired)?,
            Reference::Nth { base, nth, from, .. } => {
                let base = base.select(scene, expired)?;
                Selected::of(relate::ordinal(scene, &base.objects, *nth, *from))
            }
        })
    }
}

/// "I cannot tell which box is the biggest: I do not know how big every box is."
fn untold_measure(reference: &Reference, superlative: Superlative, said: &str) -> String {
    let noun = reference.noun().unwrap_or_else(|| "one".to_owned());
    format!(
        "I cannot tell which {noun} is the {said}: I do not know {} every {noun} is.",
        superlative.unknown()
    )
}
