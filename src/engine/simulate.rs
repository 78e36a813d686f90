//! Simulating one reading in its own copy of the world, gathering every reason it cannot be done.
//!
//! Owns: DIARC's check order, step expansion, effects, and feasibility (reach, preconditions).
//! Must not: stop at the first failure (every reason is gathered), share a world between
//! readings, or decide what to say.

use super::action::{Library, Method, Step};
use super::norms::{CompiledNorms, InForce, NormKind, Scope, SoftMatch};
use super::scene::{PERSON, Scene, grasp_width, room_on};
use super::term::{Bound, Subst, Sym, Term};
use super::world::{Base, KeyBit, World};

/// Steps may expand into steps at most this deep; a deeper plan is a reason, not a crash.
pub const MAX_PLAN_DEPTH: usize = 8;

mod reason;

pub use reason::{Cause, NormWords, Outcome, Reason};

/// The first object an action names twice, if any.
fn repeated_argument(action: &Term) -> Option<Sym> {
    let args = action.args();
    args.iter()
        .enumerate()
        .find(|(i, a)| args[..*i].contains(a))
        .and_then(|(_, a)| a.name().cloned())
}

/// The `when` facts of a norm met in a simulation of `reading` that its words name: those that
/// name one of the reading's objects and are not just that object's type, as the world holds
/// them (a `when` fact held when it matched).
fn about(env: &Env<'_>, world: &World, reading: &Term, found: &SoftMatch<'_>) -> Vec<Term> {
    let objects = reading.args();
    let subst = found.solution;
    // An argument as the bindings make it: an object's id, or another constant.
    let value = |term| Bound { term, subst }.resolved();
    let mut about = Vec::new();
    for literal in found.when {
        if !literal.args().iter().any(|arg| objects.contains(value(arg))) {
            continue;
        }
        let its_type = match (literal.name(), literal.args()) {
            (Some(name), [subject]) => (value(subject).name())
                .and_then(|id| env.scene.object(id))
                .is_some_and(|o| o.kind == **name),
            _ => false,
        };
        if !its_type {
            let (key, _) = Bound { term: literal, subst }.hashed();
            about.push(world.find(key).cloned().unwrap_or_else(|| literal.substitute(subst)));
        }
    }
    about
}

/// The soft reason for a norm met by `what` in a simulation of `reading`.
fn soft(env: &Env<'_>, world: &World, reading: &Term, kind: NormKind, what: Term, found: SoftMatch<'_>) -> Cause {
    Cause::Soft {
        kind,
        what,
        about: about(env, world, reading, &found),
        note: found.note.cloned(),
    }
}

/// What a forbidden norm met in a simulation of `reading` says beyond its kind.
fn norm_words(env: &Env<'_>, world: &World, reading: &Term, found: Option<SoftMatch<'_>>) -> Option<Box<NormWords>> {
    let found = found?;
    let conditional =
        !found.when.is_empty() || !found.roles.is_empty() || !found.exempt_roles.is_empty() || found.context.is_some();
    Some(Box::new(NormWords {
        note: found.note.cloned(),
        conditional,
        about: about(env, world, reading, &found),
        roles: (found.roles.iter())
            .filter(|r| env.roles.contains(r))
            .cloned()
            .collect(),
        exempt_roles: found.exempt_roles.to_vec(),
        context: found.context.map(str::to_owned),
    }))
}

/// `did(self,action)`: the paper's convention for "action is done".
pub fn did(action: &Term) -> Term {
    Term::Compound(DID.0.clone(), std::sync::Arc::from([DID.1.clone(), action.clone()]))
}

/// `did` and `self`: built once per reading and step, so the two names are looked up once per
/// process.
static DID: std::sync::LazyLock<(Sym, Term)> = std::sync::LazyLock::new(|| {
    let names = (Sym::new("did"), Term::constant("self"));
    names.0.make_lasting();
    names.1.make_lasting();
    names
});

