//! Norms compiled for checking: indexed by the action or fact that can meet them, and which
//! of them one request can meet at all.
//!
//! Owns: the rules, their indexes, and the two checks (an action, the facts just made true).
//! Must not: know how a reading is simulated or worded; report in any order but norm id's.

use std::sync::Arc;

use rustc_hash::FxHashMap;

use super::{Norm, NormKind, Scope};
use crate::engine::term::{Subst, Sym, Term};
use crate::engine::world::{KeyBit, World};

/// A norm as checks use it.
#[derive(Debug)]
struct Rule {
    norm: Norm,
    /// For a state rule: the state followed by its `when` conditions; any of them may be the
    /// literal a newly made-true fact matched.
    literals: Vec<Term>,
    /// For a state rule, by position: the literals but that one. A new fact that matched the
    /// literal at a position holds already; only the others are left to solve.
    others: Vec<Vec<Term>>,
    /// The note, shared by every reason the norm gives.
    note: Option<Arc<str>>,
    /// The functor and arity of each of `literals` (for an action rule, of each `when`
    /// condition): a rule with a literal no fact of the world has cannot be met, and is passed
    /// over before anything is matched or joined.
    keys: Vec<Option<KeyBit>>,
}

/// A norm set compiled once per stored version: a check is a hash lookup plus unification.
/// Soft norms sit in the same indexes as forbidden ones: a norm nobody's action or fact names
/// costs nothing.
#[derive(Debug, Default)]
pub struct CompiledNorms {
    pub version: i64,
    rules: Vec<Rule>,
    /// Action rules by the action's name, in id order.
    actions_by_name: FxHashMap<Sym, Vec<usize>>,
    /// State rules by the functor/arity of each of their literals, with the literal's
    /// position; in id order.
    states_by_key: FxHashMap<(Sym, usize), Vec<(usize, usize)>>,
    /// Ground literals of state rules (`on(o1,o2)`), by the very fact: a new fact finds them
    /// with one hash lookup instead of a unification per norm.
    states_by_fact: FxHashMap<Term, Vec<(usize, usize)>>,
    /// The functors and arities of `states_by_fact`'s keys: another fact is not hashed whole.
    fact_keys: rustc_hash::FxHashSet<(Sym, usize)>,
}

/// What a norm that counted was about, for the words of the reason: its `when` facts and the
/// bindings under which they held (borrowed for the moment the check hands it over, so that
/// only the facts that are spoken are ever built), its note, and whom and where it is for.
#[derive(Clone, Copy, Debug)]
pub struct SoftMatch<'a> {
    pub when: &'a [Term],
    pub solution: &'a Subst,
    pub note: Option<&'a Arc<str>>,
    pub roles: &'a [String],
    pub exempt_roles: &'a [String],
    pub context: Option<&'a str>,
}

/// An action norm met: which norm, and the name it is about (spoken in refusals).
#[derive(Clone, Copy, Debug)]
pub struct ActionViolation<'a> {
    pub norm_id: i64,
    pub kind: NormKind,
    pub severity: u8,
    pub name: &'a Sym,
    /// Set for a soft norm only.
    pub soft: Option<SoftMatch<'a>>,
    /// Set for a forbidden norm that is spoken by more than its kind: one with a note, or with
    /// conditions (`when`, roles, exempt roles, a context), which must never be spoken as if
    /// it forbade the action outright.
    pub words: Option<SoftMatch<'a>>,
}

/// A state norm met by a state entered: which norm, and the fact (the norm's state,
/// instantiated).
#[derive(Clone, Debug)]
pub struct StateViolation<'a> {
    pub norm_id: i64,
    pub kind: NormKind,
    pub severity: u8,
    pub fact: Term,
    /// Set for a soft norm only.
    pub soft: Option<SoftMatch<'a>>,
    /// As for an action norm: a forbidden norm's note and conditions.
    pub words: Option<SoftMatch<'a>>,
}

impl Rule {
    /// Whether each literal but the one at `skip` (a new fact matched it) may hold in `world`.
    fn may_hold(&self, world: &World, skip: Option<usize>) -> bool {
        (self.keys.iter().enumerate()).all(|(i, key)| Some(i) == skip || key.as_ref().is_none_or(|k| world.may_hold(k)))
    }

