//! Checks while acting: the next step, or the rest of a plan, against the norms in force now.
//!
//! Owns: a check request's constructor (ground steps naming verbs, the scope, the style) and
//! simulating the steps in order in one private world, each starting where the last left off.
//! Must not: resolve references or choose among readings; the steps are ground.

use std::time::Duration;

use super::action::{Library, verb_name};
use super::decision::{LimitKind, Limits, Style};
use super::describe::Describer;
use super::input::{Invalid, RequestLimits};
use super::norms::{CompiledNorms, Force, Scope};
use super::request::{context_of, speaker_roles_of};
use super::scene::{DEFAULT_SPEAKER, Scene, SceneInput};
use super::simulate::{Env, Outcome, Reason, simulate_from};
use super::speech;
use super::term::Term;
use super::world::{Base, World};

/// Most steps one check may carry.
pub const MAX_STEPS: usize = 1000;

/// A check as a client sent it, before anything is checked.
#[derive(Clone, Debug)]
pub struct CheckInput {
    pub scene: SceneInput,
    pub steps: Vec<String>,
    pub context: Option<String>,
    pub speaker_roles: Option<Vec<String>>,
    pub style: Option<Style>,
    pub deadline_ms: Option<u64>,
}

/// A check request, valid: ground steps that name verbs, in a scene, under a scope.
#[derive(Debug)]
pub struct CheckRequest {
    pub scene: Scene,
    pub steps: Vec<Term>,
    pub context: String,
    pub speaker_roles: Vec<String>,
    pub style: Style,
    /// How long the check may take, from the request's arrival.
    pub deadline: Duration,
}

impl CheckRequest {
    /// Checks every member within the operator's limits; the first fault is reported with its
    /// field, as the request's JSON names it.
    pub fn from_input(input: CheckInput, limits: &RequestLimits) -> Result<CheckRequest, Invalid> {
        let context = context_of(input.context)?;
        let speaker_roles = speaker_roles_of(input.speaker_roles)?;
        let scene = Scene::from_input(input.scene, limits).map_err(|e| e.within("/scene"))?;
        if input.steps.is_empty() || input.steps.len() > MAX_STEPS {
            return Err(Invalid::new("/steps", format!("give 1 to {MAX_STEPS} steps")));
        }
        let steps = (input.steps.iter().enumerate())
            .map(|(i, text)| {
                let field = format!("/steps/{i}");
                let step = Term::parse_within(text, limits.terms)
                    .map_err(|e| Invalid::new(&field, format!("not a term: {e}")))?;
                if step.is_var() || !step.is_ground() {
                    return Err(Invalid::new(field, "a step is a ground action, such as get(object4)"));
                }
                if let Some(name) = step.name() {
                    verb_name(name).map_err(|m| Invalid::new(&field, m))?;
                }
                Ok(step)
            })
            .collect::<Result<_, _>>()?;
        Ok(CheckRequest {
            scene,
            steps,
            context,
            speaker_roles,
            style: input.style.unwrap_or_default(),
            deadline: limits.deadline(input.deadline_ms)?,
        })
    }
}

/// One step, simulated.
#[derive(Clone, Debug, PartialEq)]
pub struct StepCheck {
    pub step: Term,
    /// The step in words: "get the plastic vase".
    pub reading: String,
    pub outcome: Outcome,
    /// Each reason in words, in the request's style.
    pub reason_words: Vec<String>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Check {
    pub steps: Vec<StepCheck>,
    /// "Okay." when every step may be done; otherwise why not the first step that may not.
    pub utterance: String,
    pub norm_version: i64,
    /// Set when the deadline kept steps from being checked to the end (`simulated` counts the
    /// steps checked fully); the check is then not permitted.
    pub limits: Option<Limits>,
}

impl Check {
    /// Every step was checked and is permissible and feasible.
    pub fn permitted(&self) -> bool {
        self.limits.is_none()
            && self
                .steps
                .iter()
                .all(|s| s.outcome.permissible() && s.outcome.feasible())
    }
}

/// Simulates `steps` in order from `scene`, under the norms in force in `scope`.
pub fn check(
    steps: &[Term],
    scene: &Scene,
    norms: &CompiledNorms,
    library: &Library,
    scope: Scope<'_>,
    style: Style,
    expired: &(dyn Fn() -> bool + Sync),
) -> Check {
    // A check names no speaker: the default one, with the request's roles.
    let base = Base::new(scene.facts_with_speaker(DEFAULT_SPEAKER, scope.roles));
    let env = Env::new(scene, norms, library, scope, &base, &[], expired);
    let mut describer = Describer::new(scene, library);
    let mut world = World::new(&base);
    let mut checked = Vec::with_capacity(steps.len());
    for step in steps {
        // Past the deadline no further step is begun: the check says how far it got.
        if !checked.is_empty() && expired() {
            break;
        }
        let (outcome, after) = simulate_from(&env, world, step, None);
        world = after;
        let reason_words = outcome
            .reasons
            .iter()
            .map(|r| speech::reason_words(r, style, &mut describer))
            .collect();
        checked.push(StepCheck {
            step: step.clone(),
            reading: describer.reading(step),
            outcome,
            reason_words,
        });
    }
    let done = checked.iter().filter(|s| !s.outcome.unfinished()).count();
    let limits = (done < steps.len()).then_some(Limits {
        kind: LimitKind::Deadline,
        readings: steps.len() as u128,
        simulated: done,
    });
    // A refusal speaks the first reason that is not a soft norm's.
    let first_refused = checked
        .iter()
        .find(|s| !(s.outcome.permissible() && s.outcome.feasible()))
        .and_then(|s| {
            let hard = s.outcome.reasons.iter().position(|r| !r.is_soft())?;
            Some((s.reading.clone(), s.reason_words[hard].clone()))
        });
    // Steps that may be done but should not: "Okay, although the mug is dirty."
    let although: Vec<String> = (checked.iter())
        .flat_map(|s| s.outcome.reasons.iter().zip(&s.reason_words))
        .filter(|(r, _)| r.force() == Some(Force::Discouraged))
        .map(|(_, words)| words.clone())
        .collect();
    // Steps never begun (the deadline) are not "okay": the first of them is why not.
    let not_begun = || {
        let step = &steps[checked.len()];
        let why = speech::reason_words(&Reason::unfinished(), style, &mut describer);
        (describer.reading(step), why)
    };
    let utterance = match first_refused.or_else(|| (checked.len() < steps.len()).then(not_begun)) {
        None => match (style, although.is_empty()) {
            (Style::Diarc, true) => "Okay.".to_owned(),
            (Style::Diarc, false) => format!("Okay, although {}.", although.join(" and ")),
            (Style::Natural, true) => "Okay, I can go on.".to_owned(),
            (Style::Natural, false) => format!("Okay, I can go on, although {}.", although.join(" and ")),
        },
        Some((reading, why)) => match style {
            Style::Diarc => format!("I cannot {reading} because {why}."),
            Style::Natural => format!("I can't go on to {reading}: {why}."),
        },
    };
    Check {
        steps: checked,
        utterance,
        norm_version: norms.version,
        limits,
    }
}
