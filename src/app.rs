//! Assembling and running the service: configuration, the store, the router, the listener.
//!
//! Owns: startup order (store open and migrated before the port answers) and graceful shutdown.
//! Must not: hold request logic.

use std::future::Future;
use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;

use tokio::net::TcpListener;
use tower::Layer;
use tower::util::Either;

use crate::core::Core;
use crate::core::{DEFAULT_LEASE_MS, MAX_LEASE_MS, RequestLimits, Settings};
use crate::error::Error;
use crate::metrics::Metrics;
use crate::storage::{self, NormStore, StoreError};
use crate::transport::admission::{self, Admission, AdmissionConfig};
use crate::transport::auth::{LabelledSecret, Tokens};
use crate::transport::conn::{self, ConnConfig, Served};
use crate::transport::cors::CorsOrigins;
use crate::transport::tls::{Tls, TlsFiles};
use crate::transport::{AppState, Shared, grpc, observe, rest};

pub use crate::core::DEFAULT_MAX_BODY_BYTES;

#[derive(Clone, Debug)]
pub struct Config {
    /// `host:port`; port 0 picks a free one.
    pub listen: String,
    /// `sqlite://path` (created if missing), `sqlite::memory:`, or `postgres://user:pw@host/db`.
    pub database_url: String,
    /// Write token, labelled `admin` in the audit trail (`Debug` never shows it: see `auth`).
    pub admin_token: Option<Secret>,
    /// More write tokens, each with its label.
    pub curator_tokens: Vec<LabelledSecret>,
    /// Read-only tokens: once any is set, reading norms, verbs and the audit trail needs a token.
    pub reader_tokens: Vec<LabelledSecret>,
    pub max_body_bytes: usize,
    pub limits: RequestLimits,
    pub admission: AdmissionConfig,
    /// Log the human's words, the speaker and the robot's answer with each decision (debug).
    pub log_utterances: bool,
    /// Serve REST and gRPC over TLS with this certificate and key; cleartext (HTTP/1.1 and h2c)
    /// without.
    pub tls: Option<TlsFiles>,
    /// Connection limits and timeouts, and the drain deadline.
    pub connections: ConnConfig,
    /// How long the stored versions are trusted before they are read again; every write waits
    /// it out before it is acknowledged (see `Settings::lease`).
    pub lease: Duration,
    /// The browser origins that may call the REST API from a page (`--cors-origin`); none: off.
    pub cors: Option<CorsOrigins>,
}

impl Config {
    /// Every default, listening on `listen` with the store at `database_url`.
    pub fn new(listen: impl Into<String>, database_url: impl Into<String>) -> Config {
        Config {
            listen: listen.into(),
            database_url: database_url.into(),
            admin_token: None,
            curator_tokens: Vec::new(),
            reader_tokens: Vec::new(),
            max_body_bytes: DEFAULT_MAX_BODY_BYTES,
            limits: RequestLimits::default(),
            admission: AdmissionConfig::default(),
            log_utterances: false,
            tls: None,
            connections: ConnConfig::default(),
            lease: Duration::from_millis(DEFAULT_LEASE_MS),
            cors: None,
        }
    }
}

/// A secret whose `Debug` is redacted, so a logged configuration never carries it.
#[derive(Clone, PartialEq, Eq)]
pub struct Secret(pub String);

impl std::fmt::Debug for Secret {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("<redacted>")
    }
}

#[derive(Debug, thiserror::Error)]
pub enum StartError {
    #[error("cannot listen on {addr}: {source}")]
    Listen { addr: String, source: std::io::Error },
    #[error(transparent)]
    Store(#[from] StoreError),
    #[error("cannot set up gRPC: {0}")]
    Grpc(Error),
    #[error("bad configuration: {0}")]
    Config(String),
    #[error("cannot set up TLS: {0}")]
    Tls(String),
}

/// A service bound to its port, ready to run.
pub struct Application {
    listener: TcpListener,
    router: Served,
    tls: Option<Tls>,
    connections: ConnConfig,
    store: Arc<dyn NormStore>,
    /// The record of this process's versions lease in the store, released once it has drained.
    lease: i64,
}

/// Who holds a lease, as an operator reading the store's `leases` table would look for it: the
/// host and the process id.
fn holder() -> String {
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap_or_default();
    let host = match host.trim() {
        "" => "an unknown host",
        host => host,
    };
    format!("{host}, process {}", std::process::id())
}

impl Application {
    /// Opens and migrates the store, then binds the port: once `build` returns, `/healthz` will
    /// answer 200.
    pub async fn build(config: Config) -> Result<Application, StartError> {
        let tokens = Tokens::new(
            config.admin_token.as_ref().map(|t| t.0.as_str()),
            &config.curator_tokens,
            &config.reader_tokens,
        )
        .map_err(StartError::Config)?;
        if config.admission.max_concurrent == 0 {
            return Err(StartError::Config("--max-concurrent must be at least 1".to_owned()));
        }
        config.connections.check().map_err(StartError::Config)?;
        if config.lease > Duration::from_millis(MAX_LEASE_MS) {
            return Err(StartError::Config(format!(
                "--versions-lease-ms must be at most {MAX_LEASE_MS} (every write waits it out)"
            )));
        }
        // Before the store, so that bad certificate files fail fast and touch nothing.
        let tls = config.tls.clone().map(Tls::load).transpose().map_err(StartError::Tls)?;
        let store = storage::open(&config.database_url).await?;
        // Recorded before this process first reads the versions (the gRPC router's first probe
        // does): a writer that reads the records after its commit counts this lease, and a
        // commit made before this record was readable comes before this process's first read.
        let lease = store.hold_lease(config.lease, &holder()).await?;
        match Application::serving(config, tokens, tls, store.clone(), lease).await {
            Ok(app) => Ok(app),
            Err(e) => {
                if let Err(release) = store.release_lease(lease).await {
                    tracing::warn!(error = %release, "the versions lease recorded for this process stays in the store");
                }
                Err(e)
            }
        }
    }

