//! The service's own routes: probes (`/livez`, `/readyz`, `/healthz`), `/version`, the OpenAPI
//! document and the metrics. None reads the store or is queued behind load (see `admission`).
//!
//! Must not: answer anything about norms or decisions.

use std::sync::OnceLock;

use axum::Json;
use axum::extract::State;
use axum::http::{HeaderValue, header};
use axum::response::{IntoResponse, Response};
use serde::Serialize;
use utoipa::ToSchema;

use super::doc;
use crate::error::Error;
use crate::transport::AppState;

/// The crate's version, as `Cargo.toml` gives it.
const VERSION: &str = env!("CARGO_PKG_VERSION");
/// The commit built, when the build knew it (`build.rs`: `SCRUPLE_BUILD_COMMIT`, else git).
const COMMIT: Option<&str> = option_env!("SCRUPLE_COMMIT");

/// What is running.
#[derive(Serialize, ToSchema)]
pub struct VersionInfo {
    /// The service's version (semver).
    pub version: &'static str,
    /// The commit it was built from, when the build knew it.
    pub commit: Option<&'static str>,
    /// The newest migration of the store's schema this build applies (a migration's version,
    /// `YYYYMMDDNNNNNN`); every one up to it was found applied, or applied, at start.
    pub schema_version: i64,
}

#[utoipa::path(get, path = "/healthz", tag = "service",
    summary = "Readiness: a decision can be made (the last read of the norms and verbs succeeded)",
    description = "Reports the outcome of the last read of what a decision needs, by a request or by a probe at most a second old; it never reads the store itself, so it answers at once under any load. The same as `/readyz`.",
    responses(
        (status = 200, description = "Ready", body = doc::Health, example = json!({"status": "ok"})),
        doc::problems::Store,
    ))]
pub async fn healthz(State(app): State<AppState>) -> Result<Json<doc::Health>, Error> {
    ready(&app)
}

#[utoipa::path(get, path = "/readyz", tag = "service",
    summary = "Readiness, for an orchestrator: 200 when a decision can be made, else 503",
    description = "The same answer as `/healthz`: the outcome of the last read of the norms and verbs, at most a second old. Route traffic to a replica only while it answers 200.",
    responses(
        (status = 200, description = "Ready", body = doc::Health, example = json!({"status": "ok"})),
        doc::problems::Store,
    ))]
pub async fn readyz(State(app): State<AppState>) -> Result<Json<doc::Health>, Error> {
    ready(&app)
}

fn ready(app: &AppState) -> Result<Json<doc::Health>, Error> {
    app.core.readiness()?;
    Ok(Json(doc::Health::ok()))
}

#[utoipa::path(get, path = "/livez", tag = "service",
    summary = "Liveness: the process answers",
    description = "200 whenever the process can answer at all, whatever the store's state: restart a replica only when this fails (a store outage is `/readyz`'s to report, and a restart would not mend it).",
    responses(
        (status = 200, description = "Alive", body = doc::Health, example = json!({"status": "ok"})),
    ))]
pub async fn livez() -> Json<doc::Health> {
    Json(doc::Health::ok())
}

#[utoipa::path(get, path = "/version", tag = "service",
    summary = "The version, the commit and the store schema's version",
    responses(
        (status = 200, description = "What is running", body = VersionInfo,
         example = json!({"version": "0.1.0", "commit": "24537e9d1c0a", "schema_version": 20261207000002_i64})),
    ))]
pub async fn version(State(app): State<AppState>) -> Result<Json<VersionInfo>, Error> {
    Ok(Json(VersionInfo {
        version: VERSION,
        commit: COMMIT,
        schema_version: app.core.schema_version()?,
    }))
}

#[utoipa::path(get, path = "/openapi.json", tag = "service",
    summary = "This API's OpenAPI 3.1 document",
    description = "The document `openapi/openapi.json` holds (a test keeps the two the same), for generators and validators.",
    responses(
        (status = 200, description = "The document", body = Object, content_type = "application/json"),
    ))]
pub async fn openapi_json() -> Result<Response, Error> {
    // Made once: the document is the routes', fixed for the process's life.
    static DOCUMENT: OnceLock<Result<String, String>> = OnceLock::new();
    let made = DOCUMENT.get_or_init(|| {
        (super::openapi().to_pretty_json())
            .map(|text| format!("{text}\n"))
            .map_err(|e| format!("the OpenAPI document does not serialize: {e}"))
    });
    let text = made.as_ref().map_err(|e| Error::Internal(e.clone()))?;
    let content_type = HeaderValue::from_static("application/json");
    Ok(([(header::CONTENT_TYPE, content_type)], text.as_str()).into_response())
}

#[utoipa::path(get, path = "/metrics", tag = "service",
    summary = "Prometheus metrics (OpenMetrics text)",
    description = "Requests by route template and status, latency histograms, decisions by kind, readings simulated per decision, norm-cache hits and refreshes, admission refusals. Never queued behind load.",
    responses(
        (status = 200, description = "The metrics", body = String, content_type = "application/openmetrics-text"),
    ))]
pub async fn metrics(State(app): State<AppState>) -> Response {
    let content_type = HeaderValue::from_static("application/openmetrics-text; version=1.0.0; charset=utf-8");
    ([(header::CONTENT_TYPE, content_type)], app.metrics.render()).into_response()
}
