//! The human's words turned into the directive the structured API takes, as DIARC's parser and
//! pragmatic rules do: "Pepper, can you go steal the cash box for me?" is a request to steal the
//! cash box, spoken to Pepper.
//!
//! Owns: the grammar of directives (`grammar`), the words the scene and the verbs make known
//! (`lexicon`), and what was understood (`Parse`). Must not: guess. A word that would narrow a
//! reference and is not known makes that reference match nothing; what is not a directive at
//! all is said to be so (`NotUnderstood`), never read as the nearest directive.

mod answer;
mod grammar;
mod lexicon;
mod number;
mod purpose;
mod reference;
mod relations;
mod splits;
mod steps;
mod tokens;
mod vocabulary;

pub use grammar::grammar_word;
pub use lexicon::inflects;

use super::action::Library;
use super::decision::{
    Act, BoundTo, PronounBound, PurposeUnderstood, ReferenceParse, StepUnderstood, Unclear, Understood,
};
use super::request::{Answer, Directive};
use super::resolve::Reference;
use super::scene::Scene;
use super::simulate::did;
use super::task::Argument;
use super::term::{Sym, Term};

/// One reference as the human said it.
#[derive(Clone, Debug, PartialEq)]
pub struct Phrase {
    /// The words, as said ("the cash box").
    pub words: String,
    pub reference: Reference,
}

/// What the words were understood as.
#[derive(Clone, Debug, PartialEq)]
pub struct Parse {
    pub act: Act,
    /// Who was addressed, if a vocative named someone ("pepper").
    pub addressee: Option<String>,
    /// The verb the words name (or the unknown word in its place: "juggle"); a task's first.
    pub verb: String,
    /// Each reference that makes an object of its own, in order (a pronoun bound to an earlier
    /// step's argument is that argument's).
    pub references: Vec<Phrase>,
    /// Trailing words that select no object and were left out ("for reheating", "now").
    pub ignored: Vec<String>,
    /// A task's steps, in order; empty for a directive of one step and no purpose.
    pub steps: Vec<StepRead>,
    /// What the task is for, when it names an act the robot knows and objects.
    pub purposes: Vec<PurposeRead>,
}

/// One step of a task as said.
#[derive(Clone, Debug, PartialEq)]
pub struct StepRead {
    pub act: Act,
    pub verb: String,
    pub arguments: Vec<ArgumentRead>,
}

/// One argument as said, and, for a pronoun or a shared argument, the earlier step's argument
/// it is: (step, argument).
#[derive(Clone, Debug, PartialEq)]
pub struct ArgumentRead {
    pub phrase: Phrase,
    pub bound: Option<(usize, usize)>,
}

impl ArgumentRead {
    fn said(phrase: Phrase) -> ArgumentRead {
        ArgumentRead { phrase, bound: None }
    }
}

/// A purpose read: "to smash the vase", the verb it names, its arguments, and the step it was
/// said with.
#[derive(Clone, Debug, PartialEq)]
pub struct PurposeRead {
    pub words: String,
    pub verb: String,
    pub arguments: Vec<ArgumentRead>,
    pub after: usize,
}

/// The variable of the `i`th object in a parse's forms.
fn variable(i: usize) -> Term {
    const VARIABLES: [&str; 4] = ["X", "Y", "Z", "W"];
    Term::Var(match VARIABLES.get(i) {
        Some(v) => Sym::from(*v),
        None => Sym::from(format!("X{i}").as_str()),
    })
}

