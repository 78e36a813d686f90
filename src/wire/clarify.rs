//! A clarify request and its decision, as JSON.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

pub use super::scene::{AgentBody, ObjectBody, PersonBody, SceneBody, ShapeBody};
pub use super::spelling::ChoiceBody;
use crate::engine::decision::{BoundTo, Decision, Interpretation, Limits, Style, Understood};
use crate::engine::request::{
    Alternatives, AnswerInput, BindingInput, DirectiveInput, OptionsInput, RequestInput, SinglePermissible, SoftNorms,
    StepArgumentInput, StepInput, Strategy,
};
use crate::engine::resolve::ReferenceInput;
use crate::engine::simulate::Reason;
use crate::engine::term::Term;

/// Unknown members are refused here and in the directive and options (a misspelt `options`
/// would silently change an experiment's condition); scenes and objects accept extra members,
/// since perception pipelines attach their own.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ClarifyBody {
    #[serde(default)]
    pub speaker: Option<String>,
    pub directive: DirectiveBody,
    pub scene: SceneBody,
    #[serde(default)]
    pub context: Option<String>,
    #[serde(default)]
    pub options: Option<OptionsBody>,
    /// The speaker's roles (`owner`): with `context`, they select the norms in force.
    #[serde(default)]
    pub speaker_roles: Option<Vec<String>>,
    /// The human's answer to the question this request's directive led to.
    #[serde(default)]
    pub answer: Option<AnswerBody>,
    /// Object ids in the focus of attention from earlier turns, most salient first: what "it"
    /// and "that one" mean in a directive in words.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub focus: Option<Vec<String>>,
}

/// A follow-up: exactly one of `choice` (the position, from 0, among the readings the question
/// named: the `offered` of the answer to the original request; or `"alternative"`, the
/// alternative a refusal offered), `id`, `reference`, or `text`.
#[derive(Clone, Debug, Default, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct AnswerBody {
    #[serde(default)]
    pub choice: Option<ChoiceBody>,
    #[serde(default)]
    pub id: Option<String>,
    #[serde(default)]
    pub reference: Option<ReferenceBody>,
    /// The answer in the human's words: "the red one", "the second one", an object's id,
    /// "yes" or "no" (to a question to confirm).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub text: Option<String>,
}

/// `action` + `arguments`, or `form` + `bindings`, or `text` alone: the human's words, read
/// against the scene and the verbs. With `action` or `form`, `text` is only echoed.
#[derive(Clone, Debug, Default, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct DirectiveBody {
    #[serde(default)]
    pub action: Option<String>,
    #[serde(default)]
    pub arguments: Option<Vec<ReferenceBody>>,
    #[serde(default)]
    pub form: Option<String>,
    #[serde(default)]
    pub bindings: Option<BTreeMap<String, Vec<BindingBody>>>,
    #[serde(default)]
    pub text: Option<String>,
    /// With `action`: the word said between its two arguments when not the verb's own ("in"
    /// for `put`, whose own is "on"). It is spoken, and a joiner naming another relation makes
    /// that relation the verb's effect (`put` by "in" makes `in(X,Y)` true).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joiner: Option<String>,
    /// Several steps, in order, instead of `action` or `form` (1 to 8): each reading binds
    /// every reference once and is simulated as one plan, the steps in order.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steps: Option<Vec<StepBody>>,
}

/// One step of a task: a verb, its arguments, and the joiner said between two of them.
#[derive(Clone, Debug, Default, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct StepBody {
    pub action: String,
    #[serde(default)]
    pub arguments: Vec<StepArgumentBody>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joiner: Option<String>,
}

/// A reference (`id`, or `type` with attributes and properties), or `step` and `argument`:
/// the object of argument `argument` of the earlier step `step` (both from 0).
#[derive(Clone, Debug, Default, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct StepArgumentBody {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub id: Option<String>,
    #[serde(rename = "type", default, skip_serializing_if = "Option::is_none")]
    pub kind: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub attributes: Option<BTreeMap<String, Scalar>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub properties: Option<Vec<String>>,
    /// Relations to other objects, as a reference's.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub relations: Vec<RelationBody>,
    /// As a reference's: that many of the matches at once (with `all`, exactly that many).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(minimum = 1, maximum = 32)]
    pub count: Option<u64>,
    /// As a reference's: every match, one act each.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub all: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step: Option<u64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub argument: Option<u64>,
}

