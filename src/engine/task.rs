//! A task: several steps in one directive ("Get the mug and put it in the sink."), and the
//! purposes said with them ("… to smash the vase").
//!
//! Owns: a task's shape and its checks (an argument refers back only to an earlier step, at
//! most [`MAX_STEPS`] steps), the slots its references make (each reference once: an argument
//! that refers back shares the earlier step's slot, so every reading binds it to one object),
//! and a task reading's action, words and simulation (its steps in order in one private
//! world, effects carrying over, then its purposes against the forbidden norms). Must not:
//! choose among readings or word a decision.

use super::action::Library;
use super::describe::Describer;
use super::resolve::{Reference, Slot, members, objects_of, slot};
use super::scene::Scene;
use super::simulate::{Env, Outcome, Reason, did, purpose_reasons, simulate_from};
use super::term::{Sym, Term};
use super::world::World;

/// `and`, the functor of a task's action: made once, for the process.
static AND: std::sync::LazyLock<Sym> = std::sync::LazyLock::new(|| {
    let and = Sym::new("and");
    and.make_lasting();
    and
});

/// Most steps one directive may hold.
pub const MAX_STEPS: usize = 8;
/// A purpose's objects are checked combination by combination; the deadline is asked between
/// this many.
const PURPOSE_LOOK: usize = 64;

/// One argument of a step: a reference of its own, or the object of an earlier step's argument.
#[derive(Clone, Debug, PartialEq)]
pub enum Argument {
    Reference(Reference),
    /// The object of argument `argument` of step `step` (both from 0), an earlier step: "it"
    /// in "get the mug and put it in the sink" is step 0's argument 0.
    Earlier {
        step: usize,
        argument: usize,
    },
}

/// One step: a verb and its arguments, and the joiner said between two of them.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    pub verb: String,
    pub arguments: Vec<Argument>,
    pub joiner: Option<String>,
}

/// What the human said the task is for ("to smash the vase"): not a step of the robot's, but
/// checked against the forbidden norms as the act it names, in the world after step `after`.
#[derive(Clone, Debug, PartialEq)]
pub struct Purpose {
    /// The words as said ("to smash the vase").
    pub words: String,
    pub verb: String,
    /// Its references; `Earlier` may name step `after` itself ("to smash it").
    pub arguments: Vec<Argument>,
    pub after: usize,
}

/// Steps in order, each checked as a directive's action is, and the purposes said with them.
#[derive(Clone, Debug, PartialEq)]
pub struct Task {
    pub steps: Vec<Step>,
    pub purposes: Vec<Purpose>,
}

impl Task {
    /// Every reference of the task that makes a slot, in order: each step's own references,
    /// arguments in order, steps in order.
    pub fn references(&self) -> impl Iterator<Item = &Reference> {
        (self.steps.iter().flat_map(|s| &s.arguments)).filter_map(|a| match a {
            Argument::Reference(r) => Some(r),
            Argument::Earlier { .. } => None,
        })
    }

    /// The first argument (step, argument) that is a second plural in its step, its own or
    /// one it refers back to: a step makes an act per object of one plural, and which cup goes
    /// on which plate is not guessed ("put the cups on the plates").
    pub fn second_plural(&self) -> Option<(usize, usize)> {
        fn plural<'a>(steps: &'a [Step], mut argument: &'a Argument) -> bool {
            loop {
                match argument {
                    Argument::Reference(r) => return r.number().is_some(),
                    Argument::Earlier { step, argument: j } => {
                        match steps.get(*step).and_then(|s| s.arguments.get(*j)) {
                            Some(earlier) => argument = earlier,
                            None => return false,
                        }
                    }
                }
            }
        }
        self.steps.iter().enumerate().find_map(|(i, step)| {
            let mut plurals = (step.arguments.iter().enumerate()).filter(|(_, a)| plural(&self.steps, a));
            plurals.next()?;
            plurals.next().map(|(j, _)| (i, j))
        })
    }

    /// The slots of the task's references, and how each step's arguments and each purpose's
    /// name them. An `Earlier` argument must name an earlier step's existing argument (the
    /// constructors check it; here it is trusted).
    pub(super) fn shape(&self, scene: &Scene, expired: &dyn Fn() -> bool) -> (Shape, Vec<Slot>, Vec<Slot>) {
        let mut slots = Vec::new();
        let mut steps: Vec<(Sym, Vec<usize>)> = Vec::with_capacity(self.steps.len());
        let place = |argument: &Argument, steps: &[(Sym, Vec<usize>)], slots: &mut Vec<Slot>| match argument {
            Argument::Reference(reference) => {
                slots.push(slot(reference, scene, expired));
                slots.len() - 1
            }
            Argument::Earlier { step, argument } => steps[*step].1[*argument],
        };
        for step in &self.steps {
            let arguments = (step.arguments.iter()).map(|a| place(a, &steps, &mut slots)).collect();
            steps.push((Sym::from(step.verb.as_str()), arguments));
        }
        // A purpose's own references are not slots: no reading binds them, and a purpose is
        // forbidden when it is for any object they match.
        let mut purpose_slots = Vec::new();
        let purposes = (self.purposes.iter())
            .map(|p| PurposeShape {
                verb: Sym::from(p.verb.as_str()),
                after: p.after,
                said: (p.arguments.iter())
                    .map(|a| match a {
                        Argument::Reference(r) => Some(r.words(scene)),
                        Argument::Earlier { .. } => None,
                    })
                    .collect(),
                arguments: (p.arguments.iter())
                    .map(|a| match a {
                        Argument::Reference(reference) => {
                            let found = slot(reference, scene, expired);
                            // A plural's groups share objects: each is checked once.
                            let mut seen = std::collections::HashSet::new();
                            let objects = (found.candidates.iter())
                                .flat_map(|(t, _)| objects_of(t))
                                .filter(|o| seen.insert(*o))
                                .cloned()
                                .collect();
                            purpose_slots.push(found);
                            PurposeArgument::Objects(objects)
                        }
                        Argument::Earlier { step, argument } => PurposeArgument::Slot(steps[*step].1[*argument]),
                    })
                    .collect(),
            })
            .collect();
        let joiners = self.steps.iter().map(|s| s.joiner.clone()).collect();
        let shape = Shape {
            steps,
            joiners,
            relations: Vec::new(),
            purposes,
        };
        (shape, slots, purpose_slots)
    }
}

