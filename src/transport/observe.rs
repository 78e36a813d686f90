//! Per-request observation for both transports: the request counter and latency histogram by
//! route template, and the span every log line of a request carries (with its request id): one
//! layer, so that a request is wrapped, timed and labelled once.
//!
//! Must not: label or log a request's content: routes are templates (or a gRPC method that
//! exists), never raw paths an attacker could multiply; methods are the standard ones or
//! `other`, statuses the ones the service answers with; the words stay out of spans.

use rustc_hash::FxHashSet;
use std::convert::Infallible;
use std::future::Future;
use std::pin::Pin;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::task::{Context, Poll};
use std::time::Instant;

use axum::extract::Request;
use axum::http::{HeaderName, HeaderValue, Method};
use axum::response::Response;
use prost::Message;
use tracing::Instrument;

use crate::metrics::{Metrics, RequestLabels, RouteLabels, Status};

/// The header a request id travels in, both ways. A `HeaderName`, not text: looking a header up
/// by text parses the name first, on every request.
pub const REQUEST_ID: HeaderName = HeaderName::from_static("x-request-id");

/// Where a failed gRPC call's code is, in the answer's head.
const GRPC_STATUS: HeaderName = HeaderName::from_static("grpc-status");

/// What the observing layer needs: the metrics, and the gRPC methods that exist (a gRPC path is
/// a label only when it names one of them, whatever the answer). Both sets are looked up on
/// every request and filled only here, from the binary's own names, so FxHash, not SipHash: a
/// client's path is only ever looked up, never inserted.
pub struct Observer {
    pub metrics: Arc<Metrics>,
    grpc_methods: FxHashSet<Arc<str>>,
    /// The router's route templates by path, each text kept once, so that labelling a request
    /// copies none: the REST routes, and gRPC's one a service (`/{service}/{*rest}`, as tonic
    /// routes it), which a request without gRPC's content type is labelled with. The layer runs
    /// before the router (no boxed level for it on every route), so it finds the template as
    /// the router will: the same matcher, on the same path.
    routes: matchit::Router<Arc<str>>,
    unmatched: Arc<str>,
}

impl Observer {
    /// `descriptor_sets`: the encoded `FileDescriptorSet` of every gRPC service served; `routes`:
    /// the REST route templates.
    pub fn new(
        metrics: Arc<Metrics>,
        descriptor_sets: &[&[u8]],
        routes: impl IntoIterator<Item = String>,
    ) -> Arc<Observer> {
        let mut grpc_methods = FxHashSet::default();
        let mut templates: Vec<String> = routes.into_iter().collect();
        for encoded in descriptor_sets {
            // The sets are compiled into the binary; one that does not decode names no method.
            let Ok(set) = prost_types::FileDescriptorSet::decode(*encoded) else {
                continue;
            };
            for file in &set.file {
                let package = file.package();
                for service in &file.service {
                    let name = match package {
                        "" => service.name().to_owned(),
                        package => format!("{package}.{}", service.name()),
                    };
                    for method in &service.method {
                        grpc_methods.insert(Arc::from(format!("/{name}/{}", method.name())));
                    }
                    templates.push(format!("/{name}/{{*rest}}"));
                }
            }
        }
        templates.sort_unstable();
        templates.dedup();
        let mut matcher = matchit::Router::new();
        for template in templates {
            // The router took every one of these templates with this matcher, so none
            // conflicts (a unit test checks each labels itself); if one did, its requests
            // would be counted as unmatched, never as another route.
            let label = Arc::from(template.as_str());
            if let Err(e) = matcher.insert(template, label) {
                tracing::warn!("route template not labelled: {e}");
            }
        }
        Arc::new(Observer {
            metrics,
            grpc_methods,
            routes: matcher,
            unmatched: Arc::from("unmatched"),
        })
    }

