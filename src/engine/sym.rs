//! Interned symbols: the names of constants, variables and functors, one allocation per text.
//!
//! Owns: the process-wide table of names, its bound, and which names last (the vocabulary of
//! verbs and norms, and the names requests use most; each set bounded), which each thread also
//! finds without the table. Must not: keep a name nobody holds past the next sweep unless it
//! lasts (names come from requests), or order anything by address (order is by text).

use std::borrow::Borrow;
use std::cell::RefCell;
use std::collections::{HashMap, HashSet};
use std::fmt;
use std::hash::{BuildHasher, BuildHasherDefault, Hash, Hasher};
use std::ops::Deref;
use std::ptr::NonNull;
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicUsize, Ordering};
use std::sync::{LazyLock, Mutex};

use rustc_hash::FxBuildHasher;

/// A symbol. Every symbol of one text is the same allocation, so equality is one address
/// comparison and hashing writes one precomputed word; order and printing go by the text.
///
/// A symbol counts its holders as `Arc` does, except a lasting one: the words of verbs and
/// norms, which every reading of every request clones and drops on every core, and the names
/// requests intern most often ("vase", "table", "red"), which requests on every core clone and
/// drop at once. Counting those made the cores take turns at one cache line (two threads
/// simulated 10,000 readings slower than one did), so a lasting name is never counted and
/// never freed.
pub struct Sym(NonNull<Name>);

// SAFETY: a `Name` is immutable but for its atomic count and flag, and is freed only by the
// table's sweep, under the shard's lock, once no symbol holds it: it is shared as `Arc` shares.
unsafe impl Send for Sym {}
unsafe impl Sync for Sym {}

#[repr(C)]
struct Name {
    /// FxHash of the text: the same in every process and run, so hash-keyed output stays
    /// deterministic.
    hash: u64,
    text: Box<str>,
    /// Set once, never unset: the table keeps the name for the life of the process, and
    /// symbols of it neither count nor are counted.
    lasting: AtomicBool,
    /// How often the name was interned while in the table; written only under its shard's
    /// lock. At [`OFTEN`] the name lasts, if the budget of [`MAX_OFTEN`] allows.
    interned: AtomicU32,
    holders: Holders,
}

/// How many hold a name that does not last, the table's own hold included; on a cache line
/// apart from the hash and the text, which every comparison and hash reads.
#[repr(align(64))]
struct Holders(AtomicUsize);

/// More holders than this is a leak of symbols gone wrong: abort, as `Arc` does.
const MAX_HOLDERS: usize = isize::MAX as usize;

/// At most this many names last; more are counted as any other. Verbs and norms are curated, so
/// a deployment has a few thousand names at most; the bound keeps a flood of new norms from
/// growing the table for ever.
const MAX_LASTING: usize = 1 << 16;
static LASTING: AtomicUsize = AtomicUsize::new(0);

/// A name interned this often while in the table lasts (the paper's request interns each of
/// its names a few times, so a name common to requests lasts after a few dozen of them).
const OFTEN: u32 = 64;
/// At most this many names last for being interned often, apart from [`MAX_LASTING`]: names
/// come from requests, so a client repeating junk names can fill this budget, never the
/// curated one; past it, names are counted as any other. With [`OFTEN_AT_MOST`] this keeps
/// at most a few MiB.
const MAX_OFTEN: usize = 1 << 14;
/// Only names of at most this many bytes (a request's object ids, types and properties are
/// no longer) last for being interned often: a fact may carry a longer name, which must not
/// be kept for ever.
const OFTEN_AT_MOST: usize = MAX_NAME_LEN;

/// Longest name of an id, a type, a property, an attribute or a context, in bytes: what a
/// request may name (`input` holds requests to it).
pub const MAX_NAME_LEN: usize = 128;
static OFTEN_LASTING: AtomicUsize = AtomicUsize::new(0);

/// The table holds a name as long as a symbol does; a name only the table holds is garbage,
/// swept once a shard has doubled since its last sweep, so the table stays within about twice
/// the names alive (plus `FLOOR` per shard, plus the lasting names) however many requests have
/// come and gone.
const SHARDS: usize = 16;
const FLOOR: usize = 256;