    /// The rest of [`Application::build`], once the store is open and this process's lease is
    /// recorded in it.
    async fn serving(
        config: Config,
        tokens: Tokens,
        tls: Option<Tls>,
        store: Arc<dyn NormStore>,
        lease: i64,
    ) -> Result<Application, StartError> {
        let metrics = Arc::new(Metrics::new());
        let state = AppState::new(Shared {
            core: Arc::new(Core::new(
                store.clone(),
                metrics.clone(),
                Settings {
                    limits: config.limits,
                    log_utterances: config.log_utterances,
                    lease: config.lease,
                },
            )),
            tokens: Arc::new(tokens),
            max_body_bytes: config.max_body_bytes,
            metrics: metrics.clone(),
        });
        let listener = TcpListener::bind(&config.listen)
            .await
            .map_err(|source| StartError::Listen {
                addr: config.listen.clone(),
                source,
            })?;
        Ok(Application {
            listener,
            router: one_port(state, Admission::new(config.admission, metrics), config.cors.as_ref()).await?,
            tls,
            connections: config.connections,
            store,
            lease,
        })
    }

    pub fn local_addr(&self) -> std::io::Result<SocketAddr> {
        self.listener.local_addr()
    }

    /// Serves until `shutdown` completes, then drains in-flight requests and returns, at the
    /// latest at the drain deadline (`--drain-timeout-ms`). Once drained, the process's lease
    /// record leaves the store: it answers no more requests, so no write need wait for it.
    pub async fn run_until(self, shutdown: impl Future<Output = ()> + Send + 'static) -> std::io::Result<()> {
        let Application {
            listener,
            router,
            tls,
            connections,
            store,
            lease,
        } = self;
        let served = conn::serve(listener, tls, router, connections, shutdown).await;
        if let Err(e) = store.release_lease(lease).await {
            tracing::warn!(error = %e, "the versions lease recorded for this process stays in the store: writes wait it out until it is deleted");
        }
        served
    }
}

/// REST and gRPC on one router. gRPC's routes bring a fallback that answers any path with
/// `grpc-status: 12`; the REST fallbacks set after the merge replace it, so an unknown REST path
/// is a 404 problem, while gRPC paths (`/package.Service/Method`) still reach tonic.
/// Around the router, outermost first: observing (a request id, the caller's `x-request-id` or a
/// fresh UUID, set and echoed on the response; the span carrying it; metrics), then admission.
/// A refused request is still traced and counted. They wrap the router itself, not its routes:
/// axum's `Router::layer` wraps every route in a boxed service each request clones and a boxed
/// future, and that level cost the paper's request about 1% of its instructions and 3-4% of its
/// instruction-cache misses (BENCHMARKS.md, twenty-first sitting).
async fn one_port(
    state: AppState,
    admission: Arc<Admission>,
    cors: Option<&CorsOrigins>,
) -> Result<Served, StartError> {
    let observer = observe::Observer::new(
        state.metrics.clone(),
        &grpc::SERVED_DESCRIPTOR_SETS,
        rest::openapi().paths.paths.into_keys(),
    );
    let grpc = grpc::router(state.clone()).await.map_err(StartError::Grpc)?;
    let router = rest::router(state)
        .merge(grpc)
        .fallback(|| async { Error::NoRoute })
        .method_not_allowed_fallback(|| async { Error::MethodNotAllowed });
    let admitted = admission::AdmitLayer(admission).layer(router);
    let browsers = match cors {
        Some(origins) => Either::Left(origins.layer().layer(admitted)),
        None => Either::Right(admitted),
    };
    Ok(observe::ObserveLayer::new(observer).layer(browsers))
}
