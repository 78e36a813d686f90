//! REST over axum: routes, body parsing, the admin-token check.
//!
//! Owns: HTTP concerns only. Must not: validate domain input (that is `api`), decide anything
//! (that is `core`), or answer any failure except through `Error`.

use std::sync::Arc;

use axum::extract::{DefaultBodyLimit, FromRequest, FromRequestParts, Path, Request, State};
use axum::http::request::Parts;
use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use bytes::Bytes;
use serde::de::DeserializeOwned;
use subtle::ConstantTimeEq;
use tower_http::catch_panic::CatchPanicLayer;
use tower_http::trace::TraceLayer;

use crate::api::{ClarifyBody, ClarifyInput, DecisionDto, NormBody, NormDto, parse_json};
use crate::core::Core;
use crate::error::Error;

/// What every handler shares.
#[derive(Clone)]
pub struct AppState {
    pub core: Arc<Core>,
    /// When set, requests that change norms must carry `Authorization: Bearer <token>`.
    pub admin_token: Option<Arc<str>>,
    /// Largest request body accepted, bytes.
    pub max_body_bytes: usize,
}

pub fn router(state: AppState) -> Router {
    let limit = state.max_body_bytes;
    Router::new()
        .route("/healthz", get(healthz))
        .route("/v1/norms", get(list_norms).post(create_norm))
        .route("/v1/norms/{id}", get(get_norm).delete(delete_norm))
        .route("/v1/clarify", post(clarify))
        .fallback(|| async {
            Error::NotFound {
                what: "this path".to_owned(),
            }
        })
        .method_not_allowed_fallback(|| async { Error::MethodNotAllowed })
        .layer(DefaultBodyLimit::max(limit))
        .layer(CatchPanicLayer::custom(|_: Box<dyn std::any::Any + Send>| {
            Error::Internal("a handler panicked".to_owned()).into_response()
        }))
        .layer(TraceLayer::new_for_http())
        .with_state(state)
}

/// A JSON body: not JSON → 400, wrong shape → 422 naming the field, too large → 413.
pub struct JsonBody<T>(pub T);

impl<T: DeserializeOwned> FromRequest<AppState> for JsonBody<T> {
    type Rejection = Error;

    async fn from_request(req: Request, state: &AppState) -> Result<Self, Error> {
        if let Some(content_type) = req.headers().get(header::CONTENT_TYPE) {
            let text = content_type.to_str().unwrap_or_default().to_ascii_lowercase();
            let essence = text.split(';').next().unwrap_or_default().trim();
            if essence != "application/json" && !essence.ends_with("+json") {
                return Err(Error::UnsupportedMediaType {
                    detail: format!("send the body as application/json, not `{essence}`"),
                });
            }
        }
        let bytes = Bytes::from_request(req, state).await.map_err(|rejection| {
            if rejection.status() == StatusCode::PAYLOAD_TOO_LARGE {
                Error::PayloadTooLarge {
                    limit: state.max_body_bytes,
                }
            } else {
                Error::MalformedBody {
                    detail: rejection.body_text(),
                }
            }
        })?;
        parse_json(&bytes).map(JsonBody)
    }
}

/// Proof that the caller may change norms: the admin token, compared in constant time, or no
/// token configured at all.
pub struct Admin;

impl FromRequestParts<AppState> for Admin {
    type Rejection = Error;

    async fn from_request_parts(parts: &mut Parts, state: &AppState) -> Result<Self, Error> {
        let Some(expected) = &state.admin_token else {
            return Ok(Admin);
        };
        let sent = parts
            .headers
            .get(header::AUTHORIZATION)
            .and_then(|v| v.to_str().ok())
            .and_then(|v| v.strip_prefix("Bearer ").or_else(|| v.strip_prefix("bearer ")))
            .map(str::trim)
            .ok_or(Error::Unauthenticated)?;
        if bool::from(sent.as_bytes().ct_eq(expected.as_bytes())) {
            Ok(Admin)
        } else {
            Err(Error::Forbidden)
        }
    }
}

/// A norm id from the path; anything but an integer names no norm.
fn norm_id(text: &str) -> Result<i64, Error> {
    text.parse().map_err(|_| Error::NotFound {
        what: format!("norm `{text}`"),
    })
}

async fn healthz(State(app): State<AppState>) -> Result<Json<serde_json::Value>, Error> {
    app.core.ready().await?;
    Ok(Json(serde_json::json!({"status": "ok"})))
}

async fn list_norms(State(app): State<AppState>) -> Result<Json<Vec<NormDto>>, Error> {
    let norms = app.core.list_norms().await?;
    Ok(Json(norms.iter().map(NormDto::from).collect()))
}

async fn create_norm(
    State(app): State<AppState>,
    _: Admin,
    JsonBody(body): JsonBody<NormBody>,
) -> Result<Response, Error> {
    let norm = app.core.create_norm(body.into_input()).await?;
    let mut response = (StatusCode::CREATED, Json(NormDto::from(&norm))).into_response();
    if let Ok(location) = HeaderValue::from_str(&format!("/v1/norms/{}", norm.id)) {
        response.headers_mut().insert(header::LOCATION, location);
    }
    Ok(response)
}

async fn get_norm(State(app): State<AppState>, Path(id): Path<String>) -> Result<Json<NormDto>, Error> {
    let norm = app.core.get_norm(norm_id(&id)?).await?;
    Ok(Json(NormDto::from(&norm)))
}

async fn delete_norm(State(app): State<AppState>, _: Admin, Path(id): Path<String>) -> Result<StatusCode, Error> {
    app.core.delete_norm(norm_id(&id)?).await?;
    Ok(StatusCode::NO_CONTENT)
}

async fn clarify(
    State(app): State<AppState>,
    JsonBody(body): JsonBody<ClarifyBody>,
) -> Result<Json<DecisionDto>, Error> {
    let input = ClarifyInput::try_from(body)?;
    let decision = app.core.clarify(&input).await?;
    Ok(Json(DecisionDto::new(&decision, input.text)))
}