struct Shard {
    names: HashSet<Entry, FxBuildHasher>,
    /// How many names the last sweep kept.
    kept: usize,
}

/// The table's own hold on a name: dropping the entry frees the name.
struct Entry(NonNull<Name>);

// SAFETY: entries live in the shards' sets, under their locks; see `Sym`.
unsafe impl Send for Entry {}

impl Entry {
    fn name(&self) -> &Name {
        // SAFETY: the entry owns the allocation until it is dropped.
        unsafe { self.0.as_ref() }
    }

    /// Only the table holds this name, and it does not last: it may be freed.
    fn is_garbage(&self) -> bool {
        let name = self.name();
        // Acquire: every holder's last use, released by its decrement, happens before the free.
        !name.lasting.load(Ordering::Acquire) && name.holders.0.load(Ordering::Acquire) == 1
    }
}

impl Drop for Entry {
    fn drop(&mut self) {
        // SAFETY: made by `Box::leak` in `Sym::new`; only garbage entries are dropped (the
        // sweep's `retain`), and no symbol of a garbage name exists, nor can one be made but
        // under the shard's lock, which the sweep holds.
        drop(unsafe { Box::from_raw(self.0.as_ptr()) });
    }
}

impl Hash for Entry {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.name().text.hash(state);
    }
}

impl PartialEq for Entry {
    fn eq(&self, other: &Self) -> bool {
        self.name().text == other.name().text
    }
}

impl Eq for Entry {}

impl Borrow<str> for Entry {
    fn borrow(&self) -> &str {
        &self.name().text
    }
}

static TABLE: LazyLock<[Mutex<Shard>; SHARDS]> = LazyLock::new(|| {
    std::array::from_fn(|_| {
        Mutex::new(Shard {
            names: HashSet::default(),
            kept: 0,
        })
    })
});

/// Lasting names this thread has met, by hash: found without taking a shard's lock (which the
/// cores took in turn, a dozen times a request). A lasting name is never freed, so a thread
/// may keep its address for ever; at most [`NEAR_MOST`] a thread, so that the blocking pool's
/// many threads cannot hold much.
const NEAR_MOST: usize = 4096;

thread_local! {
    static NEAR: RefCell<HashMap<u64, NonNull<Name>, BuildHasherDefault<HashIs>>> = RefCell::default();
}

/// A hasher for keys that are already FxHashes.
#[derive(Default)]
struct HashIs(u64);

impl Hasher for HashIs {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        // Only `write_u64` is used, for the `u64` keys; any other input still hashes.
        for &byte in bytes {
            self.0 = self.0.rotate_left(8) ^ u64::from(byte);
        }
    }

    fn write_u64(&mut self, hash: u64) {
        self.0 = hash;
    }
}

/// The lasting name of `text` (whose FxHash is `hash`), if this thread has met it.
fn near(hash: u64, text: &str) -> Option<NonNull<Name>> {
    let found = NEAR.try_with(|near| near.borrow().get(&hash).copied()).ok()??;
    // SAFETY: only lasting names are kept, and those are never freed.
    (unsafe { found.as_ref() }.text.as_ref() == text).then_some(found)
}

/// Keeps `name` near for this thread if it lasts (and there is room, and no other name of its
/// hash is kept).
fn keep_near(name: NonNull<Name>) {
    // SAFETY: the caller holds the name.
    let n = unsafe { name.as_ref() };
    // Acquire, as the sweep reads it: once set it stays, and the name is never freed.
    if !n.lasting.load(Ordering::Acquire) {
        return;
    }
    // A thread being torn down keeps nothing.
    let _ = NEAR.try_with(|near| {
        let mut near = near.borrow_mut();
        if near.len() < NEAR_MOST {
            near.entry(n.hash).or_insert(name);
        }
    });
}

/// The shard a name of this hash lives in.
fn shard_of(hash: u64) -> &'static Mutex<Shard> {
    &TABLE[(hash >> 60) as usize % SHARDS]
}

