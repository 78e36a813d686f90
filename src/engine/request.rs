//! What a request asks: the directive, the options, a follow-up answer, and who speaks in which
//! context; and the constructor that builds all of it, with its scene, from what a client sent.
//!
//! Owns: the request's types and their checks (every fault named by its field, as the request's
//! JSON names it). Must not: resolve, simulate or decide; a `Request` that exists is valid
//! against the scene it was built with.

use std::collections::BTreeMap;
use std::time::Duration;

use super::action::verb_name;
use super::input::{Invalid, RequestLimits, constant, pointer_segment};
use super::norms::{context_name, validate_roles};
use super::resolve::{Candidate, Reference, ReferenceInput};
use super::scene::{DEFAULT_SPEAKER, Scene, SceneInput};
use super::task::{Argument, MAX_STEPS, Step, Task};
use super::term::{Sym, Term};

mod options;
pub use options::{
    Alternatives, DEFAULT_MAX_READINGS, DEFAULT_MAX_SPOKEN, MOST_READINGS, Options, OptionsInput, SinglePermissible,
    SoftNorms, Strategy,
};

#[derive(Clone, Debug, PartialEq)]
pub enum Directive {
    /// A verb and one reference per argument; readings are every combination of candidates.
    /// `joiner`: the word said between two arguments ("in"), when not the verb's own ("on"):
    /// it is spoken, and a joiner naming another relation makes that relation the verb's effect.
    Action {
        verb: String,
        arguments: Vec<Reference>,
        joiner: Option<String>,
    },
    /// An action with variables, already unwrapped from `want(S,did(self,...))` by the caller
    /// (`get(X)`), and each variable's candidates, in the order the variables first appear.
    Form {
        action: Term,
        bindings: Vec<(Sym, Vec<Candidate>)>,
    },
    /// The human's words, to be read against the scene and the verbs (`words`) before anything
    /// is resolved; then decided as the directive they are read as.
    Words { text: String },
    /// Several steps ("Get the mug and put it in the sink."), or one with a purpose: each
    /// reading binds every reference once and is simulated as one plan.
    Task(Task),
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
    /// "yes": after a question to confirm, the confirmed reading, decided afresh.
    Yes,
    /// "no": after a question to confirm, nothing is done.
    No,
    /// `{"choice": "alternative"}`: the alternative a refusal offered, decided afresh.
    Alternative,
    /// "never mind", "none of them" (the words): after any question, nothing is done.
    Cancel(String),
    /// A whole new directive in words ("Get the vase."): decided afresh, as if said first.
    Directive(String),
    /// The answer in words, read when it is decided (against the scene and the verbs in force)
    /// into one of the others.
    Words(String),
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
    /// Objects in the focus of attention from earlier turns, most salient first: what "it"
    /// and "that one" refer to in words.
    pub focus: Vec<String>,
}

/// A candidate from an upstream resolver, before it is checked: an id, or an id with a score.
#[derive(Clone, Debug)]
pub enum BindingInput {
    Id(String),
    Scored { id: String, score: f64 },
}

/// A directive as a request gives it, before it is checked: `action` with `arguments`, or
/// `form` with `bindings`.
#[derive(Clone, Debug, Default)]
pub struct DirectiveInput {
    pub action: Option<String>,
    pub arguments: Option<Vec<ReferenceInput>>,
    pub form: Option<String>,
    pub bindings: Option<BTreeMap<String, Vec<BindingInput>>>,
    /// The human's words: read as the directive when neither `action` nor `form` is given,
    /// else only echoed.
    pub text: Option<String>,
    /// With `action`: the word said between its two arguments, when not the verb's own.
    pub joiner: Option<String>,
    /// Several steps, in order, instead of `action` or `form`.
    pub steps: Option<Vec<StepInput>>,
}

/// One step of a structured task, before it is checked.
#[derive(Clone, Debug, Default)]
pub struct StepInput {
    pub action: Option<String>,
    pub arguments: Option<Vec<StepArgumentInput>>,
    pub joiner: Option<String>,
}

/// One argument of a step: a reference, or `step` and `argument` naming an earlier step's
/// argument (its object), with no reference member beside them.
#[derive(Clone, Debug, Default)]
pub struct StepArgumentInput {
    pub reference: ReferenceInput,
    pub step: Option<u64>,
    pub argument: Option<u64>,
}

