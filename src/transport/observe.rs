//! Per-request observation for both transports: the request counter and latency histogram by
//! route template, and the span every log line of a request carries (with its request id): one
//! layer, so that a request is wrapped, timed and labelled once.
//!
//! Must not: label or log a request's content: routes are templates (or a gRPC method that
//! exists), never raw paths an attacker could multiply; methods are the standard ones or
//! `other`, statuses the ones the service answers with; the words stay out of spans.

use std::collections::HashSet;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use axum::extract::{MatchedPath, Request, State};
use axum::http::Method;
use axum::middleware::Next;
use axum::response::Response;
use prost::Message;
use tracing::Instrument;

use crate::metrics::{Metrics, RequestLabels, RouteLabels};

/// The header a request id travels in, both ways.
pub const REQUEST_ID: &str = "x-request-id";

/// What the observing layer needs: the metrics, and the gRPC methods that exist (a gRPC path is
/// a label only when it names one of them, whatever the answer).
pub struct Observer {
    pub metrics: Arc<Metrics>,
    grpc_methods: HashSet<String>,
}

impl Observer {
    /// `descriptor_sets`: the encoded `FileDescriptorSet` of every gRPC service served.
    pub fn new(metrics: Arc<Metrics>, descriptor_sets: &[&[u8]]) -> Arc<Observer> {
        let mut grpc_methods = HashSet::new();
        for encoded in descriptor_sets {
            // The sets are compiled into the binary; one that does not decode names no method.
            let Ok(set) = prost_types::FileDescriptorSet::decode(*encoded) else {
                continue;
            };
            for file in &set.file {
                let package = file.package();
                for service in &file.service {
                    for method in &service.method {
                        let service = match package {
                            "" => service.name().to_owned(),
                            package => format!("{package}.{}", service.name()),
                        };
                        grpc_methods.insert(format!("/{service}/{}", method.name()));
                    }
                }
            }
        }
        Arc::new(Observer { metrics, grpc_methods })
    }
}

/// The method as a label: the nine of RFC 9110 (with PATCH); any other is `other`, so that
/// made-up methods cannot multiply the series.
pub fn method_label(method: &Method) -> &'static str {
    match *method {
        Method::GET => "GET",
        Method::HEAD => "HEAD",
        Method::POST => "POST",
        Method::PUT => "PUT",
        Method::DELETE => "DELETE",
        Method::PATCH => "PATCH",
        Method::OPTIONS => "OPTIONS",
        Method::CONNECT => "CONNECT",
        Method::TRACE => "TRACE",
        _ => "other",
    }
}

/// A `grpc-status` as a label: a code of the gRPC spec (0..=16), else `other`.
fn grpc_status_label(value: &[u8]) -> &'static str {
    const CODES: [&str; 17] = [
        "0", "1", "2", "3", "4", "5", "6", "7", "8", "9", "10", "11", "12", "13", "14", "15", "16",
    ];
    std::str::from_utf8(value)
        .ok()
        .and_then(|text| CODES.iter().find(|code| **code == text))
        .copied()
        .unwrap_or("other")
}

/// Counts and times each request, inside its span: every log line of the request carries it.
pub async fn observe(State(observer): State<Arc<Observer>>, request: Request, next: Next) -> Response {
    let span = span(&request);
    measured(observer, request, next).instrument(span).await
}

async fn measured(observer: Arc<Observer>, mut request: Request, next: Next) -> Response {
    let started = Instant::now();
    request.extensions_mut().insert(crate::transport::Arrival(started));
    let method = method_label(request.method());
    let grpc = request
        .headers()
        .get(axum::http::header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|t| t.starts_with("application/grpc"));
    let matched = request.extensions().get::<MatchedPath>().map(|m| m.as_str().to_owned());
    let known_grpc_method = grpc && observer.grpc_methods.contains(request.uri().path());
    let path = known_grpc_method.then(|| request.uri().path().to_owned());
    let response = next.run(request).await;
    let (route, status) = if grpc {
        // A good call's code is in the trailers, after this; a failed one's is in the head.
        let status = response
            .headers()
            .get("grpc-status")
            .map_or("0", |v| grpc_status_label(v.as_bytes()));
        (path.unwrap_or_else(|| "unmatched".to_owned()), status.to_owned())
    } else {
        let route = matched.unwrap_or_else(|| "unmatched".to_owned());
        (route, response.status().as_u16().to_string())
    };
    let metrics = &observer.metrics;
    let seconds = started.elapsed().as_secs_f64();
    tracing::debug!(status = status.as_str(), seconds, "answered");
    metrics
        .latency
        .get_or_create(&RouteLabels {
            route: route.clone(),
            method,
        })
        .observe(seconds);
    metrics
        .requests
        .get_or_create(&RequestLabels { route, method, status })
        .inc();
    response
}