impl Sym {
    pub fn new(text: &str) -> Sym {
        let hash = Sym::hash_of(text);
        if let Some(name) = near(hash, text) {
            // Lasting: not counted.
            return Sym(name);
        }
        let shard = shard_of(hash);
        // A poisoned shard still holds a consistent set: no code that can panic runs under it.
        let mut shard = shard.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some(entry) = shard.names.get(text) {
            entry.name().interned_again();
            keep_near(entry.0);
            return Sym::held(entry.0);
        }
        if shard.names.len() >= (2 * shard.kept).max(FLOOR) {
            shard.names.retain(|entry| !entry.is_garbage());
            shard.kept = shard.names.len();
        }
        let name = NonNull::from(Box::leak(Box::new(Name {
            hash,
            text: text.into(),
            lasting: AtomicBool::new(false),
            interned: AtomicU32::new(1),
            // The table's hold and the symbol returned.
            holders: Holders(AtomicUsize::new(2)),
        })));
        shard.names.insert(Entry(name));
        Sym(name)
    }

    /// A new symbol of a name someone holds.
    fn held(name: NonNull<Name>) -> Sym {
        // SAFETY: the caller holds the name (a symbol, or the table under its lock).
        let n = unsafe { name.as_ref() };
        // Relaxed, as `Arc::clone`: a new holder is made from an existing one, which keeps the
        // name alive meanwhile.
        if !n.lasting.load(Ordering::Relaxed) && n.holders.0.fetch_add(1, Ordering::Relaxed) > MAX_HOLDERS {
            std::process::abort();
        }
        Sym(name)
    }

    fn name(&self) -> &Name {
        // SAFETY: a symbol keeps its name alive (it is counted, or the name lasts).
        unsafe { self.0.as_ref() }
    }

    /// Makes this name last for the life of the process, uncounted, while fewer than
    /// [`MAX_LASTING`] do: for the words of verbs and norms, which every reading uses.
    pub fn make_lasting(&self) {
        // This symbol is counted, so the count stays above the table's own hold from here on:
        // whatever holders see the flag late, the sweep never finds the name garbage.
        self.name().last_within(&LASTING, MAX_LASTING);
    }

    pub fn as_str(&self) -> &str {
        &self.name().text
    }

    /// The hash of a text, as its symbol keeps it: a table keyed by symbols' [`Sym::text_hash`]
    /// finds one by text alone, without interning it.
    pub fn hash_of(text: &str) -> u64 {
        FxBuildHasher.hash_one(text)
    }

    /// The hash of this symbol's text ([`Sym::hash_of`]), computed when it was interned.
    pub fn text_hash(&self) -> u64 {
        self.name().hash
    }
}

impl Name {
    /// Makes the name last if `budget` has room below `bound`. The caller holds the name (a
    /// counted symbol, or the table under the shard's lock), so no sweep can find it garbage
    /// while the flag is set. Two threads making one name last at once take two places in
    /// the budget, which only lowers the bound.
    fn last_within(&self, budget: &AtomicUsize, bound: usize) {
        if self.lasting.load(Ordering::Relaxed) {
            return;
        }
        if budget.fetch_add(1, Ordering::Relaxed) >= bound {
            budget.fetch_sub(1, Ordering::Relaxed);
            return;
        }
        self.lasting.store(true, Ordering::Release);
    }

    /// Counts one more interning of a name found in the table (under its shard's lock, so the
    /// load and the store cannot interleave with another's), and makes it last at [`OFTEN`].
    fn interned_again(&self) {
        let times = self.interned.load(Ordering::Relaxed);
        if times < OFTEN && self.text.len() <= OFTEN_AT_MOST {
            self.interned.store(times + 1, Ordering::Relaxed);
            if times + 1 == OFTEN {
                self.last_within(&OFTEN_LASTING, MAX_OFTEN);
            }
        }
    }
}

impl Clone for Sym {
    fn clone(&self) -> Sym {
        Sym::held(self.0)
    }
}

