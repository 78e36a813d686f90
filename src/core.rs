//! The one internal API every transport calls: norms in and out of the store, and decisions made
//! under the current norm set.
//!
//! Owns: the caches of compiled norms and of the action library (each refreshed only when its
//! stored version moves) and failing closed when either cannot be read. Must not: parse wire formats or know which transport asked.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, RwLock};
use std::time::{Duration, Instant};

use crate::engine::Library;
use crate::engine::action::{ActionDef, ActionInput};
use crate::engine::check::{Check, check};
use crate::engine::clarify::clarify;
use crate::engine::clarify::{Directive, Request};
use crate::engine::decision::Decision;
use crate::engine::decision::Style;
use crate::engine::norms::{CompiledNorms, MAX_NORM_ID, Norm, NormInput, NormSpec, Scope};
use crate::engine::resolve::Reference;
use crate::engine::scene::Scene;
use crate::engine::term::Term;
use crate::error::Error;
use crate::metrics::{Cache, DecisionLabels, Metrics, Outcome};
use crate::storage::{AuditEntry, NormStore, StoredAction, Write};

/// A clarify request as core takes it: engine values, valid (the wire layer builds them and
/// reports every fault with its field), and how long the answer may take.
#[derive(Debug)]
pub struct ClarifyInput {
    pub request: Request,
    pub scene: Scene,
    /// The human's words, echoed back for logs.
    pub text: Option<String>,
    /// How long the decision may take.
    pub deadline: std::time::Duration,
}

impl ClarifyInput {
    /// The verb the directive names and its arity (a form's action), for its expansion cost.
    pub fn verb(&self) -> (&str, usize) {
        match &self.request.directive {
            Directive::Action { verb, arguments } => (verb, arguments.len()),
            Directive::Form { action, .. } => (action.name().map_or("", |n| &**n), action.arity()),
        }
    }

    /// An upper bound on the readings this request can have, from its arguments' possible
    /// candidates (every object for a reference, the bindings for a variable), before resolving.
    pub fn at_most_readings(&self) -> u128 {
        let objects = self.scene.objects.len() as u128;
        match &self.request.directive {
            Directive::Action { arguments, .. } => arguments.iter().fold(1u128, |n, a| {
                n.saturating_mul(if matches!(a, Reference::Id(_)) { 1 } else { objects })
            }),
            Directive::Form { bindings, .. } => bindings
                .iter()
                .fold(1u128, |n, (_, c)| n.saturating_mul(c.len() as u128)),
        }
    }
}

/// A check request as core takes it, likewise.
#[derive(Debug)]
pub struct CheckInput {
    pub scene: Scene,
    pub steps: Vec<Term>,
    pub context: String,
    pub speaker_roles: Vec<String>,
    pub style: Style,
    /// How long the check may take, from the request's arrival.
    pub deadline: std::time::Duration,
}

/// Requests that may cost at most this many simulated steps (readings × the verb's expansion)
/// are decided on the calling task (see `clarify`); the rest go to the blocking pool, so a
/// costly one never holds a runtime thread that health checks need.
const INLINE_STEPS: u128 = 32;

/// Set when the request's future is dropped (its client went away): the decision it started
/// stops at its next step instead of keeping a core busy for nobody.
struct CancelOnDrop(Arc<AtomicBool>);

impl Drop for CancelOnDrop {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
    }
}

/// Counts a simulation in `simulations_in_flight` while it runs.
struct InFlight<'a>(&'a Metrics);

impl<'a> InFlight<'a> {
    fn new(metrics: &'a Metrics) -> Self {
        metrics.in_flight.inc();
        InFlight(metrics)
    }
}

impl Drop for InFlight<'_> {
    fn drop(&mut self) {
        self.0.in_flight.dec();
    }
}

/// What ends a decision early: its deadline, or its client leaving. The guard must live as long
/// as the request's future.
fn stop_signal(deadline: Instant) -> (CancelOnDrop, impl Fn() -> bool + Send + Sync + 'static) {
    let cancelled = Arc::new(AtomicBool::new(false));
    let flag = cancelled.clone();
    let expired = move || flag.load(Ordering::Relaxed) || Instant::now() >= deadline;
    (CancelOnDrop(cancelled), expired)
}

/// Longest wait for a turn at a costly simulation before the request is refused as overload.
const COSTLY_WAIT: Duration = Duration::from_millis(100);

/// How far past a request's deadline it may wait for the norms and verbs before it is overload.
const KNOWLEDGE_GRACE: Duration = Duration::from_millis(100);

/// How long the last read of the knowledge may stand for readiness; past it, readiness says the
/// store has stopped answering (a probe refreshes it every second when no request does).
const READINESS_STALE: Duration = Duration::from_secs(10);

