//! The `scruple` binary: flags and environment, telemetry, startup, graceful shutdown, and the
//! offline commands (their logic lives in `scruple::offline`).

use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::process::ExitCode;

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use clap::builder::TypedValueParser;
use clap::{Args, Parser, Subcommand};
use scruple::app::{Application, Config, DEFAULT_MAX_BODY_BYTES, Secret};
use scruple::core::{
    DEFAULT_DEADLINE_MS, DEFAULT_LEASE_MS, DEFAULT_MAX_DEADLINE_MS, DEFAULT_MAX_OBJECTS, DEFAULT_MAX_TEXT_BYTES,
    MAX_LEASE_MS, RequestLimits,
};
use scruple::engine::term::{MAX_DEPTH, MAX_LEN, TermLimits};
use scruple::offline::{self, Failure, Sources, emit};
use scruple::transport::admission::{
    AdmissionConfig, DEFAULT_MAX_CONCURRENT, DEFAULT_MAX_QUEUED, DEFAULT_QUEUE_TIMEOUT_MS,
};
use scruple::transport::auth::LabelledSecret;
use scruple::transport::conn::{
    ConnConfig, DEFAULT_BODY_TIMEOUT_MS, DEFAULT_DRAIN_TIMEOUT_MS, DEFAULT_HEADER_TIMEOUT_MS, DEFAULT_IDLE_TIMEOUT_MS,
    DEFAULT_MAX_CONNECTIONS,
};
use scruple::transport::cors::CorsOrigins;
use scruple::transport::logs::Deferred;
use scruple::transport::tls::TlsFiles;
use tracing_subscriber::fmt::format::{DefaultFields, JsonFields};
use tracing_subscriber::layer::{Context, Layered, SubscriberExt};
use tracing_subscriber::util::SubscriberInitExt;
use tracing_subscriber::{EnvFilter, Layer, Registry};

/// mimalloc instead of glibc's malloc: a request allocates and frees many small blocks across
/// the runtime's threads, where glibc spent about a tenth of the service's time under load
/// (BENCHMARKS.md, "Service under load"). Through `allocator::Allocator`, which says why not
/// through `mimalloc::MiMalloc`.
#[global_allocator]
static ALLOCATOR: scruple::allocator::Allocator = scruple::allocator::Allocator;

#[derive(Parser)]
#[command(
    name = "scruple",
    version,
    about = "Morally sensitive clarification of ambiguous robot directives"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Serve REST and gRPC on one port until SIGTERM or Ctrl-C.
    Serve(Box<ServeArgs>),
    /// Print the REST API's OpenAPI 3.1 document (as `openapi/openapi.json` holds it).
    Openapi,
    /// Decide one request (a `POST /v1/clarify` body) without a server; print the answer.
    ///
    /// Exit status: 0 decided, 2 the input is at fault (the problem, with the file and the
    /// field, goes to stderr), 1 anything else.
    Clarify(ClarifyArgs),
    /// Decide every request of a JSON Lines file; print decisions by kind and by condition.
    ///
    /// A line is a `POST /v1/clarify` body, or `{"id": "...", "condition": "...", "request":
    /// BODY}` (id and condition optional). Lines that are not valid requests are counted as
    /// errors with their line numbers; the others still run. Exit status: 0 when every line was
    /// decided, 2 when some line could not be (or an input file is at fault), 1 on any other
    /// failure. With `--diff`, changes do not change the exit status.
    Replay(ReplayArgs),
}

/// Where decisions take their norms and verbs from. No environment variables: an offline run
/// should not pick up a server's store by accident.
#[derive(Args)]
struct SourceArgs {
    /// Norms from a JSON file: a list of norms as `POST /v1/norms` takes them (numbered 1, 2, ...
    /// as on an empty store), or a norm set as `GET /v1/norm-set` gives it. Replaces the store's
    /// norms; without either, there are none.
    #[arg(long, value_name = "FILE")]
    norms: Option<PathBuf>,
    /// A store to read norms and verbs from (`sqlite://PATH` or `postgres://…`, which must
    /// already hold one; an older one is migrated). Without it: the default action library.
    #[arg(long, value_name = "URL")]
    database_url: Option<String>,
}