impl Drop for Sym {
    fn drop(&mut self) {
        let name = self.name();
        if !name.lasting.load(Ordering::Relaxed) {
            // Release: this holder's uses happen before the sweep that frees the name. The
            // table holds one count of its own, so no drop here ever frees.
            name.holders.0.fetch_sub(1, Ordering::Release);
        }
    }
}

impl PartialEq for Sym {
    fn eq(&self, other: &Self) -> bool {
        self.0 == other.0
    }
}

impl Eq for Sym {}

impl PartialEq<str> for Sym {
    fn eq(&self, other: &str) -> bool {
        self.as_str() == other
    }
}

impl PartialEq<&str> for Sym {
    fn eq(&self, other: &&str) -> bool {
        self.as_str() == *other
    }
}

impl Hash for Sym {
    fn hash<H: Hasher>(&self, state: &mut H) {
        state.write_u64(self.name().hash);
    }
}

impl PartialOrd for Sym {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Sym {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        if self == other {
            return std::cmp::Ordering::Equal;
        }
        self.as_str().cmp(other.as_str())
    }
}

impl Deref for Sym {
    type Target = str;

    fn deref(&self) -> &str {
        self.as_str()
    }
}

impl AsRef<str> for Sym {
    fn as_ref(&self) -> &str {
        self.as_str()
    }
}

impl fmt::Display for Sym {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl fmt::Debug for Sym {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self.as_str(), f)
    }
}

impl From<&str> for Sym {
    fn from(text: &str) -> Sym {
        Sym::new(text)
    }
}

impl From<&String> for Sym {
    fn from(text: &String) -> Sym {
        Sym::new(text)
    }
}

