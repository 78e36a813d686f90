//! Transports: thin adapters that convert wire formats, call `core`, and convert back.
//!
//! Owns: what REST and gRPC share: the state handed to handlers, tokens and admission.
//! Must not: decide anything or validate domain input.

pub mod admission;
pub mod auth;
pub mod conn;
pub mod cors;
pub mod grpc;
pub mod logs;
pub mod observe;
pub mod rest;
pub mod tls;

use std::sync::Arc;

use crate::core::Core;

/// What every handler of either transport shares, behind one pointer: the router copies it
/// into each request, and a copy is then one count on one cache line.
#[derive(Clone)]
pub struct AppState(Arc<Shared>);

impl AppState {
    pub fn new(shared: Shared) -> AppState {
        AppState(Arc::new(shared))
    }
}

impl std::ops::Deref for AppState {
    type Target = Shared;

    fn deref(&self) -> &Shared {
        &self.0
    }
}

pub struct Shared {
    pub core: Arc<Core>,
    /// Who may read and change norms and verbs.
    pub tokens: Arc<auth::Tokens>,
    /// Largest REST request body accepted, bytes (gRPC messages likewise).
    pub max_body_bytes: usize,
    pub metrics: Arc<crate::metrics::Metrics>,
}

/// When a request arrived, stamped by the outermost observing layer: a decision's deadline
/// counts from here, so time spent queued and parsing the body is inside it.
#[derive(Clone, Copy, Debug)]
pub struct Arrival(pub std::time::Instant);

impl Arrival {
    /// The stamp in a request's extensions, or now when a caller built the request without it.
    pub fn of(extensions: &axum::http::Extensions) -> std::time::Instant {
        extensions
            .get::<Arrival>()
            .map_or_else(std::time::Instant::now, |a| a.0)
    }
}

/// Whether a request is a gRPC call (its content type is `application/grpc`, `+proto` or not):
/// how it must be answered, and how it is labelled.
pub fn is_grpc(request: &axum::extract::Request) -> bool {
    request
        .headers()
        .get(axum::http::header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|t| t.starts_with("application/grpc"))
}

/// Answers with more readings than this are converted and written on the blocking pool.
const LARGE_ANSWER: usize = 512;

/// A decision's answer, as `write` makes it: here, for an answer of at most [`LARGE_ANSWER`]
/// readings; else on the blocking pool (tens of megabytes of words take a runtime thread for
/// tens of milliseconds, and health checks and small decisions must not wait behind it). A
/// large decision is freed there too, after the answer is handed back: freeing 100,000 readings
/// is milliseconds the client need not wait for.
pub async fn answer<T: Send + 'static>(
    decision: crate::engine::Decision,
    write: impl FnOnce(&crate::engine::Decision) -> T + Send + 'static,
) -> Result<T, crate::error::Error> {
    if decision.interpretations.len() <= LARGE_ANSWER {
        return Ok(write(&decision));
    }
    let (answer, answered) = tokio::sync::oneshot::channel();
    tokio::task::spawn_blocking(move || {
        // A receiver gone means the client went away: the answer is dropped with the rest.
        let _ = answer.send(write(&decision));
        drop(decision);
    });
    answered
        .await
        .map_err(|_| crate::error::Error::Internal("writing the answer failed".to_owned()))
}
