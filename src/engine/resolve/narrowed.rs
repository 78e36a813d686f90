//! The readings a follow-up answer keeps: those with an argument the answer names, counted
//! and built without going through the others.
//!
//! Owns: that narrowing. Must not: resolve references (the slots are given) or simulate.

use super::{Slot, combinations, members};
use crate::engine::request::Answer;
use crate::engine::scene::Scene;
use crate::engine::term::Term;

/// Whether an object the answer names is this candidate; `named`: the objects (by index) an
/// answer that is a reference selects.
fn answer_names(answer: &Answer, named: &[bool], value: &Term, scene: &Scene) -> bool {
    // A group is named when one of its objects is.
    if let Some(members) = members(value) {
        return members.iter().any(|m| answer_names(answer, named, m, scene));
    }
    let Some(index) = value.name().and_then(|id| scene.index_of(id)) else {
        return false;
    };
    match answer {
        Answer::Id(id) => scene.objects[index].id == id.as_str(),
        Answer::Reference(_) => named[index],
        Answer::Choice(_)
        | Answer::Yes
        | Answer::No
        | Answer::Alternative
        | Answer::Cancel(_)
        | Answer::Directive(_)
        | Answer::Words(_) => true,
    }
}

/// The readings a follow-up keeps (those with an argument the answer names), counted and built
/// without going through the others: the answer narrows the readings before `max_readings` is
/// applied, so five cups and "c2" are one reading, not five times five.
pub(in crate::engine) struct Narrowed {
    /// Per slot: the candidates the answer names, and the others.
    named: Vec<Vec<(Term, f64)>>,
    others: Vec<Vec<(Term, f64)>>,
}

impl Narrowed {
    pub(in crate::engine) fn new(
        answer: &Answer,
        slots: &[Slot],
        scene: &Scene,
        expired: &dyn Fn() -> bool,
    ) -> Narrowed {
        let mut selected = vec![false; scene.objects.len()];
        if let Answer::Reference(reference) = answer {
            for i in reference.select(scene, expired).unwrap_or_default().objects {
                selected[i] = true;
            }
        }
        let (named, others) = slots
            .iter()
            .map(|s| {
                s.candidates
                    .iter()
                    .cloned()
                    .partition(|(t, _)| answer_names(answer, &selected, t, scene))
            })
            .unzip();
        Narrowed { named, others }
    }

    /// All combinations less those that name nothing the answer names.
    pub(in crate::engine) fn count(&self) -> u128 {
        let product = |lists: &[Vec<(Term, f64)>], with: &[Vec<(Term, f64)>]| {
            lists
                .iter()
                .zip(with)
                .try_fold(1u128, |n, (a, b)| n.checked_mul((a.len() + b.len()) as u128))
        };
        let none = self
            .others
            .iter()
            .try_fold(1u128, |n, l| n.checked_mul(l.len() as u128));
        match (product(&self.named, &self.others), none) {
            (Some(all), Some(none)) => all - none,
            _ => u128::MAX,
        }
    }

    /// Each kept combination once: slot `i` is the first whose value the answer names.
    pub(in crate::engine) fn combinations(&self) -> Vec<(Vec<Term>, f64)> {
        let all: Vec<Vec<(Term, f64)>> = self
            .named
            .iter()
            .zip(&self.others)
            .map(|(a, b)| a.iter().chain(b).cloned().collect())
            .collect();
        let mut out = Vec::new();
        for first in 0..self.named.len() {
            let lists: Vec<&[(Term, f64)]> = (0..self.named.len())
                .map(|j| match j.cmp(&first) {
                    std::cmp::Ordering::Less => self.others[j].as_slice(),
                    std::cmp::Ordering::Equal => self.named[j].as_slice(),
                    std::cmp::Ordering::Greater => all[j].as_slice(),
                })
                .collect();
            out.extend(combinations(&lists));
        }
        out
    }
}
