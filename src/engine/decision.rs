//! What a decision is: the readings simulated, the plan of what to say, and the answer.
//!
//! Owns: the types Algorithm 1 (`clarify`) produces and the words (`speech`) render, so that
//! neither has to import the other for them. Must not: decide or word anything itself.

use rayon::prelude::*;

use super::input::Spelled;
use super::simulate::Outcome;
use super::term::Term;

/// How the robot phrases its answer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Style {
    /// The paper's exact words (the default).
    #[default]
    Diarc,
    /// Fluent English; refusals are gentler for mild norms and firmer for grave ones.
    Natural,
}

impl Spelled for Style {
    const ALL: &'static [Style] = &[Style::Diarc, Style::Natural];

    fn as_str(self) -> &'static str {
        match self {
            Style::Diarc => "diarc",
            Style::Natural => "natural",
        }
    }
}

/// What to say, by reading index into the interpretations (in the contract's order).
#[derive(Clone, Debug, PartialEq)]
pub enum Plan {
    Comply(usize),
    Refuse(usize),
    /// Ask which of `offered` is meant; `more` when other readings exist that are not named.
    Ask {
        offered: Vec<usize>,
        more: bool,
    },
    /// Too many readings to name: ask which thing each ambiguous reference means ("notebook").
    AskWhich {
        nouns: Vec<String>,
    },
    Assume {
        chosen: usize,
        others: Vec<usize>,
    },
    Confirm {
        chosen: usize,
        others: Vec<usize>,
    },
    Explain(Vec<usize>),
    /// References that match nothing, in words ("the spoon").
    Unresolved(Vec<Unfound>),
    /// The human took back what was asked ("never mind"): nothing is done.
    Cancelled,
    /// Words that are not a directive, and those that could not be placed.
    NotUnderstood {
        why: Unclear,
        words: String,
    },
}

/// A reference that matches nothing: what the human said ("the spoon"), and the words of it
/// that could not be placed at all ("pls" in "the mug pls"), if any.
#[derive(Clone, Debug, PartialEq)]
pub struct Unfound {
    pub words: String,
    pub unplaced: Option<String>,
    /// What the scene could not tell, said whole ("I cannot tell which box is the biggest: I
    /// do not know how big every box is."), when that is why nothing matched.
    pub untold: Option<String>,
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
    NotUnderstood,
    Cancelled,
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
            DecisionKind::NotUnderstood => "not_understood",
            DecisionKind::Cancelled => "cancelled",
        }
    }
}

/// One reading of the directive, simulated.
#[derive(Clone, Debug, PartialEq)]
pub struct Interpretation {
    /// `did(self,action)`, ground.
    pub action: Term,
    /// The arguments in words: "the plastic vase"; the reading in words ("get the plastic
    /// vase") is made from them only for the readings an answer speaks (`speech::reading`).
    pub description: String,
    pub score: f64,
    pub outcome: Outcome,
    /// Each reason of `outcome` in words, in the request's style.
    pub reason_words: Vec<String>,
    /// The value chosen for each slot (argument or variable), in slot order.
    pub values: Vec<Term>,
}

impl Interpretation {
    pub fn permissible(&self) -> bool {
        self.outcome.permissible()
    }

    pub fn feasible(&self) -> bool {
        self.outcome.feasible()
    }

    pub fn acceptable(&self) -> bool {
        self.permissible() && self.feasible()
    }

    /// Preferred norms met minus discouraged norms broken, by severity (0 with none in force).
    pub fn norm_score(&self) -> i32 {
        self.outcome.norm_score()
    }
}

/// Why not every reading was simulated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LimitKind {
    /// More readings than `max_readings`: none was simulated.
    TooManyReadings,
    /// The request's deadline passed before every reading was simulated.
    Deadline,
}

impl LimitKind {
    pub fn as_str(self) -> &'static str {
        match self {
            LimitKind::TooManyReadings => "too_many_readings",
            LimitKind::Deadline => "deadline",
        }
    }
}

/// A limit that was hit: the answer says so rather than truncating silently.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    pub kind: LimitKind,
    /// How many readings the directive has.
    pub readings: u128,
    /// How many were simulated.
    pub simulated: usize,
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
    /// The readings the utterance proposes, in order: those a question names (a follow-up's
    /// `choice` counts from 0 among them), or the one assumed, confirmed or obeyed.
    pub offered: Vec<Term>,
    /// Set when a cap or the deadline kept readings from being simulated.
    pub limits: Option<Limits>,
    /// The version of the norm set the decision was made under.
    pub norm_version: i64,
    /// The version of the action library it was simulated with.
    pub library_version: i64,
    /// What the human's words were understood as, when the directive came in words.
    pub parse: Option<Understood>,
    /// After a refusal or an explanation, the nearest acceptable reading offered instead.
    pub alternative: Option<Term>,
}

