//! Algorithm 1 and what the paper left open: from a directive and a scene to a decision.
//!
//! Owns: reference resolution, the readings (interpretations) and their order, follow-up answers,
//! the caps on how many readings are simulated and named, and the decision as a `Plan`.
//! Must not: do I/O or read a clock (the deadline arrives as a callback), word anything (that is
//! `speech`), or offer, assume, confirm or obey a reading that is impermissible or infeasible
//! under the moral strategy.

use std::cmp::Reverse;
use std::collections::BTreeMap;

use rayon::prelude::*;
use std::sync::Arc;

use super::action::Library;
use super::decision::{Decision, DecisionKind, Interpretation, LimitKind, Limits, Plan, Style};
use super::describe::Describer;
use super::norms::{CompiledNorms, Scope};
use super::scene::{Object, Scene, spoken};
use super::simulate::{Env, Outcome, did, simulate};
use super::speech;
use super::term::{Subst, Sym, Term};
use super::world::{Base, World};

/// Defaults of the options that bound a request's work and words.
pub const DEFAULT_MAX_SPOKEN: usize = 5;
pub const DEFAULT_MAX_READINGS: usize = 10_000;
/// How many of the likeliest readings are named when there are too many to name them all.
pub const FEW: usize = 3;
/// From this many readings on, simulation runs on rayon's pool: a reading costs about 8 µs
/// (BENCHMARKS.md), so 64 of them outweigh the tens of µs that splitting work across threads costs.
pub const PARALLEL_FROM: usize = 64;
/// Readings simulated between two looks at the deadline when running in parallel.
const PARALLEL_BATCH: usize = 512;
/// Readings described between two looks at the deadline.
const PREPARE_BATCH: usize = 1024;

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

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    pub strategy: Strategy,
    pub single_permissible: SinglePermissible,
    pub style: Style,
    /// Most readings a question names; above it the question names the few likeliest and ends
    /// "or something else", or names the ambiguous words.
    pub max_spoken: usize,
    /// Most readings simulated; above it nothing is simulated and the ambiguous words are named.
    pub max_readings: usize,
    /// When exactly one reading is acceptable and the share of the others is above this ratio,
    /// confirm instead of assuming. `None`: always Algorithm 1's assumption.
    pub confirm_above_ratio: Option<f64>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            strategy: Strategy::Moral,
            single_permissible: SinglePermissible::Assume,
            style: Style::Diarc,
            max_spoken: DEFAULT_MAX_SPOKEN,
            max_readings: DEFAULT_MAX_READINGS,
            confirm_above_ratio: None,
        }
    }
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

    /// The reference in words: "the spoon", "the blue notebook", "the red one".
    fn words(&self, scene: &Scene) -> String {
        match self {
            Reference::Id(id) => match scene.object(id) {
                Some(object) => super::describe::describe_object(scene, object),
                None => id.clone(),
            },
            Reference::Described {
                attributes, properties, ..
            } => {
                let mut words = vec!["the".to_owned()];
                words.extend(properties.iter().map(|p| spoken(p)));
                words.extend(attributes.values().map(|v| spoken(v)));
                words.push(self.noun().unwrap_or_else(|| "one".to_owned()));
                words.join(" ")
            }
        }
    }

    /// The head noun: the type spoken, if the reference names one.
    fn noun(&self) -> Option<String> {
        match self {
            Reference::Described { kind: Some(k), .. } => Some(spoken(k)),
            _ => None,
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

/// The human's answer to a question the robot asked, sent with the original request.
#[derive(Clone, Debug, PartialEq)]
pub enum Answer {
    /// The position (from 0) of a reading among those the question named (`offered`).
    Choice(usize),
    /// An object of the scene: keeps the readings that involve it.
    Id(String),
    /// "the red one": keeps the readings with an argument that matches.
    Reference(Reference),
}

#[derive(Clone, Debug, PartialEq)]
pub struct Request {
    pub speaker: Sym,
    /// The speaker's roles (`owner`): with the context, they select the norms in force.
    pub speaker_roles: Vec<String>,
    pub directive: Directive,
    pub context: String,
    pub options: Options,
    pub answer: Option<Answer>,
}

#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EngineError {
    #[error("choice {choice} is not among the {offered} readings the question named")]
    BadChoice { choice: usize, offered: usize },
    #[error("the original request asks nothing to choose from: it is decided `{decision}`")]
    NothingAsked { decision: &'static str },
}

/// A score ordered by `f64::total_cmp`, so readings sort the same on every run.
#[derive(PartialEq)]
struct Score(f64);

impl Eq for Score {}

impl PartialOrd for Score {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Score {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// One argument (or variable) of the directive and its candidates.
struct Slot {
    candidates: Vec<(Term, f64)>,
    /// The slot in words when nothing matches it ("the spoon").
    words: String,
    /// The slot's head noun when asking which one is meant ("spoon").
    noun: String,
}

/// How one choice of candidates, one per slot, becomes an action.
enum Template<'a> {
    /// The verb applied to the chosen objects, in argument order.
    Verb(Sym),
    /// The form with each variable (in first-appearance order) bound to its choice.
    Form(&'a Term, Vec<Sym>),
}

impl Template<'_> {
    fn action(&self, values: &[Term]) -> Term {
        match self {
            Template::Verb(verb) => Term::compound(verb, values.to_vec()),
            Template::Form(form, variables) => {
                let mut subst = Subst::new();
                for (variable, value) in variables.iter().zip(values) {
                    subst.bind(variable.clone(), value.clone());
                }
                form.substitute(&subst)
            }
        }
    }
}

/// The common type of a slot's candidate objects, spoken; "one" when they differ.
fn common_noun(scene: &Scene, candidates: &[(Term, f64)]) -> String {
    let mut kinds = candidates
        .iter()
        .filter_map(|(t, _)| t.name().and_then(|id| scene.object(id)))
        .map(|o| o.kind.as_str());
    match kinds.next() {
        Some(first) if kinds.all(|k| k == first) => spoken(first),
        _ => "one".to_owned(),
    }
}

fn slots<'a>(directive: &'a Directive, scene: &Scene) -> (Template<'a>, Vec<Slot>) {
    match directive {
        Directive::Action { verb, arguments } => {
            let slots = arguments
                .iter()
                .map(|reference| {
                    let candidates: Vec<(Term, f64)> = scene
                        .objects
                        .iter()
                        .filter(|o| reference.matches(o))
                        .map(|o| (Term::constant(&o.id), 1.0))
                        .collect();
                    let noun = reference.noun().unwrap_or_else(|| common_noun(scene, &candidates));
                    Slot {
                        candidates,
                        words: reference.words(scene),
                        noun,
                    }
                })
                .collect();
            (Template::Verb(Sym::from(verb.as_str())), slots)
        }
        Directive::Form { action, bindings } => {
            let variables = action.variables();
            let slots = variables
                .iter()
                .map(|variable| {
                    let given = bindings
                        .iter()
                        .find(|(v, _)| v == variable)
                        .map(|(_, cs)| cs.as_slice());
                    let candidates: Vec<(Term, f64)> = given
                        .unwrap_or_default()
                        .iter()
                        .filter(|c| scene.object(&c.id).is_some())
                        .map(|c| (Term::constant(&c.id), c.score))
                        .collect();
                    let noun = common_noun(scene, &candidates);
                    Slot {
                        candidates,
                        words: variable.to_string(),
                        noun,
                    }
                })
                .collect();
            (Template::Form(action, variables), slots)
        }
    }
}

/// Every combination of one candidate from each list (last list fastest): the values and the
/// score.
fn combinations(lists: &[&[(Term, f64)]]) -> Vec<(Vec<Term>, f64)> {
    let mut out = Vec::new();
    if lists.iter().any(|l| l.is_empty()) {
        return out;
    }
    let mut choice = vec![0usize; lists.len()];
    loop {
        let values = choice.iter().zip(lists).map(|(&i, l)| l[i].0.clone()).collect();
        let score = choice.iter().zip(lists).map(|(&i, l)| l[i].1).product();
        out.push((values, score));
        let mut slot = lists.len();
        loop {
            if slot == 0 {
                return out;
            }
            slot -= 1;
            choice[slot] += 1;
            if choice[slot] < lists[slot].len() {
                break;
            }
            choice[slot] = 0;
        }
    }
}

/// Whether an object the answer names is this candidate.
fn answer_names(answer: &Answer, value: &Term, scene: &Scene) -> bool {
    let Some(object) = value.name().and_then(|id| scene.object(id)) else {
        return false;
    };
    match answer {
        Answer::Id(id) => &object.id == id,
        Answer::Reference(reference) => reference.matches(object),
        Answer::Choice(_) => true,
    }
}

/// The readings a follow-up keeps (those with an argument the answer names), counted and built
/// without going through the others: the answer narrows the readings before `max_readings` is
/// applied, so five cups and "c2" are one reading, not five times five.
struct Narrowed {
    /// Per slot: the candidates the answer names, and the others.
    named: Vec<Vec<(Term, f64)>>,
    others: Vec<Vec<(Term, f64)>>,
}

impl Narrowed {
    fn new(answer: &Answer, slots: &[Slot], scene: &Scene) -> Narrowed {
        let (named, others) = slots
            .iter()
            .map(|s| {
                s.candidates
                    .iter()
                    .cloned()
                    .partition(|(t, _)| answer_names(answer, t, scene))
            })
            .unzip();
        Narrowed { named, others }
    }

    /// All combinations less those that name nothing the answer names.
    fn count(&self) -> u128 {
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
    fn combinations(&self) -> Vec<(Vec<Term>, f64)> {
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

/// Decides what to say about `request` in `scene`, under `norms`, with `library`'s verbs.
/// `expired` tells whether the request's deadline has passed; it is asked before each reading
/// after the first is simulated (the first always is).
pub fn clarify(
    request: &Request,
    scene: &Scene,
    norms: &CompiledNorms,
    library: &Library,
    expired: &(dyn Fn() -> bool + Sync),
) -> Result<Decision, EngineError> {
    let speaker = Term::Const(request.speaker.clone());
    let options = request.options;
    let mut describer = Describer::new(scene, library);
    let finish = |plan: Plan, interpretations: Vec<Interpretation>, limits, describer: &mut Describer<'_>| {
        let mut decision = render(
            &speaker,
            options.style,
            plan,
            interpretations,
            limits,
            norms.version,
            describer,
        );
        decision.library_version = library.version;
        decision
    };

    let (template, slots) = slots(&request.directive, scene);
    let missing: Vec<String> = slots
        .iter()
        .filter(|s| s.candidates.is_empty())
        .map(|s| s.words.clone())
        .collect();
    if !missing.is_empty() {
        return Ok(finish(Plan::Unresolved(missing), Vec::new(), None, &mut describer));
    }
    let narrowed = match &request.answer {
        Some(answer @ (Answer::Id(_) | Answer::Reference(_))) => Some(Narrowed::new(answer, &slots, scene)),
        _ => None,
    };
    let count = match &narrowed {
        Some(narrowed) => narrowed.count(),
        None => slots
            .iter()
            .try_fold(1u128, |acc, s| acc.checked_mul(s.candidates.len() as u128))
            .unwrap_or(u128::MAX),
    };
    if count > options.max_readings as u128 {
        // Too ambiguous to simulate: name the references that have more than one candidate.
        let nouns = slots
            .iter()
            .filter(|s| s.candidates.len() > 1)
            .map(|s| s.noun.clone())
            .collect();
        let limits = Limits {
            kind: LimitKind::TooManyReadings,
            readings: count,
            simulated: 0,
        };
        return Ok(finish(
            Plan::AskWhich { nouns },
            Vec::new(),
            Some(limits),
            &mut describer,
        ));
    }

    let chosen = match &narrowed {
        Some(narrowed) => narrowed.combinations(),
        None => combinations(&slots.iter().map(|s| s.candidates.as_slice()).collect::<Vec<_>>()),
    };
    // Describing every reading is work too (a tenth of a second for 100,000): the deadline is
    // asked here as well, and past it nothing is simulated and the ambiguous words are named.
    let mut readings: Vec<Interpretation> = Vec::with_capacity(chosen.len());
    let prepared = chosen.len() as u128;
    for (n, (values, score)) in chosen.into_iter().enumerate() {
        if n % PREPARE_BATCH == PREPARE_BATCH - 1 && expired() {
            let limits = Limits {
                kind: LimitKind::Deadline,
                readings: prepared,
                simulated: 0,
            };
            let plan = decide(options, &[], &slots, true);
            return Ok(finish(plan, Vec::new(), Some(limits), &mut describer));
        }
        let action = template.action(&values);
        readings.push(Interpretation {
            description: describer.arguments(&action),
            reading: describer.reading(&action),
            action,
            score,
            outcome: Outcome::default(),
            reason_words: Vec::new(),
            values,
        });
    }
    if readings.is_empty() {
        // The answer matches none of the readings.
        let words = match &request.answer {
            Some(Answer::Reference(reference)) => reference.words(scene),
            Some(Answer::Id(id)) => Reference::Id(id.clone()).words(scene),
            _ => String::new(),
        };
        return Ok(finish(Plan::Unresolved(vec![words]), Vec::new(), None, &mut describer));
    }
    // The contract's order, before simulating: likeliest first, so a deadline cuts the least likely.
    readings.sort_by_cached_key(|r| (Reverse(Score(r.score)), r.description.clone(), r.action.to_string()));

    let base = Arc::new(Base::new(scene.all_facts()));
    let world = World::new(base);
    let env = Env {
        scene,
        norms,
        library,
        scope: Scope {
            context: &request.context,
            roles: &request.speaker_roles,
        },
        expired,
    };
    let total = readings.len();
    let simulate_one = |reading: &mut Interpretation| {
        reading.outcome = simulate(&env, &world, &reading.action);
        reading.action = did(&reading.action);
    };
    // Readings are simulated in batches, in the contract's order, with the deadline asked
    // between batches (the first batch always runs). Many readings go to rayon's pool; each is
    // independent and lands in its own slot, so the result is the same whatever the threads.
    let batch = if total >= PARALLEL_FROM { PARALLEL_BATCH } else { 1 };
    let mut simulated = 0;
    while simulated < total {
        if simulated > 0 && expired() {
            break;
        }
        let end = (simulated + batch).min(total);
        if total >= PARALLEL_FROM {
            readings[simulated..end].par_iter_mut().for_each(simulate_one);
        } else {
            readings[simulated..end].iter_mut().for_each(simulate_one);
        }
        simulated = end;
    }
    // Readings the deadline cut short mid-plan are not simulated: only those finished before
    // the first such one are kept, in the contract's order. A lone reading cut short is kept,
    // infeasible (`unfinished`), so that the robot can say why it will not act.
    let finished = readings[..simulated]
        .iter()
        .position(|r| r.outcome.unfinished())
        .unwrap_or(simulated);
    readings.truncate(if total == 1 { simulated } else { finished });
    let limits = (finished < total).then_some(Limits {
        kind: LimitKind::Deadline,
        readings: total as u128,
        simulated: finished,
    });

    let mut plan = decide(options, &readings, &slots, limits.is_some());
    if let Some(Answer::Choice(choice)) = request.answer {
        let offered = match &plan {
            Plan::Ask { offered, .. } => offered.clone(),
            Plan::Confirm { chosen, .. } => vec![*chosen],
            other => {
                return Err(EngineError::NothingAsked {
                    decision: plan_kind(other).as_str(),
                });
            }
        };
        let Some(&picked) = offered.get(choice) else {
            return Err(EngineError::BadChoice {
                choice,
                offered: offered.len(),
            });
        };
        readings = vec![readings.swap_remove(picked)];
        plan = decide(options, &readings, &slots, false);
    }
    Ok(finish(plan, readings, limits, &mut describer))
}

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

/// Algorithm 1 (two or more readings), the single-reading cases, and the caps.
fn decide(options: Options, all: &[Interpretation], slots: &[Slot], incomplete: bool) -> Plan {
    let good: Vec<usize> = (0..all.len()).filter(|&i| all[i].acceptable()).collect();
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
    let others: Vec<usize> = (0..all.len()).filter(|&i| !all[i].acceptable()).collect();
    match good.as_slice() {
        [] => Plan::Explain(others),
        [chosen] => {
            let share = others.len() as f64 / all.len() as f64;
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

fn plan_kind(plan: &Plan) -> DecisionKind {
    match plan {
        Plan::Comply(_) => DecisionKind::Comply,
        Plan::Refuse(_) => DecisionKind::Refuse,
        Plan::Ask { .. } | Plan::AskWhich { .. } => DecisionKind::Ask,
        Plan::Assume { .. } => DecisionKind::Assume,
        Plan::Confirm { .. } => DecisionKind::Confirm,
        Plan::Explain(_) => DecisionKind::Explain,
        Plan::Unresolved(_) => DecisionKind::Unresolved,
    }
}

fn render(
    speaker: &Term,
    style: Style,
    plan: Plan,
    mut interpretations: Vec<Interpretation>,
    limits: Option<Limits>,
    norm_version: i64,
    describer: &mut Describer<'_>,
) -> Decision {
    let (goal, offered) = match &plan {
        Plan::Comply(i) | Plan::Assume { chosen: i, .. } => {
            let action = interpretations[*i].action.clone();
            (Some(action.clone()), vec![action])
        }
        Plan::Confirm { chosen, .. } => (None, vec![interpretations[*chosen].action.clone()]),
        Plan::Ask { offered, .. } => (
            None,
            offered.iter().map(|&i| interpretations[i].action.clone()).collect(),
        ),
        _ => (None, Vec::new()),
    };
    for i in &mut interpretations {
        i.reason_words = i
            .outcome
            .reasons
            .iter()
            .map(|r| speech::reason_words(r, style, describer))
            .collect();
    }
    Decision {
        kind: plan_kind(&plan),
        utterance: speech::utterance(&plan, &interpretations, style, describer),
        speech_act: speech::speech_act(&plan, &interpretations, speaker),
        goal,
        interpretations,
        offered,
        limits,
        norm_version,
        library_version: 0,
    }
}
