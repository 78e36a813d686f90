//! The nearest reading not named that the norms permit and the robot can do, offered after a
//! refusal or an explanation under the moral strategy ("Shall I heat the soup with the stove
//! instead?"): the same verb, one argument replaced by another object of its type (or one
//! meeting the verb's implied facts for it), fewest differing features first.
//!
//! Owns: which readings are tried, in which order, and the bound on them (the request's
//! readings cap and deadline). Must not: offer one the simulation did not find permissible
//! and feasible, offer a different verb, or look under the reflexive strategy.

use serde::{Deserialize, Serialize};

use crate::engine::decision::{Decision, Interpretation, Plan, Style};
use crate::engine::describe::Describer;
use crate::engine::input::Spelled;
use crate::engine::norms::{CompiledNorms, Scope};
use crate::engine::request::{Options, Request, Strategy};
use crate::engine::resolve::Template;
use crate::engine::scene::{Object, PERSON, Scene};
use crate::engine::simulate::{Env, simulate};
use crate::engine::term::{Sym, Term};
use crate::engine::world::{Base, World};

/// Whether a refusal offers the nearest acceptable reading instead.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Alternatives {
    Offer,
    Off,
}

impl Spelled for Alternatives {
    const ALL: &'static [Alternatives] = &[Alternatives::Offer, Alternatives::Off];

    fn as_str(self) -> &'static str {
        match self {
            Alternatives::Offer => "offer",
            Alternatives::Off => "off",
        }
    }
}

impl Options {
    /// Whether alternatives are looked for: as asked, else in the natural style only (the
    /// paper's words stay exact), and never under the reflexive strategy.
    pub fn offers_alternatives(&self) -> bool {
        let asked = self.alternatives.unwrap_or(match self.style {
            Style::Diarc => Alternatives::Off,
            Style::Natural => Alternatives::Offer,
        });
        asked == Alternatives::Offer && self.strategy == Strategy::Moral
    }
}

/// What the search needs of the request being decided.
pub(super) struct Search<'a> {
    pub request: &'a Request,
    pub scene: &'a Scene,
    pub norms: &'a CompiledNorms,
    pub library: &'a crate::engine::action::Library,
    pub relation: Option<&'a (Sym, Sym)>,
    pub expired: &'a (dyn Fn() -> bool + Sync),
}

/// Whether the plan is one an alternative answers: a refusal or an explanation, every reading
/// seen.
pub(super) fn wanted(options: &Options, plan: &Plan, cut_short: bool) -> bool {
    options.offers_alternatives() && !cut_short && matches!(plan, Plan::Refuse(_) | Plan::Explain(_))
}

impl Search<'_> {
    /// The nearest acceptable reading none of `readings` names, simulated; `None` when there is
    /// none, the verb's readings are not of one action, or the cap or deadline ran out first.
    pub(super) fn nearest(&self, template: &Template<'_>, readings: &[Interpretation]) -> Option<Interpretation> {
        let Template::Verb(verb) = template else { return None };
        let def = self.library.get(verb, readings.first()?.values.len())?;
        let named: Vec<Term> = readings
            .iter()
            .map(|r| Term::compound(verb, r.values.clone()))
            .collect();
        // (differing features, reading, argument, object) for every one-argument change.
        let mut tried: Vec<(usize, usize, usize, usize)> = Vec::new();
        for (r, reading) in readings.iter().enumerate() {
            for (a, value) in reading.values.iter().enumerate() {
                let Some(was) = value.name().and_then(|id| self.scene.object(id)) else {
                    continue;
                };
                let implied = def.params.get(a).and_then(|p| def.implied.iter().find(|(q, _)| q == p));
                let meets = implied.map(|(p, facts)| {
                    crate::engine::resolve::meeting(self.scene, p, facts, self.expired).unwrap_or_default()
                });
                for (o, object) in self.scene.objects.iter().enumerate() {
                    let kin = object.kind == was.kind || meets.as_ref().is_some_and(|m| m.contains(&o));
                    if !kin || object.id == was.id || (object.kind == PERSON) != (was.kind == PERSON) {
                        continue;
                    }
                    tried.push((differing(was, object), r, a, o));
                }
                if (self.expired)() {
                    return None;
                }
            }
        }
        tried.sort();
        let request = self.request;
        let base = Base::new(self.scene.facts_with_speaker(&request.speaker, &request.speaker_roles));
        let scope = Scope {
            context: &request.context,
            roles: &request.speaker_roles,
            soft: false,
        };
        let said: Vec<(Sym, Sym)> = self.relation.into_iter().cloned().collect();
        let env = Env::new(self.scene, self.norms, self.library, scope, &base, &said, self.expired);
        let world = World::new(&base);
        let mut seen: Vec<Term> = Vec::new();
        for (n, &(_, r, a, o)) in tried.iter().enumerate() {
            if n >= request.options.max_readings || (n > 0 && (self.expired)()) {
                return None;
            }
            let mut values = readings[r].values.clone();
            values[a] = Term::Const(self.scene.objects[o].id.clone());
            let action = Term::compound(verb, values.clone());
            if named.contains(&action) || seen.contains(&action) {
                continue;
            }
            let (outcome, done) = simulate(&env, &world, &action, self.relation);
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
            seen.push(action);
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

/// Puts the alternative found into the decision: its action term, and the question that ends
/// the utterance.
pub(super) fn offer(
    decision: &mut Decision,
    found: Option<Interpretation>,
    style: Style,
    describer: &mut Describer<'_>,
) {
    let Some(found) = found else { return };
    let inner = found
        .action
        .args()
        .get(1)
        .cloned()
        .unwrap_or_else(|| found.action.clone());
    let reading = describer.reading(&inner);
    decision.utterance.push_str(&match style {
        Style::Diarc => format!(" Do you want me to {reading} instead?"),
        Style::Natural => format!(" Shall I {reading} instead?"),
    });
    decision.alternative = Some(found.action);
}
