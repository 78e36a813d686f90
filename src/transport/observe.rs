//! Per-request observation for both transports: the request counter and latency histogram by
//! route template, and the span every log line of a request carries (with its request id).
//!
//! Must not: label or log a request's content: routes are templates (or a gRPC method that
//! exists), never raw paths an attacker could multiply; methods are the standard ones or
//! `other`, statuses the ones the service answers with; the words stay out of spans.

use std::collections::HashSet;
use std::sync::Arc;
use std::time::Instant;

use axum::extract::{MatchedPath, Request, State};
use axum::http::Method;
use axum::middleware::Next;
use axum::response::Response;
use prost::Message;

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

pub async fn observe(State(observer): State<Arc<Observer>>, mut request: Request, next: Next) -> Response {
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
    metrics
        .latency
        .get_or_create(&RouteLabels {
            route: route.clone(),
            method,
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
