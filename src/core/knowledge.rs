//! What a decision is made under, and how current it is: the store's norms and verbs, compiled
//! and cached by version, trusted for a lease between reads of the stored versions; writes wait
//! out the longest lease of any process serving the store before they are acknowledged;
//! readiness is the outcome of the last read.
//!
//! Must not: decide, or answer a write before every process's lease taken before it has run out.

use std::sync::{Arc, RwLock};
use std::time::{Duration, Instant};

use super::{Core, poisoned};
use crate::engine::Library;
use crate::engine::norms::CompiledNorms;
use crate::error::Error;
use crate::metrics::{Cache, Metrics, Outcome};
use crate::storage::{NormStore, Write};

/// Default for `--versions-lease-ms`: the stored versions are read again by the first request
/// past three quarters of the lease, so at most about 27 times a second per process, and a
/// write is acknowledged 56 ms (the lease and [`lease_margin`]) after it commits.
pub const DEFAULT_LEASE_MS: u64 = 50;
/// The longest lease `--versions-lease-ms` takes: every write waits this long.
pub const MAX_LEASE_MS: u64 = 10_000;

/// How much longer than the lease a write waits: a tenth of it and a millisecond, for monotonic
/// clocks that run at different rates on different machines (far less than a tenth, in
/// practice) and a timer that fires late (never early).
pub fn lease_margin(lease: Duration) -> Duration {
    lease / 10 + Duration::from_millis(1)
}

/// What decisions are made under: one compiled norm set and one action library.
#[derive(Clone, Debug)]
pub struct Knowledge {
    pub norms: Arc<CompiledNorms>,
    pub library: Arc<Library>,
}

/// Whether a read of the knowledge may be spared by a lease that holds (a request's) or must be
/// made (a readiness probe's, which is about the store itself).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Read {
    UnlessLeased,
    Always,
}

/// Where a core's norms and verbs come from.
pub(super) enum Source {
    /// The store, re-read whenever its stored versions move (by any process sharing it).
    Store(Arc<dyn NormStore>),
    /// Fixed for the core's life: the offline CLI's, from a store read once or from files.
    Fixed(Knowledge),
}

/// How far past a request's deadline it may wait for the norms and verbs before it is overload.
const KNOWLEDGE_GRACE: Duration = Duration::from_millis(100);

/// The share of the lease after which the versions are read again ahead of its end.
const AHEAD: f64 = 0.75;

/// The knowledge under a lease that holds now, and whether the lease is past [`AHEAD`] of its
/// time, so due to be read again ahead of its end.
struct Hit {
    knowledge: Knowledge,
    due: bool,
    /// Whether answering with it is a lookup the metrics count (a lease's is; fixed knowledge
    /// is none).
    counted: bool,
}

impl Hit {
    /// Counts the lookup of a request answered with this hit: one per cache, as every request
    /// answered with knowledge counts exactly one outcome per cache.
    fn answer(self, metrics: Option<&Metrics>) -> Knowledge {
        if let (true, Some(m)) = (self.counted, metrics) {
            m.cache(Cache::Norms, Outcome::Hit);
            m.cache(Cache::Library, Outcome::Hit);
        }
        self.knowledge
    }
}

/// How long the last read of the knowledge may stand for readiness; past it, readiness says the
/// store has stopped answering (a probe refreshes it every second when no request does).
const READINESS_STALE: Duration = Duration::from_secs(10);

/// The knowledge read under one lease: trusted by every request that starts before `from` +
/// the lease, because every write acknowledged before such a request committed before `from`
/// (the writer waited the lease out) and so is in what was read.
pub(super) struct Leased {
    /// Taken before the versions were asked for, so the read saw every commit before it.
    from: Instant,
    knowledge: Knowledge,
}

/// The outcome of the last read of what a decision needs, and when it ended.
pub(super) struct Readiness {
    at: Instant,
    outcome: Result<(), String>,
}

/// Keeps the newer of two values refreshed concurrently.
fn keep_newer<T>(slot: &RwLock<Option<Arc<T>>>, fresh: &Arc<T>, version: impl Fn(&T) -> i64) -> Result<(), Error> {
    let mut slot = slot.write().map_err(|_| poisoned())?;
    if slot.as_ref().is_none_or(|c| version(c) <= version(fresh)) {
        *slot = Some(fresh.clone());
    }
    Ok(())
}

fn cached<T>(slot: &RwLock<Option<Arc<T>>>, version: i64, of: impl Fn(&T) -> i64) -> Result<Option<Arc<T>>, Error> {
    Ok(slot
        .read()
        .map_err(|_| poisoned())?
        .as_ref()
        .filter(|c| of(c) == version)
        .cloned())
}

impl Core {
    /// Whether a decision can be made now: the outcome of the last read of the norms and verbs
    /// (by a request, or by [`Core::probe`]), without reading anything itself.
    pub fn readiness(&self) -> Result<(), Error> {
        let last = self.readiness.lock().map_err(|_| poisoned())?;
        match &*last {
            None => Err(Error::NormsUnavailable("the norms have not been read yet".to_owned())),
            Some(r) if r.at.elapsed() > READINESS_STALE => Err(Error::NormsUnavailable(format!(
                "the norm store has not answered for {} s",
                r.at.elapsed().as_secs()
            ))),
            Some(r) => r.outcome.clone().map_err(Error::NormsUnavailable),
        }
    }