impl Drop for Decision {
    /// A decision of many readings is freed on rayon's pool, in parallel: its readings were
    /// made there, and freeing them one by one on the caller's thread took an eighth of the
    /// time a 10,000-reading decision took to make.
    fn drop(&mut self) {
        if self.interpretations.len() >= FREE_APART_FROM {
            std::mem::take(&mut self.interpretations)
                .into_par_iter()
                .with_min_len(FREE_APART_FROM / 4)
                .for_each(drop);
        }
    }
}

/// From this many readings on, a decision is freed on rayon's pool.
const FREE_APART_FROM: usize = 2048;

/// How words were read: the act they perform, after the pragmatic rules.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Act {
    /// An imperative: "Get the vase."
    Command,
    /// A question that conveys a request: "Can you get the vase?", "Would you mind getting it?"
    IndirectRequest,
    /// A statement of the speaker's wish: "I want you to get the vase."
    Want,
}

impl Act {
    pub fn as_str(self) -> &'static str {
        match self {
            Act::Command => "command",
            Act::IndirectRequest => "indirect_request",
            Act::Want => "want_statement",
        }
    }
}

/// Why words are not a directive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unclear {
    /// Nothing but punctuation, politeness or a name.
    Empty,
    /// A question that asks for information, not an action: "What colour is the mug?"
    Question,
    /// What not to do: "Don't destroy the plate."
    Negated,
    /// More steps at once than a directive may hold (`task::MAX_STEPS`).
    Several,
    /// No verb, or words that are not a directive's shape.
    Unplaced,
    /// "yes", "no" or "never mind" when nothing was asked that it answers.
    Unasked,
    /// The deadline passed (or the client left) before the words were read.
    Deadline,
    /// The words part into a verb's arguments in more than one way that names objects here:
    /// "Put the cup on the table in the box." with a cup on a table and a table in a box.
    Ambiguous,
}

impl Unclear {
    pub fn as_str(self) -> &'static str {
        match self {
            Unclear::Empty => "empty",
            Unclear::Question => "question",
            Unclear::Negated => "negated",
            Unclear::Several => "several",
            Unclear::Unplaced => "unplaced",
            Unclear::Unasked => "unasked",
            Unclear::Deadline => "deadline",
            Unclear::Ambiguous => "ambiguous",
        }
    }
}

/// One reference as the human said it, and the objects it matches.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceParse {
    pub words: String,
    pub candidates: Vec<String>,
}

/// What the words were understood as, for the answer to show.
#[derive(Clone, Debug, PartialEq)]
pub struct Understood {
    pub act: Act,
    /// Who was addressed, if a vocative named someone ("pepper").
    pub addressee: Option<String>,
    /// The logical form after pragmatics, in DIARC's syntax: `want(human,did(self,steal(X)))`,
    /// one variable per reference, in order; absent when the words are not a directive.
    pub form: Option<Term>,
    pub references: Vec<ReferenceParse>,
    /// Trailing words that select no object and were left out ("for reheating").
    pub ignored: Vec<String>,
    /// Why the words are not a directive, when they are not.
    pub unclear: Option<Unclear>,
    /// Each step of a task of several steps (or of one with a purpose), in order; empty for a
    /// directive of one step.
    pub steps: Vec<StepUnderstood>,
    /// What the human said the task is for ("to smash the vase").
    pub purposes: Vec<PurposeUnderstood>,
}

/// One step of a task as the words were read.
#[derive(Clone, Debug, PartialEq)]
pub struct StepUnderstood {
    pub act: Act,
    /// The step's action, one variable per object as in the whole form: `put(X,Y)`.
    pub form: Term,
    /// Each argument's words and the objects it may be.
    pub references: Vec<ReferenceParse>,
    /// How each pronoun of the step was bound.
    pub pronouns: Vec<PronounBound>,
}

/// A pronoun ("it") and what it was taken to mean.
#[derive(Clone, Debug, PartialEq)]
pub struct PronounBound {
    pub words: String,
    /// The argument of its step it stands in (from 0).
    pub argument: usize,
    pub to: BoundTo,
}

#[derive(Clone, Debug, PartialEq)]
pub enum BoundTo {
    /// The object of argument `argument` of the earlier step `step`.
    Step { step: usize, argument: usize },
    /// The first object of the request's `focus` (none in the words came before it).
    Focus(String),
    /// Nothing: no antecedent in the words and no focus.
    Nothing,
}

/// A purpose as the words were read: checked against the forbidden norms when its verb is
/// known and it names an object (`form`), else only shown.
#[derive(Clone, Debug, PartialEq)]
pub struct PurposeUnderstood {
    pub words: String,
    /// The act it names, `destroy(Z)`, with the whole form's variables; `None` when its verb
    /// is unknown or it names no object.
    pub form: Option<Term>,
    /// The step it is said with (from 0).
    pub after: usize,
}

impl Understood {
    /// What the answer shows when the words, or the answer to a question, are not a directive.
    pub fn not_a_directive(why: Unclear) -> Understood {
        Understood {
            act: Act::Command,
            addressee: None,
            form: None,
            references: Vec::new(),
            ignored: Vec::new(),
            unclear: Some(why),
            steps: Vec::new(),
            purposes: Vec::new(),
        }
    }
}