impl Parse {
    /// What the answer shows of a parse: the logical form after pragmatics, one variable per
    /// reference (`want(human,did(self,put(X,Y)))`; a task's `and(get(X),put(X,Y))`), each
    /// reference's candidates, and a task's steps with how each pronoun was bound.
    /// Past the deadline, a reference resolving did not finish shows no candidates.
    pub fn understood(&self, speaker: &Term, scene: &Scene, expired: &dyn Fn() -> bool) -> Understood {
        let candidates = |reference: &Reference| -> Vec<String> {
            // What resolving the directive selected, kept for the costly ones.
            (reference.select_once(scene, expired).unwrap_or_default().objects.iter())
                .map(|&i| scene.objects[i].id.to_string())
                .collect()
        };
        let references: Vec<ReferenceParse> = (self.references.iter())
            .map(|p| ReferenceParse {
                words: p.words.clone(),
                candidates: candidates(&p.reference),
            })
            .collect();
        let mut understood = Understood {
            act: self.act,
            addressee: self.addressee.clone(),
            form: None,
            references,
            ignored: self.ignored.clone(),
            unclear: None,
            steps: Vec::new(),
            purposes: Vec::new(),
        };
        if self.steps.is_empty() {
            let arguments = (0..self.references.len()).map(variable).collect();
            let action = Term::compound(&self.verb, arguments);
            understood.form = Some(Term::compound("want", vec![speaker.clone(), did(&action)]));
            return understood;
        }
        // Each argument's variable: its own, or the one of the argument it is bound to.
        let mut variables: Vec<Vec<Term>> = Vec::with_capacity(self.steps.len());
        let mut next = 0;
        let mut var_of = |a: &ArgumentRead, variables: &[Vec<Term>]| match a.bound {
            Some((s, j)) => variables[s][j].clone(),
            None => {
                next += 1;
                variable(next - 1)
            }
        };
        for step in &self.steps {
            let vars: Vec<Term> = step.arguments.iter().map(|a| var_of(a, &variables)).collect();
            variables.push(vars);
        }
        let actions: Vec<Term> = (self.steps.iter().zip(&variables))
            .map(|(s, vars)| Term::compound(&s.verb, vars.clone()))
            .collect();
        let whole = match actions.as_slice() {
            [one] => one.clone(),
            all => Term::compound("and", all.to_vec()),
        };
        understood.form = Some(Term::compound("want", vec![speaker.clone(), did(&whole)]));
        let bound_to = |a: &ArgumentRead| match (a.bound, &a.phrase.reference) {
            (Some((step, argument)), _) => BoundTo::Step { step, argument },
            (None, Reference::Id(id)) => BoundTo::Focus(id.clone()),
            (None, _) => BoundTo::Nothing,
        };
        let pronouns = |arguments: &[ArgumentRead]| -> Vec<PronounBound> {
            (arguments.iter().enumerate())
                .filter(|(_, a)| {
                    let head = a.phrase.words.split(" (").next().unwrap_or_default();
                    PRONOUN_WORDS.contains(&head)
                })
                .map(|(i, a)| PronounBound {
                    words: a.phrase.words.clone(),
                    argument: i,
                    to: bound_to(a),
                })
                .collect()
        };
        // Each argument's candidates: its own reference's, found once above (the references are
        // the unbound arguments in order), or those of the argument it is bound to.
        let mut own = understood.references.iter();
        let mut found: Vec<Vec<Vec<String>>> = Vec::with_capacity(self.steps.len());
        for step in &self.steps {
            let lists = (step.arguments.iter())
                .map(|a| match a.bound {
                    Some((s, j)) => found[s][j].clone(),
                    None => own.next().map(|r| r.candidates.clone()).unwrap_or_default(),
                })
                .collect();
            found.push(lists);
        }
        understood.steps = (self.steps.iter().zip(actions).zip(found))
            .map(|((step, form), lists)| StepUnderstood {
                act: step.act,
                form,
                references: (step.arguments.iter().zip(lists))
                    .map(|(a, candidates)| ReferenceParse {
                        words: a.phrase.words.clone(),
                        candidates,
                    })
                    .collect(),
                pronouns: pronouns(&step.arguments),
            })
            .collect();
        understood.purposes = (self.purposes.iter())
            .map(|p| {
                let vars = (p.arguments.iter())
                    .map(|a| match a.bound {
                        Some((s, j)) => variables[s][j].clone(),
                        None => {
                            next += 1;
                            variable(next - 1)
                        }
                    })
                    .collect();
                PurposeUnderstood {
                    words: p.words.clone(),
                    form: Some(Term::compound(&p.verb, vars)),
                    after: p.after,
                }
            })
            .collect();
        understood
    }
}

/// The words read as a pronoun, for the parse to say how each was bound.
const PRONOUN_WORDS: &[&str] = &["it", "them", "this", "that", "this one", "that one"];

/// The outcome of reading the words.
#[derive(Clone, Debug, PartialEq)]
pub enum Understanding {
    /// A directive, decided exactly as the same directive sent structured.
    Directive { directive: Directive, parse: Parse },
    /// Not a directive; `words` are those that could not be placed (possibly all of them).
    NotUnderstood { why: Unclear, words: String },
    /// The deadline passed (or the client left) before the words were read: nothing of them
    /// may be acted on.
    Expired,
}

/// Who spoke the words, and what they were speaking of.
#[derive(Clone, Copy, Debug)]
pub struct Heard<'a> {
    /// Object ids, most salient first: what a pronoun names.
    pub focus: &'a [String],
    /// The speaker's id: what "me" names.
    pub speaker: &'a str,
}

impl<'a> Heard<'a> {
    /// The request's speaker and focus.
    pub fn of(request: &'a crate::engine::request::Request) -> Heard<'a> {
        Heard {
            focus: &request.focus,
            speaker: &request.speaker,
        }
    }
}

/// Words heard from the default speaker, about `focus`: for tests and tools.
pub fn heard(focus: &[String]) -> Heard<'_> {
    Heard {
        focus,
        speaker: crate::engine::scene::DEFAULT_SPEAKER,
    }
}