/// The limits a request is held to: the service's, with its flags, variables and defaults, so
/// that an offline answer is the one the server would give (or the problem it would answer).
#[derive(Args)]
struct LimitArgs {
    /// Largest request body (REST) or message (gRPC) accepted, in bytes; larger ones get 413.
    /// Offline: the largest request file, replay line or norms file.
    #[arg(long, env = "SCRUPLE_MAX_BODY_BYTES", default_value_t = DEFAULT_MAX_BODY_BYTES,
          value_parser = clap::value_parser!(u64).range(1..).map(|n| usize::try_from(n).unwrap_or(usize::MAX)))]
    max_body_bytes: usize,
    /// Most objects in one scene; more is a 422 at /scene/objects.
    #[arg(long, env = "SCRUPLE_MAX_OBJECTS", default_value_t = DEFAULT_MAX_OBJECTS)]
    max_objects: usize,
    /// Deepest nesting of a term in a request (1..=128); deeper is a 422 naming the field.
    #[arg(long, env = "SCRUPLE_MAX_TERM_DEPTH", default_value_t = MAX_DEPTH,
          value_parser = clap::value_parser!(u16).range(1..=128).map(usize::from))]
    max_term_depth: usize,
    /// Longest term text in a request, bytes (16..=65536); longer is a 422 naming the field.
    #[arg(long, env = "SCRUPLE_MAX_TERM_LENGTH", default_value_t = MAX_LEN,
          value_parser = clap::value_parser!(u32).range(16..=65_536).map(|n| n as usize))]
    max_term_length: usize,
    /// Decision deadline when a request names none (`options.deadline_ms`), milliseconds.
    #[arg(long, env = "SCRUPLE_DEADLINE_MS", default_value_t = DEFAULT_DEADLINE_MS)]
    deadline_ms: u64,
    /// Longest `options.deadline_ms` a request may ask for, milliseconds.
    #[arg(long, env = "SCRUPLE_MAX_DEADLINE_MS", default_value_t = DEFAULT_MAX_DEADLINE_MS)]
    max_deadline_ms: u64,
    /// Longest human's words a directive may carry in `text`, bytes; longer is a 422.
    #[arg(long, env = "SCRUPLE_MAX_TEXT_BYTES", default_value_t = DEFAULT_MAX_TEXT_BYTES)]
    max_text_bytes: usize,
}

impl LimitArgs {
    fn limits(&self) -> Result<offline::Limits, String> {
        if !(1..=self.max_deadline_ms).contains(&self.deadline_ms) {
            return Err(format!(
                "--deadline-ms {} must be within 1..=--max-deadline-ms ({})",
                self.deadline_ms, self.max_deadline_ms
            ));
        }
        Ok(offline::Limits {
            max_body_bytes: self.max_body_bytes,
            request: RequestLimits {
                max_objects: self.max_objects,
                terms: TermLimits {
                    depth: self.max_term_depth,
                    len: self.max_term_length,
                },
                default_deadline_ms: self.deadline_ms,
                max_deadline_ms: self.max_deadline_ms,
                max_text_bytes: self.max_text_bytes,
            },
        })
    }
}

#[derive(Args)]
struct ClarifyArgs {
    /// The request; `-` reads standard input.
    file: PathBuf,
    #[command(flatten)]
    sources: SourceArgs,
    #[command(flatten)]
    limits: LimitArgs,
}

