//! Admission control: at most so many requests are worked on at once; the next ones wait in a
//! bounded queue for a bounded time; past that, the answer is 503 with `Retry-After` (gRPC:
//! UNAVAILABLE), so an overload slows callers down instead of collapsing the service.
//!
//! Must not: hold a request's work itself, or queue the probes (`/healthz`, gRPC health), which
//! must answer even under load.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use axum::extract::{Request, State};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use tokio::sync::Semaphore;

use crate::error::Error;

/// Defaults for `--max-concurrent`, `--max-queued` and `--queue-timeout-ms`: 128 clients at once
/// are all served (64 at work, the rest queued) without a 503.
pub const DEFAULT_MAX_CONCURRENT: usize = 64;
pub const DEFAULT_MAX_QUEUED: usize = 1024;
pub const DEFAULT_QUEUE_TIMEOUT_MS: u64 = 10_000;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AdmissionConfig {
    /// Requests worked on at once (≥ 1).
    pub max_concurrent: usize,
    /// Requests waiting for a turn; one more is refused at once.
    pub max_queued: usize,
    /// Longest wait for a turn before the request is refused.
    pub queue_timeout: Duration,
}

impl Default for AdmissionConfig {
    fn default() -> Self {
        AdmissionConfig {
            max_concurrent: DEFAULT_MAX_CONCURRENT,
            max_queued: DEFAULT_MAX_QUEUED,
            queue_timeout: Duration::from_millis(DEFAULT_QUEUE_TIMEOUT_MS),
        }
    }
}

pub struct Admission {
    metrics: Arc<crate::metrics::Metrics>,
    permits: Semaphore,
    waiting: AtomicUsize,
    config: AdmissionConfig,
}

/// Seconds a refused caller is told to wait.
const RETRY_AFTER_S: u64 = 1;

impl Admission {
    pub fn new(config: AdmissionConfig, metrics: Arc<crate::metrics::Metrics>) -> Arc<Admission> {
        Arc::new(Admission {
            metrics,
            permits: Semaphore::new(config.max_concurrent.max(1)),
            waiting: AtomicUsize::new(0),
            config,
        })
    }
}

/// Probes (and scrapes) answer whatever the load: a liveness check that queues behind work would
/// restart a healthy, busy replica, and an overload is when metrics matter most.
fn is_probe(path: &str) -> bool {
    path == "/healthz" || path == "/metrics" || path.starts_with("/grpc.health.v1.Health/")
}

fn is_grpc(request: &Request) -> bool {
    request
        .headers()
        .get(axum::http::header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|t| t.starts_with("application/grpc"))
}

/// Decrements the waiting count however the wait ends (a turn, a timeout, a dropped request).
struct Waiting<'a>(&'a AtomicUsize);

impl Drop for Waiting<'_> {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::AcqRel);
    }
}

pub async fn admit(State(admission): State<Arc<Admission>>, request: Request, next: Next) -> Response {
    if is_probe(request.uri().path()) {
        return next.run(request).await;
    }
    let permit = match admission.permits.try_acquire() {
        Ok(permit) => permit,
        Err(_) => {
            let queued = admission.waiting.fetch_add(1, Ordering::AcqRel);
            let _waiting = Waiting(&admission.waiting);
            if queued >= admission.config.max_queued {
                return refuse(&admission, &request);
            }
            match tokio::time::timeout(admission.config.queue_timeout, admission.permits.acquire()).await {
                Ok(Ok(permit)) => permit,
                // Timed out, or the semaphore closed (never: it is not closed while serving).
                Ok(Err(_)) | Err(_) => return refuse(&admission, &request),
            }
        }
    };
    let response = next.run(request).await;
    drop(permit);
    response
}

fn refuse(admission: &Admission, request: &Request) -> Response {
    admission.metrics.overloaded.inc();
    let error = Error::Overloaded {
        retry_after_s: RETRY_AFTER_S,
    };
    if is_grpc(request) {
        tonic::Status::from(error).into_http::<axum::body::Body>()
    } else {
        error.into_response()
    }
}