/// The outcome of the last read of what a decision needs, and when it ended.
struct Readiness {
    at: Instant,
    outcome: Result<(), String>,
}

pub struct Core {
    store: Arc<dyn NormStore>,
    metrics: Arc<Metrics>,
    /// What readiness reports: never a read of its own, so a probe answers at once under load.
    readiness: std::sync::Mutex<Option<Readiness>>,
    /// Turns for costly simulations (see `costly_turn`): one per core.
    costly: Arc<tokio::sync::Semaphore>,
    /// The last norm set compiled, tagged with the store version it was compiled from.
    compiled: RwLock<Option<Arc<CompiledNorms>>>,
    /// The last action library loaded, likewise tagged.
    library: RwLock<Option<Arc<Library>>>,
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
    pub fn new(store: Arc<dyn NormStore>, metrics: Arc<Metrics>) -> Core {
        Core {
            store,
            metrics,
            compiled: RwLock::new(None),
            library: RwLock::new(None),
            readiness: std::sync::Mutex::new(None),
            costly: Arc::new(tokio::sync::Semaphore::new(
                std::thread::available_parallelism().map_or(2, usize::from),
            )),
        }
    }

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
            let _ = self.knowledge_for(None).await;
        }
    }

    fn note_readiness(&self, outcome: &Result<(Arc<CompiledNorms>, Arc<Library>), Error>) {
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

    /// The norms and the verbs in force now: one versions read per call; a reload only of what
    /// another write (from this process or any other sharing the store) has changed.
    async fn knowledge(&self) -> Result<(Arc<CompiledNorms>, Arc<Library>), Error> {
        self.knowledge_for(Some(&self.metrics)).await
    }

    /// The knowledge, if it can be had before `deadline`; a store too busy to answer by then is
    /// overload (503 with Retry-After), so a decision is never answered late for want of it.
    async fn knowledge_by(&self, deadline: Instant) -> Result<(Arc<CompiledNorms>, Arc<Library>), Error> {
        // A little past the deadline, so that a request whose deadline is (nearly) spent still
        // gets its answer with `limits` when the store is quick, as it is unless overloaded.
        tokio::time::timeout_at((deadline + KNOWLEDGE_GRACE).into(), self.knowledge())
            .await
            .unwrap_or(Err(Error::Overloaded { retry_after_s: 1 }))
    }

    /// `metrics`: where a request's cache hits and refreshes are counted (a probe's are not).
    async fn knowledge_for(&self, metrics: Option<&Metrics>) -> Result<(Arc<CompiledNorms>, Arc<Library>), Error> {
        let outcome = self.read_knowledge(metrics).await;
        self.note_readiness(&outcome);
        outcome
    }

    async fn read_knowledge(&self, metrics: Option<&Metrics>) -> Result<(Arc<CompiledNorms>, Arc<Library>), Error> {
        let count = |cache, outcome| {
            if let Some(m) = metrics {
                m.cache(cache, outcome);
            }
        };
        // Waiting for a connection is overload, never "norms unavailable".
        let unavailable = |e: crate::storage::StoreError| e.answer(Error::NormsUnavailable);
        let versions = self.store.versions().await.map_err(unavailable)?;
        let norms = match cached(&self.compiled, versions.norms, |c| c.version)? {
            Some(norms) => {
                count(Cache::Norms, Outcome::Hit);
                norms
            }
            None => {
                count(Cache::Norms, Outcome::Refresh);
                let (version, norms) = self.store.load().await.map_err(unavailable)?;
                let fresh = Arc::new(CompiledNorms::compile(version, norms));
                keep_newer(&self.compiled, &fresh, |c| c.version)?;
                fresh
            }
        };
        let library = match cached(&self.library, versions.actions, |l| l.version)? {
            Some(library) => {
                count(Cache::Library, Outcome::Hit);
                library
            }
            None => {
                count(Cache::Library, Outcome::Refresh);
                let (version, verbs) = self.store.load_actions().await.map_err(unavailable)?;
                let fresh = Library::from_written(version, &verbs).map_err(|(name, e)| {
                    Error::NormsUnavailable(format!("the stored verb `{name}` is invalid: {e}"))
                })?;
                let fresh = Arc::new(fresh);
                keep_newer(&self.library, &fresh, |l| l.version)?;
                fresh
            }
        };
        Ok((norms, library))
    }

    /// Decides what to say about a directive. Fails closed: without readable norms, no decision.
    /// The engine runs on the blocking pool, so a large request does not stall other requests;
    /// its deadline counts from here.
    pub async fn clarify(&self, input: ClarifyInput, arrived: Instant) -> Result<Decision, Error> {
        let deadline = arrived + input.deadline;
        let (_guard, expired) = stop_signal(deadline);
        let (norms, library) = self.knowledge_by(deadline).await?;
        let (verb, arity) = input.verb();
        let steps = input
            .at_most_readings()
            .saturating_mul(u128::from(library.expansion(verb, arity)));
        let small = steps <= INLINE_STEPS;
        let turn = if small {
            None
        } else {
            Some(self.costly_turn(deadline).await?)
        };
        let metrics = self.metrics.clone();
        let decide = move || {
            let _turn = turn;
            let _running = InFlight::new(&metrics);
            clarify(&input.request, &input.scene, &norms, &library, &expired)
        };
        // A small request (most are) is decided in microseconds: handing it to another thread
        // would cost more than the decision. Large ones go to the blocking pool.
        let decision = if small {
            decide()?
        } else {
            tokio::task::spawn_blocking(decide)
                .await
                .map_err(|e| Error::Internal(format!("the decision task failed: {e}")))??
        };
        let kind = DecisionLabels {
            kind: decision.kind.as_str().to_owned(),
        };
        self.metrics.decisions.get_or_create(&kind).inc();
        self.metrics.readings.observe(decision.interpretations.len() as f64);
        Ok(decision)
    }

    /// A turn to run a costly simulation: at most one per core at once, so that each finishes
    /// within its deadline rather than all of them late. A request that gets no turn within
    /// [`COSTLY_WAIT`] (nor before its deadline) is overload: 503 with Retry-After at once,
    /// never an answer long after the robot stopped waiting.
    async fn costly_turn(&self, deadline: Instant) -> Result<tokio::sync::OwnedSemaphorePermit, Error> {
        let until = (Instant::now() + COSTLY_WAIT).min(deadline);
        match tokio::time::timeout_at(until.into(), self.costly.clone().acquire_owned()).await {
            Ok(Ok(permit)) => Ok(permit),
            Ok(Err(_)) | Err(_) => {
                self.metrics.overloaded.inc();
                Err(Error::Overloaded { retry_after_s: 1 })
            }
        }
    }

    /// Checks steps while acting, under the norms in force now. Fails closed like `clarify`.
    pub async fn check(&self, input: CheckInput, arrived: Instant) -> Result<Check, Error> {
        let deadline = arrived + input.deadline;
        let (_guard, expired) = stop_signal(deadline);
        let (norms, library) = self.knowledge_by(deadline).await?;
        let steps: u128 = (input.steps.iter())
            .map(|s| u128::from(library.expansion(s.name().map_or("", |n| &**n), s.arity())))
            .sum();
        let turn = if steps <= INLINE_STEPS {
            None
        } else {
            Some(self.costly_turn(deadline).await?)
        };
        let metrics = self.metrics.clone();
        tokio::task::spawn_blocking(move || {
            let _turn = turn;
            let _running = InFlight::new(&metrics);
            let scope = Scope {
                context: &input.context,
                roles: &input.speaker_roles,
            };
            check(
                &input.steps,
                &input.scene,
                &norms,
                &library,
                scope,
                input.style,
                &expired,
            )
        })
        .await
        .map_err(|e| Error::Internal(format!("the check task failed: {e}")))
    }

    /// Validates and stores a norm; nothing is written unless every field is valid.
    pub async fn create_norm(&self, input: NormInput, actor: &str) -> Result<Norm, Error> {
        let spec = input.validate().map_err(|e| Error::invalid(e.field, e.message))?;
        Ok(self.store.create(&spec, actor).await?)
    }

    pub async fn list_norms(&self) -> Result<Vec<Norm>, Error> {
        Ok(self.store.load().await?.1)
    }

    pub async fn get_norm(&self, id: i64) -> Result<Norm, Error> {
        self.store.get(id).await?.ok_or_else(|| not_found(id))
    }

    /// Replaces a norm's content (its id stays) when `expected` is its revision, or always
    /// without one; nothing is written unless every field is valid and the revision matches.
    pub async fn replace_norm(
        &self,
        id: i64,
        input: NormInput,
        expected: Option<i64>,
        actor: &str,
    ) -> Result<Norm, Error> {
        let spec = input.validate().map_err(|e| Error::invalid(e.field, e.message))?;
        written(id, expected, self.store.replace(id, &spec, expected, actor).await?)
    }

    pub async fn delete_norm(&self, id: i64, expected: Option<i64>, actor: &str) -> Result<(), Error> {
        written(id, expected, self.store.delete(id, expected, actor).await?)
    }

    /// The whole norm set and its version, for backups and review.
    pub async fn export_norms(&self) -> Result<(i64, Vec<Norm>), Error> {
        Ok(self.store.load().await?)
    }

    /// Replaces the whole norm set in one transaction when `expected` is the set's version (or
    /// always without one). Every norm is validated first (errors point into `/norms/i`); ids
    /// given are kept (a restored backup keeps its ids) and must be distinct and positive; norms
    /// without one get fresh ids, never used before.
    pub async fn import_norms(
        &self,
        inputs: Vec<(Option<i64>, NormInput)>,
        expected: Option<i64>,
        actor: &str,
    ) -> Result<(i64, Vec<Norm>), Error> {
        let norms = validate_norm_set(inputs)?;
        match self.store.import(&norms, expected, actor).await? {
            Write::Done(set) => Ok(set),
            Write::Missing => Err(Error::Internal("the norm set row is missing".to_owned())),
            Write::Stale { current } => Err(Error::Stale {
                what: "the norm set".to_owned(),
                expected: expected.map_or_else(|| "*".to_owned(), |e| e.to_string()),
                current,
            }),
        }
    }

    /// Up to `limit` audit entries after entry `after`, oldest first.
    pub async fn audit(&self, after: i64, limit: i64) -> Result<Vec<AuditEntry>, Error> {
        Ok(self.store.audit(after, limit).await?)
    }

    /// Every verb, by name, as written.
    pub async fn list_actions(&self) -> Result<Vec<ActionInput>, Error> {
        let (_, library) = self.knowledge().await?;
        Ok(library.verbs().into_iter().map(ActionDef::to_input).collect())
    }

    pub async fn get_action(&self, name: &str) -> Result<ActionInput, Error> {
        let (_, library) = self.knowledge().await?;
        library
            .verbs()
            .into_iter()
            .find(|d| &*d.name == name)
            .map(ActionDef::to_input)
            .ok_or_else(|| Error::NotFound {
                what: format!("verb `{name}`"),
            })
    }

    /// Adds or replaces a verb; returns it as stored and whether it is new. Nothing is written
    /// unless the verb is valid and the library it makes has no loop through its steps.
    pub async fn put_action(&self, name: &str, input: ActionInput, actor: &str) -> Result<(ActionInput, bool), Error> {
        let def = input.validate(name).map_err(|e| Error::invalid(e.field, e.message))?;
        let written = def.to_input();
        let this = name.to_owned();
        let accept = move |all: &[StoredAction]| {
            // The expansion bound holds for what is written from now on; a library stored before
            // it still loads, and the deadline bounds its cost.
            Library::from_written(0, all)
                .and_then(|library| library.check_expansion(&this))
                .map_err(|(verb, e)| {
                    let field = if verb == this { e.field } else { "/methods".to_owned() };
                    Error::invalid(field, format!("{}: {}", verb, e.message))
                })
        };
        let created = self.store.put_action(name, &written, &accept, actor).await??;
        Ok((written, created))
    }

    pub async fn delete_action(&self, name: &str, actor: &str) -> Result<(), Error> {
        if self.store.delete_action(name, actor).await? {
            Ok(())
        } else {
            Err(Error::NotFound {
                what: format!("verb `{name}`"),
            })
        }
    }
}