/// Everything a simulation reads; shared by all readings of a request.
pub struct Env<'a> {
    pub scene: &'a Scene,
    pub norms: &'a CompiledNorms,
    pub library: &'a Library,
    /// The norms the request's context and speaker's roles put in force, less those no world
    /// of the request can meet.
    in_force: InForce,
    /// The speaker's roles: a conditional norm's words say which of its roles made it apply.
    roles: Vec<String>,
    /// Whether the request's deadline has passed or its client has gone: asked before every step
    /// is expanded, so that a verb whose plan explodes cannot hold a core past the deadline.
    pub expired: &'a (dyn Fn() -> bool + Sync),
}

impl<'a> Env<'a> {
    /// The simulations of one request over `base`, the facts of `scene`.
    pub fn new(
        scene: &'a Scene,
        norms: &'a CompiledNorms,
        library: &'a Library,
        scope: Scope<'_>,
        base: &Base,
        relations: &[(Sym, Sym)],
        expired: &'a (dyn Fn() -> bool + Sync),
    ) -> Env<'a> {
        // A fact holds in a reading's world only if the scene states it or a step made it true:
        // a verb's effect, or `did(self,step)`. An effect that is a bare variable could be any.
        // The relations a joiner said makes true hold too ("put X in Y": `in`).
        let (effects, any) = library.effects();
        let made = |name: &Sym, arity: usize| {
            (name == &DID.0 && arity == 2)
                || relations.iter().any(|(_, to)| to == name && arity == 2)
                || effects.iter().any(|(n, a)| n == name && *a == arity)
        };
        let can_hold = |key: &KeyBit| {
            let (name, arity) = key.key();
            any || base.may_have(key) || made(name, *arity)
        };
        let in_force = norms.in_force(scope, &can_hold);
        Env {
            scene,
            norms,
            library,
            in_force,
            roles: scope.roles.to_vec(),
            expired,
        }
    }
}

struct Run<'a, 'b> {
    env: &'a Env<'a>,
    /// The reading's own action: a soft reason's words name only facts about its objects.
    reading: &'a Term,
    /// `did(self,reading)`, made once: the goal state checked first and the fact the reading's
    /// own step makes true.
    done: &'a Term,
    /// The relation the reading's own verb makes true, and the one the joiner said names
    /// instead ("put X in Y": `on` becomes `in`). The reading's own step only: a step it calls
    /// is not what the human said.
    relation: Option<&'a (Sym, Sym)>,
    world: World<'b>,
    outcome: Outcome,
    /// Set once `expired` said so: nothing more is expanded.
    stopped: bool,
}

impl Run<'_, '_> {
    fn stop(&mut self) {
        self.stopped = true;
        self.push(Reason::unfinished());
    }

    fn push(&mut self, reason: Reason) {
        self.outcome.push(reason);
    }

    fn check_action(&mut self, action: &Term) {
        let (env, reading, world, outcome) = (self.env, self.reading, &self.world, &mut self.outcome);
        env.norms.check_action(action, world, &env.in_force, &mut |v| {
            let cause = match v.soft {
                Some(found) => soft(env, world, reading, v.kind, action.clone(), found),
                None => Cause::ForbiddenAction {
                    step: action.clone(),
                    name: v.name.clone(),
                    words: norm_words(env, world, reading, v.words),
                },
            };
            outcome.push(Reason::of_norm(cause, v.norm_id, v.severity));
        });
    }

    /// State norms the world meets because of `new_facts`, just made true in it.
    fn check_entered(&mut self, new_facts: &[Term]) {
        let (env, reading, world, outcome) = (self.env, self.reading, &self.world, &mut self.outcome);
        env.norms.check_entered(new_facts, world, &env.in_force, &mut |v| {
            let cause = match v.soft {
                Some(found) => soft(env, world, reading, v.kind, v.fact, found),
                None => Cause::ForbiddenState {
                    words: norm_words(env, world, reading, v.words),
                    fact: v.fact,
                },
            };
            outcome.push(Reason::of_norm(cause, v.norm_id, v.severity));
        });
    }

