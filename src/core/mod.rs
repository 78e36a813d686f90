//! The one internal API every transport calls: norms in and out of the store, and decisions made
//! under the current norm set.
//!
//! Owns: the request limits, the deadline, the decision log, and (in `knowledge`) what a
//! decision is made under: the store's, cached, trusted for a lease and refreshed only when a
//! stored version moves, or fixed for the offline CLI; failing closed when it cannot be read.
//! Must not: know a wire format or which transport (or command) asked.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, RwLock};
use std::time::{Duration, Instant};

mod knowledge;

pub use knowledge::{DEFAULT_LEASE_MS, Knowledge, MAX_LEASE_MS, lease_margin};
use knowledge::{Leased, Readiness, Source};

use crate::engine::Library;
use crate::engine::action::{ActionDef, ActionInput};
use crate::engine::check::{Check, CheckInput, CheckRequest, check};
use crate::engine::clarify::{clarify, clarify_read, read_words};
use crate::engine::decision::Decision;
pub use crate::engine::input::{
    DEFAULT_DEADLINE_MS, DEFAULT_MAX_DEADLINE_MS, DEFAULT_MAX_OBJECTS, DEFAULT_MAX_TEXT_BYTES, RequestLimits,
};
use crate::engine::norms::{CompiledNorms, MAX_NORM_ID, Norm, NormInput, NormSetMode, NormSpec, Scope};
use crate::engine::request::{Answer, Checked, Directive, Request, RequestInput};
use crate::engine::resolve::Reference;
use crate::engine::scene::Scene;
use crate::engine::task::{Argument, MAX_STEPS};
use crate::engine::words::Understanding;
use crate::error::Error;
use crate::metrics::Metrics;
use crate::storage::{AuditEntry, NormStore, StoredAction, Write};

/// Default for `--max-body-bytes`: the largest request body (REST), message (gRPC) or offline
/// input (a `clarify` file, a `replay` line, a norms file); generous for scenes of thousands of
/// objects.
pub const DEFAULT_MAX_BODY_BYTES: usize = 4 * 1024 * 1024;

/// What one request may ask, whether the human's words may be logged, and how long the stored
/// versions are trusted.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    pub limits: RequestLimits,
    /// Whether the human's words, the speaker and the robot's answer may be logged (off by
    /// default: they are personal data).
    pub log_utterances: bool,
    /// How long a read of the stored versions is trusted, on this process's monotonic clock,
    /// counted from before the read began; every write waits it out (plus [`lease_margin`])
    /// after its commit before it is acknowledged. Zero: read them for every request, and
    /// acknowledge writes at once.
    pub lease: Duration,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            limits: RequestLimits::default(),
            log_utterances: false,
            lease: Duration::from_millis(DEFAULT_LEASE_MS),
        }
    }
}

/// The most steps one reading of the directive may expand to: its verb's, or, for words not
/// yet read, the costliest verb's.
fn expansion_of(directive: &Directive, library: &Library) -> u64 {
    match directive {
        Directive::Action { verb, arguments, .. } => library.expansion(verb, arguments.len()),
        Directive::Form { action, .. } => library.expansion(action.name().map_or("", |n| &**n), action.arity()),
        // Words not yet read may hold several steps.
        Directive::Words { .. } => library.most_expansion().saturating_mul(MAX_STEPS as u64),
        Directive::Task(task) => (task.steps.iter())
            .map(|s| library.expansion(&s.verb, s.arguments.len()))
            .fold(0u64, u64::saturating_add),
    }
}

