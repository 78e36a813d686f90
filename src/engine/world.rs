//! The world a simulation runs in: an immutable base of facts shared by every reading, and a
//! private copy-on-write overlay per reading.
//!
//! Owns: fact storage indexed by functor and arity, overlays, and conjunctive queries over them.
//! Must not: copy the base per reading (a copy costs what the simulation changes), or iterate a
//! hash set where order reaches the output (every iteration here is in insertion order).
//! Hashing is FxHash: the keys are terms the engine built, and speed matters per reading.

use std::hash::{BuildHasher, Hash};

use indexmap::Equivalent;
use rustc_hash::{FxBuildHasher, FxHashMap};

use super::term::{Bound, Prehashed, Subst, Sym, Term};

/// Up to this many facts, an overlay is a list that is scanned: comparing a few terms costs
/// less than hashing one.
const SCAN_AT_MOST: usize = 8;

/// What one reading's simulation made true, or made false: facts in the order they came,
/// each once, found by a term or by a term under a substitution ([`Bound`]) unbuilt. A reading
/// changes a few facts, so until it holds more than [`SCAN_AT_MOST`] the overlay is only its
/// list: no fact is hashed into it, and cloning it (once a reading) is one allocation. Past
/// that, it keeps positions by hash beside the list, hashed as the base's set is.
#[derive(Clone, Debug, Default)]
struct Overlay {
    facts: Vec<Term>,
    /// Positions in `facts` by each fact's hash; `Some` exactly when there are more than
    /// [`SCAN_AT_MOST`] facts.
    index: Option<hashbrown::HashTable<u32>>,
}

impl Overlay {
    fn len(&self) -> usize {
        self.facts.len()
    }

    fn is_empty(&self) -> bool {
        self.facts.is_empty()
    }

    fn iter(&self) -> std::slice::Iter<'_, Term> {
        self.facts.iter()
    }

    fn position<Q: Hash + Equivalent<Term> + ?Sized>(&self, fact: &Q) -> Option<usize> {
        match &self.index {
            None => self.facts.iter().position(|f| fact.equivalent(f)),
            Some(index) => {
                let hash = FxBuildHasher.hash_one(fact);
                index
                    .find(hash, |&i| fact.equivalent(&self.facts[i as usize]))
                    .map(|&i| i as usize)
            }
        }
    }

    fn get<Q: Hash + Equivalent<Term> + ?Sized>(&self, fact: &Q) -> Option<&Term> {
        self.position(fact).map(|i| &self.facts[i])
    }

    fn contains<Q: Hash + Equivalent<Term> + ?Sized>(&self, fact: &Q) -> bool {
        self.position(fact).is_some()
    }

    /// Adds `fact`; returns whether it was not here before.
    fn insert(&mut self, fact: Term) -> bool {
        if self.contains(&fact) {
            return false;
        }
        self.push_absent(fact);
        true
    }

    /// Adds `fact`, which the caller has found absent.
    fn push_absent(&mut self, fact: Term) {
        let position = self.facts.len() as u32;
        self.facts.push(fact);
        if let Some(index) = &mut self.index {
            let facts = &self.facts;
            index.insert_unique(hash_at(facts, position), position, |&i| hash_at(facts, i));
        } else if self.facts.len() > SCAN_AT_MOST {
            self.reindex();
        }
    }

    /// Removes `fact`, keeping the others in order; returns whether it was here.
    fn remove(&mut self, fact: &Term) -> bool {
        let Some(position) = self.position(fact) else {
            return false;
        };
        self.facts.remove(position);
        // Positions after it moved: rare (a reading that retracts what it made true, with many
        // facts made), so the index is made again rather than patched.
        self.reindex();
        true
    }

    /// Makes the index agree with the list: none up to [`SCAN_AT_MOST`] facts.
    fn reindex(&mut self) {
        if self.facts.len() <= SCAN_AT_MOST {
            self.index = None;
            return;
        }
        let mut index = hashbrown::HashTable::with_capacity(self.facts.len() * 2);
        for position in 0..self.facts.len() as u32 {
            index.insert_unique(hash_at(&self.facts, position), position, |&i| hash_at(&self.facts, i));
        }
        self.index = Some(index);
    }
}

/// The hash of the fact at a position of `facts`, as the base's set and an overlay's index
/// hash it: how either table finds, and rehashes, a position.
fn hash_at(facts: &[Term], position: u32) -> u64 {
    FxBuildHasher.hash_one(&facts[position as usize])
}

