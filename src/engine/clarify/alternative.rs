//! The nearest reading not named that the norms permit and the robot can do, offered after a
//! refusal or an explanation under the moral strategy ("Shall I heat the soup with the stove
//! instead?"): the same verb, one argument replaced by another object of its type (or one
//! meeting the verb's implied facts for it), fewest differing features first.
//!
//! Owns: which readings are tried, in which order, and the bound on them (the request's
//! readings cap and deadline). Must not: offer one the simulation did not find permissible
//! and feasible, offer a different verb, or look under the reflexive strategy.

use rustc_hash::FxHashSet;

use crate::engine::decision::{Decision, Interpretation, Plan, Style};
use crate::engine::describe::Describer;
use crate::engine::request::Options;
use crate::engine::resolve::Template;
use crate::engine::scene::{Object, PERSON};
use crate::engine::simulate::{Env, simulate};
use crate::engine::speech;
use crate::engine::term::{Sym, Term};
use crate::engine::world::World;

/// The world the request's readings were simulated in, and the bound on the search.
pub(super) struct Search<'a, 'b> {
    pub env: &'a Env<'b>,
    pub world: &'a World<'b>,
    /// The relation the human's joiner made the verb's effect, as for the readings.
    pub relation: Option<&'a (Sym, Sym)>,
    /// Most changes looked at: the request's readings cap.
    pub most: usize,
    /// Objects the words excluded ("…, not the stove"), by index, sorted: never offered.
    pub excluded: &'a [usize],
}

/// Whether the plan is one an alternative answers: a refusal or an explanation, every reading
/// seen.
pub(super) fn wanted(options: &Options, plan: &Plan, cut_short: bool) -> bool {
    options.offers_alternatives() && !cut_short && matches!(plan, Plan::Refuse(_) | Plan::Explain(_))
}

/// How often the search asks the deadline, in changes looked at.
const ASK_EVERY: usize = 1024;

impl Search<'_, '_> {
    /// The nearest acceptable reading none of `readings` names, simulated; `None` when there is
    /// none, the readings are not of one verb's action, or the cap or the deadline ran out
    /// first. The changes looked at are the first [`Search::most`] in the readings' order (so
    /// that ten thousand readings of ten thousand look-alikes are not a product); among them,
    /// fewest differing features first.
    pub(super) fn nearest(&self, template: &Template<'_>, readings: &[Interpretation]) -> Option<Interpretation> {
        let Template::Verb(verb) = template else { return None };
        let (scene, expired) = (self.env.scene, self.env.expired);
        let def = self.env.library.get(verb, readings.first()?.values.len())?;
        let named: FxHashSet<Term> = (readings.iter())
            .map(|r| Term::compound(verb, r.values.clone()))
            .collect();
        // Per argument, the objects meeting its implied facts, if it has any: once, not per
        // reading.
        let mut meets: Vec<Option<Vec<usize>>> = Vec::with_capacity(def.params.len());
        for param in &def.params {
            let implied = def.implied.iter().find(|(q, _)| q == param);
            meets.push(match implied {
                Some((p, facts)) => Some(crate::engine::resolve::meeting(scene, p, facts, expired)?),
                None => None,
            });
        }
        // (differing features, reading, argument, object) for each one-argument change.
        let mut tried: Vec<(usize, usize, usize, usize)> = Vec::new();
        'readings: for (r, reading) in readings.iter().enumerate() {
            for (a, value) in reading.values.iter().enumerate() {
                let Some(was) = value.name().and_then(|id| scene.object(id)) else {
                    continue;
                };
                let meets = meets.get(a).and_then(Option::as_ref);
                for (o, object) in scene.objects.iter().enumerate() {
                    if o % ASK_EVERY == ASK_EVERY - 1 && expired() {
                        return None;
                    }
                    let kin = object.kind == was.kind || meets.is_some_and(|m| m.binary_search(&o).is_ok());
                    let ruled_out = self.excluded.binary_search(&o).is_ok();
                    if !kin || ruled_out || object.id == was.id || (object.kind == PERSON) != (was.kind == PERSON) {
                        continue;
                    }
                    tried.push((differing(was, object), r, a, o));
                    if tried.len() >= self.most {
                        break 'readings;
                    }
                }
            }
        }
        tried.sort();
        let mut seen: FxHashSet<Term> = FxHashSet::default();
        for (n, &(_, r, a, o)) in tried.iter().enumerate() {
            if n > 0 && expired() {
                return None;
            }
            let mut values = readings[r].values.clone();
            values[a] = Term::Const(scene.objects[o].id.clone());
            let action = Term::compound(verb, values.clone());
            if named.contains(&action) || !seen.insert(action.clone()) {
                continue;
            }
            let (outcome, done) = simulate(self.env, self.world, &action, self.relation);
            if outcome.unfinished() {
                return None;
            }
            let reading = Interpretation {
                action: done,
                description: String::new(),
                score: readings[r].score,
                outcome,
                reason_words: Vec::new(),
                values,
            };
            if reading.permissible() && reading.feasible() {
                return Some(reading);
            }
        }
        None
    }
}

/// How many properties and attribute values tell two objects apart.
fn differing(a: &Object, b: &Object) -> usize {
    let properties = (a.properties.iter().filter(|p| !b.properties.contains(p)))
        .chain(b.properties.iter().filter(|p| !a.properties.contains(p)))
        .count();
    let keys = (a.attributes.keys()).chain(b.attributes.keys().filter(|k| !a.attributes.contains_key(*k)));
    properties + keys.filter(|k| a.attributes.get(*k) != b.attributes.get(*k)).count()
}

/// The alternative found with its words (the search leaves them unsaid: most readings it
/// looks at are never spoken).
pub(super) fn described(mut found: Interpretation, describer: &mut Describer<'_>) -> Interpretation {
    found.description = describer.arguments(speech::action_of(&found));
    found
}

/// Puts the alternative found into the decision: its action term, and the question that ends
/// the utterance.
pub(super) fn offer(
    decision: &mut Decision,
    found: Option<Interpretation>,
    style: Style,
    describer: &mut Describer<'_>,
) {
    let Some(found) = found else { return };
    let found = described(found, describer);
    let reading = speech::reading(&found);
    decision.utterance.push_str(&match style {
        Style::Diarc => format!(" Do you want me to {reading} instead?"),
        Style::Natural => format!(" Shall I {reading} instead?"),
    });
    decision.alternative = Some(found.action);
}
