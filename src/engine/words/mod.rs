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
mod tokens;

pub use grammar::grammar_word;
pub use lexicon::inflects;

use super::action::Library;
use super::decision::{Act, ReferenceParse, Unclear, Understood};
use super::request::{Answer, Directive};
use super::resolve::Reference;
use super::scene::Scene;
use super::simulate::did;
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
    /// The verb the words name (or the unknown word in its place: "juggle").
    pub verb: String,
    pub references: Vec<Phrase>,
    /// Trailing words that select no object and were left out ("for reheating", "now").
    pub ignored: Vec<String>,
}

impl Parse {
    /// What the answer shows of a parse: the logical form after pragmatics, one variable per
    /// reference (`want(human,did(self,put(X,Y)))`), and each reference's candidates.
    pub fn understood(&self, speaker: &Term, scene: &Scene) -> Understood {
        const VARIABLES: [&str; 4] = ["X", "Y", "Z", "W"];
        let arguments = (0..self.references.len())
            .map(|i| {
                Term::Var(match VARIABLES.get(i) {
                    Some(v) => Sym::from(*v),
                    None => Sym::from(format!("X{i}").as_str()),
                })
            })
            .collect();
        let action = Term::compound(&self.verb, arguments);
        let form = Term::compound("want", vec![speaker.clone(), did(&action)]);
        Understood {
            act: self.act,
            addressee: self.addressee.clone(),
            form: Some(form),
            references: (self.references.iter())
                .map(|p| ReferenceParse {
                    words: p.words.clone(),
                    candidates: (scene.objects.iter())
                        .filter(|o| p.reference.matches(o))
                        .map(|o| o.id.to_string())
                        .collect(),
                })
                .collect(),
            ignored: self.ignored.clone(),
            unclear: None,
        }
    }
}

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

/// Reads `text` against the objects of `scene` and the verbs of `library`; a pronoun is the
/// first object of `focus` (most salient first), and with no focus it matches nothing.
/// `expired` is asked while the scene's words are gathered and while long references are read.
pub fn understand(
    text: &str,
    scene: &Scene,
    library: &Library,
    focus: &[String],
    expired: &dyn Fn() -> bool,
) -> Understanding {
    let lexicon = lexicon::Lexicon::new(scene, library, expired);
    let mut understood = grammar::read(text, &lexicon);
    if let Understanding::Directive { directive, parse } = &mut understood
        && let (Some(first), Directive::Action { arguments, .. }) = (focus.first(), directive)
    {
        for (argument, phrase) in arguments.iter_mut().zip(&mut parse.references) {
            if point_at(argument, first) {
                phrase.reference = argument.clone();
            }
        }
    }
    understood
}

/// Makes a pronoun of `reference` (itself, or the reference a narrowing narrows) the object
/// `id`; whether there was one.
fn point_at(reference: &mut Reference, id: &str) -> bool {
    match reference {
        Reference::Pronoun { .. } => {
            *reference = Reference::Id(id.to_owned());
            true
        }
        Reference::Narrowed { base, .. } => point_at(base, id),
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