/// A fact's index key: its functor name and arity (`on/2`).
pub type Key = (Sym, usize);

fn key_of(term: &Term) -> Option<Key> {
    term.name().map(|name| (name.clone(), term.arity()))
}

/// The facts of the scene, built once per request and shared by every reading. Each fact is
/// held once: the set and the index hold positions, not copies.
#[derive(Debug, Default)]
pub struct Base {
    /// Every fact once, in the order the scene states them.
    facts: Vec<Term>,
    /// Positions in `facts`, by each fact's hash: asked whether a fact is in it, never iterated.
    set: hashbrown::HashTable<u32>,
    /// Positions in `facts`, grouped by functor and arity (each group in scene order).
    grouped: Vec<u32>,
    /// Each functor and arity's group, as a range of `grouped`.
    index: FxHashMap<Key, (u32, u32)>,
    /// One bit per functor and arity of `index` (a key's hash picks one of 1,024): a key whose
    /// bit is clear has no fact here, found without a lookup.
    keys: [u64; 16],
}

/// The word and the bit of `Base::keys` that stand for a key.
fn key_bit(key: &Key) -> (usize, u64) {
    key_bit_of(&key.0, key.1)
}

/// [`key_bit`] of a functor and arity held apart (a `Key` hashes as the pair does).
fn key_bit_of(name: &Sym, arity: usize) -> (usize, u64) {
    let bit = (FxBuildHasher.hash_one((name, arity)) >> 54) as usize;
    (bit / 64, 1 << (bit % 64))
}

/// A functor and arity with its bit among a base's keys, worked out once (for a norm's
/// literal, when the norms are compiled).
#[derive(Clone, Debug)]
pub struct KeyBit {
    key: Key,
    word: usize,
    bit: u64,
}

impl KeyBit {
    pub fn new(key: Key) -> KeyBit {
        let (word, bit) = key_bit(&key);
        KeyBit { key, word, bit }
    }

    pub fn key(&self) -> &Key {
        &self.key
    }
}

/// How many functors a fact base's index has room for from the start, at most.
const KEYS_RESERVED: usize = 32;

impl Base {
    /// Whether a fact of the key may be here: `false` only when none is.
    pub fn may_have(&self, key: &KeyBit) -> bool {
        self.keys[key.word] & key.bit != 0
    }

    pub fn new(facts: impl IntoIterator<Item = Term>) -> Base {
        let facts = facts.into_iter();
        let mut base = Base::default();
        base.facts.reserve(facts.size_hint().0);
        base.set.reserve(facts.size_hint().0, |&i| hash_at(&base.facts, i));
        // Each fact's group (its key's, numbered as keys first appear), and how many each has.
        let mut groups: Vec<u32> = Vec::with_capacity(facts.size_hint().0);
        let mut sizes: Vec<u32> = Vec::new();
        // A scene has few functors (types, properties, attribute names), however many objects:
        // room for a small scene's, so that most bases never grow the index.
        base.index.reserve(facts.size_hint().0.min(KEYS_RESERVED));
        for fact in facts {
            let hash = FxBuildHasher.hash_one(&fact);
            if base.set.find(hash, |&i| base.facts[i as usize] == fact).is_some() {
                continue;
            }
            let group = match key_of(&fact) {
                Some(key) => {
                    let (word, bit) = key_bit(&key);
                    base.keys[word] |= bit;
                    let next = sizes.len() as u32;
                    let (group, _) = *base.index.entry(key).or_insert((next, 0));
                    if group == next {
                        sizes.push(0);
                    }
                    sizes[group as usize] += 1;
                    group
                }
                // A variable is never a fact of a scene; kept findable, in no group.
                None => u32::MAX,
            };
            groups.push(group);
            let position = base.facts.len() as u32;
            let facts = &base.facts;
            base.set.insert_unique(hash, position, |&i| hash_at(facts, i));
            base.facts.push(fact);
        }
        // Where each group starts, then each position into its group in scene order.
        let mut starts: Vec<u32> = Vec::with_capacity(sizes.len());
        let mut at = 0;
        for size in &sizes {
            starts.push(at);
            at += size;
        }
        for range in base.index.values_mut() {
            let group = range.0 as usize;
            *range = (starts[group], starts[group] + sizes[group]);
        }
        base.grouped = vec![0; at as usize];
        for (position, &group) in groups.iter().enumerate() {
            if let Some(next) = starts.get_mut(group as usize) {
                base.grouped[*next as usize] = position as u32;
                *next += 1;
            }
        }
        base
    }