    /// Reads the knowledge as a decision would, unless a request did within `max_age`: keeps
    /// readiness current when no request comes.
    pub async fn probe(&self, max_age: Duration) {
        let fresh = self
            .readiness
            .lock()
            .map(|last| last.as_ref().is_some_and(|r| r.at.elapsed() < max_age))
            .unwrap_or(false);
        if !fresh {
            let outcome = self.read_knowledge(None, Read::Always).await;
            self.note_readiness(&outcome);
        }
    }

    fn note_readiness(&self, outcome: &Result<Knowledge, Error>) {
        // A read that could not get a connection in time says nothing about the store.
        if matches!(outcome, Err(Error::Overloaded { .. })) {
            return;
        }
        if let Ok(mut last) = self.readiness.lock() {
            *last = Some(Readiness {
                at: Instant::now(),
                outcome: outcome.as_ref().map(|_| ()).map_err(|e| match e {
                    Error::NormsUnavailable(detail) => detail.clone(),
                    other => other.to_string(),
                }),
            });
        }
    }

    /// The norms and the verbs in force now: those of the lease while it holds, else one read of
    /// the stored versions; a reload only of what another write (from this process or any other
    /// sharing the store) has changed.
    pub async fn knowledge(&self) -> Result<Knowledge, Error> {
        self.knowledge_for(Some(&self.metrics)).await
    }

    /// The knowledge, if it can be had before `deadline`; a store too busy to answer by then is
    /// overload (503 with Retry-After), so a decision is never answered late for want of it.
    pub(super) async fn knowledge_by(&self, deadline: Instant) -> Result<Knowledge, Error> {
        // Under a lease nothing is awaited, so nothing can be late: no timer is set. The file
        // was checked here once; the read below does not check it again before it waits.
        let outcome = match self.leased() {
            Ok(Some(hit)) => return Ok(self.ahead(hit, deadline).await),
            // A little past the deadline, so that a request whose deadline is (nearly) spent
            // still gets its answer with `limits` when the store is quick, as it is unless
            // overloaded.
            Ok(None) => tokio::time::timeout_at(
                (deadline + KNOWLEDGE_GRACE).into(),
                self.read_knowledge(Some(&self.metrics), Read::UnlessLeased),
            )
            .await
            .unwrap_or(Err(Error::Overloaded { retry_after_s: 1 })),
            Err(e) => Err(e),
        };
        self.note_readiness(&outcome);
        outcome
    }

    /// Refresh ahead: once three quarters of the lease have run, the first request to see it
    /// reads the versions again (if no read is under way) while the others keep the lease, which
    /// still holds; so no request waits for the read when the lease runs out, unless the store
    /// is slower than a quarter of the lease. What this request answers with is the fresh read,
    /// or, if the read fails or is late, the lease it already had (it held when the request began).
    /// Either way the request counts one lookup a cache: the read's outcomes, or the lease's hit.
    async fn ahead(&self, hit: Hit, deadline: Instant) -> Knowledge {
        let metrics = Some(&*self.metrics);
        let Some(_only_reader) = hit.due.then(|| self.refreshing.try_lock().ok()).flatten() else {
            return hit.answer(metrics);
        };
        let read = self.read_locked(metrics, Read::Always);
        let outcome = tokio::time::timeout_at((deadline + KNOWLEDGE_GRACE).into(), read)
            .await
            .unwrap_or(Err(Error::Overloaded { retry_after_s: 1 }));
        self.note_readiness(&outcome);
        outcome.unwrap_or_else(|_| hit.answer(metrics))
    }

    /// `metrics`: where a request's cache hits and refreshes are counted (a probe's are not).
    /// Readiness is noted when the store is read or found wanting, not on every lease hit.
    async fn knowledge_for(&self, metrics: Option<&Metrics>) -> Result<Knowledge, Error> {
        let outcome = match self.leased() {
            Ok(Some(hit)) => return Ok(hit.answer(metrics)),
            Ok(None) => self.read_knowledge(metrics, Read::UnlessLeased).await,
            Err(e) => Err(e),
        };
        self.note_readiness(&outcome);
        outcome
    }

    /// The knowledge without a read, when it may be had so: fixed, or under a lease that holds
    /// now. The database file is checked on every call (a `poll` of the watch on its path, a
    /// `stat` after a change), so that a file deleted or replaced fails closed on the very next
    /// request, lease or not.
    fn leased(&self) -> Result<Option<Hit>, Error> {
        let store = match &self.source {
            Source::Fixed(knowledge) => {
                return Ok(Some(Hit {
                    knowledge: knowledge.clone(),
                    due: false,
                    counted: false,
                }));
            }
            Source::Store(store) => store,
        };
        store.still_there().map_err(|e| e.answer(Error::NormsUnavailable))?;
        self.lease_hit()
    }