#[derive(Args)]
struct ReplayArgs {
    /// The requests, one JSON value per line; `-` reads standard input.
    file: PathBuf,
    #[command(flatten)]
    sources: SourceArgs,
    /// Also write one answer per line, in line order: `{"line": N, "id": ..., "condition": ...,
    /// "decision": ANSWER}` or, for a line not decided, `{..., "error": PROBLEM}`. With `--diff`,
    /// the answers under the proposed `--norms`.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Compare the proposed `--norms` with the norms in force (`--baseline-norms`, else the
    /// store's): list every request whose decision or utterance would change, and the count.
    #[arg(long, requires = "norms")]
    diff: bool,
    /// The norms in force, for `--diff`, as a norms file.
    #[arg(long, value_name = "FILE", requires = "diff")]
    baseline_norms: Option<PathBuf>,
    /// Decide every line once under each of these conditions, comma-separated, in this order:
    /// `moral` and `reflexive` (the request's `options.strategy`) or the conditions of
    /// `--conditions-file`. The summary (decisions per condition, agreement between them, the
    /// lines whose decisions differ) then goes to stderr, and `--out` holds each line's answers
    /// under each condition, in turn. A line may not name its own condition then.
    #[arg(long, value_name = "NAMES", conflicts_with = "diff")]
    conditions: Option<String>,
    /// The conditions an experiment may name: a JSON object, condition → the request `options`
    /// it sets over each line's (`{"moral": {"strategy": "moral"}, "terse": {"strategy":
    /// "moral", "style": "natural", "max_spoken": 1}}`). Without `--conditions`, every condition
    /// it defines, in its order.
    #[arg(long, value_name = "FILE", conflicts_with = "diff")]
    conditions_file: Option<PathBuf>,
    /// The scene of every line that has none (a clarify body's `scene`), so a file of directives
    /// need not repeat it.
    #[arg(long, value_name = "FILE")]
    scene: Option<PathBuf>,
    /// Write the experiment as one self-contained HTML page: a chart of decisions by condition,
    /// the counts, the agreement, and the lines whose decisions differ. Needs conditions.
    #[arg(long, value_name = "FILE")]
    report: Option<PathBuf>,
    #[command(flatten)]
    limits: LimitArgs,
}

async fn clarify_command(args: ClarifyArgs) -> Result<(), Failure> {
    let limits = args.limits.limits().map_err(|detail| Failure::Usage { detail })?;
    let sources = Sources::open(args.sources.database_url.as_deref()).await?;
    let knowledge = sources
        .knowledge(args.sources.norms.as_deref(), limits.max_body_bytes)
        .await?;
    let answer = offline::clarify_file(&args.file, knowledge, &limits).await?;
    let text = serde_json::to_string_pretty(&answer).map_err(|e| Failure::Run { detail: e.to_string() })?;
    emit(&format!("{text}\n"))
}

/// Returns whether every line was decided.
async fn replay_command(args: ReplayArgs) -> Result<bool, Failure> {
    let limits = args.limits.limits().map_err(|detail| Failure::Usage { detail })?;
    offline::replay_command(offline::ReplayCommand {
        file: args.file,
        norms: args.sources.norms,
        database_url: args.sources.database_url,
        out: args.out,
        diff: args.diff,
        baseline_norms: args.baseline_norms,
        conditions: args.conditions,
        conditions_file: args.conditions_file,
        scene: args.scene,
        report: args.report,
        limits,
    })
    .await
}

/// The problem goes to stderr as one JSON line, for people and scripts alike (unless nobody
/// reads stderr either).
fn failed(failure: &Failure) -> ExitCode {
    let _ = writeln!(std::io::stderr(), "{failure}");
    ExitCode::from(failure.exit_code())
}

