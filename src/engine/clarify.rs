//! The decision pipeline: from a directive and a scene to a decision, stage by stage (resolve
//! the references, `resolve`; build and order the readings; simulate them; choose, `algorithm`;
//! word it, `speech`).
//!
//! Owns: the readings' order, the caps on how many are simulated, and the
//! deadline between stages. Must not: do I/O or read a clock (the deadline arrives as a
//! callback), or offer, assume, confirm or obey a reading that is impermissible or infeasible
//! under the moral strategy.

use rayon::prelude::*;

use super::action::Library;
use super::algorithm::{decide, kept, plan_kind};
use super::decision::{Decision, Interpretation, LimitKind, Limits, Plan, Style};
use super::decision::{DecisionKind, Unclear, Understood, Unfound};
use super::describe::Describer;
use super::norms::{CompiledNorms, Scope};
use super::request::{Answer, Directive, Request, SinglePermissible, SoftNorms, Strategy};
use super::resolve::Reference;
use super::resolve::{Narrowed, Template, combinations, slots};
use super::scene::Scene;
use super::simulate::{Env, Outcome, simulate};
use super::speech;
use super::term::Term;
use super::words::{self, Understanding};
use super::world::{Base, World};

/// From this many readings on, simulation (and the sort) runs on rayon's pool. A reading costs
/// about 2 µs at 1,000 objects, and handing work to the pool costs a wake-up and the other core
/// reading the fact base into its cache: 100 readings took longer on two threads than on one,
/// 200 slightly less (BENCHMARKS.md, fifteenth sitting). Below this, one thread also spends less
/// CPU, which a loaded server needs more than the microseconds.
pub const PARALLEL_FROM: usize = 128;
/// From this many readings on, each slot's candidates are put in the contract's order before
/// the readings are made (see [`presort`]), when they are at most an eighth of the readings. A
/// hint that only spares the sort: below this the sort is a few microseconds either way.
const PRESORT_FROM: usize = 64;
/// Candidates described for the presort between two looks at the deadline.
const PRESORT_LOOK: usize = 32;
/// At most this many readings are simulated by one thread between two looks at the deadline
/// when running in parallel: tens of microseconds of work, against a look that reads a clock.
const SIMULATE_CHUNK: usize = 64;
/// From this many readings on, they are described on rayon's pool, a batch per task: a reading
/// is described in about a microsecond once its objects are, so fewer are not worth a task and
/// a describer (whose descriptions are then made again) each.
pub(crate) const DESCRIBE_APART_FROM: usize = 2048;
/// Facts from which a decision's fact base is freed on rayon's pool rather than by the caller.
const LARGE_BASE: usize = 4096;
/// Readings described by one task of the pool (each looks at the deadline as it goes).
const PREPARE_BATCH: usize = 1024;
/// Readings described between two looks at the deadline.
const DESCRIBE_LOOK: usize = 64;

#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EngineError {
    #[error("choice {choice} is not among the {} the question named", readings(*offered))]
    BadChoice { choice: usize, offered: usize },
    #[error("the original request asks nothing to choose from: it is decided `{decision}`")]
    NothingAsked { decision: &'static str },
    /// A structured directive's joiner that its verb does not take.
    #[error("`{joiner}` does not join the arguments of `{verb}`")]
    BadJoiner { verb: String, joiner: String },
    /// The question asked which thing was meant, naming no readings: a choice by position has
    /// nothing to count.
    #[error(
        "the question asked which {nouns} you mean and named no readings to choose from: answer with a description (\"the red one\") or an object's id"
    )]
    AskedWhich { nouns: String },
}