/// A task resolved into slots: what a reading's values make of it.
pub(super) struct Shape {
    /// Each step's verb and, for each of its arguments, the slot it takes its object from.
    pub(super) steps: Vec<(Sym, Vec<usize>)>,
    /// The joiner said in each step, if any.
    pub(super) joiners: Vec<Option<String>>,
    /// The relation each step's joiner makes true instead of its verb's own, once checked
    /// against the verbs ([`Shape::join`]).
    pub(super) relations: Vec<Option<(Sym, Sym)>>,
    pub(super) purposes: Vec<PurposeShape>,
}

pub(super) struct PurposeShape {
    verb: Sym,
    after: usize,
    arguments: Vec<PurposeArgument>,
    /// The words said for each argument that is the purpose's own reference.
    said: std::sync::Arc<[Option<String>]>,
}

enum PurposeArgument {
    Slot(usize),
    /// Every object the purpose's own reference matches.
    Objects(Vec<Term>),
}

impl Shape {
    /// Checks each step's joiner against its verb and finds the relation it makes true; the
    /// first joiner a verb does not take is handed back as (verb, joiner).
    pub(super) fn join(&mut self, library: &Library) -> Result<(), (String, String)> {
        self.relations = Vec::with_capacity(self.steps.len());
        for ((verb, arguments), joiner) in self.steps.iter().zip(&self.joiners) {
            let relation = match (joiner, library.get(verb, arguments.len())) {
                (Some(said), Some(def)) => {
                    if !def.takes_joiner(said) {
                        return Err((verb.to_string(), said.clone()));
                    }
                    def.relation_for(said)
                }
                _ => None,
            };
            self.relations.push(relation);
        }
        Ok(())
    }

    /// The relations the steps' joiners make true, for the simulation's index of what can hold.
    pub(super) fn said_relations(&self) -> Vec<(Sym, Sym)> {
        self.relations.iter().flatten().cloned().collect()
    }

    /// A reading's acts in order, each with the step it is of: a step names one act, or one
    /// for each object of the group a plural argument binds ("put the cups in the sink": one
    /// `put` per cup, in scene order).
    fn acts(&self, values: &[Term]) -> Vec<(usize, Term)> {
        let mut acts = Vec::with_capacity(self.steps.len());
        for (i, (verb, slots)) in self.steps.iter().enumerate() {
            // The verbs' symbols as they are: a reading is built without looking a name up.
            let act = |value: &dyn Fn(usize) -> Term| match slots.is_empty() {
                true => Term::Const(verb.clone()),
                false => Term::Compound(verb.clone(), slots.iter().map(|&s| value(s)).collect()),
            };
            // A step names at most one plural (the constructors see to it); its slot may stand
            // in more than one of its places ("put them on them").
            match slots.iter().find(|&&s| members(&values[s]).is_some()) {
                None => acts.push((i, act(&|s| values[s].clone()))),
                Some(&plural) => {
                    for member in objects_of(&values[plural]) {
                        acts.push((
                            i,
                            act(&|s| if s == plural { member.clone() } else { values[s].clone() }),
                        ));
                    }
                }
            }
        }
        acts
    }

    /// The step each act of [`Shape::acts`] is of, counted without making the acts.
    fn step_of_each_act(&self, values: &[Term]) -> Vec<usize> {
        let acts = |slots: &Vec<usize>| slots.iter().find_map(|&s| members(&values[s]).map(<[Term]>::len));
        (self.steps.iter().enumerate())
            .flat_map(|(i, (_, slots))| std::iter::repeat_n(i, acts(slots).unwrap_or(1)))
            .collect()
    }