/// Every flag has an environment variable; secrets are better passed that way (a command line
/// shows in `ps`).
#[derive(Args)]
struct ServeArgs {
    /// Address to listen on; port 0 picks a free port (printed as `listening on ADDR`).
    #[arg(long, env = "SCRUPLE_LISTEN", default_value = "127.0.0.1:8080")]
    listen: String,
    /// Norm store; a SQLite file is created if missing and migrated at start.
    #[arg(long, env = "SCRUPLE_DATABASE_URL", default_value = "sqlite://scruple.db")]
    database_url: String,
    /// When set, writes to norms and verbs need `Authorization: Bearer TOKEN` (audit label `admin`).
    #[arg(long, env = "SCRUPLE_ADMIN_TOKEN", hide_env_values = true)]
    admin_token: Option<String>,
    /// More write tokens, as LABEL=SECRET (secret ≥ 16 bytes); the label names the writer in the
    /// audit trail. Repeat the flag, or separate with commas in the variable.
    #[arg(
        long = "curator-token",
        env = "SCRUPLE_CURATOR_TOKENS",
        value_delimiter = ',',
        hide_env_values = true
    )]
    curator_tokens: Vec<LabelledSecret>,
    /// Read-only tokens, as LABEL=SECRET: once any is set, listing norms, verbs, the norm set and
    /// the audit trail needs a token (clarify and check never do).
    #[arg(
        long = "reader-token",
        env = "SCRUPLE_READER_TOKENS",
        value_delimiter = ',',
        hide_env_values = true
    )]
    reader_tokens: Vec<LabelledSecret>,
    #[command(flatten)]
    limits: LimitArgs,
    /// Requests worked on at once; the next ones queue.
    #[arg(long, env = "SCRUPLE_MAX_CONCURRENT", default_value_t = DEFAULT_MAX_CONCURRENT)]
    max_concurrent: usize,
    /// Requests that may wait for a turn; beyond that, 503 with Retry-After at once.
    #[arg(long, env = "SCRUPLE_MAX_QUEUED", default_value_t = DEFAULT_MAX_QUEUED)]
    max_queued: usize,
    /// Longest wait for a turn, milliseconds; then 503 with Retry-After.
    #[arg(long, env = "SCRUPLE_QUEUE_TIMEOUT_MS", default_value_t = DEFAULT_QUEUE_TIMEOUT_MS)]
    queue_timeout_ms: u64,
    /// Longest wait for the whole head of a request, milliseconds, from the connection's start
    /// or a head's first byte: a connection that says nothing is closed, part of a head is
    /// answered 408.
    #[arg(long, env = "SCRUPLE_HEADER_TIMEOUT_MS", default_value_t = DEFAULT_HEADER_TIMEOUT_MS,
          value_parser = clap::value_parser!(u64).range(1..))]
    header_timeout_ms: u64,
    /// Longest wait for a whole request body once its handler reads it, milliseconds (then
    /// 408); a client that does not read an answer for this long is disconnected.
    #[arg(long, env = "SCRUPLE_BODY_TIMEOUT_MS", default_value_t = DEFAULT_BODY_TIMEOUT_MS,
          value_parser = clap::value_parser!(u64).range(1..))]
    body_timeout_ms: u64,
    /// A kept-alive connection with no request open is closed after this many milliseconds
    /// without a next request (HTTP/2: GOAWAY).
    #[arg(long, env = "SCRUPLE_IDLE_TIMEOUT_MS", default_value_t = DEFAULT_IDLE_TIMEOUT_MS,
          value_parser = clap::value_parser!(u64).range(1..))]
    idle_timeout_ms: u64,
    /// Connections open at once; more wait in the kernel's backlog until one closes. Lowered
    /// (with a warning) to what the open-file limit leaves room for.
    #[arg(long, env = "SCRUPLE_MAX_CONNECTIONS", default_value_t = DEFAULT_MAX_CONNECTIONS,
          value_parser = clap::value_parser!(u64).range(1..).map(|n| usize::try_from(n).unwrap_or(usize::MAX)))]
    max_connections: usize,
    /// After SIGTERM or Ctrl-C, milliseconds to let open requests finish; then the connections
    /// still open are closed and the process exits 0 all the same.
    #[arg(long, env = "SCRUPLE_DRAIN_TIMEOUT_MS", default_value_t = DEFAULT_DRAIN_TIMEOUT_MS,
          value_parser = clap::value_parser!(u64).range(1..))]
    drain_timeout_ms: u64,
    /// Log lines as text for people or JSON for collectors (one object per line, with the
    /// request's span and its request id). Levels come from RUST_LOG (default info).
    #[arg(long, env = "SCRUPLE_LOG_FORMAT", value_enum, default_value_t = LogFormat::Text)]
    log_format: LogFormat,
    /// Also log the human's words, the speaker and the robot's answer with each decision (at
    /// debug). Off by default: they are personal data.
    #[arg(long, env = "SCRUPLE_LOG_UTTERANCES")]
    log_utterances: bool,
    /// Milliseconds a read of the stored norm and verb versions is trusted; the first request
    /// past three quarters of it reads them again (at the default, at most about 27 times a
    /// second per process). Every write waits the longest lease of any process serving the
    /// database (each records its own while it serves), and a tenth more (56 ms at the
    /// default), after it commits before it is acknowledged, so a change is seen by every
    /// request that starts after its acknowledgement, on every process sharing the database.
    /// 0 reads them for every request.
    #[arg(long, env = "SCRUPLE_VERSIONS_LEASE_MS", default_value_t = DEFAULT_LEASE_MS,
          value_parser = clap::value_parser!(u64).range(0..=MAX_LEASE_MS))]
    versions_lease_ms: u64,
    /// Serve REST and gRPC over TLS (ALPN h2 and http/1.1) with this PEM certificate chain,
    /// server certificate first. Renewed files are taken up within seconds, without a restart.
    #[arg(long, env = "SCRUPLE_TLS_CERT", value_name = "FILE", requires = "tls_key")]
    tls_cert: Option<PathBuf>,
    /// The PEM private key of `--tls-cert`.
    #[arg(long, env = "SCRUPLE_TLS_KEY", value_name = "FILE", requires = "tls_cert")]
    tls_key: Option<PathBuf>,
    /// A browser origin (`https://app.example`, `http://localhost:5173`) whose pages may call the
    /// REST API (CORS; repeat the flag for more), or `*` for any page (then never with
    /// credentials). Off by default: browsers refuse cross-origin calls.
    #[arg(
        long = "cors-origin",
        env = "SCRUPLE_CORS_ORIGINS",
        value_name = "ORIGIN",
        value_delimiter = ','
    )]
    cors_origins: Vec<String>,
}