/// An upper bound on the readings a directive can have, from its arguments' possible
/// candidates (every object for a reference, the bindings for a variable), before resolving.
fn at_most_readings(directive: &Directive, scene: &Scene) -> u128 {
    let objects = scene.objects.len() as u128;
    match directive {
        Directive::Action { arguments, .. } => arguments.iter().fold(1u128, |n, a| {
            n.saturating_mul(if matches!(a, Reference::Id(_)) { 1 } else { objects })
        }),
        Directive::Form { bindings, .. } => bindings
            .iter()
            .fold(1u128, |n, (_, c)| n.saturating_mul(c.len() as u128)),
        // Words of one step name at most two references; those of several steps are simulated
        // up to `max_readings` readings whatever their references (their steps counted in
        // `expansion_of`).
        Directive::Words { .. } => objects.saturating_mul(objects),
        Directive::Task(task) => task.references().fold(1u128, |n, a| {
            n.saturating_mul(if matches!(a, Reference::Id(_)) { 1 } else { objects })
        }),
    }
}

/// Requests that may cost at most this many simulated steps (readings × the verb's expansion)
/// are decided on the calling task (see `clarify`); the rest go to the blocking pool, so a
/// costly one never holds a runtime thread that health checks need. A step costs a few
/// microseconds (BENCHMARKS.md: about 4 µs a reading at 1,000 objects), so the most a request
/// decided inline can hold a runtime thread is about a millisecond. Words in a small scene are
/// read first and admitted by the readings they give (see [`read_first`]).
const INLINE_STEPS: u128 = 256;

/// Words are read before admission when the scene's names to be read against them (in bytes,
/// with a few for each name's entry) are at most this: reading them then costs less than
/// handing the request to another thread, and the decision is admitted by the readings the
/// words give rather than by every pair of objects (64 clients of "Get the plastic vase." on
/// 200 objects were refused where the same request structured was not).
const READ_FIRST_BYTES: usize = 32 * 1024;

/// Whether `request`'s words are read before it is admitted: only words in a scene with few
/// enough names, so that reading them never holds a runtime thread long.
fn read_first(request: &Request, scene: &Scene) -> bool {
    if !matches!(request.directive, Directive::Words { .. }) {
        return false;
    }
    let mut bytes = 0usize;
    for o in &scene.objects {
        bytes += 16 + o.kind.len();
        bytes += o.names.iter().chain(&o.properties).map(|n| 16 + n.len()).sum::<usize>();
        bytes += o.attributes.values().map(|v| 16 + v.len()).sum::<usize>();
        if bytes > READ_FIRST_BYTES {
            return false;
        }
    }
    true
}

/// The steps a request read first may take: its readings (each reference's matches, multiplied)
/// times its verb's expansion; nothing for words that are not a directive. An answer that is a
/// new directive in words is not read yet: the bound of every pair of objects stands for it.
fn steps_read(request: &Request, read: &Understanding, scene: &Scene, library: &Library) -> u128 {
    if matches!(request.answer, Some(Answer::Words(_))) {
        return at_most_readings(&request.directive, scene).saturating_mul(u128::from(library.most_expansion()));
    }
    let Understanding::Directive { directive, .. } = read else {
        return 0;
    };
    let readings = match directive {
        Directive::Action { arguments, .. } => arguments.iter().fold(1u128, |n, reference| {
            let matches = scene.objects.iter().filter(|o| reference.head_matches(o)).count();
            n.saturating_mul(matches as u128)
        }),
        Directive::Task(task) => task.references().fold(1u128, |n, reference| {
            let matches = scene.objects.iter().filter(|o| reference.head_matches(o)).count();
            n.saturating_mul(matches as u128)
        }),
        other => at_most_readings(other, scene),
    };
    // Each reading also checks its purposes, once for every object a purpose's own references
    // match: a step's worth of work each.
    let purposes = match directive {
        Directive::Task(task) => (task.purposes.iter().flat_map(|p| &p.arguments))
            .filter_map(|a| match a {
                Argument::Reference(reference) => {
                    Some(scene.objects.iter().filter(|o| reference.head_matches(o)).count())
                }
                Argument::Earlier { .. } => None,
            })
            .fold(0u128, |n, m| n.saturating_add(m as u128)),
        _ => 0,
    };
    readings.saturating_mul(u128::from(expansion_of(directive, library)).saturating_add(purposes))
}