    /// A reading's action from its slots' values: its one act, else `and(A1,A2,…)`, the acts
    /// in order ([`Shape::acts`]).
    pub(super) fn action(&self, values: &[Term]) -> Term {
        let mut acts = self.acts(values);
        match acts.len() {
            1 => acts.pop().expect("one act").1,
            _ => Term::Compound(AND.clone(), acts.into_iter().map(|(_, act)| act).collect()),
        }
    }

    /// A reading in words: each step's verb and arguments, joined by " and ", an object named
    /// by an earlier step spoken as "it" ("get the red mug and put it in the sink") and a
    /// group as its objects listed ("get the red cup and the blue cup"), as "them" after; for
    /// one step of one act, its arguments only, as a directive's reading is described.
    pub(super) fn words(&self, values: &[Term], describer: &mut Describer<'_>) -> String {
        let step = |(verb, slots): &(Sym, Vec<usize>)| match slots.is_empty() {
            true => Term::Const(verb.clone()),
            false => Term::Compound(verb.clone(), slots.iter().map(|&s| values[s].clone()).collect()),
        };
        // One step of one act (said with a purpose, or of a plural of one) is described as any
        // action is: by its arguments.
        if let [one] = self.steps.as_slice()
            && one.1.iter().all(|&s| objects_of(&values[s]).len() == 1)
        {
            return describer.arguments_in_task(&step(one), self.joiners[0].as_deref(), &[]);
        }
        let mut named: Vec<Term> = Vec::new();
        let mut out = String::with_capacity(64);
        for (i, said) in self.steps.iter().enumerate() {
            if i > 0 {
                out.push_str(" and ");
            }
            let step = step(said);
            describer.step_in_task_onto(&step, self.joiners[i].as_deref(), &named, &mut out);
            named.extend(step.args().iter().cloned());
        }
        out
    }

    /// Simulates a reading: its steps in order in one private copy of `world`, each starting
    /// where the last left off and checked as a directive's action is, then each purpose in
    /// the world its step left. Every reason of every step is kept, once; a step cut short by
    /// the deadline ends the simulation (the reading is then unfinished). Hands back the
    /// outcome and `did(self,action)`.
    pub(super) fn simulate(&self, env: &Env<'_>, world: &World, action: &Term, values: &[Term]) -> (Outcome, Term) {
        let mut outcome = Outcome::default();
        let mut world = world.clone();
        let of = self.step_of_each_act(values);
        let acts = match of.len() {
            1 => std::slice::from_ref(action),
            _ => action.args(),
        };
        for (k, act) in acts.iter().enumerate() {
            let i = of[k];
            let (found, after) = simulate_from(env, world, act, self.relations.get(i).and_then(Option::as_ref));
            world = after;
            let unfinished = found.unfinished();
            outcome.plan.extend(found.plan);
            for reason in found.reasons {
                outcome.push(reason);
            }
            if unfinished {
                break;
            }
            // A step's purposes, once its last act is done.
            if of.get(k + 1) == Some(&i) {
                continue;
            }
            for purpose in self.purposes.iter().filter(|p| p.after == i) {
                if !purpose.check(env, &world, values, &mut outcome) {
                    outcome.push(Reason::unfinished());
                    return (outcome, did(action));
                }
            }
        }
        (outcome, did(action))
    }
}

impl PurposeShape {
    /// Checks the purpose for every combination of its objects, pushing what the forbidden
    /// norms say; false when the deadline passed first.
    fn check(&self, env: &Env<'_>, world: &World, values: &[Term], outcome: &mut Outcome) -> bool {
        let lists: Vec<Vec<Term>> = (self.arguments.iter())
            .map(|a| match a {
                // "to smash them": a purpose is for each object of a group.
                PurposeArgument::Slot(s) => values.get(*s).map(|v| objects_of(v).to_vec()).unwrap_or_default(),
                PurposeArgument::Objects(objects) => objects.clone(),
            })
            .collect();
        if lists.is_empty() || lists.iter().any(Vec::is_empty) {
            return true;
        }
        // "to smash them": an argument that is a plural of the reading's is said as the group.
        let group =
            |a: &PurposeArgument| matches!(a, PurposeArgument::Slot(s) if values.get(*s).and_then(members).is_some());
        let said = match self.arguments.iter().any(group) {
            false => self.said.clone(),
            true => (self.said.iter().zip(&self.arguments))
                .map(|(words, a)| match group(a) {
                    true => Some("them".to_owned()),
                    false => words.clone(),
                })
                .collect(),
        };
        let mut choice = vec![0usize; lists.len()];
        let mut n = 0usize;
        loop {
            if n > 0 && n.is_multiple_of(PURPOSE_LOOK) && (env.expired)() {
                return false;
            }
            n += 1;
            let purpose = Term::compound(
                &self.verb,
                choice.iter().zip(&lists).map(|(&i, l)| l[i].clone()).collect(),
            );
            for reason in purpose_reasons(env, world, &purpose, &said) {
                outcome.push(reason);
            }
            // The next combination, the last list fastest.
            let mut k = lists.len();
            loop {
                if k == 0 {
                    return true;
                }
                k -= 1;
                choice[k] += 1;
                if choice[k] < lists[k].len() {
                    break;
                }
                choice[k] = 0;
            }
        }
    }
}