    /// The template of the route a path reaches, as the router will match it.
    fn template(&self, path: &str) -> Option<Arc<str>> {
        self.routes.at(path).ok().map(|found| found.value.clone())
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

/// The observing layer: gives each request its id (the caller's `x-request-id`, or a fresh one)
/// and echoes it on the answer, runs the request inside its span, and counts and times it.
/// A plain service, so that observing costs no boxed future and no copy of the service under it.
#[derive(Clone)]
pub struct ObserveLayer {
    observer: Arc<Observer>,
    ids: RequestIds,
}

impl ObserveLayer {
    pub fn new(observer: Arc<Observer>) -> ObserveLayer {
        ObserveLayer {
            observer,
            ids: RequestIds::new(),
        }
    }
}

impl<S> tower::Layer<S> for ObserveLayer {
    type Service = Observe<S>;

    fn layer(&self, inner: S) -> Observe<S> {
        Observe {
            inner,
            layer: self.clone(),
        }
    }
}

#[derive(Clone)]
pub struct Observe<S> {
    inner: S,
    layer: ObserveLayer,
}

/// What is known of a request before its answer: enough to label and time the answer.
struct Asked {
    observer: Arc<Observer>,
    started: Instant,
    method: &'static str,
    /// For gRPC, the method path when it names one that exists, else `unmatched`; for REST,
    /// the route template, or `unmatched`.
    route: Arc<str>,
    grpc: bool,
    id: HeaderValue,
}

pin_project_lite::pin_project! {
    pub struct Observed<F> {
        #[pin]
        answer: tracing::instrument::Instrumented<F>,
        asked: Option<Asked>,
    }
}

impl<S> tower::Service<Request> for Observe<S>
where
    S: tower::Service<Request, Response = Response, Error = Infallible>,
{
    type Response = Response;
    type Error = Infallible;
    type Future = Observed<S::Future>;

    fn poll_ready(&mut self, cx: &mut Context<'_>) -> Poll<Result<(), Infallible>> {
        self.inner.poll_ready(cx)
    }

    fn call(&mut self, mut request: Request) -> Observed<S::Future> {
        let started = Instant::now();
        let id = match request.headers().get(&REQUEST_ID) {
            Some(id) => id.clone(),
            None => {
                let id = self.layer.ids.next();
                request.headers_mut().insert(REQUEST_ID, id.clone());
                id
            }
        };
        request.extensions_mut().insert(crate::transport::Arrival(started));
        let observer = &self.layer.observer;
        let grpc = crate::transport::is_grpc(&request);
        let route = if grpc {
            observer.grpc_methods.get(request.uri().path()).cloned()
        } else {
            observer.template(request.uri().path())
        };
        let span = span(&request, &id);
        let asked = Asked {
            observer: observer.clone(),
            started,
            method: method_label(request.method()),
            route: route.unwrap_or_else(|| observer.unmatched.clone()),
            grpc,
            id,
        };
        Observed {
            answer: self.inner.call(request).instrument(span),
            asked: Some(asked),
        }
    }
}

impl<F: Future<Output = Result<Response, Infallible>>> Future for Observed<F> {
    type Output = Result<Response, Infallible>;

    fn poll(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Self::Output> {
        let mut this = self.project();
        let Ok(mut response) = std::task::ready!(this.answer.as_mut().poll(cx));
        // Polled once more after its answer, a future has nothing left to count.
        let Some(asked) = this.asked.take() else {
            return Poll::Ready(Ok(response));
        };
        let status = if asked.grpc {
            // A good call's code is in the trailers, after this; a failed one's is in the head.
            Status::Grpc(
                response
                    .headers()
                    .get(&GRPC_STATUS)
                    .map_or("0", |v| grpc_status_label(v.as_bytes())),
            )
        } else {
            Status::Http(response.status().as_u16())
        };
        let seconds = asked.started.elapsed().as_secs_f64();
        // Entered, not named as the event's parent: a filter on the span's fields
        // (`[request{path=...}]=debug`) looks at the spans entered. Not entered when no
        // directive reaches debug at all.
        if tracing::level_enabled!(tracing::Level::DEBUG) {
            this.answer
                .span()
                .in_scope(|| tracing::debug!(status = %status, seconds, "answered"));
        }
        let metrics = &asked.observer.metrics;
        metrics.timed(
            &RouteLabels {
                route: asked.route.clone(),
                method: asked.method,
            },
            seconds,
        );
        metrics.answered(&RequestLabels {
            route: asked.route,
            method: asked.method,
            status,
        });
        if !response.headers().contains_key(&REQUEST_ID) {
            // Never indexed by HTTP/2's header compression: each id is sent once, and adding it
            // to the connection's table costs work and pushes out the headers that do repeat.
            let mut id = asked.id;
            id.set_sensitive(true);
            response.headers_mut().insert(REQUEST_ID, id);
        }
        Poll::Ready(Ok(response))
    }
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

    /// The next id, as a header value.
    fn next(&self) -> HeaderValue {
        let n = self.next.fetch_add(1, Ordering::Relaxed);
        // Hex digits and dashes only: always a valid header value.
        HeaderValue::from_bytes(&self.id(n)).unwrap_or(HeaderValue::from_static("unnumbered"))
    }

    /// The `n`th id: a four-round Feistel network over 122 bits (two halves of 61), a
    /// permutation whatever its round function, so distinct `n` (below 2^61) give distinct ids.
    fn id(&self, n: u64) -> [u8; 36] {
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
        let value = (high << 64) | low;
        // Written in place, most significant digit first: the id is made per request.
        let mut text = [b'-'; 36];
        let digits = (0..36).filter(|at| ![8, 13, 18, 23].contains(at));
        for (nibble, at) in (0..32).rev().zip(digits) {
            text[at] = b"0123456789abcdef"[((value >> (4 * nibble)) & 0xf) as usize];
        }
        text
    }
}

impl Default for RequestIds {
    fn default() -> Self {
        RequestIds::new()
    }
}

/// The span of one request: method, path and request id, nothing from the body. Given as text,
/// so that a log that defers them ([`crate::transport::logs`], see [`deferred`]) copies them
/// and formats them (as Display) only when a line is written inside the span.
fn span(request: &Request, id: &HeaderValue) -> tracing::Span {
    let id = id.to_str().unwrap_or_default();
    tracing::info_span!(
        "request",
        method = request.method().as_str(),
        path = request.uri().path(),
        request_id = id
    )
}

/// Whether `metadata` is the request span's, whose fields a log may defer.
pub fn deferred(metadata: &tracing::Metadata<'_>) -> bool {
    metadata.name() == "request" && metadata.target() == module_path!()
}

#[cfg(test)]
mod tests {
    use super::{Observer, RequestIds};
    use crate::metrics::Metrics;
    use std::sync::Arc;

    /// The layer runs before the router, so it must find the route the router will: each REST
    /// template (with its parameters), each gRPC service's catch-all, and nothing for a path no
    /// route takes.
    #[test]
    fn a_path_is_labelled_with_the_template_of_the_route_it_reaches() {
        let templates: Vec<String> = crate::transport::rest::openapi().paths.paths.into_keys().collect();
        let observer = Observer::new(
            Arc::new(Metrics::new()),
            &crate::transport::grpc::SERVED_DESCRIPTOR_SETS,
            templates.clone(),
        );
        let label = |path: &str| observer.template(path).map(|t| t.to_string());
        assert_eq!(label("/v1/clarify").as_deref(), Some("/v1/clarify"));
        assert_eq!(label("/v1/norms/7").as_deref(), Some("/v1/norms/{id}"));
        assert_eq!(label("/v1/norms/").as_deref(), None);
        assert_eq!(label("/v1/nowhere").as_deref(), None);
        assert_eq!(
            label("/scruple.v1.Clarifier/Clarify").as_deref(),
            Some("/scruple.v1.Clarifier/{*rest}")
        );
        assert!(observer.grpc_methods.contains("/scruple.v1.Clarifier/Clarify"));
        // Every REST template labels itself: none was lost to a conflict in the matcher.
        // So does each gRPC service's catch-all (health and reflection's too).
        for service in ["/grpc.health.v1.Health", "/grpc.reflection.v1.ServerReflection"] {
            assert_eq!(label(&format!("{service}/Any")), Some(format!("{service}/{{*rest}}")));
        }
        for template in templates {
            let path = template.replace("{id}", "1").replace("{name}", "get");
            assert_eq!(label(&path), Some(template.clone()), "{path}");
        }
    }

    #[test]
    fn request_ids_are_version_4_uuids_and_never_repeat() {
        let ids = RequestIds::new();
        let mut seen = std::collections::HashSet::new();
        for n in 0..20_000 {
            let id = String::from_utf8(ids.id(n).to_vec()).unwrap();
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
        let tail = |n| u64::from_str_radix(std::str::from_utf8(&ids.id(n)[24..]).unwrap(), 16).unwrap();
        assert!((0..1000).all(|n| tail(n + 1).wrapping_sub(tail(n)) != 1));
        // Another process draws another key.
        assert_ne!(RequestIds::new().id(0), ids.id(0));
    }
}
