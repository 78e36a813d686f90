//! Arguments a directive leaves unsaid ("Heat up the soup.": with what; "Bring the mug.": to
//! whom): the references that stand for them, made from the verb's definition, and the
//! objects an implied one may be.
//!
//! Owns: filling them in before anything is resolved. Must not: choose among their candidates
//! (the readings vary over them, as over any reference's) or simulate anything.

use std::borrow::Cow;

use rustc_hash::FxHashSet;

use super::Reference;
use crate::engine::action::{Library, Unsaid};
use crate::engine::request::Directive;
use crate::engine::scene::{Scene, spoken};
use crate::engine::task::{Argument, Task};
use crate::engine::term::{Subst, Sym, Term};

/// Most parameters a verb has (`ActionInput::validate` holds them to it).
const MOST_PARAMETERS: usize = 8;

/// How often the search for implied objects asks the deadline, in objects.
const ASK_EVERY: usize = 1024;

impl Directive {
    /// The directive as it is resolved: each act given the arguments its verb lets it leave
    /// unsaid, and an action with a plural argument as the task of one step it is.
    pub fn as_resolved<'a>(&'a self, library: &Library, scene: &Scene, speaker: &Sym) -> Cow<'a, Directive> {
        let filled = match self {
            Directive::Action {
                verb,
                arguments,
                joiner,
            } => unsaid(library, scene, speaker, verb, arguments.len(), |i| Some(&arguments[i])).map(|more| {
                Directive::Action {
                    verb: verb.clone(),
                    arguments: arguments.iter().cloned().chain(more).collect(),
                    joiner: joiner.clone(),
                }
            }),
            Directive::Task(task) => {
                let mut filled: Option<Task> = None;
                for (k, step) in task.steps.iter().enumerate() {
                    let first = |i: usize| match &step.arguments[i] {
                        Argument::Reference(r) => Some(r),
                        Argument::Earlier { .. } => None,
                    };
                    if let Some(more) = unsaid(library, scene, speaker, &step.verb, step.arguments.len(), first) {
                        let task = filled.get_or_insert_with(|| task.clone());
                        task.steps[k]
                            .arguments
                            .extend(more.into_iter().map(Argument::Reference));
                    }
                }
                filled.map(Directive::Task)
            }
            Directive::Form { .. } | Directive::Words { .. } => None,
        };
        let directive = match filled {
            Some(d) => Cow::Owned(d),
            None => Cow::Borrowed(self),
        };
        match directive.plural_action() {
            Some(task) => Cow::Owned(Directive::Task(task)),
            None => directive,
        }
    }
}

/// The references for the arguments after the `given` ones that `verb` lets a directive leave
/// unsaid; `None` when the verb is known with `given` arguments, or no definition of it lets
/// the rest be left unsaid (it is then found unknown, as before). `argument(0)` words what is
/// missing ("the soup" in "I do not see anything to heat the soup with.").
fn unsaid<'r>(
    library: &Library,
    scene: &Scene,
    speaker: &Sym,
    verb: &str,
    given: usize,
    argument: impl Fn(usize) -> Option<&'r Reference>,
) -> Option<Vec<Reference>> {
    if given == 0 || library.get(verb, given).is_some() {
        return None;
    }
    let def = (given + 1..=MOST_PARAMETERS).find_map(|n| library.get(verb, n))?;
    let stand_ins = def.unsaid(given)?;
    let first = argument(0).map_or_else(|| "it".to_owned(), |r| r.words(scene));
    let joiner = def.joiner.as_deref().unwrap_or("with");
    let what = format!("{} {first} {joiner}", spoken(verb));
    Some(
        (stand_ins.into_iter())
            .map(|stand_in| match stand_in {
                Unsaid::Implied(param, facts) => Reference::Implied {
                    param: param.clone(),
                    facts: facts.to_vec(),
                    words: format!("something to {what}"),
                    untold: format!("I do not see anything to {what}."),
                },
                Unsaid::Speaker => Reference::Speaker(speaker.to_string()),
            })
            .collect(),
    )
}

/// The objects of the scene, in scene order, for which every one of `facts` holds with `param`
/// bound to the object; `None` when the deadline passed on the way.
pub(in crate::engine) fn meeting(
    scene: &Scene,
    param: &Sym,
    facts: &[Term],
    expired: &dyn Fn() -> bool,
) -> Option<Vec<usize>> {
    // The facts are about `param` alone: bound, each is ground, and holds when stated.
    let stated: FxHashSet<Term> = scene.all_facts().into_iter().collect();
    let mut objects = Vec::new();
    for (i, object) in scene.objects.iter().enumerate() {
        if i % ASK_EVERY == ASK_EVERY - 1 && expired() {
            return None;
        }
        let mut bound = Subst::new();
        bound.bind(param.clone(), Term::Const(object.id.clone()));
        if facts.iter().all(|f| stated.contains(&f.substitute(&bound))) {
            objects.push(i);
        }
    }
    Some(objects)
}