    /// Runs `action`'s steps. `checked` is true when the action was already checked against the
    /// forbidden actions (the directive itself, in check (1)).
    fn run(&mut self, action: &Term, checked: bool, depth: usize) {
        if self.stopped {
            return;
        }
        if (self.env.expired)() {
            self.stop();
            return;
        }
        if depth > MAX_PLAN_DEPTH {
            self.push(Reason::infeasible(Cause::PlanTooDeep { step: action.clone() }));
            return;
        }
        if !checked {
            self.check_action(action);
        }
        let env = self.env;
        let Some(def) = env.library.lookup(action) else {
            self.push(Reason::infeasible(Cause::UnknownAction {
                verb: action.name().cloned().unwrap_or_else(|| Sym::from(action.to_string())),
            }));
            return;
        };
        let Some(bindings) = def.bind(action) else {
            return;
        };
        if def.distinct
            && let Some(object) = repeated_argument(action)
        {
            self.push(Reason::infeasible(Cause::SameObject {
                verb: def.name.clone(),
                object,
                joiner: def.joiner.clone(),
            }));
        }
        if let [method] = def.methods.as_slice() {
            self.run_method(action, method, &bindings, depth, true);
            return;
        }
        // Several methods: each is tried from the same world. The first that meets no reason is
        // the plan; when none does, the reading carries the reasons of every method tried and
        // goes on in the world of the first.
        let mut tried: Vec<Run<'_, '_>> = Vec::with_capacity(def.methods.len());
        for method in &def.methods {
            let mut attempt = Run {
                env,
                reading: self.reading,
                done: self.done,
                relation: self.relation,
                world: self.world.clone(),
                outcome: Outcome::default(),
                stopped: false,
            };
            attempt.run_method(action, method, &bindings, depth, false);
            if attempt.stopped {
                self.stop();
                return;
            }
            // Soft norms do not make a method fail: they rank readings, not plans.
            if attempt.outcome.reasons.iter().all(Reason::is_soft) {
                for reason in attempt.outcome.reasons {
                    self.push(reason);
                }
                self.world = attempt.world;
                self.outcome.plan.extend(attempt.outcome.plan);
                return;
            }
            tried.push(attempt);
        }
        for attempt in &tried {
            for reason in &attempt.outcome.reasons {
                self.push(reason.clone());
            }
        }
        let first = tried.swap_remove(0);
        self.world = first.world;
        self.outcome.plan.extend(first.outcome.plan);
    }

    /// Runs one method's steps. `checked_here` is true when `action` was checked against the
    /// action norms in this very world, into this outcome, just before (its only method).
    fn run_method(&mut self, action: &Term, method: &Method, bindings: &Subst, depth: usize, checked_here: bool) {
        for (n, step) in method.steps.iter().enumerate() {
            match step {
                Step::Do(sub) => self.run(&sub.substitute(bindings), false, depth + 1),
                Step::Itself => {
                    // The verb's own step, in the world its earlier steps made (a `when` may
                    // hold only now); the same reason found by check (1) is kept once. As the
                    // first step it is in the world just checked: checking again finds nothing new.
                    if !(checked_here && n == 0) {
                        self.check_action(action);
                    }
                    self.execute(action, method, bindings);
                }
            }
        }
    }