/// A follow-up answer as a request gives it: exactly one of the three.
#[derive(Clone, Debug, Default)]
pub struct AnswerInput {
    pub choice: Option<Choice>,
    pub id: Option<String>,
    pub reference: Option<ReferenceInput>,
    /// The answer in the human's words: "the red one", "the second one", "yes".
    pub text: Option<String>,
}

/// A whole clarify request as a client sent it, before anything is checked.
#[derive(Clone, Debug)]
pub struct RequestInput {
    pub speaker: Option<String>,
    pub directive: DirectiveInput,
    pub scene: SceneInput,
    pub context: Option<String>,
    pub options: Option<OptionsInput>,
    pub speaker_roles: Option<Vec<String>>,
    pub answer: Option<AnswerInput>,
    pub focus: Option<Vec<String>>,
}

/// A request checked: what the engine decides on, and how long the decision may take.
#[derive(Debug)]
pub struct Checked {
    pub request: Request,
    pub scene: Scene,
    pub deadline: Duration,
}

/// The context norms are selected by: normalised as a norm's context is, so that the two meet;
/// absent, `default`.
pub fn context_of(context: Option<String>) -> Result<String, Invalid> {
    context.map_or_else(|| Ok("default".to_owned()), |c| context_name(&c))
}

/// The speaker's roles, as a norm's are checked.
pub fn speaker_roles_of(roles: Option<Vec<String>>) -> Result<Vec<String>, Invalid> {
    validate_roles("/speaker_roles", roles)
}

impl Request {
    /// Checks a whole request within the operator's limits, in the order of its members; the
    /// first fault is reported with its field, and nothing reaches a simulation.
    pub fn from_input(input: RequestInput, limits: &RequestLimits) -> Result<Checked, Invalid> {
        let speaker = input.speaker.unwrap_or_else(|| DEFAULT_SPEAKER.to_owned());
        constant("/speaker", &speaker, "the speaker")?;
        let context = context_of(input.context)?;
        let scene = Scene::from_input(input.scene, limits).map_err(|e| e.within("/scene"))?;
        let (directive, form_speaker) =
            Directive::from_input(input.directive, &scene, limits).map_err(|e| e.within("/directive"))?;
        let speaker_roles = speaker_roles_of(input.speaker_roles)?;
        let answer = (input.answer)
            .map(|a| Answer::from_input(a, &scene, limits).map_err(|e| e.within("/answer")))
            .transpose()?;
        let (options, deadline) = Options::from_input(input.options.unwrap_or_default(), limits)?;
        let focus = focus_of(input.focus.unwrap_or_default(), &scene)?;
        Ok(Checked {
            request: Request {
                speaker: form_speaker.unwrap_or_else(|| Sym::from(speaker)),
                speaker_roles,
                directive,
                context,
                options,
                answer,
                focus,
            },
            scene,
            deadline,
        })
    }
}

/// Most objects in focus.
pub const MAX_FOCUS: usize = 16;

/// The focus: objects of the scene, each once.
fn focus_of(focus: Vec<String>, scene: &Scene) -> Result<Vec<String>, Invalid> {
    if focus.len() > MAX_FOCUS {
        return Err(Invalid::new("/focus", format!("at most {MAX_FOCUS} objects")));
    }
    for (i, id) in focus.iter().enumerate() {
        if scene.object(id).is_none() {
            return Err(Invalid::new(
                format!("/focus/{i}"),
                format!("no object `{id}` in the scene"),
            ));
        }
        if focus[..i].contains(id) {
            return Err(Invalid::new(format!("/focus/{i}"), format!("`{id}` is listed twice")));
        }
    }
    Ok(focus)
}

/// A follow-up's `choice`: a position among the readings a question named, or the alternative
/// a refusal offered.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Choice {
    At(u64),
    Alternative,
}