    /// Whether the base states `fact` (a term, or a ground key with its hash known).
    fn contains<Q: Hash + Equivalent<Term> + ?Sized>(&self, fact: &Q) -> bool {
        self.get(fact).is_some()
    }

    /// The base's own copy of `fact`, if it states it.
    fn get<Q: Hash + Equivalent<Term> + ?Sized>(&self, fact: &Q) -> Option<&Term> {
        let hash = FxBuildHasher.hash_one(fact);
        let found = self.set.find(hash, |&i| fact.equivalent(&self.facts[i as usize]))?;
        Some(&self.facts[*found as usize])
    }

    /// The facts of one functor and arity, in scene order.
    fn of_key<'a>(&'a self, key: &Key) -> impl Iterator<Item = &'a Term> + use<'a> {
        let (start, end) = self.index.get(key).copied().unwrap_or((0, 0));
        (self.grouped[start as usize..end as usize].iter()).map(|&i| &self.facts[i as usize])
    }

    pub fn len(&self) -> usize {
        self.facts.len()
    }

    pub fn is_empty(&self) -> bool {
        self.facts.is_empty()
    }
}

/// One reading's view of the world: the shared base plus what its simulation added and removed.
/// Cloning it copies only the overlay. The base is borrowed, not counted: every reading clones a
/// world, and a shared count would be one cache line that every thread writes twice a reading.
#[derive(Clone, Debug)]
pub struct World<'b> {
    base: &'b Base,
    /// Facts made true by the simulation that the base does not hold, in the order made true.
    added: Overlay,
    /// Base facts the simulation made false.
    removed: Overlay,
    /// The bit of [`key_bit`] of every functor and arity ever added, whatever its word: a
    /// superset (a bit stays set when its fact is retracted, and keys share bits), so that a
    /// clear bit proves no added fact has the key.
    added_keys: u64,
}

impl<'b> World<'b> {
    pub fn new(base: &'b Base) -> World<'b> {
        World {
            base,
            added: Overlay::default(),
            removed: Overlay::default(),
            added_keys: 0,
        }
    }

    pub fn holds(&self, fact: &Term) -> bool {
        self.holds_as(fact)
    }

    /// [`World::holds`] for a ground term under a substitution, without building it.
    fn holds_bound(&self, fact: Prehashed<'_>) -> bool {
        self.holds_as(&fact)
    }

    /// Whether the fact `fact` stands for holds. A small overlay (a reading changes a fact or
    /// two) is scanned rather than hashed into.
    fn holds_as<Q: Hash + Equivalent<Term> + ?Sized>(&self, fact: &Q) -> bool {
        self.added.contains(fact) || (self.base.contains(fact) && !self.removed.contains(fact))
    }

    /// The fact a ground key stands for, as this world holds it; `None` if it does not hold.
    pub fn find(&self, fact: Prehashed<'_>) -> Option<&Term> {
        if let Some(added) = self.added.get(&fact) {
            return Some(added);
        }
        let found = self.base.get(&fact)?;
        (self.removed.is_empty() || !self.removed.contains(found)).then_some(found)
    }

    /// Whether a fact of this functor and arity may hold: `false` only when neither the base
    /// nor this world's additions have one, so that any literal of that key fails.
    pub fn may_hold(&self, at: &KeyBit) -> bool {
        let KeyBit { key, bit, .. } = at;
        self.base.may_have(at)
            || (self.added_keys & bit != 0
                && match self.added.len() {
                    0 => false,
                    1..=SCAN_AT_MOST => (self.added.iter()).any(|f| f.arity() == key.1 && f.name() == Some(&key.0)),
                    _ => true,
                })
    }

    /// Makes `fact` true; returns whether it was false before.
    pub fn assert(&mut self, fact: Term) -> bool {
        // While the overlay is small, the base's lookup is the only hash of `fact`.
        if self.holds(&fact) {
            return false;
        }
        if !self.removed.remove(&fact) {
            if let Some(name) = fact.name() {
                self.added_keys |= key_bit_of(name, fact.arity()).1;
            }
            self.added.push_absent(fact);
        }
        true
    }

    /// Makes `fact` false; returns whether it was true before.
    pub fn retract(&mut self, fact: &Term) -> bool {
        if self.added.remove(fact) {
            return true;
        }
        if self.base.contains(fact) {
            return self.removed.insert(fact.clone());
        }
        false
    }

    /// Facts that may match `pattern`: those sharing its functor and arity, base first (scene
    /// order), then the overlay (order made true). A variable pattern yields every fact.
    fn candidates<'a>(&'a self, pattern: &Term) -> Box<dyn Iterator<Item = &'a Term> + 'a> {
        let live = move |fact: &&Term| !self.removed.contains(*fact);
        match key_of(pattern) {
            Some(key) => {
                let base = self.base.of_key(&key);
                let name = key.0.clone();
                let arity = key.1;
                Box::new(
                    base.filter(live).chain(
                        self.added
                            .iter()
                            .filter(move |f| f.name() == Some(&name) && f.arity() == arity),
                    ),
                )
            }
            None => Box::new(self.base.facts.iter().filter(live).chain(self.added.iter())),
        }
    }

