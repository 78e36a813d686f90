//! Admission control: at most so many requests are worked on at once; the next ones wait in a
//! bounded queue for a bounded time; past that, the answer is 503 with `Retry-After` (gRPC:
//! UNAVAILABLE), so an overload slows callers down instead of collapsing the service.
//!
//! Must not: hold a request's work itself, or queue the probes (`/healthz`, gRPC health), which
//! must answer even under load.

use std::convert::Infallible;
use std::future::Future;
use std::pin::Pin;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::task::{Context, Poll};
use std::time::Duration;

use axum::extract::Request;
use axum::response::{IntoResponse, Response};
use tokio::sync::{OwnedSemaphorePermit, Semaphore};

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
    permits: Arc<Semaphore>,
    waiting: AtomicUsize,
    config: AdmissionConfig,
}

/// Seconds a refused caller is told to wait.
const RETRY_AFTER_S: u64 = 1;

impl Admission {
    pub fn new(config: AdmissionConfig, metrics: Arc<crate::metrics::Metrics>) -> Arc<Admission> {
        Arc::new(Admission {
            metrics,
            permits: Arc::new(Semaphore::new(config.max_concurrent.max(1))),
            waiting: AtomicUsize::new(0),
            config,
        })
    }
}

/// Probes (and scrapes) answer whatever the load: a liveness check that queues behind work would
/// restart a healthy, busy replica, and an overload is when metrics matter most.
fn is_probe(path: &str) -> bool {
    matches!(path, "/healthz" | "/livez" | "/readyz" | "/metrics") || path.starts_with("/grpc.health.v1.Health/")
}

/// Decrements the waiting count however the wait ends (a turn, a timeout, a dropped request).
struct Waiting<'a>(&'a AtomicUsize);

impl Drop for Waiting<'_> {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::AcqRel);
    }
}

/// The layer that admits each request (see the module), written as a plain service so that a
/// request with a turn free at once costs a permit and nothing else: no boxed future, no copy
/// of the service under it.
#[derive(Clone)]
pub struct AdmitLayer(pub Arc<Admission>);

impl<S> tower::Layer<S> for AdmitLayer {
    type Service = Admit<S>;

    fn layer(&self, inner: S) -> Admit<S> {
        Admit {
            inner,
            admission: self.0.clone(),
        }
    }
}

#[derive(Clone)]
pub struct Admit<S> {
    inner: S,
    admission: Arc<Admission>,
}

type Waited = Pin<Box<dyn Future<Output = Result<Response, Infallible>> + Send>>;

pin_project_lite::pin_project! {
    /// A request with its turn (held until its answer is made), or one waiting for a turn.
    #[project = AdmittedProjection]
    pub enum Admitted<F> {
        Now { #[pin] answer: F, turn: Option<OwnedSemaphorePermit> },
        Queued { waited: Waited },
    }
}

impl<F: Future<Output = Result<Response, Infallible>>> Future for Admitted<F> {
    type Output = Result<Response, Infallible>;

    fn poll(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Self::Output> {
        match self.project() {
            AdmittedProjection::Now { answer, turn } => {
                let answer = std::task::ready!(answer.poll(cx));
                drop(turn.take());
                Poll::Ready(answer)
            }
            AdmittedProjection::Queued { waited } => waited.as_mut().poll(cx),
        }
    }
}

impl<S> tower::Service<Request> for Admit<S>
where
    S: tower::Service<Request, Response = Response, Error = Infallible> + Clone + Send + 'static,
    S::Future: Send + 'static,
{
    type Response = Response;
    type Error = Infallible;
    type Future = Admitted<S::Future>;

    fn poll_ready(&mut self, cx: &mut Context<'_>) -> Poll<Result<(), Infallible>> {
        self.inner.poll_ready(cx)
    }

    fn call(&mut self, request: Request) -> Admitted<S::Future> {
        if is_probe(request.uri().path()) {
            return Admitted::Now {
                answer: self.inner.call(request),
                turn: None,
            };
        }
        if let Ok(turn) = self.admission.permits.clone().try_acquire_owned() {
            return Admitted::Now {
                answer: self.inner.call(request),
                turn: Some(turn),
            };
        }
        // The service made ready is the one that is called, after the wait (tower's contract).
        let ready = self.inner.clone();
        let inner = std::mem::replace(&mut self.inner, ready);
        Admitted::Queued {
            waited: Box::pin(queued(self.admission.clone(), inner, request)),
        }
    }
}

/// A request that found every turn taken: it waits for one in the bounded queue, or is refused.
async fn queued<S>(admission: Arc<Admission>, mut inner: S, request: Request) -> Result<Response, Infallible>
where
    S: tower::Service<Request, Response = Response, Error = Infallible>,
{
    let turn = {
        let queued = admission.waiting.fetch_add(1, Ordering::AcqRel);
        let _waiting = Waiting(&admission.waiting);
        if queued >= admission.config.max_queued {
            return Ok(refuse(&admission, &request));
        }
        match tokio::time::timeout(
            admission.config.queue_timeout,
            admission.permits.clone().acquire_owned(),
        )
        .await
        {
            Ok(Ok(turn)) => turn,
            // Timed out, or the semaphore closed (never: it is not closed while serving).
            Ok(Err(_)) | Err(_) => return Ok(refuse(&admission, &request)),
        }
    };
    let response = inner.call(request).await;
    drop(turn);
    response
}

fn refuse(admission: &Admission, request: &Request) -> Response {
    admission.metrics.overloaded.inc();
    let error = Error::Overloaded {
        retry_after_s: RETRY_AFTER_S,
    };
    if super::is_grpc(request) {
        tonic::Status::from(error).into_http::<axum::body::Body>()
    } else {
        error.into_response()
    }
}