#[derive(Clone, Debug, Default, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ReferenceBody {
    #[serde(default)]
    pub id: Option<String>,
    #[serde(rename = "type", default)]
    pub kind: Option<String>,
    #[serde(default)]
    pub attributes: Option<BTreeMap<String, Scalar>>,
    #[serde(default)]
    pub properties: Option<Vec<String>>,
    /// Relations the object must stand in: `[{"relation": "on", "to": {"type": "table"}}]`
    /// is "the … on the table". Nested through `to`; at most 8 in all.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub relations: Vec<RelationBody>,
    /// That many of the matching objects at once, any of them ("two cups": each choice is a
    /// reading), one step each; with `all`, exactly that many must match ("both cups"). 1 to
    /// 32. Not on a landmark or with `id`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(minimum = 1, maximum = 32)]
    pub count: Option<u64>,
    /// Every matching object, one step each ("the cups"). Not on a landmark or with `id`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub all: Option<bool>,
}

/// A relation to a landmark: `on`, `in`, `under`, `near`, `left_of`, `right_of`, `behind`,
/// `in_front_of` (stated in `scene.facts` or decided by the objects' boxes), or `from` (on
/// or in).
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct RelationBody {
    pub relation: String,
    /// The landmark, a reference of its own.
    #[schema(no_recursion)]
    pub to: Box<ReferenceBody>,
}

/// A candidate from an upstream resolver: an object id, or an id with a score.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(untagged, expecting = "an object id, or {\"id\": ID, \"score\": NUMBER}")]
pub enum BindingBody {
    Id(String),
    Scored { id: String, score: f64 },
}

/// An attribute value: a string, or a number or boolean taken as its JSON text.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(untagged, expecting = "a string, number or boolean")]
pub enum Scalar {
    Text(String),
    Number(f64),
    Bool(bool),
}

impl Scalar {
    /// The value as the engine compares it: a number or boolean as its JSON text.
    fn text(self) -> String {
        match self {
            Scalar::Text(s) => s,
            Scalar::Number(n) => n.to_string(),
            Scalar::Bool(b) => b.to_string(),
        }
    }
}

#[derive(Clone, Debug, Default, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct OptionsBody {
    #[serde(default)]
    pub strategy: Option<Strategy>,
    #[serde(default)]
    pub single_permissible: Option<SinglePermissible>,
    /// `diarc` (default, the paper's words) or `natural`.
    #[serde(default)]
    pub style: Option<Style>,
    /// Most readings a question names (2..=50, default 5).
    #[serde(default)]
    #[schema(minimum = 2, maximum = 50)]
    pub max_spoken: Option<u64>,
    /// Most readings simulated (1..=100000, default 10000).
    #[serde(default)]
    #[schema(minimum = 1, maximum = 100000)]
    pub max_readings: Option<u64>,
    /// Milliseconds the decision may take (1..=60000, default 2000); past it, what is not yet
    /// simulated is not offered and the answer says the deadline was hit.
    #[serde(default)]
    #[schema(minimum = 1, maximum = 60000)]
    pub deadline_ms: Option<u64>,
    /// Confirm instead of assuming when the share of unacceptable readings is above this
    /// (0 ≤ ratio < 1). Absent: Algorithm 1's assumption.
    #[serde(default)]
    #[schema(minimum = 0, exclusive_maximum = 1)]
    pub confirm_above_ratio: Option<f64>,
    /// `rank` (default: among the acceptable readings only those with the highest norm score
    /// are kept) or `ignore` (soft norms are not checked: a control condition).
    #[serde(default)]
    pub soft_norms: Option<SoftNorms>,
    /// `offer` (after a refusal or an explanation, the nearest acceptable reading is offered:
    /// `alternative`, and a question ending the utterance) or `off`. Default: `offer` in the
    /// natural style, `off` in the diarc style (the paper's words stay exact). Never under
    /// the reflexive strategy.
    #[serde(default)]
    pub alternatives: Option<Alternatives>,
}

// ---------------------------------------------------------------------------------------------
// Into the engine's inputs: member for member; the engine's constructors check them.

