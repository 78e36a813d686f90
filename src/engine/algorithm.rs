//! Algorithm 1 of the paper, with the caps the paper left open: from simulated readings to the
//! plan of what to say.
//!
//! Owns: which readings are offered, assumed, confirmed, obeyed or explained. Must not: offer,
//! assume, confirm or obey a reading that is impermissible or infeasible under the moral
//! strategy, simulate anything, or word anything.

use super::decision::{DecisionKind, Interpretation, Plan};
use super::request::{Options, SinglePermissible, Strategy};
use super::resolve::Slot;

/// How many of the likeliest readings are named when there are too many to name them all.
pub const FEW: usize = 3;

/// The nouns of the slots whose value differs among `readings` ("which notebook").
fn varying_nouns(readings: &[&Interpretation], slots: &[Slot]) -> Vec<String> {
    slots
        .iter()
        .enumerate()
        .filter(|(j, _)| readings.windows(2).any(|w| w[0].values[*j] != w[1].values[*j]))
        .map(|(_, s)| s.noun.clone())
        .collect()
}

/// The question for more acceptable readings than may be named: the few likeliest, or, when
/// they are all equally likely, the words that are ambiguous.
fn too_many(good: &[usize], all: &[Interpretation], slots: &[Slot], max_spoken: usize) -> Plan {
    let evenly = good.windows(2).all(|w| all[w[0]].score == all[w[1]].score);
    let nouns = varying_nouns(&good.iter().map(|&i| &all[i]).collect::<Vec<_>>(), slots);
    if evenly && !nouns.is_empty() {
        Plan::AskWhich { nouns }
    } else {
        Plan::Ask {
            offered: good.iter().copied().take(FEW.min(max_spoken)).collect(),
            more: true,
        }
    }
}

/// The readings Algorithm 1 chooses among: the acceptable (permissible and feasible) ones with
/// the highest norm score, in the contract's order. The other acceptable ones are dispreferred:
/// never offered. With no soft norm in force every score is 0 and these are all acceptable ones.
pub(super) fn kept(all: &[Interpretation]) -> Vec<usize> {
    let good = (0..all.len()).filter(|&i| all[i].acceptable());
    let Some(best) = good.clone().map(|i| all[i].norm_score()).max() else {
        return Vec::new();
    };
    good.filter(|&i| all[i].norm_score() == best).collect()
}

/// Algorithm 1 (two or more readings), the single-reading cases, and the caps.
pub(super) fn decide(options: Options, all: &[Interpretation], slots: &[Slot], incomplete: bool) -> Plan {
    let good = kept(all);
    if incomplete {
        // Unsimulated readings remain: never assume, obey or explain on a partial view; name
        // only simulated acceptable readings, and say there may be something else.
        let nouns: Vec<String> = slots
            .iter()
            .filter(|s| s.candidates.len() > 1)
            .map(|s| s.noun.clone())
            .collect();
        return if all.len() == 1 && all[0].outcome.unfinished() {
            // The one reading, cut short by the deadline: refused, saying so.
            Plan::Refuse(0)
        } else if good.is_empty() {
            Plan::AskWhich { nouns }
        } else {
            Plan::Ask {
                offered: good.into_iter().take(FEW.min(options.max_spoken)).collect(),
                more: true,
            }
        };
    }
    if all.len() == 1 {
        return if good.len() == 1 {
            Plan::Comply(0)
        } else {
            Plan::Refuse(0)
        };
    }
    if options.strategy == Strategy::Reflexive {
        return Plan::Ask {
            offered: (0..all.len().min(options.max_spoken)).collect(),
            more: all.len() > options.max_spoken,
        };
    }
    let refused: Vec<usize> = (0..all.len()).filter(|&i| !all[i].acceptable()).collect();
    match good.as_slice() {
        [] => Plan::Explain(refused),
        [chosen] => {
            // Every other reading is explained: those that cannot be done, and those dispreferred.
            let others = (0..all.len()).filter(|i| i != chosen).collect();
            let share = refused.len() as f64 / all.len() as f64;
            let confirm = options.single_permissible == SinglePermissible::Confirm
                || options.confirm_above_ratio.is_some_and(|ratio| share > ratio);
            if confirm {
                Plan::Confirm {
                    chosen: *chosen,
                    others,
                }
            } else {
                Plan::Assume {
                    chosen: *chosen,
                    others,
                }
            }
        }
        several if several.len() <= options.max_spoken => Plan::Ask {
            offered: several.to_vec(),
            more: false,
        },
        several => too_many(several, all, slots, options.max_spoken),
    }
}

pub(super) fn plan_kind(plan: &Plan) -> DecisionKind {
    match plan {
        Plan::Comply(_) => DecisionKind::Comply,
        Plan::Refuse(_) => DecisionKind::Refuse,
        Plan::Ask { .. } | Plan::AskWhich { .. } => DecisionKind::Ask,
        Plan::Assume { .. } => DecisionKind::Assume,
        Plan::Confirm { .. } => DecisionKind::Confirm,
        Plan::Explain(_) => DecisionKind::Explain,
        Plan::Unresolved(_) => DecisionKind::Unresolved,
        Plan::NotUnderstood { .. } => DecisionKind::NotUnderstood,
        Plan::Cancelled => DecisionKind::Cancelled,
    }
}
