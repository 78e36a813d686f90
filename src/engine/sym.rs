//! Interned symbols: the names of constants, variables and functors, one allocation per text.
//!
//! Owns: the process-wide table of names and its bound. Must not: keep a name nobody holds past
//! the next sweep (names come from requests), or order anything by address (order is by text).

use std::borrow::Borrow;
use std::collections::HashSet;
use std::fmt;
use std::hash::{BuildHasher, Hash, Hasher};
use std::ops::Deref;
use std::sync::{Arc, LazyLock, Mutex};

use rustc_hash::FxBuildHasher;

/// A symbol. Every symbol of one text is the same allocation, so equality is one address
/// comparison and hashing writes one precomputed word; order and printing go by the text.
#[derive(Clone)]
pub struct Sym(Arc<Name>);

struct Name {
    /// FxHash of the text: the same in every process and run, so hash-keyed output stays
    /// deterministic.
    hash: u64,
    text: Box<str>,
}

/// The table holds a name as long as a symbol does; a name only the table holds is garbage,
/// swept once a shard has doubled since its last sweep, so the table stays within about twice
/// the names alive (plus `FLOOR` per shard) however many requests have come and gone.
const SHARDS: usize = 16;
const FLOOR: usize = 256;

struct Shard {
    names: HashSet<Entry, FxBuildHasher>,
    /// How many names the last sweep kept.
    kept: usize,
}

/// A table entry, found by its text.
struct Entry(Arc<Name>);

impl Hash for Entry {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.0.text.hash(state);
    }
}

impl PartialEq for Entry {
    fn eq(&self, other: &Self) -> bool {
        self.0.text == other.0.text
    }
}

impl Eq for Entry {}

impl Borrow<str> for Entry {
    fn borrow(&self) -> &str {
        &self.0.text
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

impl Sym {
    pub fn new(text: &str) -> Sym {
        let hash = FxBuildHasher.hash_one(text);
        let shard = &TABLE[(hash >> 60) as usize % SHARDS];
        // A poisoned shard still holds a consistent set: no code that can panic runs under it.
        let mut shard = shard.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some(entry) = shard.names.get(text) {
            return Sym(entry.0.clone());
        }
        if shard.names.len() >= (2 * shard.kept).max(FLOOR) {
            // Only the table holds a name whose count is 1, and only the table (under this
            // lock) can hand it out again: dropping it here races with nobody.
            shard.names.retain(|entry| Arc::strong_count(&entry.0) > 1);
            shard.kept = shard.names.len();
        }
        let name = Arc::new(Name {
            hash,
            text: text.into(),
        });
        shard.names.insert(Entry(name.clone()));
        Sym(name)
    }

    pub fn as_str(&self) -> &str {
        &self.0.text
    }
}

impl PartialEq for Sym {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
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
        state.write_u64(self.0.hash);
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

    #[test]
    fn one_text_is_one_symbol_and_order_is_by_text() {
        let (a, b) = (Sym::new("vase"), Sym::from(String::from("vase")));
        assert!(Arc::ptr_eq(&a.0, &b.0));
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
                assert!(Arc::ptr_eq(&a.0, &b.0), "{a} was interned twice");
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
            live += shard.names.iter().filter(|e| Arc::strong_count(&e.0) > 1).count();
        }
        assert!(
            total <= 2 * live + SHARDS * FLOOR,
            "the table kept {total} names, {live} alive"
        );
        let again = Sym::new("held-across-sweeps");
        assert!(Arc::ptr_eq(&held.0, &again.0));
    }
}