/// Requests that may cost more than this many simulated steps (about 100 ms of a core at the
/// 4 µs a step of BENCHMARKS.md) are heavy: they take one of fewer turns than the cores, so a
/// flood of them leaves a core to requests of middling cost, which would otherwise wait behind
/// them and be refused. A heavy one simulates its readings on every core (rayon), so running
/// fewer at once costs a flood little throughput and finishes each sooner.
const HEAVY_STEPS: u128 = 25_000;

/// A turn at a costly simulation, held while it runs.
struct Turn {
    _heavy: Option<tokio::sync::OwnedSemaphorePermit>,
    _core: tokio::sync::OwnedSemaphorePermit,
}

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

pub struct Core {
    source: Source,
    settings: Settings,
    metrics: Arc<Metrics>,
    /// What readiness reports: never a read of its own, so a probe answers at once under load.
    readiness: std::sync::Mutex<Option<Readiness>>,
    /// Turns for costly simulations (see `turn_for`): one per core.
    costly: Arc<tokio::sync::Semaphore>,
    /// Turns for heavy ones among them: one fewer than the cores (at least one) over a store,
    /// so that a request of middling cost always finds a core no heavy one holds.
    heavy: Arc<tokio::sync::Semaphore>,
    /// The knowledge of the last versions read, while its lease holds.
    lease: RwLock<Option<Leased>>,
    /// Held by the one request that reads the versions when the lease has run out; the others
    /// wait for its read instead of each making their own.
    refreshing: tokio::sync::Mutex<()>,
    /// The last norm set compiled, tagged with the store version it was compiled from.
    compiled: RwLock<Option<Arc<CompiledNorms>>>,
    /// The last action library loaded, likewise tagged.
    library: RwLock<Option<Arc<Library>>>,
}

impl Core {
    /// A core over the store: what it decides under is what the store holds now.
    pub fn new(store: Arc<dyn NormStore>, metrics: Arc<Metrics>, settings: Settings) -> Core {
        Core::over(Source::Store(store), metrics, settings)
    }

    /// A core over fixed norms and verbs (the offline CLI's): it decides as a server holding
    /// them would, and has no store to curate.
    pub fn fixed(knowledge: Knowledge, settings: Settings) -> Core {
        Core::over(Source::Fixed(knowledge), Arc::new(Metrics::default()), settings)
    }

    fn over(source: Source, metrics: Arc<Metrics>, settings: Settings) -> Core {
        let cores = std::thread::available_parallelism().map_or(2, usize::from);
        // Offline, nothing waits behind a heavy line: replay runs one line per core, each with a
        // turn of its own.
        let heavy = match source {
            Source::Store(_) => cores.saturating_sub(1).max(1),
            Source::Fixed(_) => cores,
        };
        Core {
            source,
            settings,
            metrics,
            lease: RwLock::new(None),
            refreshing: tokio::sync::Mutex::new(()),
            compiled: RwLock::new(None),
            library: RwLock::new(None),
            readiness: std::sync::Mutex::new(None),
            costly: Arc::new(tokio::sync::Semaphore::new(cores)),
            heavy: Arc::new(tokio::sync::Semaphore::new(heavy)),
        }
    }

    /// The store, for curation; a core over fixed knowledge has none.
    /// The newest migration of the store's schema this build applies.
    pub fn schema_version(&self) -> Result<i64, Error> {
        Ok(self.store()?.schema_version())
    }

    fn store(&self) -> Result<&dyn NormStore, Error> {
        match &self.source {
            Source::Store(store) => Ok(store.as_ref()),
            Source::Fixed(_) => Err(Error::Internal(
                "norms and verbs are fixed here: there is no store to change".to_owned(),
            )),
        }
    }