impl From<ClarifyBody> for RequestInput {
    fn from(body: ClarifyBody) -> Self {
        RequestInput {
            speaker: body.speaker,
            directive: body.directive.into(),
            scene: body.scene.into(),
            context: body.context,
            options: body.options.map(Into::into),
            speaker_roles: body.speaker_roles,
            answer: body.answer.map(|a| AnswerInput {
                choice: a.choice.map(Into::into),
                id: a.id,
                reference: a.reference.map(Into::into),
                text: a.text,
            }),
            focus: body.focus,
        }
    }
}

impl From<DirectiveBody> for DirectiveInput {
    fn from(d: DirectiveBody) -> Self {
        let bindings = d.bindings.map(|all| {
            (all.into_iter())
                .map(|(variable, list)| {
                    let list = (list.into_iter())
                        .map(|b| match b {
                            BindingBody::Id(id) => BindingInput::Id(id),
                            BindingBody::Scored { id, score } => BindingInput::Scored { id, score },
                        })
                        .collect();
                    (variable, list)
                })
                .collect()
        });
        DirectiveInput {
            action: d.action,
            arguments: d.arguments.map(|a| a.into_iter().map(Into::into).collect()),
            form: d.form,
            bindings,
            text: d.text,
            joiner: d.joiner,
            steps: d.steps.map(|steps| steps.into_iter().map(Into::into).collect()),
        }
    }
}

impl From<StepBody> for StepInput {
    fn from(s: StepBody) -> Self {
        StepInput {
            action: Some(s.action),
            arguments: Some(s.arguments.into_iter().map(Into::into).collect()),
            joiner: s.joiner,
        }
    }
}

impl From<StepArgumentBody> for StepArgumentInput {
    fn from(a: StepArgumentBody) -> Self {
        StepArgumentInput {
            reference: ReferenceInput {
                id: a.id,
                kind: a.kind,
                attributes: a.attributes.map(texts),
                properties: a.properties,
                relations: relations(a.relations),
                count: a.count,
                all: a.all,
            },
            step: a.step,
            argument: a.argument,
        }
    }
}

impl From<ReferenceBody> for ReferenceInput {
    fn from(r: ReferenceBody) -> Self {
        ReferenceInput {
            id: r.id,
            kind: r.kind,
            attributes: r.attributes.map(texts),
            properties: r.properties,
            relations: relations(r.relations),
            count: r.count,
            all: r.all,
        }
    }
}

fn relations(relations: Vec<RelationBody>) -> Vec<(String, ReferenceInput)> {
    (relations.into_iter())
        .map(|r| (r.relation, ReferenceInput::from(*r.to)))
        .collect()
}

pub(super) fn texts(attributes: BTreeMap<String, Scalar>) -> BTreeMap<String, String> {
    attributes.into_iter().map(|(k, v)| (k, v.text())).collect()
}