/// Fresh request ids: UUID-shaped (version 4, RFC 9562 §5.4). The `n`th id is `n` under a
/// permutation keyed once per process, so ids never repeat within a process, cannot be told
/// from random ones, and do not tell a client how many requests came between two of its own.
/// A system random read per request (what a v4 UUID generator makes) is not spent on them.
#[derive(Clone)]
pub struct RequestIds {
    /// SipHash keys drawn from the system's randomness: the round function of the permutation.
    keys: std::collections::hash_map::RandomState,
    next: Arc<AtomicU64>,
}

/// Half of an id's 122 free bits.
const HALF: u32 = 61;
const HALF_MASK: u128 = (1 << HALF) - 1;

impl RequestIds {
    pub fn new() -> RequestIds {
        RequestIds {
            keys: std::collections::hash_map::RandomState::new(),
            next: Arc::new(AtomicU64::new(0)),
        }
    }

    /// The `n`th id: a four-round Feistel network over 122 bits (two halves of 61), a
    /// permutation whatever its round function, so distinct `n` (below 2^61) give distinct ids.
    fn id(&self, n: u64) -> String {
        use std::hash::BuildHasher;
        let (mut left, mut right) = (0u128, u128::from(n));
        for round in 0..4u8 {
            let f = u128::from(self.keys.hash_one((round, right as u64)));
            (left, right) = (right, (left ^ f) & HALF_MASK);
        }
        let bits = (left << HALF) | right;
        // 60 bits before the variant, 62 after; the version nibble within the first part.
        let (a, b) = (bits >> 62, bits & ((1 << 62) - 1));
        let high = ((a >> 12) << 16) | (0x4 << 12) | (a & 0xfff);
        let low = (0x2 << 62) | b;
        let hex = format!("{:032x}", (high << 64) | low);
        format!(
            "{}-{}-{}-{}-{}",
            &hex[..8],
            &hex[8..12],
            &hex[12..16],
            &hex[16..20],
            &hex[20..]
        )
    }
}

impl Default for RequestIds {
    fn default() -> Self {
        RequestIds::new()
    }
}

impl tower_http::request_id::MakeRequestId for RequestIds {
    fn make_request_id<B>(&mut self, _: &axum::http::Request<B>) -> Option<tower_http::request_id::RequestId> {
        let n = self.next.fetch_add(1, Ordering::Relaxed);
        let id = axum::http::HeaderValue::from_str(&self.id(n)).ok()?;
        Some(tower_http::request_id::RequestId::new(id))
    }
}

/// The span of one request: method, path and request id, nothing from the body.
fn span(request: &axum::http::Request<axum::body::Body>) -> tracing::Span {
    let id = request
        .headers()
        .get(REQUEST_ID)
        .and_then(|v| v.to_str().ok())
        .unwrap_or_default();
    tracing::info_span!("request", method = %request.method(), path = %request.uri().path(), request_id = %id)
}

#[cfg(test)]
mod tests {
    use super::RequestIds;

    #[test]
    fn request_ids_are_version_4_uuids_and_never_repeat() {
        let ids = RequestIds::new();
        let mut seen = std::collections::HashSet::new();
        for n in 0..20_000 {
            let id = ids.id(n);
            let groups: Vec<&str> = id.split('-').collect();
            assert_eq!(
                groups.iter().map(|g| g.len()).collect::<Vec<_>>(),
                [8, 4, 4, 4, 12],
                "{id}"
            );
            assert!(
                id.chars()
                    .all(|c| c == '-' || c.is_ascii_hexdigit() && !c.is_ascii_uppercase())
            );
            assert!(groups[2].starts_with('4'), "version nibble of {id}");
            assert!(
                matches!(groups[3].as_bytes()[0], b'8' | b'9' | b'a' | b'b'),
                "variant of {id}"
            );
            assert!(seen.insert(id));
        }
        // Consecutive ids share no run a client could count requests by.
        let tail = |n| u64::from_str_radix(&ids.id(n)[24..], 16).unwrap();
        assert!((0..1000).all(|n| tail(n + 1).wrapping_sub(tail(n)) != 1));
        // Another process draws another key.
        assert_ne!(RequestIds::new().id(0), ids.id(0));
    }
}