    /// The verb's own execution: effects (and the states they enter), then needs, judged on the
    /// world before the effects.
    fn execute(&mut self, action: &Term, def: &Method, bindings: &Subst) {
        // Preconditions are judged on the world before the effects; copy it only if asked.
        let before = (!def.preconditions.is_empty()).then(|| self.world.clone());
        self.outcome.plan.push(action.clone());
        for fact in &def.removes {
            self.world.retract(&fact.substitute(bindings));
        }
        let mut new_facts: smallvec::SmallVec<[Term; 4]> = smallvec::SmallVec::new();
        // The reading's own step (the same term, not only an equal one) is already done.
        let own = std::ptr::eq(action, self.reading);
        let done = if own { self.done.clone() } else { did(action) };
        let relation = self.relation.filter(|_| own);
        let said = |fact: Term| match relation {
            Some((from, to)) if fact.name() == Some(from) && fact.arity() == 2 => {
                Term::compound(to, fact.args().to_vec())
            }
            _ => fact,
        };
        for fact in def.adds.iter().map(|f| said(f.substitute(bindings))).chain([done]) {
            if self.world.assert(fact.clone()) {
                new_facts.push(fact);
            }
        }
        self.check_entered(&new_facts);
        let scene = self.env.scene;
        // The scene object a parameter is bound to, if any.
        let object_of = |param: &Sym| match bindings.get(param) {
            Some(Term::Const(id)) => scene.object(id),
            _ => None,
        };
        // A person is a referent, never an object to handle: a parameter the verb reaches for,
        // grasps or places may be bound to a person only where the method declares it one.
        let handled =
            (def.reach.iter().chain(&def.grasp)).chain(def.place.iter().flat_map(|(item, support)| [item, support]));
        let mut people: smallvec::SmallVec<[&Sym; 2]> = smallvec::SmallVec::new();
        // (One the scene knows by facts alone is a person too: the speaker it does not place.)
        let world = &self.world;
        let person_of = |param: &Sym| match bindings.get(param) {
            Some(Term::Const(id)) => match scene.object(id) {
                Some(o) => (o.kind == PERSON).then_some(&o.id),
                None => known_person(world, &Term::Const(id.clone())).then_some(id),
            },
            _ => None,
        };
        let mut found = Vec::new();
        for param in handled {
            if let Some(person) = person_of(param)
                && !people.contains(&person)
                && !def.takes_person(param)
            {
                people.push(person);
                found.push(Reason::infeasible(Cause::Person { person: person.clone() }));
            }
        }
        found.into_iter().for_each(|r| self.push(r));
        let object_of = |param: &Sym| object_of(param).filter(|o| !people.contains(&&o.id));
        for param in &def.reach {
            let Some(target) = bindings.get(param) else { continue };
            if target.name().is_some_and(|id| people.contains(&id)) {
                continue;
            }
            let Some(object) = object_of(param) else {
                // A person the scene knows by facts alone (the speaker, whom it does not place)
                // comes for what they are handed: there is nowhere to reach for.
                if !known_person(&self.world, target) {
                    self.push(Reason::infeasible(Cause::UnknownObject { object: target.clone() }));
                }
                continue;
            };
            if scene.within_reach(&object.id) != Some(true) {
                let object = object.id.clone();
                self.push(Reason::infeasible(Cause::Unreachable { object }));
            } else if let Some(obstacle) = scene.blocked_by(&object.id) {
                self.push(Reason::infeasible(Cause::Blocked {
                    object: object.id.clone(),
                    by: obstacle.id.clone(),
                }));
            }
        }
        let agent = &scene.agent;
        for object in def.grasp.iter().filter_map(object_of) {
            let id = || object.id.clone();
            if agent
                .gripper_aperture
                .is_some_and(|aperture| grasp_width(object) > aperture)
            {
                self.push(Reason::infeasible(Cause::TooWide { object: id() }));
            }
            if let (Some(payload), Some(mass)) = (agent.payload, object.mass)
                && mass > payload
            {
                self.push(Reason::infeasible(Cause::TooHeavy { object: id() }));
            }
        }
        // Room is room on top: an item put in or under its support is not placed on it.
        if let Some((item, support)) = &def.place
            && relation.is_none_or(|(_, to)| &**to == "on")
            && let (Some(item), Some(support)) = (object_of(item), object_of(support))
            && support.shape.is_some()
            && !room_on(support, item)
        {
            self.push(Reason::infeasible(Cause::NoRoom {
                item: item.id.clone(),
                support: support.id.clone(),
            }));
        }
        if let Some(before) = before {
            for precondition in &def.preconditions {
                let fact = precondition.substitute(bindings);
                if !before.satisfiable(std::slice::from_ref(&fact), &Subst::new()) {
                    self.push(Reason::infeasible(Cause::Precondition { fact }));
                }
            }
        }
    }
}

