//! Prometheus metrics: requests by route and status, latency, decisions by kind, readings per
//! request, norm-cache hits and refreshes, admission refusals.
//!
//! Owns: the registry and its OpenMetrics text. Must not: label anything with a request's
//! content (no words, speaker ids, object ids or raw paths: routes are templates), so label
//! sets stay few and nothing private reaches a scrape.

use std::sync::{Arc, OnceLock};

use prometheus_client::encoding::text::encode;
use prometheus_client::encoding::{EncodeLabelSet, EncodeLabelValue, LabelValueEncoder};
use prometheus_client::metrics::counter::Counter;
use prometheus_client::metrics::family::Family;
use prometheus_client::metrics::gauge::Gauge;
use prometheus_client::metrics::histogram::{Histogram, exponential_buckets};
use prometheus_client::registry::Registry;

#[derive(Clone, Debug, Hash, PartialEq, Eq, EncodeLabelSet)]
pub struct RequestLabels {
    /// The route template (`/v1/norms/{id}`), the gRPC method path, or `unmatched`: one of a
    /// few texts, shared rather than copied per request.
    pub route: Arc<str>,
    /// One of the standard methods, or `other`.
    pub method: &'static str,
    pub status: Status,
}

/// The HTTP status the service answered; for gRPC, the `grpc-status` code (0..=16, or
/// `other`) when the call failed in its head, else 0. Written as its number either way.
#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq)]
pub enum Status {
    Http(u16),
    Grpc(&'static str),
}

impl std::fmt::Display for Status {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Status::Http(code) => write!(f, "{code}"),
            Status::Grpc(code) => f.write_str(code),
        }
    }
}

impl EncodeLabelValue for Status {
    fn encode(&self, encoder: &mut LabelValueEncoder) -> Result<(), std::fmt::Error> {
        match self {
            Status::Http(code) => EncodeLabelValue::encode(code, encoder),
            Status::Grpc(code) => EncodeLabelValue::encode(code, encoder),
        }
    }
}

#[derive(Clone, Debug, Hash, PartialEq, Eq, EncodeLabelSet)]
pub struct RouteLabels {
    pub route: Arc<str>,
    /// One of the standard methods, or `other`.
    pub method: &'static str,
}

#[derive(Clone, Debug, Hash, PartialEq, Eq, EncodeLabelSet)]
pub struct DecisionLabels {
    pub kind: &'static str,
}

#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq)]
pub enum Cache {
    Norms,
    Library,
}

#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq)]
pub enum Outcome {
    /// The compiled value for the stored version was already in memory.
    Hit,
    /// The stored version had moved: reloaded and recompiled.
    Refresh,
}

#[derive(Clone, Debug, Hash, PartialEq, Eq, EncodeLabelSet)]
pub struct CacheLabels {
    /// `norms` or `library`.
    pub cache: &'static str,
    /// `hit` or `refresh`.
    pub outcome: &'static str,
}

type HistogramFamily<L> = Family<L, Histogram, fn() -> Histogram>;

fn latency() -> Histogram {
    // 100 µs .. ~6.5 s: an inline decision is tens of microseconds, a big one seconds.
    Histogram::new(exponential_buckets(0.0001, 2.0, 17))
}

pub struct Metrics {
    registry: Registry,
    pub requests: Family<RequestLabels, Counter>,
    pub latency: HistogramFamily<RouteLabels>,
    pub decisions: Family<DecisionLabels, Counter>,
    /// Readings simulated per decision (not counting those a limit left unsimulated).
    pub readings: Histogram,
    pub cache: Family<CacheLabels, Counter>,
    /// Each (cache, outcome) series of `cache`, looked up once, at its first count: counted on
    /// every request, so neither a lock nor a hash is spent on it after that.
    cache_series: [OnceLock<Counter>; 4],
    /// Requests refused by admission control (503 / UNAVAILABLE).
    pub overloaded: Counter,
    /// Decisions and checks being simulated right now; work whose client left stops within a
    /// step, so this falls back at once.
    pub in_flight: Gauge,
}

impl Default for Metrics {
    fn default() -> Self {
        Metrics::new()
    }
}

impl std::fmt::Debug for Metrics {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Metrics")
    }
}

impl Metrics {
    pub fn new() -> Metrics {
        let mut registry = Registry::with_prefix("scruple");
        let requests = Family::<RequestLabels, Counter>::default();
        registry.register(
            "http_requests",
            "Requests answered, by route template, method and status",
            requests.clone(),
        );
        let latency: HistogramFamily<RouteLabels> = Family::new_with_constructor(latency as fn() -> Histogram);
        registry.register(
            "http_request_duration_seconds",
            "Time from request to response head, by route template and method",
            latency.clone(),
        );
        let decisions = Family::<DecisionLabels, Counter>::default();
        registry.register("decisions", "Decisions made, by kind", decisions.clone());
        let readings = Histogram::new(exponential_buckets(1.0, 4.0, 9));
        registry.register(
            "readings_simulated",
            "Readings simulated per decision",
            readings.clone(),
        );
        let cache = Family::<CacheLabels, Counter>::default();
        registry.register(
            "knowledge_cache",
            "Norm-set and action-library lookups per request: hits, and refreshes after a stored version moved",
            cache.clone(),
        );
        let overloaded = Counter::default();
        registry.register(
            "overloaded",
            "Requests refused by admission control (503 with Retry-After, gRPC UNAVAILABLE)",
            overloaded.clone(),
        );
        let in_flight = Gauge::default();
        registry.register(
            "simulations_in_flight",
            "Decisions and checks being simulated now (abandoned ones stop within a step)",
            in_flight.clone(),
        );
        Metrics {
            in_flight,
            registry,
            requests,
            latency,
            decisions,
            readings,
            cache,
            cache_series: Default::default(),
            overloaded,
        }
    }

    pub fn cache(&self, cache: Cache, outcome: Outcome) {
        let labels = CacheLabels {
            cache: match cache {
                Cache::Norms => "norms",
                Cache::Library => "library",
            },
            outcome: match outcome {
                Outcome::Hit => "hit",
                Outcome::Refresh => "refresh",
            },
        };
        self.cache_series[cache as usize * 2 + outcome as usize]
            .get_or_init(|| self.cache.get_or_create(&labels).clone())
            .inc();
    }

    /// The OpenMetrics text exposition of every metric.
    pub fn render(&self) -> String {
        let mut text = String::new();
        // Writing to a String cannot fail.
        let _ = encode(&mut text, &self.registry);
        text
    }
}