impl Answer {
    /// Fields named relative to the answer.
    fn from_input(input: AnswerInput, scene: &Scene, limits: &RequestLimits) -> Result<Answer, Invalid> {
        let one = || Invalid::new("", "give exactly one of `choice`, `id`, `reference`, `text`");
        if let Some(text) = input.text {
            if input.choice.is_some() || input.id.is_some() || input.reference.is_some() {
                return Err(one());
            }
            limits.text(&text)?;
            return Ok(Answer::Words(text));
        }
        match (input.choice, input.id, input.reference) {
            (Some(Choice::At(at)), None, None) => Ok(Answer::Choice(usize::try_from(at).unwrap_or(usize::MAX))),
            (Some(Choice::Alternative), None, None) => Ok(Answer::Alternative),
            (None, Some(id), None) => {
                if scene.object(&id).is_none() {
                    return Err(Invalid::new("/id", format!("no object `{id}` in the scene")));
                }
                Ok(Answer::Id(id))
            }
            (None, None, Some(reference)) => {
                // An answer names which objects are meant, not how many.
                for (field, given) in [("count", reference.count.is_some()), ("all", reference.all.is_some())] {
                    if given {
                        return Err(Invalid::new(
                            format!("/reference/{field}"),
                            "an answer's reference names which objects are meant; `count` and `all` go with the directive",
                        ));
                    }
                }
                match Reference::from_input(reference, scene).map_err(|e| e.within("/reference"))? {
                    Reference::Id(id) => Ok(Answer::Id(id)),
                    described => Ok(Answer::Reference(described)),
                }
            }
            _ => Err(one()),
        }
    }
}

/// Splits a logical form into its speaker (when wrapped as `want(S,...)`) and the action of
/// `did(self,ACTION)`; a bare action is taken as the action itself.
fn unwrap_form(form: &Term, agent: &str) -> Result<(Option<Sym>, Term), String> {
    let (speaker, inner) = match (form.name().map(|n| &**n), form.args()) {
        (Some("want"), [speaker, inner]) => match speaker {
            Term::Const(s) => (Some(s.clone()), inner.clone()),
            _ => return Err("the speaker in want(S,...) must be a constant".to_owned()),
        },
        _ => (None, form.clone()),
    };
    let action = match (inner.name().map(|n| &**n), inner.args()) {
        (Some("did"), [actor, action]) => {
            match actor {
                Term::Const(a) if &**a == "self" || &**a == agent => {}
                _ => {
                    let names = if agent == "self" {
                        "`self`".to_owned()
                    } else {
                        format!("`self` or `{agent}`")
                    };
                    return Err(format!("did(A,...) must name the agent: {names}"));
                }
            }
            action.clone()
        }
        _ => inner,
    };
    if action.is_var() {
        return Err("the action must name a verb, not be a variable".to_owned());
    }
    Ok((speaker, action))
}

impl Directive {
    /// The first argument (step, argument) that is a second plural in its step
    /// ([`Task::second_plural`]); an action is step 0.
    pub fn second_plural(&self) -> Option<(usize, usize)> {
        match self {
            Directive::Task(task) => task.second_plural(),
            one => one.plural_action()?.second_plural(),
        }
    }

    /// An action with a plural argument, as the task of one step it is: the step makes an act
    /// per object ([`Task`]); `None` for any other directive.
    pub fn plural_action(&self) -> Option<Task> {
        let Directive::Action {
            verb,
            arguments,
            joiner,
        } = self
        else {
            return None;
        };
        arguments.iter().any(|a| a.number().is_some()).then(|| Task {
            steps: vec![Step {
                verb: verb.clone(),
                arguments: arguments.iter().cloned().map(Argument::Reference).collect(),
                joiner: joiner.clone(),
            }],
            purposes: Vec::new(),
        })
    }