    /// Decides what to say about a directive: checks it within the request limits, reads the
    /// norms and verbs in force (fails closed: without them, no decision), simulates within the
    /// deadline counted from `arrived`, and logs the decision. `text`, the human's words, is
    /// logged only when the settings allow. A costly request runs on the blocking pool, so it
    /// does not stall other requests.
    pub async fn clarify(&self, input: RequestInput, text: Option<&str>, arrived: Instant) -> Result<Decision, Error> {
        let Checked {
            request,
            scene,
            deadline,
        } = Request::from_input(input, &self.settings.limits)?;
        let deadline = arrived + deadline;
        let (_guard, expired) = stop_signal(deadline);
        let Knowledge { norms, library } = self.knowledge_by(deadline).await?;
        let read = read_first(&request, &scene).then(|| read_words(&request, &scene, &library, &expired));
        let steps = match &read {
            Some(Some(understood)) => steps_read(&request, understood, &scene, &library),
            _ => at_most_readings(&request.directive, &scene)
                .saturating_mul(u128::from(expansion_of(&request.directive, &library))),
        };
        let turn = self.turn_for(steps, deadline).await?;
        let small = turn.is_none();
        let speaker = request.speaker.clone();
        let metrics = self.metrics.clone();
        let decide = move || {
            let _turn = turn;
            let _running = InFlight::new(&metrics);
            match read {
                Some(read) => clarify_read(&request, read, &scene, &norms, &library, &expired),
                None => clarify(&request, &scene, &norms, &library, &expired),
            }
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
        self.metrics.decided(decision.kind.as_str());
        self.metrics.readings.observe(decision.interpretations.len() as f64);
        self.log(&decision, text, &speaker);
        Ok(decision)
    }

    /// The decision log: its kind and size always, the words only when the settings allow.
    fn log(&self, decision: &Decision, text: Option<&str>, speaker: &str) {
        let kind = decision.kind.as_str();
        let readings = decision.interpretations.len();
        if self.settings.log_utterances {
            tracing::debug!(decision = kind, readings, text, speaker, utterance = %decision.utterance, "decided");
        } else {
            tracing::debug!(decision = kind, readings, "decided");
        }
    }

    /// Admission by cost: the turn a request of at most `steps` simulated steps needs. None up
    /// to [`INLINE_STEPS`]; else a turn to run a costly simulation, at most one per core at once,
    /// so that each finishes within its deadline rather than all of them late. A request that
    /// gets no turn within [`COSTLY_WAIT`] (nor before its deadline) is overload: 503 with
    /// Retry-After at once, never an answer long after the robot stopped waiting. A heavy
    /// request (over [`HEAVY_STEPS`]) takes a heavy turn first, then a core's: the wait bounds
    /// both.
    async fn turn_for(&self, steps: u128, deadline: Instant) -> Result<Option<Turn>, Error> {
        if steps <= INLINE_STEPS {
            return Ok(None);
        }
        let until = (Instant::now() + COSTLY_WAIT).min(deadline);
        let turn = async {
            let heavy = match steps > HEAVY_STEPS {
                true => Some(self.heavy.clone().acquire_owned().await?),
                false => None,
            };
            let core = self.costly.clone().acquire_owned().await?;
            Ok::<_, tokio::sync::AcquireError>(Turn {
                _heavy: heavy,
                _core: core,
            })
        };
        match tokio::time::timeout_at(until.into(), turn).await {
            Ok(Ok(turn)) => Ok(Some(turn)),
            Ok(Err(_)) | Err(_) => {
                self.metrics.overloaded.inc();
                Err(Error::Overloaded { retry_after_s: 1 })
            }
        }
    }

    /// Checks steps while acting, under the norms in force now. Fails closed like `clarify`.
    pub async fn check(&self, input: CheckInput, arrived: Instant) -> Result<Check, Error> {
        let input = CheckRequest::from_input(input, &self.settings.limits)?;
        let deadline = arrived + input.deadline;
        let (_guard, expired) = stop_signal(deadline);
        let Knowledge { norms, library } = self.knowledge_by(deadline).await?;
        let steps: u128 = (input.steps.iter())
            .map(|s| u128::from(library.expansion(s.name().map_or("", |n| &**n), s.arity())))
            .sum();
        let turn = self.turn_for(steps, deadline).await?;
        let metrics = self.metrics.clone();
        tokio::task::spawn_blocking(move || {
            let _turn = turn;
            let _running = InFlight::new(&metrics);
            let scope = Scope {
                context: &input.context,
                roles: &input.speaker_roles,
                // A step that breaks a soft norm is permitted, and says so.
                soft: true,
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

    /// Validates and stores a norm under a fresh id; nothing is written unless every field is
    /// valid. `given_id`: the id the request carried, which must be none.
    pub async fn create_norm(&self, given_id: Option<i64>, input: NormInput, actor: &str) -> Result<Norm, Error> {
        let spec = norm_to_create(given_id, input)?;
        let norm = self.store()?.create(&spec, actor).await?;
        Ok(self.settled(norm).await)
    }

    pub async fn list_norms(&self) -> Result<Vec<Norm>, Error> {
        Ok(self.store()?.load().await?.1)
    }

    pub async fn get_norm(&self, id: i64) -> Result<Norm, Error> {
        self.store()?.get(id).await?.ok_or_else(|| not_found(id))
    }

    /// Replaces a norm's content (its id stays) when `expected` is its revision, or always
    /// without one; nothing is written unless every field is valid and the revision matches.
    /// `given_id`: the id the request's norm carried, which must be none or `id`.
    pub async fn replace_norm(
        &self,
        id: i64,
        given_id: Option<i64>,
        input: NormInput,
        expected: Option<i64>,
        actor: &str,
    ) -> Result<Norm, Error> {
        if let Some(given) = given_id
            && given != id
        {
            return Err(Error::invalid(
                "/id",
                format!("the body names norm {given} but the request replaces norm {id}"),
            ));
        }
        let spec = input.validate()?;
        let write = self.store()?.replace(id, &spec, expected, actor).await?;
        written(id, expected, self.settled_write(write).await)
    }

    pub async fn delete_norm(&self, id: i64, expected: Option<i64>, actor: &str) -> Result<(), Error> {
        let write = self.store()?.delete(id, expected, actor).await?;
        written(id, expected, self.settled_write(write).await)
    }

    /// The whole norm set and its version, for backups and review.
    pub async fn export_norms(&self) -> Result<(i64, Vec<Norm>), Error> {
        Ok(self.store()?.load().await?)
    }

    /// Imports a norm set in one transaction when `expected` is the set's version (or always
    /// without one): as the whole set, or merged over the stored one (`mode`). Every norm is
    /// validated first (errors point into `/norms/i`); ids given are kept (a restored backup
    /// keeps its ids) and must be distinct and positive; norms without one get fresh ids, never
    /// used before.
    pub async fn import_norms(
        &self,
        inputs: Vec<(Option<i64>, NormInput)>,
        mode: NormSetMode,
        expected: Option<i64>,
        actor: &str,
    ) -> Result<(i64, Vec<Norm>), Error> {
        let norms = validate_norm_set(inputs)?;
        let write = self.store()?.import(&norms, mode, expected, actor).await?;
        match self.settled_write(write).await {
            Write::Done(set) => Ok(set),
            Write::Missing => Err(Error::Internal("the norm set row is missing".to_owned())),
            Write::Stale { current } => Err(Error::Stale {
                what: "the norm set".to_owned(),
                expected: expected.map_or_else(|| "*".to_owned(), |e| e.to_string()),
                current,
            }),
        }
    }

    /// Up to `limit` (1..=[`MAX_AUDIT_PAGE`], default [`DEFAULT_AUDIT_PAGE`]) audit entries
    /// after entry `after`, oldest first.
    pub async fn audit(&self, after: i64, limit: Option<i64>) -> Result<AuditPage, Error> {
        let limit = limit.unwrap_or(DEFAULT_AUDIT_PAGE);
        if !(1..=MAX_AUDIT_PAGE).contains(&limit) {
            return Err(Error::invalid(
                "/limit",
                format!("{limit} is out of range 1..={MAX_AUDIT_PAGE}"),
            ));
        }
        let entries = self.store()?.audit(after, limit).await?;
        let next_after = entries.last().map_or(after, |e| e.id);
        Ok(AuditPage { entries, next_after })
    }

    /// Every verb, by name, as written.
    pub async fn list_actions(&self) -> Result<Vec<ActionInput>, Error> {
        let Knowledge { library, .. } = self.knowledge().await?;
        Ok(library.verbs().into_iter().map(ActionDef::to_input).collect())
    }

    pub async fn get_action(&self, name: &str) -> Result<ActionInput, Error> {
        let Knowledge { library, .. } = self.knowledge().await?;
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
        let def = input.validate(name)?;
        def.check_written_words()?;
        let written = def.to_input();
        let this = name.to_owned();
        let accept = move |all: &[StoredAction]| {
            // The expansion bound holds for what is written from now on; a library stored before
            // it still loads, and the deadline bounds its cost.
            Library::from_written(0, all)
                .and_then(|library| library.check_words(&this).map(|()| library))
                .and_then(|library| library.check_expansion(&this))
                .map_err(|(verb, e)| {
                    let field = if verb == this { e.field } else { "/methods".to_owned() };
                    Error::invalid(field, format!("{}: {}", verb, e.message))
                })
        };
        let created = self.store()?.put_action(name, &written, &accept, actor).await??;
        Ok((written, self.settled(created).await))
    }

    /// Removes a verb, unless another verb calls it in a method (409, naming them: they, and
    /// every reading that uses them, would fail at that step); judged and removed in one
    /// transaction.
    pub async fn delete_action(&self, name: &str, actor: &str) -> Result<(), Error> {
        let this = name.to_owned();
        let accept = move |rest: &[StoredAction]| match callers_of(rest, &this).as_slice() {
            [] => Ok(()),
            callers => Err(Error::VerbInUse {
                verb: this.clone(),
                callers: listed(callers),
            }),
        };
        if self.store()?.delete_action(name, &accept, actor).await?? {
            self.settled(()).await;
            Ok(())
        } else {
            Err(Error::NotFound {
                what: format!("verb `{name}`"),
            })
        }
    }
}

/// Default and largest page of the audit trail.
pub const DEFAULT_AUDIT_PAGE: i64 = 100;
pub const MAX_AUDIT_PAGE: i64 = 1_000;

/// A page of the audit trail, and where the next one starts.
#[derive(Debug)]
pub struct AuditPage {
    pub entries: Vec<AuditEntry>,
    /// The last id here, or the `after` asked for.
    pub next_after: i64,
}

/// A norm to create: the service assigns ids, so an id given is refused.
pub fn norm_to_create(given_id: Option<i64>, input: NormInput) -> Result<NormSpec, Error> {
    if given_id.is_some() {
        return Err(Error::invalid(
            "/id",
            "ids are assigned by the service; replace a norm with PUT /v1/norms/{id}",
        ));
    }
    Ok(input.validate()?)
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

/// The verbs, by name, whose methods call a verb named `name` (of any arity): those removing
/// it would leave failing at that step. A definition that does not validate calls nothing (a
/// library holding it fails closed anyway).
fn callers_of(verbs: &[StoredAction], name: &str) -> Vec<String> {
    let calls = |(verb, input): &&StoredAction| {
        verb != name
            && input
                .validate(verb)
                .is_ok_and(|def| def.callees().any(|(callee, _)| &*callee == name))
    };
    verbs.iter().filter(calls).map(|(verb, _)| verb.clone()).collect()
}

/// Names as a sentence lists them: "`put`", "`put` and `fetch`", "`a`, `b` and `c`".
fn listed(names: &[String]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
    match quoted.as_slice() {
        [init @ .., last] if !init.is_empty() => format!("{} and {last}", init.join(", ")),
        _ => quoted.concat(),
    }
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
