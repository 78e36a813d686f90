//! Why a reading cannot be done, or a soft norm it meets, and what simulating one found.
//!
//! Owns: the reasons' kinds, details and terms as the contract names them, and the outcome's
//! rules (each reason once, soft norms once per norm). Must not: simulate or word a reason.

use super::super::input::Spelled;
use super::super::norms::{Force, NormKind};
use super::super::term::{Sym, Term};

/// Why a reading is impermissible or infeasible, or a soft norm it meets.
#[derive(Clone, Debug, PartialEq)]
pub enum Cause {
    /// A soft norm (`kind` discouraged or preferred) met by `what`: the step done, for an action
    /// norm, or the fact entered, for a state norm. `about` holds the norm's `when` facts, as
    /// they held, that name one of the reading's own objects; `note` is the norm's.
    Soft {
        kind: NormKind,
        what: Term,
        about: Vec<Term>,
        note: Option<std::sync::Arc<str>>,
    },
    /// `step` is done, and a norm forbids actions named `name`; `words` when that norm is
    /// spoken by more than its kind (a note, or conditions).
    ForbiddenAction {
        step: Term,
        name: Sym,
        words: Option<Box<NormWords>>,
    },
    /// The world would enter a state in which `fact` holds, and a norm forbids it.
    ForbiddenState { fact: Term, words: Option<Box<NormWords>> },
    /// The library has no verb of this name and arity.
    UnknownAction { verb: Sym },
    /// The object is farther than the agent's reach.
    Unreachable { object: Sym },
    /// Another object is in the gripper's way to the object.
    Blocked { object: Sym, by: Sym },
    /// The object is wider than the gripper opens.
    TooWide { object: Sym },
    /// The object is heavier than the arm's payload.
    TooHeavy { object: Sym },
    /// The support has no room on top for the item.
    NoRoom { item: Sym, support: Sym },
    /// A handling step names something that is not an object of the scene.
    UnknownObject { object: Term },
    /// A verb's precondition does not hold when it would run.
    Precondition { fact: Term },
    /// A handling step (reach, grasp, place) names a person where the verb takes an object.
    Person { person: Sym },
    /// The plan expands deeper than [`MAX_PLAN_DEPTH`].
    PlanTooDeep { step: Term },
    /// The human said the task is for `purpose` ("to smash the vase"), which a forbidden norm
    /// forbids as `cause` says (a forbidden action or state): the robot will not help with it.
    /// `said`: for each of the purpose's arguments, the words the human said for it when it is
    /// a reference of the purpose's own ("the vase"), to be spoken as said.
    ForbiddenPurpose {
        purpose: Term,
        cause: Box<Cause>,
        said: std::sync::Arc<[Option<String>]>,
    },
    /// The request's deadline passed (or its client went away) before the simulation ended: what
    /// was not simulated cannot be vouched for, so the reading is never offered or obeyed.
    Unfinished,
    /// A verb whose arguments must be distinct names one object twice: a cup put on itself.
    SameObject {
        verb: Sym,
        object: Sym,
        /// The verb's joiner ("on"), for the words.
        joiner: Option<String>,
    },
}

/// What a forbidden norm says beyond its kind, for the words of a reason that must say no more
/// than the norm does: its note, and the conditions under which it applied.
#[derive(Clone, Debug, PartialEq)]
pub struct NormWords {
    pub note: Option<std::sync::Arc<str>>,
    /// Whether the norm has conditions: when, roles, exempt roles or a context.
    pub conditional: bool,
    /// Its `when` facts about the reading's objects, as they held (an object's type left out).
    pub about: Vec<Term>,
    /// The norm's roles that the speaker has.
    pub roles: Vec<String>,
    pub exempt_roles: Vec<String>,
    pub context: Option<String>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Reason {
    pub cause: Cause,
    /// The norm behind a `forbidden_*` reason.
    pub norm_id: Option<i64>,
    /// That norm's severity, 1..=5.
    pub severity: Option<u8>,
}

impl Reason {
    /// The reason a reading cut short by the deadline carries.
    pub fn unfinished() -> Reason {
        Reason::infeasible(Cause::Unfinished)
    }