    /// The directive and, for a form `want(S,...)`, its speaker; fields named relative to the
    /// directive. Every reference and binding must name objects of `scene`.
    fn from_input(
        input: DirectiveInput,
        scene: &Scene,
        limits: &RequestLimits,
    ) -> Result<(Directive, Option<Sym>), Invalid> {
        if let Some(text) = &input.text {
            limits.text(text)?;
        }
        if let Some(steps) = input.steps {
            if input.action.is_some() || input.form.is_some() {
                return Err(Invalid::new("", "give one of `steps`, `action` or `form`"));
            }
            for (member, given) in [
                ("arguments", input.arguments.is_some()),
                ("bindings", input.bindings.is_some()),
                ("joiner", input.joiner.is_some()),
            ] {
                if given {
                    return Err(Invalid::new(
                        format!("/{member}"),
                        format!("`{member}` go in each step, not beside `steps`"),
                    ));
                }
            }
            return Ok((Directive::Task(task_of(steps, scene)?), None));
        }
        match (input.action, input.form) {
            (Some(_), Some(_)) => Err(Invalid::new("", "give either `action` or `form`, not both")),
            (None, None) => match input.text {
                Some(text) if input.arguments.is_none() && input.bindings.is_none() && input.joiner.is_none() => {
                    Ok((Directive::Words { text }, None))
                }
                _ => Err(Invalid::new(
                    "",
                    "needs `action` (with `arguments`), `form` (with `bindings`), or `text` alone",
                )),
            },
            (Some(verb), None) => {
                verb_name(&verb).map_err(|m| Invalid::new("/action", m))?;
                if input.bindings.is_some() {
                    return Err(Invalid::new(
                        "/bindings",
                        "`bindings` go with `form`, not with `action`",
                    ));
                }
                let arguments: Vec<Reference> = (input.arguments.unwrap_or_default().into_iter().enumerate())
                    .map(|(i, r)| Reference::from_input(r, scene).map_err(|e| e.within(&format!("/arguments/{i}"))))
                    .collect::<Result<_, _>>()?;
                let joiner = input.joiner.map(joiner_word).transpose()?;
                let directive = Directive::Action {
                    verb,
                    arguments,
                    joiner,
                };
                if let Some((_, j)) = directive.second_plural() {
                    return Err(Invalid::new(format!("/arguments/{j}"), ONE_PLURAL));
                }
                Ok((directive, None))
            }
            (None, Some(text)) => {
                if input.arguments.is_some() {
                    return Err(Invalid::new(
                        "/arguments",
                        "`arguments` go with `action`, not with `form`",
                    ));
                }
                if input.joiner.is_some() {
                    return Err(Invalid::new("/joiner", "`joiner` goes with `action`, not with `form`"));
                }
                let form = Term::parse_within(&text, limits.terms)
                    .map_err(|e| Invalid::new("/form", format!("not a term: {e}")))?;
                let (speaker, action) = unwrap_form(&form, &scene.agent.id).map_err(|m| Invalid::new("/form", m))?;
                if let Some(name) = action.name() {
                    verb_name(name).map_err(|m| Invalid::new("/form", m))?;
                }
                let bindings = bindings_of(&action, input.bindings.unwrap_or_default(), scene)?;
                Ok((Directive::Form { action, bindings }, speaker))
            }
        }
    }
}

/// Why a step may not have two plural arguments.
const ONE_PLURAL: &str = "a step names at most one plural argument (`count` or `all`): \
    which object goes with which is not guessed";

/// A joiner as a client gives it: one lower-case word.
fn joiner_word(joiner: String) -> Result<String, Invalid> {
    let word = joiner.trim().to_lowercase();
    let is_word = !word.is_empty() && word.len() <= 32 && word.chars().all(|c| c.is_ascii_lowercase());
    is_word
        .then_some(word)
        .ok_or_else(|| Invalid::new("/joiner", "a joiner is one lower-case word, like `in`"))
}

