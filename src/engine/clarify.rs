//! Algorithm 1 and the single-candidate cases: from a directive and a scene to a decision, its
//! utterance and its speech act.
//!
//! Owns: reference resolution, the readings (interpretations) and their order, the decision, and
//! the `diarc`-style sentences. Must not: do I/O, or offer, assume, confirm or obey a reading that
//! is impermissible or infeasible under the moral strategy.

use std::collections::BTreeMap;
use std::sync::Arc;

use super::action::Library;
use super::describe::Describer;
use super::norms::CompiledNorms;
use super::scene::{Object, Scene, spoken};
use super::simulate::{Cause, Env, Outcome, Reason, did, simulate};
use super::term::{Sym, Term};
use super::world::{Base, World};

/// Readings beyond this many are not simulated: the request is refused as too ambiguous.
pub const MAX_READINGS: usize = 10_000;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Strategy {
    /// The paper's algorithm: simulate first, then ask only about what may be done.
    #[default]
    Moral,
    /// The status quo the paper argues against: ask about every candidate before moral reasoning.
    Reflexive,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SinglePermissible {
    #[default]
    Assume,
    Confirm,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Options {
    pub strategy: Strategy,
    pub single_permissible: SinglePermissible,
}

/// A reference to objects of the scene: by id, or by type, attributes and properties.
#[derive(Clone, Debug, PartialEq)]
pub enum Reference {
    Id(String),
    Described {
        /// `None` matches any type.
        kind: Option<String>,
        attributes: BTreeMap<String, String>,
        properties: Vec<String>,
    },
}

impl Reference {
    fn matches(&self, object: &Object) -> bool {
        match self {
            Reference::Id(id) => &object.id == id,
            Reference::Described {
                kind,
                attributes,
                properties,
            } => {
                kind.as_ref().is_none_or(|k| k == &object.kind)
                    && attributes.iter().all(|(k, v)| object.attributes.get(k) == Some(v))
                    && properties.iter().all(|p| object.properties.contains(p))
            }
        }
    }

    /// The reference in words: "the spoon", "the blue notebook".
    fn words(&self) -> String {
        match self {
            Reference::Id(id) => id.clone(),
            Reference::Described {
                kind,
                attributes,
                properties,
            } => {
                let mut words = vec!["the".to_owned()];
                words.extend(properties.iter().map(|p| spoken(p)));
                words.extend(attributes.values().map(|v| spoken(v)));
                words.push(kind.as_deref().map(spoken).unwrap_or_else(|| "thing".to_owned()));
                words.join(" ")
            }
        }
    }
}

/// A candidate binding from an upstream resolver; higher scores are likelier.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    pub id: String,
    pub score: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Directive {
    /// A verb and one reference per argument; readings are every combination of candidates.
    Action { verb: String, arguments: Vec<Reference> },
    /// An action with variables, already unwrapped from `want(S,did(self,...))` by the caller
    /// (`get(X)`), and each variable's candidates, in the order the variables first appear.
    Form {
        action: Term,
        bindings: Vec<(Sym, Vec<Candidate>)>,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Request {
    pub speaker: Sym,
    pub directive: Directive,
    pub context: String,
    pub options: Options,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DecisionKind {
    Comply,
    Refuse,
    Ask,
    Assume,
    Confirm,
    Explain,
    Unresolved,
}

impl DecisionKind {
    pub fn as_str(self) -> &'static str {
        match self {
            DecisionKind::Comply => "comply",
            DecisionKind::Refuse => "refuse",
            DecisionKind::Ask => "ask",
            DecisionKind::Assume => "assume",
            DecisionKind::Confirm => "confirm",
            DecisionKind::Explain => "explain",
            DecisionKind::Unresolved => "unresolved",
        }
    }
}

/// One reading of the directive, simulated.
#[derive(Clone, Debug, PartialEq)]
pub struct Interpretation {
    /// `did(self,action)`, ground.
    pub action: Term,
    /// The arguments in words: "the plastic vase".
    pub description: String,
    /// The reading in words: "get the plastic vase".
    pub reading: String,
    pub score: f64,
    pub outcome: Outcome,
}

impl Interpretation {
    pub fn permissible(&self) -> bool {
        self.outcome.permissible()
    }

    pub fn feasible(&self) -> bool {
        self.outcome.feasible()
    }

    fn acceptable(&self) -> bool {
        self.permissible() && self.feasible()
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Decision {
    pub kind: DecisionKind,
    pub utterance: String,
    pub speech_act: Term,
    /// Set for `comply` and `assume` only: the reading the robot will carry out.
    pub goal: Option<Term>,
    /// Every reading considered, in the contract's order.
    pub interpretations: Vec<Interpretation>,
    /// The version of the norm set the decision was made under.
    pub norm_version: i64,
}

#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EngineError {
    #[error("the directive has {count} readings; at most {limit} are simulated")]
    TooManyReadings { count: u128, limit: usize },
}

/// Decides what to say about `request` in `scene`, under `norms`, with `library`'s verbs.
pub fn clarify(
    request: &Request,
    scene: &Scene,
    norms: &CompiledNorms,
    library: &Library,
) -> Result<Decision, EngineError> {
    let speaker = Term::Const(request.speaker.clone());
    let readings = match readings(&request.directive, scene)? {
        Readings::Unresolved(words) => return Ok(unresolved(words, norms.version)),
        Readings::Found(readings) => readings,
    };
    let base = Arc::new(Base::new(scene.all_facts()));
    let world = World::new(base);
    let env = Env {
        scene,
        norms,
        library,
        context: &request.context,
    };
    let mut describer = Describer::new(scene, library);
    let mut interpretations: Vec<Interpretation> = readings
        .into_iter()
        .map(|(action, score)| Interpretation {
            outcome: simulate(&env, &world, &action),
            description: describer.arguments(&action),
            reading: describer.reading(&action),
            action: did(&action),
            score,
        })
        .collect();
    interpretations.sort_by(|a, b| {
        b.score
            .total_cmp(&a.score)
            .then_with(|| a.description.as_bytes().cmp(b.description.as_bytes()))
            .then_with(|| a.action.to_string().cmp(&b.action.to_string()))
    });
    let mut decision = decide(&speaker, request.options, &interpretations, &mut describer);
    decision.interpretations = interpretations;
    decision.norm_version = norms.version;
    Ok(decision)
}

enum Readings {
    /// The references that match nothing, in words.
    Unresolved(Vec<String>),
    /// Ground actions with their scores.
    Found(Vec<(Term, f64)>),
}

/// One argument's (or variable's) candidates, each with its score.
type Slot = Vec<(Term, f64)>;

/// How one choice of candidates, one per slot, becomes an action.
enum Template<'a> {
    /// The verb applied to the chosen objects, in argument order.
    Verb(Sym),
    /// The form with each variable (in first-appearance order) bound to its choice.
    Form(&'a Term, Vec<Sym>),
}

fn readings(directive: &Directive, scene: &Scene) -> Result<Readings, EngineError> {
    // Each slot's candidates, with the words that name the slot if nothing matches it.
    let (template, named): (Template<'_>, Vec<(Slot, String)>) = match directive {
        Directive::Action { verb, arguments } => {
            let slots = arguments
                .iter()
                .map(|reference| {
                    let found = scene
                        .objects
                        .iter()
                        .filter(|o| reference.matches(o))
                        .map(|o| (Term::constant(&o.id), 1.0))
                        .collect();
                    (found, reference.words())
                })
                .collect();
            (Template::Verb(Sym::from(verb.as_str())), slots)
        }
        Directive::Form { action, bindings } => {
            let variables = action.variables();
            let slots = variables
                .iter()
                .map(|variable| {
                    let candidates = bindings
                        .iter()
                        .find(|(v, _)| v == variable)
                        .map(|(_, cs)| cs.as_slice());
                    let found = candidates
                        .unwrap_or_default()
                        .iter()
                        .filter(|c| scene.object(&c.id).is_some())
                        .map(|c| (Term::constant(&c.id), c.score))
                        .collect();
                    (found, variable.to_string())
                })
                .collect();
            (Template::Form(action, variables), slots)
        }
    };
    let missing: Vec<String> = named
        .iter()
        .filter(|(found, _)| found.is_empty())
        .map(|(_, w)| w.clone())
        .collect();
    if !missing.is_empty() {
        return Ok(Readings::Unresolved(missing));
    }
    let slots: Vec<Slot> = named.into_iter().map(|(found, _)| found).collect();
    let count = slots
        .iter()
        .try_fold(1u128, |acc, s| acc.checked_mul(s.len() as u128))
        .unwrap_or(u128::MAX);
    if count > MAX_READINGS as u128 {
        return Err(EngineError::TooManyReadings {
            count,
            limit: MAX_READINGS,
        });
    }
    let mut out = Vec::with_capacity(count as usize);
    let mut choice = vec![0usize; slots.len()];
    loop {
        let picked: Vec<&(Term, f64)> = choice.iter().zip(&slots).map(|(&i, s)| &s[i]).collect();
        let score = picked.iter().map(|(_, s)| s).product::<f64>();
        let action = match &template {
            Template::Verb(verb) => Term::Compound(verb.clone(), picked.iter().map(|(t, _)| t.clone()).collect()),
            Template::Form(form, variables) => {
                let mut subst = super::term::Subst::new();
                for (variable, (value, _)) in variables.iter().zip(&picked) {
                    subst.bind(variable.clone(), value.clone());
                }
                form.substitute(&subst)
            }
        };
        // A verb with no arguments is a constant, not a compound with an empty list.
        let action = if action.arity() == 0 && !action.is_var() {
            Term::Const(action.name().cloned().unwrap_or_default())
        } else {
            action
        };
        out.push((action, score));
        // Odometer over the slots, last slot fastest.
        let mut slot = slots.len();
        loop {
            if slot == 0 {
                return Ok(Readings::Found(out));
            }
            slot -= 1;
            choice[slot] += 1;
            if choice[slot] < slots[slot].len() {
                break;
            }
            choice[slot] = 0;
        }
    }
}

fn unresolved(words: Vec<String>, norm_version: i64) -> Decision {
    let referents: Vec<Term> = words
        .iter()
        .map(|w| Term::compound("referent", vec![Term::constant(&w.replace(' ', "_"))]))
        .collect();
    let what = if referents.len() == 1 {
        referents[0].clone()
    } else {
        Term::compound("and", referents)
    };
    Decision {
        kind: DecisionKind::Unresolved,
        utterance: format!("I do not know what you mean by {}.", words.join(" and ")),
        speech_act: Term::compound("want_know", vec![Term::constant("self"), what]),
        goal: None,
        interpretations: Vec::new(),
        norm_version,
    }
}

/// The reason in words, as the contract's table gives it.
fn reason_words(reason: &Reason, describer: &mut Describer<'_>) -> String {
    match &reason.cause {
        Cause::ForbiddenAction { name, .. } => format!("{name} is forbidden action"),
        Cause::ForbiddenState { .. } => "it requires a forbidden state".to_owned(),
        Cause::UnknownAction { verb } => format!("I do not know how to {}", spoken(verb)),
        Cause::Unreachable { object } => {
            format!("{} is out of reach", describer.argument(&Term::Const(object.clone())))
        }
        Cause::UnknownObject { object } => format!("I do not see {}", describer.argument(object)),
        Cause::Precondition { fact } => format!("{fact} does not hold"),
        Cause::PlanTooDeep { .. } => "its plan is too deep to simulate".to_owned(),
    }
}

/// `I cannot {reading} because {reason}`, and its term `cannot(a,because(r))`. Only called for
/// readings that have a reason.
fn cannot(interpretation: &Interpretation, describer: &mut Describer<'_>) -> (String, Term) {
    let first = &interpretation.outcome.reasons[0];
    let words = format!(
        "I cannot {} because {}",
        interpretation.reading,
        reason_words(first, describer)
    );
    let term = Term::compound(
        "cannot",
        vec![
            interpretation.action.clone(),
            Term::compound("because", vec![first.term()]),
        ],
    );
    (words, term)
}

fn mean(speaker: &Term, what: Term) -> Term {
    Term::compound("mean", vec![speaker.clone(), what])
}

fn act(name: &str, what: Term) -> Term {
    Term::compound(name, vec![Term::constant("self"), what])
}

fn decision(kind: DecisionKind, utterance: String, speech_act: Term, goal: Option<Term>) -> Decision {
    Decision {
        kind,
        utterance,
        speech_act,
        goal,
        interpretations: Vec::new(),
        norm_version: 0,
    }
}

fn ask(speaker: &Term, offered: &[&Interpretation]) -> Decision {
    let readings: Vec<&str> = offered.iter().map(|i| i.reading.as_str()).collect();
    let utterance = format!(
        "Do you mean that you want me to {}?",
        readings.join(" or that you want me to ")
    );
    let or = Term::compound("or", offered.iter().map(|i| i.action.clone()).collect());
    decision(DecisionKind::Ask, utterance, act("want_know", mean(speaker, or)), None)
}

/// Algorithm 1 (two or more readings) and the single-reading cases.
fn decide(speaker: &Term, options: Options, all: &[Interpretation], describer: &mut Describer<'_>) -> Decision {
    if let [only] = all {
        return if only.acceptable() {
            decision(
                DecisionKind::Comply,
                "Okay.".to_owned(),
                act("acknowledge", mean(speaker, only.action.clone())),
                Some(only.action.clone()),
            )
        } else {
            let (words, term) = cannot(only, describer);
            decision(DecisionKind::Refuse, format!("{words}."), term, None)
        };
    }
    if options.strategy == Strategy::Reflexive {
        return ask(speaker, &all.iter().collect::<Vec<_>>());
    }
    let good: Vec<&Interpretation> = all.iter().filter(|i| i.acceptable()).collect();
    match good.as_slice() {
        [] => {
            let (sentences, terms): (Vec<String>, Vec<Term>) = all.iter().map(|i| cannot(i, describer)).unzip();
            let clauses: Vec<String> = sentences
                .iter()
                .map(|s| s.trim_start_matches("I ").to_owned())
                .collect();
            let utterance = format!("I believe that I {}.", clauses.join(" and that I "));
            decision(
                DecisionKind::Explain,
                utterance,
                act("believe", Term::compound("and", terms)),
                None,
            )
        }
        [chosen] => {
            let others: String = all
                .iter()
                .filter(|i| !i.acceptable())
                .map(|i| format!(" {}.", cannot(i, describer).0))
                .collect();
            let target = mean(speaker, chosen.action.clone());
            match options.single_permissible {
                SinglePermissible::Assume => decision(
                    DecisionKind::Assume,
                    format!("I am assuming you want me to {}.{others}", chosen.reading),
                    act("assume", target),
                    Some(chosen.action.clone()),
                ),
                SinglePermissible::Confirm => decision(
                    DecisionKind::Confirm,
                    format!("Do you want me to {}?{others}", chosen.reading),
                    act("want_know", target),
                    None,
                ),
            }
        }
        several => ask(speaker, several),
    }
}