#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum LogFormat {
    Text,
    Json,
}

/// Offline commands report on stdout and stderr themselves; their log only speaks of trouble.
fn init_logs(format: LogFormat, level: &str) {
    let from_env = std::env::var(EnvFilter::DEFAULT_ENV)
        .ok()
        .and_then(|directives| EnvFilter::try_new(&directives).ok().map(|filter| (directives, filter)));
    let (directives, filter) = from_env.unwrap_or_else(|| (level.to_owned(), EnvFilter::new(level)));
    // Only a directive on spans (`target[span{field=value}]=level`) has `[`: without one, the
    // filter's bookkeeping on entering and leaving each span (a shared lock each time) serves
    // nothing, and the filter is consulted per callsite and event only.
    let filter: Box<dyn Layer<Registry> + Send + Sync> = match directives.contains('[') {
        true => Box::new(filter),
        false => Box::new(OnEvents(filter)),
    };
    let logs = tracing_subscriber::fmt::layer()
        // Colour codes only for a person at a terminal: a log file or collector gets plain text,
        // and each request's span is not dressed in escapes no one will see.
        .with_ansi(std::io::stderr().is_terminal())
        .with_writer(std::io::stderr);
    // Each request's span fields are formatted only if a line is written inside it (at a
    // terminal, their names are then not in italics: the text is the same).
    let defer = scruple::transport::observe::deferred;
    let logs: Box<dyn Layer<Layered<Box<dyn Layer<Registry> + Send + Sync>, Registry>> + Send + Sync> = match format {
        LogFormat::Text => Box::new(Deferred::new(logs, DefaultFields::new(), defer)),
        LogFormat::Json => Box::new(Deferred::new(
            logs.json().with_current_span(true).with_span_list(false),
            JsonFields::new(),
            defer,
        )),
    };
    tracing_subscriber::registry().with(filter).with(logs).init();
}

/// An [`EnvFilter`] of static directives (targets and levels): which callsites and events are
/// on, and nothing per span.
struct OnEvents(EnvFilter);

impl<S: tracing::Subscriber> Layer<S> for OnEvents {
    fn register_callsite(&self, metadata: &'static tracing::Metadata<'static>) -> tracing::subscriber::Interest {
        Layer::<S>::register_callsite(&self.0, metadata)
    }

    fn max_level_hint(&self) -> Option<tracing::level_filters::LevelFilter> {
        Layer::<S>::max_level_hint(&self.0)
    }

    fn enabled(&self, metadata: &tracing::Metadata<'_>, context: Context<'_, S>) -> bool {
        Layer::<S>::enabled(&self.0, metadata, context)
    }
}

impl ServeArgs {
    fn into_config(self) -> Result<Config, String> {
        let limits = self.limits.limits()?;
        let cors = CorsOrigins::parse(&self.cors_origins)?;
        Ok(Config {
            listen: self.listen,
            database_url: self.database_url,
            // Set but empty is refused at start (`Tokens::new`), never taken as unset.
            admin_token: self.admin_token.map(Secret),
            curator_tokens: self.curator_tokens,
            reader_tokens: self.reader_tokens,
            max_body_bytes: limits.max_body_bytes,
            limits: limits.request,
            admission: AdmissionConfig {
                max_concurrent: self.max_concurrent,
                max_queued: self.max_queued,
                queue_timeout: Duration::from_millis(self.queue_timeout_ms),
            },
            log_utterances: self.log_utterances,
            cors,
            lease: Duration::from_millis(self.versions_lease_ms),
            tls: match (self.tls_cert, self.tls_key) {
                (Some(cert), Some(key)) => Some(TlsFiles { cert, key }),
                // clap requires each with the other.
                _ => None,
            },
            connections: ConnConfig {
                header_timeout: Duration::from_millis(self.header_timeout_ms),
                body_timeout: Duration::from_millis(self.body_timeout_ms),
                idle_timeout: Duration::from_millis(self.idle_timeout_ms),
                max_connections: self.max_connections,
                drain_timeout: Duration::from_millis(self.drain_timeout_ms),
            },
        })
    }
}