/// A structured task: 1 to [`MAX_STEPS`] steps, each a verb and its arguments, an argument
/// either a reference or `{"step": i, "argument": j}`, the object of argument j of an earlier
/// step i. Fields named relative to the directive.
fn task_of(steps: Vec<StepInput>, scene: &Scene) -> Result<Task, Invalid> {
    if steps.is_empty() || steps.len() > MAX_STEPS {
        return Err(Invalid::new("/steps", format!("give 1 to {MAX_STEPS} steps")));
    }
    let mut out: Vec<Step> = Vec::with_capacity(steps.len());
    for (i, step) in steps.into_iter().enumerate() {
        let at = format!("/steps/{i}");
        let Some(verb) = step.action else {
            return Err(Invalid::new(format!("{at}/action"), "each step needs `action`"));
        };
        verb_name(&verb).map_err(|m| Invalid::new(format!("{at}/action"), m))?;
        let mut arguments = Vec::new();
        for (j, argument) in step.arguments.unwrap_or_default().into_iter().enumerate() {
            let field = format!("{at}/arguments/{j}");
            arguments.push(match (argument.step, argument.argument) {
                (None, None) => {
                    Argument::Reference(Reference::from_input(argument.reference, scene).map_err(|e| e.within(&field))?)
                }
                (Some(earlier), Some(k)) => {
                    let r = &argument.reference;
                    let described = r.id.is_some() || r.kind.is_some() || r.attributes.is_some();
                    let narrowed = r.properties.is_some() || !r.relations.is_empty();
                    if described || narrowed || r.count.is_some() || r.all.is_some() {
                        return Err(Invalid::new(
                            field,
                            "an argument is either a reference or `step` with `argument`, not both",
                        ));
                    }
                    let Some(target) = usize::try_from(earlier).ok().filter(|&e| e < i) else {
                        let which = match i {
                            0 => "the first step has none before it".to_owned(),
                            1 => "must be 0, the step before".to_owned(),
                            _ => format!("must name an earlier step, 0 to {}", i - 1),
                        };
                        return Err(Invalid::new(format!("{field}/step"), which));
                    };
                    let count = out[target].arguments.len();
                    let Some(k) = usize::try_from(k).ok().filter(|&k| k < count) else {
                        return Err(Invalid::new(
                            format!("{field}/argument"),
                            format!(
                                "step {target} has {count} argument{}",
                                if count == 1 { "" } else { "s" }
                            ),
                        ));
                    };
                    Argument::Earlier {
                        step: target,
                        argument: k,
                    }
                }
                (Some(_), None) => return Err(Invalid::new(format!("{field}/argument"), "`step` needs `argument`")),
                (None, Some(_)) => return Err(Invalid::new(format!("{field}/step"), "`argument` needs `step`")),
            });
        }
        let joiner = step.joiner.map(joiner_word).transpose().map_err(|e| e.within(&at))?;
        out.push(Step {
            verb,
            arguments,
            joiner,
        });
    }
    let task = Task {
        steps: out,
        purposes: Vec::new(),
    };
    if let Some((i, j)) = task.second_plural() {
        return Err(Invalid::new(format!("/steps/{i}/arguments/{j}"), ONE_PLURAL));
    }
    Ok(task)
}

/// Each variable of `action`, in first-appearance order, with its candidates: every variable
/// must have some, each naming a distinct object of the scene, and nothing else may be bound.
fn bindings_of(
    action: &Term,
    given: BTreeMap<String, Vec<BindingInput>>,
    scene: &Scene,
) -> Result<Vec<(Sym, Vec<Candidate>)>, Invalid> {
    let variables = action.variables();
    for name in given.keys() {
        if !variables.iter().any(|v| &**v == name) {
            return Err(Invalid::new(
                format!("/bindings/{}", pointer_segment(name)),
                format!("`{name}` is not a variable of the form"),
            ));
        }
    }
    let mut bindings = Vec::with_capacity(variables.len());
    for variable in variables {
        let at = format!("/bindings/{}", pointer_segment(&variable));
        let Some(list) = given.get(&*variable) else {
            return Err(Invalid::new(
                at,
                format!("no candidates given for the variable `{variable}`"),
            ));
        };
        let mut candidates: Vec<Candidate> = Vec::with_capacity(list.len());
        for (j, binding) in list.iter().enumerate() {
            let (id, score, id_at) = match binding {
                BindingInput::Id(id) => (id, 1.0, format!("{at}/{j}")),
                BindingInput::Scored { id, score } => {
                    if !(score.is_finite() && *score >= 0.0) {
                        return Err(Invalid::new(format!("{at}/{j}/score"), "must be a finite number ≥ 0"));
                    }
                    (id, *score, format!("{at}/{j}/id"))
                }
            };
            if scene.object(id).is_none() {
                return Err(Invalid::new(id_at, format!("no object `{id}` in the scene")));
            }
            if candidates.iter().any(|c| &c.id == id) {
                return Err(Invalid::new(id_at, format!("`{id}` is listed twice")));
            }
            candidates.push(Candidate { id: id.clone(), score });
        }
        bindings.push((variable, candidates));
    }
    Ok(bindings)
}
