//! Per-request observation for both transports: the request counter and latency histogram by
//! route template, and the span every log line of a request carries (with its request id).
//!
//! Must not: label or log a request's content: routes are templates (or a gRPC method that
//! exists), never raw paths an attacker could multiply; the words stay out of spans.

use std::sync::Arc;
use std::time::Instant;

use axum::extract::{MatchedPath, Request, State};
use axum::middleware::Next;
use axum::response::Response;

use crate::metrics::{Metrics, RequestLabels, RouteLabels};

/// The header a request id travels in, both ways.
pub const REQUEST_ID: &str = "x-request-id";

pub async fn observe(State(metrics): State<Arc<Metrics>>, mut request: Request, next: Next) -> Response {
    let started = Instant::now();
    request.extensions_mut().insert(crate::transport::Arrival(started));
    let method = request.method().as_str().to_owned();
    let grpc = request
        .headers()
        .get(axum::http::header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|t| t.starts_with("application/grpc"));
    let matched = request.extensions().get::<MatchedPath>().map(|m| m.as_str().to_owned());
    let path = request.uri().path().to_owned();
    let response = next.run(request).await;
    let grpc_status = grpc
        .then(|| response.headers().get("grpc-status").and_then(|v| v.to_str().ok()))
        .flatten()
        .map(str::to_owned);
    let (route, status) = if grpc {
        // A gRPC method path is a label only when it names a method that exists (a status other
        // than UNIMPLEMENTED); a failed call's code is in the head, a good one's in the trailers.
        let known = matched.is_some() && grpc_status.as_deref() != Some("12");
        let route = if known { path } else { "unmatched".to_owned() };
        (route, grpc_status.unwrap_or_else(|| "0".to_owned()))
    } else {
        let route = matched.unwrap_or_else(|| "unmatched".to_owned());
        (route, response.status().as_u16().to_string())
    };
    metrics
        .latency
        .get_or_create(&RouteLabels {
            route: route.clone(),
            method: method.clone(),
        })
        .observe(started.elapsed().as_secs_f64());
    metrics
        .requests
        .get_or_create(&RequestLabels { route, method, status })
        .inc();
    response
}

/// The span of one request: method, path and request id, nothing from the body.
pub fn span(request: &axum::http::Request<axum::body::Body>) -> tracing::Span {
    let id = request
        .headers()
        .get(REQUEST_ID)
        .and_then(|v| v.to_str().ok())
        .unwrap_or_default();
    tracing::info_span!("request", method = %request.method(), path = %request.uri().path(), request_id = %id)
}

/// One debug line per decision; the words, the speaker and the answer only when the operator
/// turned `--log-utterances` on.
pub fn log_decision(
    app: &crate::transport::AppState,
    decision: &crate::engine::Decision,
    text: Option<&str>,
    speaker: Option<&str>,
) {
    let kind = decision.kind.as_str();
    let readings = decision.interpretations.len();
    if app.log_utterances {
        tracing::debug!(decision = kind, readings, text, speaker, utterance = %decision.utterance, "decided");
    } else {
        tracing::debug!(decision = kind, readings, "decided");
    }
}