/// Whether `who` is a person by the world's facts (`person(who)`): one of the scene's people,
/// or a speaker it does not place.
fn known_person(world: &World<'_>, who: &Term) -> bool {
    world.holds(&Term::compound(PERSON, vec![who.clone()]))
}

/// Simulates doing `action` (ground) in a private copy of `world`, in DIARC's order: (1) the
/// directive against the forbidden actions; (2) `did(self,action)` against the forbidden states;
/// (3) whether the verb is known; (4) each step: the step against the forbidden actions, the
/// states its effects enter, its needs. It goes on past failures so that every reason is found.
/// `relation`: the one the joiner said makes true instead of the verb's own. Hands back the
/// outcome and `did(self,action)`, the reading as the answer names it.
pub fn simulate(env: &Env<'_>, world: &World, action: &Term, relation: Option<&(Sym, Sym)>) -> (Outcome, Term) {
    let done = did(action);
    let (outcome, _) = run_from(env, world.clone(), action, &done, relation);
    (outcome, done)
}

/// [`simulate`], handing back the world as the simulation left it, for a next step to start in.
pub fn simulate_from<'b>(
    env: &Env<'_>,
    world: World<'b>,
    action: &Term,
    relation: Option<&(Sym, Sym)>,
) -> (Outcome, World<'b>) {
    run_from(env, world, action, &did(action), relation)
}

fn run_from<'b>(
    env: &Env<'_>,
    world: World<'b>,
    action: &Term,
    done: &Term,
    relation: Option<&(Sym, Sym)>,
) -> (Outcome, World<'b>) {
    let mut run = Run {
        env,
        reading: action,
        done,
        relation,
        world,
        outcome: Outcome::default(),
        stopped: false,
    };
    run.check_action(action);
    // Check (2) asks about the goal state before any step runs: a hypothetical world in which
    // only `did(self,action)` has been made true, discarded afterwards.
    if run.world.assert(done.clone()) {
        run.check_entered(std::slice::from_ref(done));
        run.world.retract(done);
    }
    run.run(action, true, 0);
    (run.outcome, run.world)
}

/// What the forbidden norms say of `purpose`, an act the human said the task is for and the
/// robot is not asked to do: checked as a directive's action is, by checks (1) and (2), in
/// `world` as the task has left it. Only hard norms: a purpose is not ranked. Each reason is
/// a [`Cause::ForbiddenPurpose`] wrapping what the norm forbids.
pub fn purpose_reasons(
    env: &Env<'_>,
    world: &World,
    purpose: &Term,
    said: &std::sync::Arc<[Option<String>]>,
) -> Vec<Reason> {
    let done = did(purpose);
    let mut run = Run {
        env,
        reading: purpose,
        done: &done,
        relation: None,
        world: world.clone(),
        outcome: Outcome::default(),
        stopped: false,
    };
    run.check_action(purpose);
    if run.world.assert(done.clone()) {
        run.check_entered(std::slice::from_ref(&done));
    }
    (run.outcome.reasons.into_iter())
        .filter(Reason::is_norm_violation)
        .map(|r| Reason {
            cause: Cause::ForbiddenPurpose {
                purpose: purpose.clone(),
                cause: Box::new(r.cause),
                said: said.clone(),
            },
            ..r
        })
        .collect()
}