async fn shutdown_signal() {
    let ctrl_c = async {
        if tokio::signal::ctrl_c().await.is_err() {
            std::future::pending::<()>().await;
        }
    };
    #[cfg(unix)]
    let terminate = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut signal) => {
                signal.recv().await;
            }
            Err(_) => std::future::pending::<()>().await,
        }
    };
    #[cfg(not(unix))]
    let terminate = std::future::pending::<()>();
    tokio::select! {
        () = ctrl_c => {},
        () = terminate => {},
    }
    tracing::info!("shutting down: draining in-flight requests until the drain deadline");
}

/// How long an idle thread of the blocking pool (costly decisions, large answers) is kept:
/// short, so that after a burst of heavy requests the threads and what their heaps held go.
const BLOCKING_KEEP_ALIVE: Duration = Duration::from_secs(1);

/// The least time between two collections of one runtime thread's heap.
const COLLECT_EVERY: Duration = Duration::from_secs(1);

/// Set once `serve` has started rayon's pool itself: only then does the idle hook below ask the
/// pool's threads to collect (asking a pool not yet built would build it there, and a failure to
/// start threads would panic inside the runtime's hook).
static POOL_COLLECTS: AtomicBool = AtomicBool::new(false);

/// Called as a runtime thread goes idle: hands what its heap holds free back to the OS, at most
/// once a [`COLLECT_EVERY`], so that RSS falls back after a burst without costing each request
/// (a busy thread rarely parks, a quiet one is woken each second by the readiness probe). In
/// `serve`, rayon's threads are asked to do the same ([`pool_collect_due`]): they never park
/// through here, and after a burst of large decisions their heaps held the blocks other threads
/// had freed into them (no thread collects those but the owner) until their next decision: RSS
/// 10 s after a heavy burst 24-29 MiB without, 21-22 MiB with, idle 19 (BENCHMARKS.md, fifteenth
/// sitting).
fn give_back_when_idle() {
    thread_local! {
        static LAST: std::cell::Cell<Option<Instant>> = const { std::cell::Cell::new(None) };
    }
    LAST.with(|last| {
        let now = Instant::now();
        if last.get().is_none_or(|at| now.duration_since(at) >= COLLECT_EVERY) {
            last.set(Some(now));
            // SAFETY: mi_collect frees only memory no live allocation uses.
            unsafe { libmimalloc_sys::mi_collect(true) };
            if POOL_COLLECTS.load(Ordering::Relaxed) && pool_collect_due(now) {
                // Queued behind any decision the pool is running; this thread does not wait.
                // SAFETY: as above, on each of the pool's threads, for its own heap.
                rayon::spawn_broadcast(|_| unsafe { libmimalloc_sys::mi_collect(true) });
            }
        }
    });
}

/// Whether the runtime thread calling it is the one to ask rayon's pool to collect: at most one
/// ask a [`COLLECT_EVERY`] for the whole process, whichever runtime thread parks first. The ask
/// wakes every pool thread, so asking once a second from each runtime thread (as each collects
/// its own heap) would wake the whole pool once a second per runtime thread, for the same work.
fn pool_collect_due(now: Instant) -> bool {
    /// When the pool was last asked. Only runtime threads that have just collected come here,
    /// each at most once a second, so the lock is all but never contended; a thread that finds it
    /// held leaves the ask to the holder.
    static ASKED: Mutex<Option<Instant>> = Mutex::new(None);
    let Ok(mut asked) = ASKED.try_lock() else { return false };
    let due = asked.is_none_or(|at| now.saturating_duration_since(at) >= COLLECT_EVERY);
    if due {
        *asked = Some(now);
    }
    due
}

