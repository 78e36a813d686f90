//! Work spread on rayon's pool: simulating readings chunk by chunk in the contract's order,
//! batches for describing, and reordering readings in place.
//!
//! Owns: how work is cut so that a deadline keeps a prefix of the likeliest readings. Must
//! not: decide or word anything.

use rayon::prelude::*;

use super::{DESCRIBE_APART_FROM, Interpretation, PREPARE_BATCH, SIMULATE_CHUNK};

/// Simulates `readings` with `one` on rayon's pool, a chunk at a time, and says how many, from
/// the first, were. The chunks are handed out in the contract's order, one to each thread that
/// asks, so that a deadline cuts the least likely; each asks the deadline before it starts (the
/// first always runs), and one that started finishes. A chunk that ran after one skipped (the
/// deadline passed between two threads' looks) is not counted: what is kept is a prefix.
pub(super) fn simulate_apart(
    readings: &mut [Interpretation],
    one: &(dyn Fn(&mut Interpretation) + Sync),
    expired: &(dyn Fn() -> bool + Sync),
) -> usize {
    let chunk = (readings.len())
        .div_ceil(8 * rayon::current_num_threads())
        .clamp(1, SIMULATE_CHUNK);
    let mut ran = vec![false; readings.len().div_ceil(chunk)];
    (readings.chunks_mut(chunk).zip(&mut ran).enumerate())
        .par_bridge()
        .for_each(|(n, (chunk, ran))| {
            if n == 0 || !expired() {
                chunk.iter_mut().for_each(one);
                *ran = true;
            }
        });
    let lead = ran.iter().take_while(|&&ran| ran).count();
    (lead * chunk).min(readings.len())
}

/// How many of `n` readings one thread describes at a time: a few batches per thread, so that
/// the threads share the work evenly, and at most [`PREPARE_BATCH`] between two looks at the
/// deadline.
pub(super) fn parallel_batch(n: usize) -> usize {
    n.div_ceil(4 * rayon::current_num_threads())
        .clamp(DESCRIBE_APART_FROM / 8, PREPARE_BATCH)
}

/// Rearranges `items` in place so that position `k` holds what was at `order[k]` (`order` is a
/// permutation of the positions): each cycle of the permutation is followed once, so every item
/// moves without a second vector of them being made.
pub(super) fn permute<T>(items: &mut [T], mut order: Vec<usize>) {
    const DONE: usize = usize::MAX;
    for start in 0..items.len() {
        let mut k = start;
        while order[k] != DONE {
            let from = std::mem::replace(&mut order[k], DONE);
            if from == start {
                break;
            }
            items.swap(k, from);
            k = from;
        }
    }
}