    /// A norm's reason: which norm, and its severity.
    pub(super) fn of_norm(cause: Cause, norm_id: i64, severity: u8) -> Reason {
        Reason {
            cause,
            norm_id: Some(norm_id),
            severity: Some(severity),
        }
    }

    pub(super) fn infeasible(cause: Cause) -> Reason {
        Reason {
            cause,
            norm_id: None,
            severity: None,
        }
    }

    /// The contract's reason kind.
    pub fn kind(&self) -> &'static str {
        match self.cause {
            Cause::Soft { kind, .. } => Spelled::as_str(kind),
            Cause::ForbiddenAction { .. } => "forbidden_action",
            Cause::ForbiddenState { .. } => "forbidden_state",
            Cause::ForbiddenPurpose { .. } => "forbidden_purpose",
            Cause::UnknownAction { .. } => "unknown_action",
            Cause::Unreachable { .. } => "unreachable",
            Cause::Blocked { .. } => "blocked",
            Cause::TooWide { .. } => "too_wide",
            Cause::TooHeavy { .. } => "too_heavy",
            Cause::NoRoom { .. } => "no_room",
            Cause::UnknownObject { .. } => "unknown_object",
            Cause::Precondition { .. } => "precondition",
            Cause::Person { .. } => "person",
            Cause::PlanTooDeep { .. } => "plan_too_deep",
            Cause::SameObject { .. } => "same_object",
            Cause::Unfinished => "unfinished",
        }
    }

    /// What exactly: the forbidden step or fact, the unknown verb, the object out of reach.
    pub fn detail(&self) -> String {
        match &self.cause {
            Cause::Soft { what, .. } => what.text(),
            Cause::ForbiddenAction { step, .. } => step.text(),
            Cause::ForbiddenState { fact, .. } | Cause::Precondition { fact } => fact.text(),
            Cause::ForbiddenPurpose { purpose, .. } => purpose.text(),
            Cause::UnknownAction { verb } => verb.to_string(),
            Cause::Unreachable { object } | Cause::TooWide { object } | Cause::TooHeavy { object } => {
                object.to_string()
            }
            Cause::Blocked { object, by } => format!("{object} blocked by {by}"),
            Cause::NoRoom { item, support } => format!("no room for {item} on {support}"),
            Cause::UnknownObject { object } | Cause::PlanTooDeep { step: object } => object.to_string(),
            Cause::SameObject { object, .. } => object.to_string(),
            Cause::Person { person } => person.to_string(),
            Cause::Unfinished => "deadline".to_owned(),
        }
    }

    /// The reason as a term, as speech acts carry it: `forbiddenAction(destroy)`.
    pub fn term(&self) -> Term {
        let (name, arg) = match &self.cause {
            Cause::Soft { kind, what, .. } => {
                // An action norm is named by its verb, as `forbiddenAction(destroy)` is.
                let arg = match (kind.on_action(), what.name()) {
                    (true, Some(verb)) => Term::Const(verb.clone()),
                    _ => what.clone(),
                };
                (kind.reason_functor(), arg)
            }
            Cause::ForbiddenAction { name, .. } => {
                (NormKind::ForbiddenAction.reason_functor(), Term::Const(name.clone()))
            }
            Cause::ForbiddenState { fact, .. } => (NormKind::ForbiddenState.reason_functor(), fact.clone()),
            Cause::ForbiddenPurpose { purpose, .. } => ("forbiddenPurpose", purpose.clone()),
            Cause::UnknownAction { verb } => ("unknownAction", Term::Const(verb.clone())),
            Cause::Unreachable { object } => ("unreachable", Term::Const(object.clone())),
            Cause::Blocked { object, by } => {
                return Term::compound("blocked", vec![Term::Const(object.clone()), Term::Const(by.clone())]);
            }
            Cause::TooWide { object } => ("tooWide", Term::Const(object.clone())),
            Cause::TooHeavy { object } => ("tooHeavy", Term::Const(object.clone())),
            Cause::NoRoom { item, support } => {
                return Term::compound("noRoom", vec![Term::Const(item.clone()), Term::Const(support.clone())]);
            }
            Cause::UnknownObject { object } => ("unknownObject", object.clone()),
            Cause::Precondition { fact } => ("precondition", fact.clone()),
            Cause::Person { person } => ("isPerson", Term::Const(person.clone())),
            Cause::PlanTooDeep { step } => ("planTooDeep", step.clone()),
            Cause::SameObject { object, .. } => ("sameObject", Term::Const(object.clone())),
            Cause::Unfinished => return Term::constant("unfinished"),
        };
        Term::compound(name, vec![arg])
    }