    /// The match under `solution`.
    fn matched<'a>(&'a self, solution: &'a Subst) -> SoftMatch<'a> {
        let spec = &self.norm.spec;
        SoftMatch {
            when: &spec.when,
            solution,
            note: self.note.as_ref(),
            roles: &spec.roles,
            exempt_roles: &spec.exempt_roles,
            context: spec.context.as_deref(),
        }
    }

    /// The soft match under `solution`, for a soft rule.
    fn soft_match<'a>(&'a self, solution: &'a Subst) -> Option<SoftMatch<'a>> {
        self.norm.spec.kind.is_soft().then(|| self.matched(solution))
    }

    /// The words of a forbidden rule beyond its kind, under `solution`: `None` for a soft rule,
    /// and for a forbidden one with no note and no condition (the paper's own norms as words).
    fn words<'a>(&'a self, solution: &'a Subst) -> Option<SoftMatch<'a>> {
        let spec = &self.norm.spec;
        (!spec.kind.is_soft() && (self.note.is_some() || spec.conditional())).then(|| self.matched(solution))
    }
}

/// Which rules one request can meet at all, by rule: those in force in its scope whose every
/// literal is of a functor and arity that can hold in some world of the request. Worked out
/// once per request, so that each step of each reading passes over the others with one look.
#[derive(Debug)]
pub struct InForce(Vec<bool>);

impl InForce {
    fn has(&self, index: usize) -> bool {
        self.0[index]
    }
}

impl CompiledNorms {
    /// The rules `scope` puts in force and that can be met where only facts of the keys
    /// `can_hold` allows ever hold. `can_hold` may allow more keys than can hold, never fewer:
    /// a rule it rules out is never checked.
    pub fn in_force(&self, scope: Scope<'_>, can_hold: &dyn Fn(&KeyBit) -> bool) -> InForce {
        InForce(
            (self.rules.iter())
                .map(|rule| rule.norm.applies_in(scope) && rule.keys.iter().flatten().all(can_hold))
                .collect(),
        )
    }

    /// Compiles norms; they are indexed in ascending id order, so checks report in that order.
    pub fn compile(version: i64, mut norms: Vec<Norm>) -> CompiledNorms {
        norms.sort_by_key(|n| n.id);
        let mut compiled = CompiledNorms {
            version,
            ..CompiledNorms::default()
        };
        for norm in norms {
            let index = compiled.rules.len();
            let mut literals = vec![norm.spec.term.clone()];
            literals.extend(norm.spec.when.iter().cloned());
            literals.iter().for_each(Term::make_lasting); // every reading's checks copy them
            if norm.spec.kind.on_action() {
                if let Some(name) = norm.spec.term.name() {
                    compiled.actions_by_name.entry(name.clone()).or_default().push(index);
                }
            } else {
                for (position, literal) in literals.iter().enumerate() {
                    if let Some(name) = literal.name() {
                        let entry = if literal.is_ground() {
                            compiled.fact_keys.insert((name.clone(), literal.arity()));
                            compiled.states_by_fact.entry(literal.clone()).or_default()
                        } else {
                            compiled
                                .states_by_key
                                .entry((name.clone(), literal.arity()))
                                .or_default()
                        };
                        if entry.last() != Some(&(index, position)) {
                            entry.push((index, position));
                        }
                    }
                }
            }
            let others = match norm.spec.kind.on_action() {
                true => Vec::new(),
                false => (0..literals.len())
                    .map(|p| [&literals[..p], &literals[p + 1..]].concat())
                    .collect(),
            };
            let note = norm.spec.note.as_deref().map(Arc::from);
            // An action rule's literals but the action: its `when` conditions.
            let keys = (literals.iter().skip(usize::from(norm.spec.kind.on_action())))
                .map(|l| l.name().map(|name| KeyBit::new((name.clone(), l.arity()))))
                .collect();
            compiled.rules.push(Rule {
                norm,
                literals,
                others,
                note,
                keys,
            });
        }
        compiled
    }

    pub fn len(&self) -> usize {
        self.rules.len()
    }

    pub fn is_empty(&self) -> bool {
        self.rules.is_empty()
    }