    /// The knowledge of the lease, if it holds now; the file is not looked at. Counts nothing:
    /// whoever answers with it does ([`Hit::answer`]).
    fn lease_hit(&self) -> Result<Option<Hit>, Error> {
        let lease = self.lease.read().map_err(|_| poisoned())?;
        let Some((leased, age)) =
            (lease.as_ref().map(|l| (l, l.from.elapsed()))).filter(|(_, age)| *age < self.settings.lease)
        else {
            return Ok(None);
        };
        Ok(Some(Hit {
            knowledge: leased.knowledge.clone(),
            due: age >= self.settings.lease.mul_f64(AHEAD),
            counted: true,
        }))
    }

    async fn read_knowledge(&self, metrics: Option<&Metrics>, read: Read) -> Result<Knowledge, Error> {
        if let Source::Fixed(knowledge) = &self.source {
            return Ok(knowledge.clone());
        }
        // Without a lease every request reads for itself, as many at once as the pool allows.
        let _only_reader = match self.settings.lease.is_zero() {
            true => None,
            false => Some(self.refreshing.lock().await),
        };
        self.read_locked(metrics, read).await
    }

    /// [`Core::read_knowledge`] with the right to read taken (or not needed: no lease). Counts
    /// one outcome a cache when it answers with knowledge, none when it fails.
    async fn read_locked(&self, metrics: Option<&Metrics>, read: Read) -> Result<Knowledge, Error> {
        let store = match &self.source {
            Source::Fixed(knowledge) => return Ok(knowledge.clone()),
            Source::Store(store) => store,
        };
        if read == Read::UnlessLeased
            && let Some(hit) = self.lease_hit()?
        {
            // Read by the request this one waited for, after this one began (and looked at the
            // file: it has not been looked at since only by the time spent waiting here).
            return Ok(hit.answer(metrics));
        }
        // Waiting for a connection is overload, never "norms unavailable".
        let unavailable = |e: crate::storage::StoreError| e.answer(Error::NormsUnavailable);
        let from = Instant::now();
        let versions = store.versions().await.map_err(unavailable)?;
        let (norms, norms_outcome) = match cached(&self.compiled, versions.norms, |c| c.version)? {
            Some(norms) => (norms, Outcome::Hit),
            None => {
                let (version, norms) = store.load().await.map_err(unavailable)?;
                let fresh = Arc::new(CompiledNorms::compile(version, norms));
                keep_newer(&self.compiled, &fresh, |c| c.version)?;
                (fresh, Outcome::Refresh)
            }
        };
        let (library, library_outcome) = match cached(&self.library, versions.actions, |l| l.version)? {
            Some(library) => (library, Outcome::Hit),
            None => {
                let (version, verbs) = store.load_actions().await.map_err(unavailable)?;
                let fresh = Library::from_written(version, &verbs)
                    .and_then(|library| library.check_words("").map(|()| library))
                    .map_err(|(name, e)| {
                        Error::NormsUnavailable(format!("the stored verb `{name}` is invalid: {e}"))
                    })?;
                let fresh = Arc::new(fresh);
                keep_newer(&self.library, &fresh, |l| l.version)?;
                (fresh, Outcome::Refresh)
            }
        };
        if let Some(m) = metrics {
            m.cache(Cache::Norms, norms_outcome);
            m.cache(Cache::Library, library_outcome);
        }
        let knowledge = Knowledge { norms, library };
        if !self.settings.lease.is_zero() {
            *self.lease.write().map_err(|_| poisoned())? = Some(Leased {
                from,
                knowledge: knowledge.clone(),
            });
        }
        Ok(knowledge)
    }

    /// Answers a write that has committed once no process can still be trusting a lease taken
    /// before the commit: this one's is dropped at once, every other's runs out within the
    /// longest lease any process serving the store records (this one's among them), so any
    /// request that starts after the answer reads what was written, whichever process it
    /// reaches and whatever lease that process was started with.
    pub(super) async fn settled<T>(&self, written: T) -> T {
        if let Ok(mut lease) = self.lease.write() {
            *lease = None;
        }
        let longest = self.longest_lease().await;
        if !longest.is_zero() {
            tokio::time::sleep(longest + lease_margin(longest)).await;
        }
        written
    }

    /// The longest lease of any process serving the store, read after the commit: a process
    /// that recorded its lease before this read is counted, and one that records it later
    /// reads the versions for the first time after the commit. A record that cannot be read
    /// counts as the longest lease a process may have, so that the wait is never too short.
    async fn longest_lease(&self) -> Duration {
        let own = self.settings.lease;
        let Source::Store(store) = &self.source else { return own };
        match store.longest_lease().await {
            Ok(longest) => longest.max(own),
            Err(e) => {
                tracing::warn!(error = %e, "the leases recorded in the store cannot be read: the write waits the longest any process may have");
                own.max(Duration::from_millis(MAX_LEASE_MS))
            }
        }
    }

    /// [`Core::settled`] for a write that may not have happened: only one that did waits.
    pub(super) async fn settled_write<T>(&self, write: Write<T>) -> Write<T> {
        match write {
            Write::Done(value) => Write::Done(self.settled(value).await),
            not_written => not_written,
        }
    }
}