/// The server's memory in 4 KiB pages, never transparent huge ones. mimalloc asks for huge
/// pages on its arena (`MADV_HUGEPAGE`), and a 2 MiB page stays resident whole while any one
/// block in it is live: after a burst of heavy requests the arena kept 25-42 MiB resident, up
/// to 2.2x the idle RSS, where 4 KiB pages keep 9-16 MiB (BENCHMARKS.md, "tenth sitting").
/// The kernel's per-process flag covers what mimalloc already asked for and a system set to
/// `always` alike. It is set here, once, before the runtime starts; a page faulted in before
/// `main` keeps its size.
#[cfg(target_os = "linux")]
fn no_huge_pages() {
    // SAFETY: PR_SET_THP_DISABLE takes integers only and changes how the kernel backs this
    // process's later page faults, not any memory already in use. A kernel without it (before
    // 3.15) refuses it, and the server runs as before, only slower to give memory back.
    let _ = unsafe { libc::prctl(libc::PR_SET_THP_DISABLE, 1, 0, 0, 0) };
}

#[cfg(not(target_os = "linux"))]
fn no_huge_pages() {}

fn main() -> ExitCode {
    // Freed pages go back to the OS after mimalloc's own delay (10 ms), as in the offline
    // commands, and all at once when a runtime thread parks (`give_back_when_idle`), which is
    // what brings RSS down after a burst. Not at once on every free: a size class whose live
    // blocks hover at a page's edge then gives the page back and faults it in again on every
    // request, and the server fell into that under gRPC load in a fifth of the rounds, at a
    // third of its throughput (BENCHMARKS.md, seventeenth sitting).
    let cli = Cli::parse();
    if matches!(cli.command, Command::Serve(_)) {
        no_huge_pages();
        // rayon's global pool, as the engine would start it on its first large decision, but
        // here, where a failure is an error message rather than a panic on a runtime thread.
        match rayon::ThreadPoolBuilder::new().build_global() {
            Ok(()) => POOL_COLLECTS.store(true, Ordering::Relaxed),
            Err(e) => eprintln!(
                "scruple: rayon's thread pool did not start here ({e}); its memory is not collected when idle"
            ),
        }
    }
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .thread_keep_alive(BLOCKING_KEEP_ALIVE)
        .on_thread_park(give_back_when_idle)
        .build();
    match runtime {
        Ok(runtime) => runtime.block_on(run(cli)),
        Err(e) => {
            eprintln!("scruple: cannot start the runtime: {e}");
            ExitCode::FAILURE
        }
    }
}

async fn run(Cli { command }: Cli) -> ExitCode {
    match &command {
        Command::Serve(args) => init_logs(args.log_format, "info"),
        _ => init_logs(LogFormat::Text, "warn"),
    }
    match command {
        Command::Clarify(args) => match clarify_command(args).await {
            Ok(()) => ExitCode::SUCCESS,
            Err(failure) => failed(&failure),
        },
        Command::Replay(args) => match replay_command(args).await {
            Ok(true) => ExitCode::SUCCESS,
            Ok(false) => ExitCode::from(2),
            Err(failure) => failed(&failure),
        },
        Command::Openapi => match scruple::transport::rest::openapi().to_pretty_json() {
            Ok(text) => match emit(&format!("{text}\n")) {
                Ok(()) => ExitCode::SUCCESS,
                Err(failure) => failed(&failure),
            },
            Err(e) => {
                let _ = writeln!(std::io::stderr(), "scruple: {e}");
                ExitCode::FAILURE
            }
        },
        Command::Serve(args) => {
            let config = match args.into_config() {
                Ok(config) => config,
                Err(e) => {
                    eprintln!("scruple: {e}");
                    return ExitCode::from(2);
                }
            };
            let app = match Application::build(config).await {
                Ok(app) => app,
                Err(e) => {
                    tracing::error!(error = %e, "cannot start");
                    eprintln!("scruple: {e}");
                    return ExitCode::FAILURE;
                }
            };
            match app.local_addr() {
                Ok(addr) => {
                    let mut stdout = std::io::stdout().lock();
                    let _ = writeln!(stdout, "listening on {addr}");
                    let _ = stdout.flush();
                }
                Err(e) => {
                    eprintln!("scruple: {e}");
                    return ExitCode::FAILURE;
                }
            }
            if let Err(e) = app.run_until(shutdown_signal()).await {
                eprintln!("scruple: {e}");
                return ExitCode::FAILURE;
            }
            ExitCode::SUCCESS
        }
    }
}
