//! The hint that orders each slot's candidates before many readings are made from them.
//!
//! Owns: when that is worth doing and the order it gives. Must not: decide the readings' order
//! (the sort in `clarify` does; this only spares it work).

use std::cmp::Reverse;

use super::{PRESORT_FROM, PRESORT_LOOK, Score, permute};
use crate::engine::describe::Describer;
use crate::engine::resolve::Slot;

/// Orders each slot's candidates as the contract orders readings (by score, highest first, then
/// by their words) when the readings far outnumber the candidates, and says whether it did. A
/// hint, not the order: the readings are sorted all the same. But when the verb's arguments are
/// the slots in order and every reading scores alike, their combinations then come out in the
/// contract's order already, and sorting 10,000 readings is one pass that finds them in order,
/// with nothing to move. Describing the candidates is work: past the deadline it is given up,
/// and the slots are left as they were.
pub(super) fn presort(slots: &mut [Slot], describer: &mut Describer<'_>, expired: &(dyn Fn() -> bool + Sync)) -> bool {
    // A group is described as its objects listed: not worth ordering ahead.
    if slots.iter().any(|s| s.group) {
        return false;
    }
    let candidates: usize = slots.iter().map(|s| s.candidates.len()).sum();
    let readings = (slots.iter())
        .try_fold(1usize, |n, s| n.checked_mul(s.candidates.len()))
        .unwrap_or(usize::MAX);
    if readings < PRESORT_FROM || candidates.saturating_mul(8) > readings {
        return false;
    }
    let mut keyed: Vec<Vec<(Reverse<Score>, String)>> = Vec::with_capacity(slots.len());
    for slot in slots.iter() {
        let mut keys = Vec::with_capacity(slot.candidates.len());
        for (n, (value, score)) in slot.candidates.iter().enumerate() {
            if n % PRESORT_LOOK == PRESORT_LOOK - 1 && expired() {
                return false;
            }
            keys.push(contract_key(*score, describer.argument(value)));
        }
        keyed.push(keys);
    }
    for (slot, keys) in slots.iter_mut().zip(keyed) {
        let mut order: Vec<usize> = (0..keys.len()).collect();
        order.sort_by(|&a, &b| keys[a].cmp(&keys[b]));
        permute(&mut slot.candidates, order);
    }
    true
}

/// What the contract orders readings by before the action as written: score, highest first,
/// then words.
pub(super) fn contract_key<W: Ord>(score: f64, words: W) -> (Reverse<Score>, W) {
    (Reverse(Score(score)), words)
}