/// Validates a whole norm set as an import takes it: ids given must be distinct and positive
/// (errors point into `/norms/i`), and every norm valid; nothing is half-accepted.
pub fn validate_norm_set(inputs: Vec<(Option<i64>, NormInput)>) -> Result<Vec<(Option<i64>, NormSpec)>, Error> {
    let mut given: Vec<i64> = Vec::with_capacity(inputs.len());
    for (i, (id, _)) in inputs.iter().enumerate() {
        if let Some(id) = *id {
            if !(1..=MAX_NORM_ID).contains(&id) {
                return Err(Error::invalid(
                    format!("/norms/{i}/id"),
                    format!("a norm id is an integer from 1 to {MAX_NORM_ID} (2^53 − 1)"),
                ));
            }
            if given.contains(&id) {
                return Err(Error::invalid(
                    format!("/norms/{i}/id"),
                    format!("id {id} is given twice"),
                ));
            }
            given.push(id);
        }
    }
    let mut norms = Vec::with_capacity(inputs.len());
    for (i, (id, input)) in inputs.into_iter().enumerate() {
        let spec = input
            .validate()
            .map_err(|e| Error::invalid(format!("/norms/{i}{}", e.field), e.message))?;
        norms.push((id, spec));
    }
    Ok(norms)
}

/// How a conditional write on norm `id` ends for the caller.
fn written<T>(id: i64, expected: Option<i64>, write: Write<T>) -> Result<T, Error> {
    match write {
        Write::Done(value) => Ok(value),
        Write::Missing => Err(not_found(id)),
        Write::Stale { current } => Err(Error::Stale {
            what: format!("norm {id}"),
            expected: expected.map_or_else(|| "*".to_owned(), |e| e.to_string()),
            current,
        }),
    }
}

fn not_found(id: i64) -> Error {
    Error::NotFound {
        what: format!("norm {id}"),
    }
}

fn poisoned() -> Error {
    Error::Internal("the norm cache lock is poisoned".to_owned())
}