/// Reads `text` against the objects of `scene` and the verbs of `library`; a pronoun is the
/// first object of the focus (most salient first), and with no focus it matches nothing; "me"
/// is the speaker (their object when the scene holds them).
/// `expired` is asked while the scene's words are gathered and while long references are read.
///
/// Where a two-argument verb's words could be parted at more than one joiner ("Put the cup on
/// the table in the box."), each way is read, and the one whose references all name something
/// in the scene is the reading; with none, the first way says what it could not find; with
/// several, the words are not understood, as choosing would be a guess.
pub fn understand(
    text: &str,
    scene: &Scene,
    library: &Library,
    heard: Heard<'_>,
    expired: &dyn Fn() -> bool,
) -> Understanding {
    let Heard { focus, speaker } = heard;
    let lexicon = lexicon::Lexicon::new(scene, library, expired).spoken_by(speaker);
    let mut first_way = splits::Splits::default();
    let first = focused(grammar::read(text, &lexicon, &mut first_way), focus);
    if !first_way.ambiguous() {
        return first;
    }
    // The first way is already read: each other way is read once.
    let mut naming = Vec::new();
    if splits::names_something(&first, scene, expired) {
        naming.push(first.clone());
    }
    for mut way in first_way.ways().into_iter().skip(1) {
        let reading = focused(grammar::read(text, &lexicon, &mut way), focus);
        if expired() {
            return Understanding::Expired;
        }
        if splits::names_something(&reading, scene, expired) {
            naming.push(reading);
        }
    }
    match naming.len() {
        0 => first,
        1 => naming.remove(0),
        _ => Understanding::NotUnderstood {
            why: Unclear::Ambiguous,
            words: text.trim().trim_end_matches(['.', '!', '?']).trim().to_owned(),
        },
    }
}

/// The reading with each pronoun that no earlier step binds made the first object of `focus`.
fn focused(mut understood: Understanding, focus: &[String]) -> Understanding {
    let (Understanding::Directive { directive, parse }, Some(first)) = (&mut understood, focus.first()) else {
        return understood;
    };
    match directive {
        Directive::Action { arguments, .. } => {
            for (argument, phrase) in arguments.iter_mut().zip(&mut parse.references) {
                if point_at(argument, first) {
                    phrase.reference = argument.clone();
                }
            }
        }
        // A pronoun no earlier step binds is the object in focus, in the task and its parse.
        Directive::Task(task) => {
            let arguments = (task.steps.iter_mut().flat_map(|s| &mut s.arguments))
                .chain(task.purposes.iter_mut().flat_map(|p| &mut p.arguments));
            for argument in arguments {
                if let Argument::Reference(reference) = argument {
                    point_at(reference, first);
                }
            }
            let said = (parse.steps.iter_mut().flat_map(|s| &mut s.arguments))
                .chain(parse.purposes.iter_mut().flat_map(|p| &mut p.arguments))
                .filter(|a| a.bound.is_none())
                .map(|a| &mut a.phrase)
                .chain(parse.references.iter_mut());
            for phrase in said {
                point_at(&mut phrase.reference, first);
            }
        }
        Directive::Form { .. } | Directive::Words { .. } => {}
    }
    understood
}

/// Makes a pronoun of `reference` (itself, the reference a narrowing narrows, or a relation's
/// landmark) the object `id`; whether there was one.
fn point_at(reference: &mut Reference, id: &str) -> bool {
    match reference {
        Reference::Pronoun { .. } => {
            *reference = Reference::Id(id.to_owned());
            true
        }
        Reference::Narrowed { base, .. } => point_at(base, id),
        // "the cup next to it": the landmark is the object in focus.
        Reference::Related { base, to, .. } => point_at(base, id) | point_at(to, id),
        Reference::Union { readings, .. } => readings.iter_mut().fold(false, |any, r| point_at(r, id) | any),
        Reference::Most { base, .. } | Reference::Nth { base, .. } | Reference::Plural { base, .. } => {
            point_at(base, id)
        }
        _ => false,
    }
}

/// Reads a follow-up answer in words: "yes", "no", "never mind", an ordinal into the question's
/// readings ("the second one"), an object's id as written, "not the red one", a whole new
/// directive of a known verb ("Get the vase."), or a reference ("the red one", whose "one" takes
/// the question's type). Words that are none of these are a reference that matches nothing.
pub fn understand_answer(text: &str, scene: &Scene, library: &Library, expired: &dyn Fn() -> bool) -> Answer {
    answer::read_answer(text, &lexicon::Lexicon::new(scene, library, expired))
}
