//! The pool's simulation keeps a prefix, and readings are permuted in place.

use proptest::prelude::*;

use super::Interpretation;
use crate::engine::simulate::Outcome;
use crate::engine::term::Term;

/// An unsimulated reading of `get(o<object>)`, scored 0.
fn reading(object: usize) -> Interpretation {
    Interpretation {
        action: Term::compound("get", vec![Term::constant(&format!("o{object}"))]),
        description: format!("the cup (o{object})"),
        score: 0.0,
        outcome: Outcome::default(),
        reason_words: Vec::new(),
        values: Vec::new(),
    }
}

proptest! {
    /// Simulating on the pool keeps a prefix of what ran, and exactly `after` chunks besides
    /// the first run when the deadline passes after `after` looks (each but the first chunk
    /// looks once, before it starts; one that started finishes), whatever the threads. How
    /// long that prefix is depends on the scheduler: a thread preempted between taking a
    /// chunk and looking lets the others look first, so the chunks that ran need not be the
    /// first ones; with one thread they are.
    #[test]
    fn simulating_on_the_pool_keeps_a_prefix_in_order(threads in 1..5usize, after in 0..40usize) {
        use std::sync::atomic::{AtomicUsize, Ordering};
        let mut readings: Vec<Interpretation> = (0..4096).map(reading).collect();
        let looks = AtomicUsize::new(0);
        let expired = || looks.fetch_add(1, Ordering::Relaxed) >= after;
        let simulated = |r: &mut Interpretation| r.score = -1.0;
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let kept = pool.install(|| super::simulate_apart(&mut readings, &simulated, &expired));
        // 4,096 readings make 64 full chunks on every pool size here, so `after` (< 64)
        // passing looks run exactly `after` + 1 chunks.
        let chunk = super::SIMULATE_CHUNK;
        let ran = (after + 1) * chunk;
        prop_assert!(readings[..kept].iter().all(|r| r.score == -1.0), "kept {kept}: not all simulated");
        prop_assert_eq!(readings.iter().filter(|r| r.score == -1.0).count(), ran, "after {} looks", after);
        prop_assert!(kept >= chunk, "the first chunk always runs: kept {kept}");
        prop_assert!(kept <= ran, "kept {kept} after {after} looks");
        if threads == 1 {
            prop_assert_eq!(kept, ran, "one thread takes the chunks in order");
        }
    }

    /// Whatever the permutation, position `k` ends holding what was at `order[k]`.
    #[test]
    fn permute_puts_each_item_where_the_order_says(order in Just((0..300usize).collect::<Vec<_>>()).prop_shuffle(), len in 0..300usize) {
        let order: Vec<usize> = order.into_iter().filter(|&i| i < len).collect();
        let mut items: Vec<String> = (0..len).map(|i| format!("item{i}")).collect();
        super::permute(&mut items, order.clone());
        let expected: Vec<String> = order.iter().map(|i| format!("item{i}")).collect();
        prop_assert_eq!(items, expected);
    }
}