    /// Calls `found` with every extension of `subst` under which all `literals` hold, in a
    /// deterministic order, until `found` returns `false`. Returns `false` if stopped early.
    pub fn solve(&self, literals: &[Term], subst: &Subst, found: &mut dyn FnMut(&Subst) -> bool) -> bool {
        let Some((first, rest)) = literals.split_first() else {
            return found(subst);
        };
        // A literal the bindings make ground is one lookup, with no term built for it.
        let (bound, ground) = Bound { term: first, subst }.hashed();
        if ground {
            return !self.holds_bound(bound) || self.solve(rest, subst, found);
        }
        let goal = first.substitute(subst);
        for fact in self.candidates(&goal) {
            let mut extended = subst.clone();
            if extended.unify_ground(&goal, fact) && !self.solve(rest, &extended, found) {
                return false;
            }
        }
        true
    }

    /// Whether some extension of `subst` makes every literal hold.
    pub fn satisfiable(&self, literals: &[Term], subst: &Subst) -> bool {
        let mut any = false;
        self.solve(literals, subst, &mut |_| {
            any = true;
            false
        });
        any
    }

    /// Facts this reading has made true that the scene did not state, in the order made true.
    pub fn added(&self) -> impl Iterator<Item = &Term> {
        self.added.iter()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(s: &str) -> Term {
        Term::parse(s).unwrap()
    }

    #[test]
    fn overlay_changes_stay_private_to_one_copy() {
        let base = Base::new([t("on(a,table)"), t("red(a)")]);
        let mut one = World::new(&base);
        let two = World::new(&base);
        assert!(one.retract(&t("on(a,table)")));
        assert!(one.assert(t("holding(self,a)")));
        assert!(!one.holds(&t("on(a,table)")));
        assert!(one.holds(&t("holding(self,a)")));
        assert!(two.holds(&t("on(a,table)")));
        assert!(!two.holds(&t("holding(self,a)")));
        // Restoring a base fact removes it from `removed` rather than duplicating it.
        assert!(one.assert(t("on(a,table)")));
        assert!(one.holds(&t("on(a,table)")));
        assert_eq!(one.added().count(), 1);
    }

    #[test]
    fn solve_joins_literals_in_order() {
        let base = Base::new([t("vase(o3)"), t("vase(o4)"), t("fragile(o3)"), t("on(o4,shelf)")]);
        let mut world = World::new(&base);
        world.assert(t("holding(self,o3)"));
        let mut found = Vec::new();
        world.solve(&[t("vase(X)"), t("fragile(X)")], &Subst::new(), &mut |s| {
            found.push(t("X").substitute(s).to_string());
            true
        });
        assert_eq!(found, vec!["o3"]);
        assert!(world.satisfiable(&[t("holding(self,Y)"), t("vase(Y)")], &Subst::new()));
        assert!(!world.satisfiable(&[t("holding(self,Y)"), t("on(Y,Z)")], &Subst::new()));
    }

    #[test]
    fn a_base_holds_each_fact_once_and_lists_a_functor_in_scene_order() {
        let base = Base::new([
            t("vase(o4)"),
            t("on(o4,shelf)"),
            t("vase(o3)"),
            t("vase(o4)"),
            t("on(o3,table)"),
            t("color(o3,red)"),
        ]);
        assert_eq!(base.len(), 5);
        let listed = |pattern: &str| -> Vec<String> {
            let key = key_of(&t(pattern)).unwrap();
            base.of_key(&key).map(Term::to_string).collect()
        };
        assert_eq!(listed("vase(X)"), ["vase(o4)", "vase(o3)"]);
        assert_eq!(listed("on(X,Y)"), ["on(o4,shelf)", "on(o3,table)"]);
        assert_eq!(listed("color(X,Y)"), ["color(o3,red)"]);
        assert!(listed("on(X)").is_empty());
        assert!(base.contains(&t("on(o3,table)")));
        assert!(!base.contains(&t("on(o3,shelf)")));
        let world = World::new(&base);
        let mut all = Vec::new();
        world.solve(&[t("X")], &Subst::new(), &mut |s| {
            all.push(t("X").substitute(s).to_string());
            true
        });
        assert_eq!(
            all,
            ["vase(o4)", "on(o4,shelf)", "vase(o3)", "on(o3,table)", "color(o3,red)"]
        );
    }

    proptest::proptest! {
        /// An overlay is a list while small and hashed past `SCAN_AT_MOST`: through any asserts
        /// and retracts (crossing that size both ways, in `added` and in `removed`), a world and
        /// its copy hold exactly what a plain set would, each change says what the set says, and
        /// the facts made true are listed in the order they were made true.
        #[test]
        fn a_world_agrees_with_a_plain_set_through_any_changes(
            steps in proptest::collection::vec((proptest::bool::ANY, 0..24usize), 0..120),
        ) {
            let fact = |i: usize| t(&format!("at(o{i},p{})", i % 3));
            // The even facts are the scene's; the odd ones only a simulation makes true.
            let base = Base::new((0..24).step_by(2).map(fact));
            let mut world = World::new(&base);
            let mut held: std::collections::BTreeSet<usize> = (0..24).step_by(2).collect();
            let mut made: Vec<usize> = Vec::new();
            for (add, i) in steps {
                if add {
                    let changed = held.insert(i);
                    if changed && i % 2 == 1 {
                        made.push(i);
                    }
                    proptest::prop_assert_eq!(world.assert(fact(i)), changed);
                } else {
                    made.retain(|&m| m != i);
                    proptest::prop_assert_eq!(world.retract(&fact(i)), held.remove(&i));
                }
                let copy = world.clone();
                let none = Subst::new();
                for one in [&world, &copy] {
                    for j in 0..24 {
                        let probe = fact(j);
                        let key = Bound { term: &probe, subst: &none }.hashed().0;
                        proptest::prop_assert_eq!(one.holds(&probe), held.contains(&j), "{}", probe);
                        proptest::prop_assert_eq!(one.find(key).is_some(), held.contains(&j), "{}", probe);
                    }
                    let listed: Vec<String> = one.added().map(Term::to_string).collect();
                    let expected: Vec<String> = made.iter().map(|&m| fact(m).to_string()).collect();
                    proptest::prop_assert_eq!(listed, expected);
                    let mut found = 0;
                    one.solve(&[t("at(X,Y)")], &Subst::new(), &mut |_| {
                        found += 1;
                        true
                    });
                    proptest::prop_assert_eq!(found, held.len());
                }
            }
        }

        /// `may_hold` may say yes wrongly, never no: after any asserts and retracts, a key
        /// some fact of the world has is always said to maybe hold.
        #[test]
        fn may_hold_never_denies_a_key_the_world_has(
            steps in proptest::collection::vec((proptest::bool::ANY, 0..12usize, 0..3usize), 0..40),
        ) {
            let names = ["red", "on", "holding", "near0", "near1", "did", "cup", "at", "in", "under", "lit", "open"];
            let fact = |name: usize, object: usize| match name % 3 {
                0 => t(&format!("{}(o{object})", names[name])),
                1 => t(&format!("{}(o{object},o{})", names[name], object + 1)),
                _ => t(names[name]),
            };
            let base = Base::new([t("red(o0)"), t("on(o1,o2)")]);
            let mut world = World::new(&base);
            for (add, name, object) in steps {
                if add {
                    world.assert(fact(name, object));
                } else {
                    world.retract(&fact(name, object));
                }
                let copy = world.clone();
                for (name, text) in names.iter().enumerate() {
                    let probe = fact(name, 0);
                    let key = KeyBit::new(key_of(&probe).unwrap());
                    let has = copy.satisfiable(&[match name % 3 {
                        0 => t(&format!("{text}(X)")),
                        1 => t(&format!("{text}(X,Y)")),
                        _ => probe.clone(),
                    }], &Subst::new());
                    proptest::prop_assert!(!has || copy.may_hold(&key), "{text} holds but may_hold says no");
                }
            }
        }
    }
}