    /// A forbidden action or state: the reading is impermissible.
    pub fn is_norm_violation(&self) -> bool {
        matches!(
            self.cause,
            Cause::ForbiddenAction { .. } | Cause::ForbiddenState { .. } | Cause::ForbiddenPurpose { .. }
        )
    }

    /// A soft norm met: it ranks the reading and never makes it impermissible or infeasible.
    pub fn is_soft(&self) -> bool {
        matches!(self.cause, Cause::Soft { .. })
    }

    /// The force of a soft reason, if it is one.
    pub fn force(&self) -> Option<Force> {
        match &self.cause {
            Cause::Soft { kind, .. } => Some(kind.force()),
            _ => None,
        }
    }

    /// The norm's own reason behind a forbidden purpose (what the purpose would be forbidden
    /// as), or the reason itself.
    pub fn behind_purpose(&self) -> std::borrow::Cow<'_, Reason> {
        match &self.cause {
            Cause::ForbiddenPurpose { cause, .. } => std::borrow::Cow::Owned(Reason {
                cause: (**cause).clone(),
                ..self.clone()
            }),
            _ => std::borrow::Cow::Borrowed(self),
        }
    }

    /// What this reason adds to the norm score: a preferred norm's severity, minus a
    /// discouraged norm's; 0 for every other reason.
    pub fn norm_score(&self) -> i32 {
        let severity = i32::from(self.severity.unwrap_or(0));
        match self.force() {
            Some(Force::Preferred) => severity,
            Some(Force::Discouraged) => -severity,
            _ => 0,
        }
    }
}

/// What simulating one reading found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Outcome {
    /// Every reason, in DIARC's check order, each once.
    pub reasons: Vec<Reason>,
    /// The primitive steps executed, in order.
    pub plan: Vec<Term>,
}

impl Outcome {
    /// Adds `reason` unless it is there already; a soft norm counts once per reading, at the
    /// first step or state that met it.
    pub(crate) fn push(&mut self, reason: Reason) {
        let seen = if reason.is_soft() {
            (self.reasons.iter()).any(|r| r.is_soft() && r.norm_id == reason.norm_id)
        } else {
            self.reasons.contains(&reason)
        };
        if !seen {
            self.reasons.push(reason);
        }
    }

    /// The simulation was cut short by the deadline: the reading is infeasible, and the answer
    /// must say a limit was hit.
    pub fn unfinished(&self) -> bool {
        self.reasons.iter().any(|r| r.cause == Cause::Unfinished)
    }

    /// No forbidden action or state (soft norms never make a reading impermissible).
    pub fn permissible(&self) -> bool {
        !self.reasons.iter().any(Reason::is_norm_violation)
    }

    /// No reason that is not a norm's (soft norms never make a reading infeasible).
    pub fn feasible(&self) -> bool {
        self.reasons.iter().all(|r| r.is_norm_violation() || r.is_soft())
    }

    /// The first reason that is not a soft norm's: what a refusal or an explanation speaks.
    pub fn first_hard(&self) -> Option<&Reason> {
        self.reasons.iter().find(|r| !r.is_soft())
    }

    /// Preferred norms met minus discouraged norms broken, each by its severity, each norm
    /// once: soft reasons are kept once per norm.
    pub fn norm_score(&self) -> i32 {
        self.reasons.iter().map(Reason::norm_score).sum()
    }

    /// The discouraged norms this reading breaks.
    pub fn discouraged(&self) -> impl Iterator<Item = &Reason> {
        self.reasons.iter().filter(|r| r.force() == Some(Force::Discouraged))
    }
}