    /// Action norms in force (`in_force`) that `action` meets in `world` (the world before the
    /// action), handed to `found` in id order: forbidden and discouraged ones it breaks,
    /// preferred ones it follows. A norm naming only an action (`destroy`) matches it at any arity.
    pub fn check_action<'a>(
        &'a self,
        action: &'a Term,
        world: &World,
        in_force: &InForce,
        found: &mut dyn FnMut(ActionViolation<'_>),
    ) {
        let Some(name) = action.name() else { return };
        let Some(indices) = self.actions_by_name.get(name) else {
            return;
        };
        let mut matches = Matches::default();
        for &index in indices {
            let rule = &self.rules[index];
            if !in_force.has(index) || !rule.may_hold(world, None) {
                continue;
            }
            // A bare name (`destroy`) matches an action of that name at any arity.
            let Some(subst) = matches.of(&rule.norm.spec.term, action, true) else {
                continue;
            };
            let spec = &rule.norm.spec;
            // The first solution of `when` is enough; a soft norm's words name it.
            world.solve(&spec.when, subst, &mut |solution| {
                found(ActionViolation {
                    norm_id: rule.norm.id,
                    kind: spec.kind,
                    severity: spec.severity,
                    name,
                    soft: rule.soft_match(solution),
                    words: rule.words(solution),
                });
                false
            });
        }
    }

    /// State norms in force (`in_force`) that `world` meets because of the facts in
    /// `new_facts` (just made true), handed to `found`: each involves at least one of them, so
    /// states the world was already in are not reported again. Deterministic: by new fact, then norm id, then solution
    /// order. A state reached through two new facts is reported for each (the caller keeps one);
    /// a soft norm stops at its first state, since it counts once.
    pub fn check_entered(
        &self,
        new_facts: &[Term],
        world: &World,
        in_force: &InForce,
        found: &mut dyn FnMut(StateViolation<'_>),
    ) {
        for fact in new_facts {
            let Some(name) = fact.name() else { continue };
            let mut matches = Matches::default();
            let key = (name.clone(), fact.arity());
            let by_key = self.states_by_key.get(&key);
            let by_fact = (self.fact_keys.contains(&key))
                .then(|| self.states_by_fact.get(fact))
                .flatten();
            // Norm-id order, whichever index found them: each list is in that order already, so
            // only hits from both are merged (and copied).
            let merged: Vec<(usize, usize)>;
            let hits: &[(usize, usize)] = match (by_key, by_fact) {
                (None, None) => continue,
                (Some(one), None) | (None, Some(one)) => one,
                (Some(a), Some(b)) => {
                    let mut both: Vec<(usize, usize)> = a.iter().chain(b).copied().collect();
                    both.sort_unstable();
                    merged = both;
                    &merged
                }
            };
            for &(index, position) in hits {
                let rule = &self.rules[index];
                if !in_force.has(index) || !rule.may_hold(world, Some(position)) {
                    continue;
                }
                let Some(seed) = matches.of(&rule.literals[position], fact, false) else {
                    continue;
                };
                let soft = rule.norm.spec.kind.is_soft();
                world.solve(&rule.others[position], seed, &mut |solution| {
                    // Matched at the state itself, the state is the new fact: nothing to build.
                    let state = match position {
                        0 => fact.clone(),
                        _ => rule.norm.spec.term.substitute(solution),
                    };
                    found(StateViolation {
                        norm_id: rule.norm.id,
                        kind: rule.norm.spec.kind,
                        severity: rule.norm.spec.severity,
                        fact: state,
                        soft: rule.soft_match(solution),
                        words: rule.words(solution),
                    });
                    !soft
                });
            }
        }
    }
}

/// The bindings of each pattern matched against one term during one check. Norms of one verb
/// or state often share their pattern (`get(X)`, `holding(self,X)`), and each is matched once.
#[derive(Default)]
struct Matches<'a> {
    seen: smallvec::SmallVec<[(&'a Term, Option<Subst>); 4]>,
}

impl<'a> Matches<'a> {
    /// The bindings under which `pattern` matches `term`; `None` when it does not. With
    /// `any_arity`, a bare name matches whatever `term`'s arguments, binding nothing.
    fn of(&mut self, pattern: &'a Term, term: &Term, any_arity: bool) -> Option<&Subst> {
        let at = match self.seen.iter().position(|(seen, _)| *seen == pattern) {
            Some(at) => at,
            None => {
                let mut subst = Subst::new();
                let matched = (any_arity && matches!(pattern, Term::Const(_))) || subst.unify_ground(pattern, term);
                self.seen.push((pattern, matched.then_some(subst)));
                self.seen.len() - 1
            }
        };
        self.seen[at].1.as_ref()
    }
}