impl From<OptionsBody> for OptionsInput {
    fn from(o: OptionsBody) -> Self {
        OptionsInput {
            strategy: o.strategy,
            single_permissible: o.single_permissible,
            style: o.style,
            max_spoken: o.max_spoken,
            max_readings: o.max_readings,
            deadline_ms: o.deadline_ms,
            confirm_above_ratio: o.confirm_above_ratio,
            soft_norms: o.soft_norms,
            alternatives: o.alternatives,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Out of the engine

#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct ReasonDto {
    /// A norm's kind (`forbidden_*`, which makes the reading impermissible; `discouraged_*`
    /// and `preferred_*`, which only rank it), or why it cannot be done (`unknown_action`,
    /// `unreachable`, `precondition`, ...).
    pub kind: String,
    /// The step or fact at fault, canonical; for a soft norm the step or state that met it.
    pub detail: String,
    /// The norm behind a norm's reason.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub norm_id: Option<i64>,
    /// The norm's severity, 1..5, for a norm's reason: for a soft norm, its strength.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub severity: Option<u8>,
    /// The reason in words, in the request's style ("it requires a forbidden state").
    pub words: String,
}

/// Reasons with their words, as both decisions and checks report them.
pub(super) fn reason_dtos(reasons: &[Reason], words: &[String]) -> Vec<ReasonDto> {
    reasons
        .iter()
        .zip(words)
        .map(|(reason, words)| ReasonDto {
            kind: reason.kind().to_owned(),
            detail: reason.detail(),
            norm_id: reason.norm_id,
            severity: reason.severity,
            words: words.clone(),
        })
        .collect()
}

#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct InterpretationDto {
    pub action: String,
    pub description: String,
    pub permissible: bool,
    pub feasible: bool,
    pub reasons: Vec<ReasonDto>,
    /// The primitive steps simulated, in order, as canonical terms.
    pub plan: Vec<String>,
    /// The resolution score (higher is likelier).
    pub score: f64,
    /// Severities of the preferred norms met minus those of the discouraged norms broken;
    /// absent when 0.
    #[serde(skip_serializing_if = "is_zero", default)]
    pub norm_score: i32,
}

fn is_zero(n: &i32) -> bool {
    *n == 0
}

impl From<&Interpretation> for InterpretationDto {
    fn from(i: &Interpretation) -> Self {
        InterpretationDto {
            action: i.action.text(),
            description: i.description.clone(),
            permissible: i.permissible(),
            feasible: i.feasible(),
            reasons: reason_dtos(&i.outcome.reasons, &i.reason_words),
            plan: i.outcome.plan.iter().map(Term::text).collect(),
            score: i.score,
            norm_score: i.norm_score(),
        }
    }
}

#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct DecisionDto {
    /// `comply`, `refuse`, `ask`, `assume`, `confirm`, `explain`, `unresolved`,
    /// `not_understood` (the words are not a directive: nothing was simulated) or `cancelled`
    /// (an answer took back the question: "no" to a question to confirm, "never mind" to any).
    pub decision: String,
    pub utterance: String,
    pub speech_act: String,
    pub goal: Option<String>,
    pub interpretations: Vec<InterpretationDto>,
    /// The readings the utterance proposes, in order: those a question names (a follow-up's
    /// `choice` counts from 0 among them), or the one assumed, confirmed or obeyed.
    pub offered: Vec<String>,
    /// Present when a cap or the deadline kept readings from being simulated.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub limits: Option<LimitsDto>,
    /// The version of the norm set this decision was made under.
    pub norm_version: i64,
    /// The version of the action library it was simulated with.
    pub library_version: i64,
    /// The human's words, as sent in `directive.text`.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub text: Option<String>,
    /// What the words were understood as: present when the directive was sent as `text` alone,
    /// or when an answer in words (`yes`, `no`) answered nothing it could.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub parse: Option<ParseDto>,
    /// After a refusal or an explanation under the moral strategy, with `alternatives` on: the
    /// nearest acceptable reading none of `interpretations` names (the same verb, one argument
    /// another object of its type), asked about at the end of the utterance; "yes" to it
    /// decides it afresh.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub alternative: Option<String>,
}

/// One reference in the human's words, and the objects it matches.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct ReferenceParseDto {
    pub words: String,
    pub candidates: Vec<String>,
}

/// What a directive in words was understood as.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct ParseDto {
    /// `command`, `indirect_request` ("Can you ...?") or `want_statement` ("I want you to ...").
    pub act: String,
    /// The name the words addressed ("pepper"), if any.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub addressee: Option<String>,
    /// The logical form after pragmatics, in DIARC's syntax: `want(human,did(self,steal(X)))`.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub form: Option<String>,
    pub references: Vec<ReferenceParseDto>,
    /// Trailing words that select no object and were left out ("for reheating").
    pub ignored: Vec<String>,
    /// Why the words are not a directive (`question`, `negated`, `several`, `unplaced`,
    /// `empty`, `unasked`: an answer to no question, `deadline`: not read in time,
    /// `ambiguous`: the words part into the verb's arguments in more than one way that names
    /// objects here), when the decision is `not_understood`.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub unclear: Option<String>,
    /// A task's steps, in order: present when the words hold several steps or a purpose.
    #[serde(skip_serializing_if = "Vec::is_empty", default)]
    pub steps: Vec<StepParseDto>,
    /// What the task is for, when the words say it with a verb the robot knows and objects
    /// ("to smash the vase"): checked against the forbidden norms.
    #[serde(skip_serializing_if = "Vec::is_empty", default)]
    pub purposes: Vec<PurposeParseDto>,
}

