//! Assembling and running the service: configuration, the store, the router, the listener.
//!
//! Owns: startup order (store open and migrated before the port answers) and graceful shutdown.
//! Must not: hold request logic.

use std::future::Future;
use std::net::SocketAddr;
use std::sync::Arc;

use axum::serve::ListenerExt;
use tokio::net::TcpListener;

use tower_http::trace::TraceLayer;

use crate::core::Core;
use crate::error::Error;
use crate::storage::{SqliteStore, StoreError};
use crate::transport::{AppState, grpc, rest};

/// Default for `--max-body-bytes`: generous for scenes of thousands of objects.
pub const DEFAULT_MAX_BODY_BYTES: usize = 4 * 1024 * 1024;

#[derive(Clone, Debug)]
pub struct Config {
    /// `host:port`; port 0 picks a free one.
    pub listen: String,
    /// `sqlite://path` (created if missing) or `sqlite::memory:`.
    pub database_url: String,
    pub admin_token: Option<String>,
    pub max_body_bytes: usize,
}

#[derive(Debug, thiserror::Error)]
pub enum StartError {
    #[error("cannot listen on {addr}: {source}")]
    Listen { addr: String, source: std::io::Error },
    #[error(transparent)]
    Store(#[from] StoreError),
    #[error("cannot set up gRPC: {0}")]
    Grpc(Error),
}

/// A service bound to its port, ready to run.
pub struct Application {
    listener: TcpListener,
    router: axum::Router,
}

impl Application {
    /// Opens and migrates the store, then binds the port: once `build` returns, `/healthz` will
    /// answer 200.
    pub async fn build(config: Config) -> Result<Application, StartError> {
        let store = SqliteStore::open(&config.database_url).await?;
        let state = AppState {
            core: Arc::new(Core::new(Arc::new(store))),
            admin_token: config.admin_token.filter(|t| !t.is_empty()).map(Arc::from),
            max_body_bytes: config.max_body_bytes,
        };
        let listener = TcpListener::bind(&config.listen)
            .await
            .map_err(|source| StartError::Listen {
                addr: config.listen.clone(),
                source,
            })?;
        Ok(Application {
            listener,
            router: one_port(state).await?,
        })
    }

    pub fn local_addr(&self) -> std::io::Result<SocketAddr> {
        self.listener.local_addr()
    }

    /// Serves until `shutdown` completes, then drains in-flight requests and returns.
    pub async fn run_until(self, shutdown: impl Future<Output = ()> + Send + 'static) -> std::io::Result<()> {
        // Small request/response exchanges must not wait on Nagle's algorithm: without
        // TCP_NODELAY, gRPC calls stall ~40 ms on delayed ACKs.
        let listener = self.listener.tap_io(|tcp| {
            if let Err(e) = tcp.set_nodelay(true) {
                tracing::warn!(error = %e, "cannot set TCP_NODELAY");
            }
        });
        axum::serve(listener, self.router)
            .with_graceful_shutdown(shutdown)
            .await
    }
}

/// REST and gRPC on one router. gRPC's routes bring a fallback that answers any path with
/// `grpc-status: 12`; the REST fallbacks set after the merge replace it, so an unknown REST path
/// is a 404 problem, while gRPC paths (`/package.Service/Method`) still reach tonic.
async fn one_port(state: AppState) -> Result<axum::Router, StartError> {
    let grpc = grpc::router(state.clone()).await.map_err(StartError::Grpc)?;
    Ok(rest::router(state)
        .merge(grpc)
        .fallback(|| async { Error::NoRoute })
        .method_not_allowed_fallback(|| async { Error::MethodNotAllowed })
        .layer(TraceLayer::new_for_http()))
}