impl From<String> for Sym {
    fn from(text: String) -> Sym {
        Sym::new(&text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Set in a child process started to spend the process-wide budgets.
    const SPEND_HERE: &str = "SCRUPLE_SYM_SPEND_BUDGETS_HERE";

    /// Whether the calling test, `test` (a test of this module that spends a process-wide budget
    /// of lasting names), may spend it in this process: only in a child process started for it.
    /// Anywhere else it runs `test` alone in such a child of this test binary, asserts that it
    /// passed, and answers false; so this process's budgets stay whole, and no test that makes a
    /// name last depends on running before the ones that spend them.
    fn spend_here(test: &str) -> bool {
        if std::env::var_os(SPEND_HERE).is_some() {
            return true;
        }
        let module = module_path!().split_once("::").map_or(module_path!(), |(_, m)| m);
        let path = format!("{module}::{test}");
        let output = std::process::Command::new(std::env::current_exe().expect("the test binary"))
            .args([path.as_str(), "--exact", "--test-threads=1"])
            .env(SPEND_HERE, "1")
            .stdin(std::process::Stdio::null())
            .output()
            .expect("the test binary runs again");
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert!(
            output.status.success() && stdout.contains("test result: ok. 1 passed"),
            "{path} in a child process: {}\n{stdout}\n{}",
            output.status,
            String::from_utf8_lossy(&output.stderr)
        );
        false
    }

    /// The tests that spend the budgets, run here first, leave them whole: a name made lasting
    /// after them, or interned often, still lasts.
    #[test]
    fn the_tests_that_spend_the_budgets_leave_this_process_budgets_whole() {
        a_name_interned_often_lasts_unless_it_is_long_or_the_budget_is_spent();
        past_the_bound_a_name_made_lasting_is_counted_and_swept_as_any_other();
        assert!(LASTING.load(Ordering::Relaxed) < MAX_LASTING);
        assert!(OFTEN_LASTING.load(Ordering::Relaxed) < MAX_OFTEN);
        let verb = Sym::new("made-lasting-after-the-budget-tests");
        verb.make_lasting();
        assert!(verb.name().lasting.load(Ordering::Relaxed));
        assert!(interned_often("interned-often-after-the-budget-tests"));
    }

    #[test]
    fn one_text_is_one_symbol_and_order_is_by_text() {
        let (a, b) = (Sym::new("vase"), Sym::from(String::from("vase")));
        assert_eq!(a.0, b.0);
        assert_eq!(a, b);
        assert_ne!(a, Sym::new("vase2"));
        assert_eq!(FxBuildHasher.hash_one(&a), FxBuildHasher.hash_one(&b));
        let mut names = [Sym::new("b"), Sym::new("a"), Sym::new("ab"), Sym::new("")];
        names.sort();
        let texts: Vec<&str> = names.iter().map(Sym::as_str).collect();
        assert_eq!(texts, ["", "a", "ab", "b"]);
        assert_eq!(a.to_string(), "vase");
        assert_eq!(format!("{a:?}"), "\"vase\"");
    }

    #[test]
    fn threads_interning_one_text_at_once_get_one_symbol() {
        // Each thread interns the same texts while dropping transient ones (so sweeps run
        // meanwhile); every thread must end up with the very same allocation per text.
        let texts: Vec<String> = (0..64).map(|i| format!("shared-{i}")).collect();
        let per_thread: Vec<Vec<Sym>> = std::thread::scope(|scope| {
            let handles: Vec<_> = (0..4)
                .map(|t| {
                    let texts = &texts;
                    scope.spawn(move || {
                        let mut held = Vec::new();
                        for (i, text) in texts.iter().enumerate() {
                            for j in 0..200 {
                                drop(Sym::new(&format!("churn-{t}-{i}-{j}")));
                            }
                            held.push(Sym::new(text));
                        }
                        held
                    })
                })
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        for syms in &per_thread[1..] {
            for (a, b) in per_thread[0].iter().zip(syms) {
                assert_eq!(a.0, b.0, "{a} was interned twice");
            }
        }
    }

    #[test]
    fn names_nobody_holds_are_swept_and_held_ones_survive() {
        let held = Sym::new("held-across-sweeps");
        // Far more unique names than any shard's floor, each dropped at once, as a stream of
        // requests naming new objects would.
        for i in 0..200_000 {
            drop(Sym::new(&format!("transient-{i}")));
        }
        // Other tests hold names meanwhile: the bound is about twice those, plus the floors.
        let (mut total, mut live) = (0, 0);
        for shard in TABLE.iter() {
            let shard = shard.lock().unwrap();
            total += shard.names.len();
            live += shard.names.iter().filter(|e| !e.is_garbage()).count();
        }
        assert!(
            total <= 2 * live + SHARDS * FLOOR,
            "the table kept {total} names, {live} alive"
        );
        let again = Sym::new("held-across-sweeps");
        assert_eq!(held.0, again.0);
    }

    #[test]
    fn a_thread_finds_the_lasting_names_it_met_and_only_those() {
        let verb = Sym::new("a-verb-found-near");
        let hash = FxBuildHasher.hash_one("a-verb-found-near");
        assert_eq!(near(hash, "a-verb-found-near"), None, "not lasting yet");
        drop(Sym::new("a-verb-found-near"));
        assert_eq!(
            near(hash, "a-verb-found-near"),
            None,
            "a counted name is never kept near"
        );
        verb.make_lasting();
        let met = Sym::new("a-verb-found-near");
        assert_eq!(near(hash, "a-verb-found-near"), Some(verb.0));
        let again = Sym::new("a-verb-found-near");
        assert_eq!((met.0, again.0), (verb.0, verb.0));
        // Another text of the same hash is not that name.
        assert_eq!(near(hash, "another text"), None);
        // Another thread has not met it.
        std::thread::spawn(move || assert_eq!(near(hash, "a-verb-found-near"), None))
            .join()
            .unwrap();
    }

    #[test]
    fn a_lasting_name_outlives_its_holders_and_is_still_one_symbol() {
        let verb = Sym::new("a-verb-that-lasts");
        verb.make_lasting();
        let address = verb.0;
        let copies: Vec<Sym> = (0..1000).map(|_| verb.clone()).collect();
        drop((verb, copies));
        // Sweeps run while nobody holds it.
        for i in 0..100_000 {
            drop(Sym::new(&format!("swept-{i}")));
        }
        let again = Sym::new("a-verb-that-lasts");
        assert_eq!(again.0, address);
        assert_eq!(again, again.clone());
        assert_eq!(again.as_str(), "a-verb-that-lasts");
    }

    #[test]
    fn a_name_made_lasting_while_other_threads_count_it_is_never_freed() {
        // Threads clone and drop a name while it is made lasting under them; sweeps run beside.
        let name = Sym::new("lasting-under-load");
        std::thread::scope(|scope| {
            for t in 0..3 {
                let name = name.clone();
                scope.spawn(move || {
                    for i in 0..20_000 {
                        let copy = name.clone();
                        if i % 50 == 0 {
                            drop(Sym::new(&format!("churn-lasting-{t}-{i}")));
                        }
                        assert_eq!(copy.as_str(), "lasting-under-load");
                    }
                });
            }
            name.make_lasting();
        });
        drop(name);
        for i in 0..50_000 {
            drop(Sym::new(&format!("after-lasting-{i}")));
        }
        assert_eq!(Sym::new("lasting-under-load").as_str(), "lasting-under-load");
    }

    /// Interns `text` [`OFTEN`] times while one symbol of it is held (so no sweep can take it
    /// in between), and says whether it lasts.
    fn interned_often(text: &str) -> bool {
        let held = Sym::new(text);
        for _ in 1..OFTEN {
            drop(Sym::new(text));
        }
        held.name().lasting.load(Ordering::Relaxed)
    }

    #[test]
    fn a_name_interned_often_lasts_unless_it_is_long_or_the_budget_is_spent() {
        if !spend_here("a_name_interned_often_lasts_unless_it_is_long_or_the_budget_is_spent") {
            return;
        }
        let common = Sym::new("interned-often");
        for _ in 2..OFTEN {
            drop(Sym::new("interned-often"));
        }
        assert!(!common.name().lasting.load(Ordering::Relaxed), "lasts too early");
        drop(Sym::new("interned-often"));
        assert!(common.name().lasting.load(Ordering::Relaxed));
        let address = common.0;
        drop(common);
        for i in 0..100_000 {
            drop(Sym::new(&format!("sweeping-the-often-one-{i}")));
        }
        assert_eq!(Sym::new("interned-often").0, address, "a lasting name was swept");

        let long = "l".repeat(OFTEN_AT_MOST + 1);
        assert!(!interned_often(&long), "a long name lasts");
        assert!(interned_often(&"s".repeat(OFTEN_AT_MOST)));

        // Spend the budget (in a process of its own: see `spend_here`), then one more.
        let mut filler = 0;
        while OFTEN_LASTING.load(Ordering::Relaxed) < MAX_OFTEN {
            interned_often(&format!("often-filler-{filler}"));
            filler += 1;
        }
        assert!(!interned_often("interned-often-too-late"));
        assert!(swept_away("interned-often-too-late"), "a name past the budget was kept");
    }

    /// Whether `text`, which nobody holds, is gone from the table once enough new names have
    /// come that every shard, lasting names and all, doubles and is swept.
    fn swept_away(text: &str) -> bool {
        for i in 0..400_000 {
            drop(Sym::new(&format!("sweeping-{text}-{i}")));
        }
        !shard_of(FxBuildHasher.hash_one(text))
            .lock()
            .unwrap()
            .names
            .contains(text)
    }

    #[test]
    fn past_the_bound_a_name_made_lasting_is_counted_and_swept_as_any_other() {
        if !spend_here("past_the_bound_a_name_made_lasting_is_counted_and_swept_as_any_other") {
            return;
        }
        // Fill the lasting budget (in a process of its own: see `spend_here`), then one more.
        let mut filler = 0;
        while LASTING.load(Ordering::Relaxed) < MAX_LASTING {
            Sym::new(&format!("lasting-filler-{filler}")).make_lasting();
            filler += 1;
        }
        let late = Sym::new("made-lasting-too-late");
        late.make_lasting();
        assert!(!late.name().lasting.load(Ordering::Relaxed));
        drop(late);
        assert!(swept_away("made-lasting-too-late"), "a name past the bound was kept");
    }
}
