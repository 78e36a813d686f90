//! Where a two-argument verb's words part its arguments, when more than one joiner could:
//! "Put the cup on the table in the box." is the cup on the table put in the box, or the cup
//! put on the table in the box, and only the scene can tell.
//!
//! Owns: the ways each clause may be parted, and the choice among whole readings of the words
//! by whether every reference names something. Must not: guess: when two ways both name
//! objects, the words are not understood.

use super::Understanding;
use crate::engine::request::Directive;
use crate::engine::resolve::Reference;
use crate::engine::scene::Scene;
use crate::engine::task::Argument;

/// Readings of one sentence tried, at most: a clause with two joiner words makes two, and
/// several such clauses multiply; the first this many are tried, in order.
pub(super) const MOST_SPLITS: usize = 16;

/// The joiner each clause was parted at, clause by clause in the order read.
#[derive(Debug, Default)]
pub(super) struct Splits {
    /// Which joiner word (0: the first) parts clause `n`; clauses past the end take the first.
    chosen: Vec<usize>,
    /// How many joiner words could part clause `n`, as its read found (0 or 1: one way).
    found: Vec<usize>,
}

impl Splits {
    /// The position of `positions` (joiner words in clause `n` with words on both sides) that
    /// parts it in this reading, and notes how many there were.
    pub(super) fn pick(&mut self, n: usize, positions: &[usize]) -> Option<usize> {
        if self.found.len() <= n {
            self.found.resize(n + 1, 1);
        }
        self.found[n] = positions.len();
        let k = self.chosen.get(n).copied().unwrap_or(0);
        positions.get(k).or(positions.first()).copied()
    }

    /// Whether some clause could be parted in more than one way.
    pub(super) fn ambiguous(&self) -> bool {
        self.found.iter().any(|&n| n > 1)
    }

    /// Every way of parting the clauses found, first joiners first, as fresh choices to read
    /// with: a mixed-radix count over the clauses, the last clause fastest, at most
    /// `MOST_SPLITS` of them.
    pub(super) fn ways(&self) -> Vec<Splits> {
        let radix: Vec<usize> = self.found.iter().map(|&n| n.max(1)).collect();
        let mut digits = vec![0; radix.len()];
        let mut ways = Vec::new();
        loop {
            ways.push(Splits {
                chosen: digits.clone(),
                found: Vec::new(),
            });
            if ways.len() == MOST_SPLITS {
                return ways;
            }
            let Some(at) = (0..radix.len()).rev().find(|&i| digits[i] + 1 < radix[i]) else {
                return ways;
            };
            digits[at] += 1;
            digits[at + 1..].iter_mut().for_each(|d| *d = 0);
        }
    }
}

/// Whether every reference the reading makes (its steps' and its purposes') selects at least
/// one object of the scene; a reading that is not a directive names nothing.
pub(super) fn names_something(reading: &Understanding, scene: &Scene, expired: &dyn Fn() -> bool) -> bool {
    let Understanding::Directive { directive, .. } = reading else {
        return false;
    };
    let found = |r: &Reference| r.select_once(scene, expired).is_some_and(|s| !s.objects.is_empty());
    match directive {
        Directive::Action { arguments, .. } => arguments.iter().all(found),
        Directive::Task(task) => (task.steps.iter().flat_map(|s| &s.arguments))
            .chain(task.purposes.iter().flat_map(|p| &p.arguments))
            .all(|a| match a {
                Argument::Reference(r) => found(r),
                Argument::Earlier { .. } => true,
            }),
        Directive::Form { .. } | Directive::Words { .. } => true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chosen(ways: &[Splits]) -> Vec<Vec<usize>> {
        ways.iter().map(|w| w.chosen.clone()).collect()
    }

    #[test]
    fn ways_count_every_clause_first_joiners_first_and_stop_at_the_cap() {
        let mut read = Splits::default();
        assert_eq!(read.pick(0, &[3, 6]), Some(3));
        assert_eq!(read.pick(2, &[2]), Some(2));
        assert!(read.ambiguous());
        assert_eq!(chosen(&read.ways()), vec![vec![0, 0, 0], vec![1, 0, 0]]);
        let mut again = read.ways().remove(1);
        assert_eq!(again.pick(0, &[3, 6]), Some(6));
        let mut many = Splits::default();
        for n in 0..8 {
            many.pick(n, &[1, 2]);
        }
        assert_eq!(many.ways().len(), MOST_SPLITS);
        let mut one = Splits::default();
        assert_eq!(one.pick(0, &[]), None);
        assert!(!one.ambiguous());
        assert_eq!(chosen(&one.ways()), vec![vec![0]]);
    }
}