/// One step of a task in words.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct StepParseDto {
    /// `command`, `indirect_request` or `want_statement`.
    pub act: String,
    /// The step's action with the whole form's variables: `put(X,Y)`.
    pub form: String,
    /// Each argument's words and the objects it may be (a pronoun's are its antecedent's).
    pub references: Vec<ReferenceParseDto>,
    /// How each pronoun of the step was bound.
    #[serde(skip_serializing_if = "Vec::is_empty", default)]
    pub pronouns: Vec<PronounParseDto>,
}

/// A pronoun and what it was taken to mean: argument `argument` of the earlier step `step`,
/// the object in `focus`, or nothing (`bound_to`: `step`, `focus` or `nothing`).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct PronounParseDto {
    pub words: String,
    /// The argument of its own step it stands in, from 0.
    pub argument: u64,
    pub bound_to: String,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub step: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub step_argument: Option<u64>,
    /// The object in focus it was taken as.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub focus: Option<String>,
}

/// A purpose as the words said it ("to smash the vase"), the act it names (`destroy(Z)`), and
/// the step it was said with (from 0).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct PurposeParseDto {
    pub words: String,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub form: Option<String>,
    pub after: u64,
}

impl From<&Understood> for ParseDto {
    fn from(u: &Understood) -> Self {
        ParseDto {
            act: u.act.as_str().to_owned(),
            addressee: u.addressee.clone(),
            form: u.form.as_ref().map(Term::text),
            references: (u.references.iter())
                .map(|r| ReferenceParseDto {
                    words: r.words.clone(),
                    candidates: r.candidates.clone(),
                })
                .collect(),
            ignored: u.ignored.clone(),
            unclear: u.unclear.map(|w| w.as_str().to_owned()),
            steps: (u.steps.iter())
                .map(|s| StepParseDto {
                    act: s.act.as_str().to_owned(),
                    form: s.form.text(),
                    references: (s.references.iter())
                        .map(|r| ReferenceParseDto {
                            words: r.words.clone(),
                            candidates: r.candidates.clone(),
                        })
                        .collect(),
                    pronouns: (s.pronouns.iter())
                        .map(|p| {
                            let (bound_to, step, step_argument, focus) = match &p.to {
                                BoundTo::Step { step, argument } => {
                                    ("step", Some(*step as u64), Some(*argument as u64), None)
                                }
                                BoundTo::Focus(id) => ("focus", None, None, Some(id.clone())),
                                BoundTo::Nothing => ("nothing", None, None, None),
                            };
                            PronounParseDto {
                                words: p.words.clone(),
                                argument: p.argument as u64,
                                bound_to: bound_to.to_owned(),
                                step,
                                step_argument,
                                focus,
                            }
                        })
                        .collect(),
                })
                .collect(),
            purposes: (u.purposes.iter())
                .map(|p| PurposeParseDto {
                    words: p.words.clone(),
                    form: p.form.as_ref().map(Term::text),
                    after: p.after as u64,
                })
                .collect(),
        }
    }
}

/// Which limit was hit, and how much of the directive was simulated.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct LimitsDto {
    /// `too_many_readings` (more than `options.max_readings`: none simulated) or `deadline`.
    pub reason: String,
    /// How many readings the directive has (saturating at the largest 64-bit number).
    pub readings: u64,
    pub simulated: u64,
}

impl From<&Limits> for LimitsDto {
    fn from(l: &Limits) -> Self {
        LimitsDto {
            reason: l.kind.as_str().to_owned(),
            readings: u64::try_from(l.readings).unwrap_or(u64::MAX),
            simulated: l.simulated as u64,
        }
    }
}

impl DecisionDto {
    pub fn new(decision: &Decision, text: Option<String>) -> Self {
        DecisionDto {
            decision: decision.kind.as_str().to_owned(),
            utterance: decision.utterance.clone(),
            speech_act: decision.speech_act.text(),
            goal: decision.goal.as_ref().map(Term::text),
            interpretations: decision.interpretations.iter().map(InterpretationDto::from).collect(),
            offered: decision.offered.iter().map(Term::text).collect(),
            limits: decision.limits.as_ref().map(LimitsDto::from),
            norm_version: decision.norm_version,
            library_version: decision.library_version,
            text,
            parse: decision.parse.as_ref().map(ParseDto::from),
            alternative: decision.alternative.as_ref().map(Term::text),
        }
    }
}