/// "1 reading", "3 readings".
fn readings(n: usize) -> String {
    match n {
        1 => "1 reading".to_owned(),
        n => format!("{n} readings"),
    }
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

/// Decides what to say about `request` in `scene`, under `norms`, with `library`'s verbs.
/// `expired` tells whether the request's deadline has passed (or its client has gone); it is
/// asked while the words are read, while the readings are described, before each chunk of them
/// is simulated, and before every step a plan expands.
pub fn clarify(
    request: &Request,
    scene: &Scene,
    norms: &CompiledNorms,
    library: &Library,
    expired: &(dyn Fn() -> bool + Sync),
) -> Result<Decision, EngineError> {
    let read = read_words(request, scene, library, expired);
    clarify_read(request, read, scene, norms, library, expired)
}

/// What the request's words are read as, before anything is decided: `None` for a structured
/// directive. Reading is bounded by the words and the scene's names, not by the readings they
/// may give, so a caller may read first and admit the decision by what was read.
pub fn read_words(
    request: &Request,
    scene: &Scene,
    library: &Library,
    expired: &(dyn Fn() -> bool + Sync),
) -> Option<Understanding> {
    let Directive::Words { text } = &request.directive else {
        return None;
    };
    let heard = words::Heard::of(request);
    Some(words::understand(text, scene, library, heard, expired))
}

/// [`clarify`], with the words already read by [`read_words`] (for the same request, scene and
/// library).
pub fn clarify_read(
    request: &Request,
    read: Option<Understanding>,
    scene: &Scene,
    norms: &CompiledNorms,
    library: &Library,
    expired: &(dyn Fn() -> bool + Sync),
) -> Result<Decision, EngineError> {
    let speaker = Term::Const(request.speaker.clone());
    let not_read = |why: Unclear, words: String, limits: Option<Limits>| {
        let mut describer = Describer::new(scene, library).to(&request.speaker);
        let plan = Plan::NotUnderstood { why, words };
        let mut decision = render(
            &speaker,
            request.options.style,
            plan,
            Vec::new(),
            limits,
            norms.version,
            &mut describer,
        );
        decision.library_version = library.version;
        decision.parse = Some(Understood::not_a_directive(why));
        decision
    };
    let deadline = Limits {
        kind: LimitKind::Deadline,
        readings: 0,
        simulated: 0,
    };
    // An answer in words is read against the verbs in force; a whole new directive is decided
    // as if it had been said first.
    let answer = match &request.answer {
        Some(Answer::Words(text)) => {
            let answer = words::understand_answer(text, scene, library, expired);
            if expired() {
                return Ok(not_read(Unclear::Deadline, String::new(), Some(deadline)));
            }
            Some(answer)
        }
        other => other.clone(),
    };
    if let Some(Answer::Directive(text)) = &answer {
        let afresh = Request {
            directive: Directive::Words { text: text.clone() },
            answer: None,
            ..request.clone()
        };
        return clarify(&afresh, scene, norms, library, expired);
    }
    let Some(understanding) = read else {
        return decide_directive(
            request,
            answer.as_ref(),
            &request.directive,
            scene,
            norms,
            library,
            expired,
        );
    };
    match understanding {
        Understanding::Directive { directive, parse } => {
            let mut decision = decide_directive(request, answer.as_ref(), &directive, scene, norms, library, expired)?;
            // An answer that was not understood says why, beside what the directive was read as.
            let unclear = decision.parse.as_ref().and_then(|p| p.unclear);
            decision.parse = Some(Understood {
                unclear,
                ..parse.understood(&speaker, scene, expired)
            });
            Ok(decision)
        }
        Understanding::NotUnderstood { why, words } => Ok(not_read(why, words, None)),
        Understanding::Expired => Ok(not_read(Unclear::Deadline, String::new(), Some(deadline))),
    }
}

/// Whether every argument with more than one candidate is indefinite ("a mug", "the mug or
/// the cup"), and one is.
fn any_will_do(directive: &Directive, slots: &[super::resolve::Slot]) -> bool {
    let references: Vec<&Reference> = match directive {
        Directive::Action { arguments, .. } => arguments.iter().collect(),
        Directive::Task(task) => task.references().collect(),
        Directive::Form { .. } | Directive::Words { .. } => return false,
    };
    let mut open = references
        .into_iter()
        .zip(slots)
        .filter(|(_, slot)| slot.candidates.len() > 1)
        .peekable();
    open.peek().is_some() && open.all(|(argument, _)| argument.indefinite())
}

/// Decides `directive` (the request's own, or the one its words were read as), with the answer
/// to a question about it, if any.
fn decide_directive(
    request: &Request,
    answer: Option<&Answer>,
    directive: &Directive,
    scene: &Scene,
    norms: &CompiledNorms,
    library: &Library,
    expired: &(dyn Fn() -> bool + Sync),
) -> Result<Decision, EngineError> {
    let speaker = Term::Const(request.speaker.clone());
    let options = request.options;
    let mut describer = Describer::new(scene, library).to(&request.speaker);
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

    // "never mind" takes back what a question asked: it answers only a question.
    if let Some(Answer::Cancel(words)) = answer {
        let asked = decide_directive(request, None, directive, scene, norms, library, expired)?;
        let plan = match asked.kind {
            DecisionKind::Ask | DecisionKind::Confirm => Plan::Cancelled,
            _ => Plan::NotUnderstood {
                why: Unclear::Unasked,
                words: words.clone(),
            },
        };
        let mut decision = finish(plan, Vec::new(), None, &mut describer);
        if asked.kind != DecisionKind::Ask && asked.kind != DecisionKind::Confirm {
            decision.parse = Some(Understood::not_a_directive(Unclear::Unasked));
        }
        return Ok(decision);
    }

    // A plural argument makes a step per object: an action with one is a task of one step.
    let resolved = directive.as_resolved(library, scene, &request.speaker);
    let directive = &*resolved;
    let relation = joined(directive, library, &mut describer)?;
    // A task's purposes name objects too, which no reading binds: one that matches nothing is
    // said as any reference that does.
    let (template, mut slots, purpose_slots) = match directive {
        Directive::Task(task) => {
            let (mut shape, slots, purpose_slots) = task.shape(scene, expired);
            shape
                .join(library)
                .map_err(|(verb, joiner)| EngineError::BadJoiner { verb, joiner })?;
            (Template::Task(Box::new(shape)), slots, purpose_slots)
        }
        _ => {
            let (template, slots) = slots(directive, scene, expired);
            (template, slots, Vec::new())
        }
    };
    // A slot cut short by the deadline is empty, and says nothing of the scene.
    if (slots.iter().chain(&purpose_slots)).any(|s| s.candidates.is_empty()) && expired() {
        let limits = Limits {
            kind: LimitKind::Deadline,
            readings: 0,
            simulated: 0,
        };
        // Nothing was found in time: every reference is named, as when too many were.
        let nouns = slots.iter().map(|s| s.noun.clone()).collect();
        return Ok(finish(
            Plan::AskWhich { nouns },
            Vec::new(),
            Some(limits),
            &mut describer,
        ));
    }
    let missing: Vec<Unfound> = (slots.iter().chain(&purpose_slots))
        .filter(|s| s.candidates.is_empty())
        .map(|s| Unfound {
            words: s.words.clone(),
            unplaced: s.unplaced.clone(),
            untold: s.untold.clone(),
        })
        .collect();
    if !missing.is_empty() {
        return Ok(finish(Plan::Unresolved(missing), Vec::new(), None, &mut describer));
    }
    let narrowing = match answer {
        Some(answer @ (Answer::Id(_) | Answer::Reference(_))) => Some(answer),
        _ => None,
    };
    let narrowed = narrowing.map(|answer| Narrowed::new(answer, &slots, scene, expired));
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

    // Only readings that will be simulated are worth putting in order: the order of a few
    // candidates is a hint to the sort, given up at the deadline.
    let narrowed = match presort(&mut slots, &mut describer, expired) {
        true => narrowing.map(|answer| Narrowed::new(answer, &slots, scene, expired)),
        false => narrowed,
    };
    let chosen = match &narrowed {
        Some(narrowed) => narrowed.combinations(),
        None => combinations(&slots.iter().map(|s| s.candidates.as_slice()).collect::<Vec<_>>()),
    };
    // Describing every reading is work too (a tenth of a second for 100,000): the deadline is
    // asked here as well, and past it nothing is simulated and the ambiguous words are named.
    let prepared = chosen.len() as u128;
    let Some(mut readings) = prepare(chosen, &template, &mut describer, expired) else {
        let limits = Limits {
            kind: LimitKind::Deadline,
            readings: prepared,
            simulated: 0,
        };
        let plan = decide(options, &[], &slots, true);
        return Ok(finish(plan, Vec::new(), Some(limits), &mut describer));
    };
    if readings.is_empty() {
        // The answer matches none of the readings.
        let unfound = match answer {
            Some(Answer::Reference(reference)) => Unfound {
                words: reference.words(scene),
                unplaced: reference.unplaced(),
                untold: None,
            },
            Some(Answer::Id(id)) => Unfound {
                words: Reference::Id(id.clone()).words(scene),
                unplaced: None,
                untold: None,
            },
            _ => Unfound {
                words: String::new(),
                unplaced: None,
                untold: None,
            },
        };
        return Ok(finish(
            Plan::Unresolved(vec![unfound]),
            Vec::new(),
            None,
            &mut describer,
        ));
    }
    // The contract's order, before simulating: likeliest first, so a deadline cuts the least likely.
    // Stable, as the order of readings alike in all three must be the order they were made in.
    let mut order: Vec<usize> = (0..readings.len()).collect();
    let contract = |&a: &usize, &b: &usize| {
        let (a, b) = (&readings[a], &readings[b]);
        (contract_key(a.score, &a.description).cmp(&contract_key(b.score, &b.description)))
            // Two readings described alike are rare: only they are printed.
            .then_with(|| a.action.to_string().cmp(&b.action.to_string()))
    };
    // A stable sort has one result, however many threads sort.
    if order.len() >= PARALLEL_FROM {
        order.par_sort_by(contract);
    } else {
        order.sort_by(contract);
    }
    permute(&mut readings, order);

    let base = Base::new(scene.facts_with_speaker(&request.speaker, &request.speaker_roles));
    let scope = Scope {
        context: &request.context,
        roles: &request.speaker_roles,
        // The reflexive strategy ignores soft norms as it ignores all norms.
        soft: options.strategy == Strategy::Moral && options.soft_norms == SoftNorms::Rank,
    };
    let total = readings.len();
    let said = match &template {
        Template::Task(shape) => shape.said_relations(),
        _ => relation.iter().cloned().collect(),
    };
    // Kept past the simulation: an alternative after a refusal is simulated in the same world.
    let env = Env::new(scene, norms, library, scope, &base, &said, expired);
    let world = World::new(&base);
    let simulated = {
        let simulate_one = |reading: &mut Interpretation| {
            (reading.outcome, reading.action) = match &template {
                Template::Task(shape) => shape.simulate(&env, &world, &reading.action, &reading.values),
                _ => simulate(&env, &world, &reading.action, relation.as_ref()),
            };
        };
        // Readings are simulated in the contract's order, with the deadline asked before each
        // (the first always runs); many go to rayon's pool a chunk at a time. Each is
        // independent and lands in its own slot, so the result is the same whatever the threads.
        if total >= PARALLEL_FROM {
            simulate_apart(&mut readings, &simulate_one, expired)
        } else {
            let mut simulated = 0;
            while simulated < total && (simulated == 0 || !expired()) {
                simulate_one(&mut readings[simulated]);
                simulated += 1;
            }
            simulated
        }
    };
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
    // "Get a mug.": when every reference with a choice is indefinite, any acceptable reading
    // will do; the first in the contract's order is taken, and only what cannot be done is
    // explained.
    // Never on a partial view: with readings left unsimulated, one of them might be the one
    // the norms forbid, and "any will do" would be a guess among what was seen.
    if options.strategy == Strategy::Moral
        && limits.is_none()
        && matches!(plan, Plan::Ask { .. } | Plan::AskWhich { .. })
        && any_will_do(directive, &slots)
        && let kept = kept(&readings)
        && let [chosen, _, ..] = kept[..]
    {
        // What cannot be done is explained, and what is dispreferred; the other readings as
        // good as the one taken go unsaid.
        let others = (0..readings.len()).filter(|i| !kept.contains(i)).collect();
        plan = match options.single_permissible {
            SinglePermissible::Assume => Plan::Assume { chosen, others },
            SinglePermissible::Confirm => Plan::Confirm { chosen, others },
        };
    }
    let mut excluded = Vec::new();
    if let Directive::Action { arguments, .. } = directive {
        arguments.iter().for_each(|r| r.excluded(scene, expired, &mut excluded));
    }
    excluded.sort_unstable();
    let search = alternative::Search {
        env: &env,
        world: &world,
        relation: relation.as_ref(),
        most: options.max_readings,
        excluded: &excluded,
    };
    let mut found = (alternative::wanted(&options, &plan, limits.is_some()))
        .then(|| search.nearest(&template, &readings))
        .flatten();
    drop((env, world));
    if base.len() >= LARGE_BASE {
        // Freeing a large fact base takes milliseconds: done on the pool while the answer is
        // worded, not before it.
        rayon::spawn(move || drop(base));
    }
    // "yes" confirms the reading a question to confirm named, or takes the alternative offered
    // (one that became unacceptable is not found again: the refusal stands), decided afresh;
    // "no" to it, or either to anything else, leaves nothing to do.
    if matches!(answer, Some(Answer::Yes | Answer::Alternative))
        && let Some(alternative) = found.take()
    {
        readings = vec![alternative::described(alternative, &mut describer)];
        plan = decide(options, &readings, &slots, false);
        return Ok(finish(plan, readings, limits, &mut describer));
    }
    match (answer, &plan) {
        (Some(Answer::Yes | Answer::Alternative), Plan::Refuse(_) | Plan::Explain(_))
            if options.offers_alternatives() => {}
        (Some(Answer::Alternative), other) => {
            return Err(EngineError::NothingAsked {
                decision: plan_kind(other).as_str(),
            });
        }
        (Some(Answer::Yes), Plan::Confirm { chosen, .. }) => {
            readings = vec![readings.swap_remove(*chosen)];
            plan = decide(options, &readings, &slots, false);
            return Ok(finish(plan, readings, limits, &mut describer));
        }
        (Some(Answer::No), Plan::Confirm { .. }) => {
            return Ok(finish(Plan::Cancelled, Vec::new(), None, &mut describer));
        }
        (Some(answer @ (Answer::Yes | Answer::No)), _) => {
            let plan = Plan::NotUnderstood {
                why: Unclear::Unasked,
                words: if matches!(answer, Answer::Yes) { "yes" } else { "no" }.to_owned(),
            };
            let mut decision = finish(plan, Vec::new(), None, &mut describer);
            decision.parse = Some(Understood::not_a_directive(Unclear::Unasked));
            return Ok(decision);
        }
        _ => {}
    }
    if let Some(&Answer::Choice(choice)) = answer {
        let offered = match &plan {
            Plan::Ask { offered, .. } => offered.clone(),
            Plan::Confirm { chosen, .. } => vec![*chosen],
            Plan::AskWhich { nouns } => {
                return Err(EngineError::AskedWhich {
                    nouns: nouns.join(" and which "),
                });
            }
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
    let mut decision = finish(plan, readings, limits, &mut describer);
    alternative::offer(&mut decision, found, options.style, &mut describer);
    Ok(decision)
}

/// Each reading's action and words, in the order chosen; `None` when the deadline passed first
/// (asked between batches, never before the first). Many readings are described batch by batch
/// on rayon's pool, each batch with its own describer: a description depends only on the scene,
/// so the words are the same whichever thread wrote them.
fn prepare(
    chosen: Vec<(Vec<Term>, f64)>,
    template: &Template<'_>,
    describer: &mut Describer<'_>,
    expired: &(dyn Fn() -> bool + Sync),
) -> Option<Vec<Interpretation>> {
    let describe = |describer: &mut Describer<'_>, (values, score): (Vec<Term>, f64)| {
        let action = template.action(&values);
        Interpretation {
            description: match template {
                Template::Task(shape) => shape.words(&values, describer),
                _ => describer.arguments(&action),
            },
            action,
            score,
            outcome: Outcome::default(),
            reason_words: Vec::new(),
            values,
        }
    };
    // A description may take a pass over the objects of its type: the deadline is asked every
    // few readings, never before the first.
    let described = |describer: &mut Describer<'_>, chosen: Vec<(Vec<Term>, f64)>, first: bool| {
        let mut readings = Vec::with_capacity(chosen.len());
        for (n, c) in chosen.into_iter().enumerate() {
            if (n > 0 || !first) && n % DESCRIBE_LOOK == 0 && expired() {
                return None;
            }
            readings.push(describe(describer, c));
        }
        Some(readings)
    };
    if chosen.len() < DESCRIBE_APART_FROM {
        return described(describer, chosen, true);
    }
    let describer = &*describer;
    let batch = parallel_batch(chosen.len());
    let batches: Vec<Option<Vec<Interpretation>>> = (chosen.into_par_iter().chunks(batch).enumerate())
        .map(|(n, batch)| described(&mut describer.fresh(), batch, n == 0))
        .collect();
    let mut readings = Vec::with_capacity(batches.iter().flatten().map(Vec::len).sum());
    for batch in batches {
        readings.extend(batch?);
    }
    Some(readings)
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
    let word = |describer: &mut Describer<'_>, i: &mut Interpretation| {
        i.reason_words = (i.outcome.reasons.iter())
            .map(|r| speech::reason_words(r, style, describer))
            .collect();
    };
    if interpretations.len() >= DESCRIBE_APART_FROM {
        // As in `prepare`: batch by batch, each with its own describer, the same words.
        let describer = &*describer;
        let batch = parallel_batch(interpretations.len());
        interpretations.par_chunks_mut(batch).for_each(|batch| {
            let mut describer = describer.fresh();
            batch.iter_mut().for_each(|i| word(&mut describer, i));
        });
    } else {
        interpretations.iter_mut().for_each(|i| word(describer, i));
    }
    let utterance = speech::answer_utterance(&plan, &mut interpretations, style, describer);
    Decision {
        kind: plan_kind(&plan),
        utterance,
        speech_act: speech::speech_act(&plan, &interpretations, speaker),
        goal,
        interpretations,
        offered,
        limits,
        norm_version,
        library_version: 0,
        parse: None,
        alternative: None,
    }
}

mod alternative;
mod pool;
mod presort;
mod said;
#[cfg(test)]
mod tests;

use pool::{parallel_batch, permute, simulate_apart};
use presort::{contract_key, presort};
use said::joined;
