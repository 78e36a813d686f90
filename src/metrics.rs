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

/// How many label sets of one family are kept at hand; later ones are looked up in the family.
const HOT: usize = 32;

/// The series of the first [`HOT`] label sets a family is asked for, found by comparing labels
/// in order: no hash and no lock, where the family hashes its labels (SipHash) and takes its
/// map's lock on every count. A service asks for a few label sets again and again, and has
/// asked for them early (its routes, its statuses), so the label sets counted per request sit
/// in the first slots.
///
/// Invariant: a slot holds a clone of the family's own series (one shared value), so a count
/// through either is the same count, and each label set is in at most one slot: a lookup tries
/// the slots in order and claims the first empty one, so it finds a set already claimed before
/// any slot after it.
struct Hot<L, M> {
    slots: [OnceLock<(L, M)>; HOT],
}

impl<L, M> Default for Hot<L, M> {
    fn default() -> Self {
        Hot {
            slots: std::array::from_fn(|_| OnceLock::new()),
        }
    }
}

impl<L: Clone + Eq + std::hash::Hash, M: Clone> Hot<L, M> {
    /// Calls `record` with `labels`'s series in `family`, made if new.
    fn with<C>(&self, family: &Family<L, M, C>, labels: &L, record: impl FnOnce(&M))
    where
        C: prometheus_client::metrics::family::MetricConstructor<M>,
    {
        for slot in &self.slots {
            let (held, series) = slot.get_or_init(|| (labels.clone(), family.get_or_create(labels).clone()));
            if held == labels {
                return record(series);
            }
        }
        record(&family.get_or_create(labels));
    }
}

fn latency() -> Histogram {
    // 100 µs .. ~6.5 s: an inline decision is tens of microseconds, a big one seconds.
    Histogram::new(exponential_buckets(0.0001, 2.0, 17))
}

pub struct Metrics {
    registry: Registry,
    requests: Family<RequestLabels, Counter>,
    requests_hot: Hot<RequestLabels, Counter>,
    latency: HistogramFamily<RouteLabels>,
    latency_hot: Hot<RouteLabels, Histogram>,
    decisions: Family<DecisionLabels, Counter>,
    decisions_hot: Hot<DecisionLabels, Counter>,
    /// Readings simulated per decision (not counting those a limit left unsimulated).
    pub readings: Histogram,
    cache: Family<CacheLabels, Counter>,
    cache_hot: Hot<CacheLabels, Counter>,
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
            requests_hot: Hot::default(),
            latency,
            latency_hot: Hot::default(),
            decisions,
            decisions_hot: Hot::default(),
            readings,
            cache,
            cache_hot: Hot::default(),
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
        self.cache_hot.with(&self.cache, &labels, |c| {
            c.inc();
        });
    }

    /// Counts one answered request.
    pub fn answered(&self, labels: &RequestLabels) {
        self.requests_hot.with(&self.requests, labels, |c| {
            c.inc();
        });
    }

    /// Records the time, in seconds, from a request to its answer's head.
    pub fn timed(&self, labels: &RouteLabels, seconds: f64) {
        self.latency_hot.with(&self.latency, labels, |h| h.observe(seconds));
    }

    /// Counts one decision of `kind`.
    pub fn decided(&self, kind: &'static str) {
        self.decisions_hot.with(&self.decisions, &DecisionLabels { kind }, |c| {
            c.inc();
        });
    }

    /// The OpenMetrics text exposition of every metric.
    pub fn render(&self) -> String {
        let mut text = String::new();
        // Writing to a String cannot fail.
        let _ = encode(&mut text, &self.registry);
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Past the label sets kept at hand, counts go to the family itself; either way each label
    /// set has one series, and every count lands in it.
    #[test]
    fn every_label_set_counts_once_per_call_past_the_ones_at_hand() {
        let metrics = Metrics::new();
        let route: Arc<str> = Arc::from("/v1/clarify");
        let statuses: Vec<u16> = (200..200 + 2 * HOT as u16).collect();
        for round in 1..=3 {
            for &status in &statuses {
                metrics.answered(&RequestLabels {
                    route: route.clone(),
                    method: "POST",
                    status: Status::Http(status),
                });
            }
            let text = metrics.render();
            for status in &statuses {
                let line = format!(
                    "scruple_http_requests_total{{route=\"/v1/clarify\",method=\"POST\",status=\"{status}\"}} {round}\n"
                );
                assert!(text.contains(&line), "missing {line:?} in\n{text}");
            }
        }
        for kind in ["assume", "ask", "assume"] {
            metrics.decided(kind);
        }
        let text = metrics.render();
        assert!(text.contains("scruple_decisions_total{kind=\"assume\"} 2\n"), "{text}");
        assert!(text.contains("scruple_decisions_total{kind=\"ask\"} 1\n"), "{text}");
    }
}
