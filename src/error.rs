//! The one error type of the service and the one table that turns it into what a client sees.
//!
//! Owns: every failure a request can end in, its status and its problem+json body.
//! Must not: grow a second mapping anywhere else; transports read `Error::codes`.

use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use serde::Serialize;

use crate::engine::clarify::EngineError;
use crate::storage::StoreError;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The body is not JSON at all.
    #[error("malformed JSON: {detail}")]
    MalformedBody { detail: String },
    /// The body is JSON but a field is wrong; `field` is a JSON Pointer into the body.
    #[error("{field}: {detail}")]
    Invalid { field: String, detail: String },
    /// The body is not sent as JSON.
    #[error("unsupported media type: {detail}")]
    UnsupportedMediaType { detail: String },
    #[error("{what} not found")]
    NotFound { what: String },
    #[error("the method is not allowed here")]
    MethodNotAllowed,
    #[error("the body is larger than the limit of {limit} bytes")]
    PayloadTooLarge { limit: usize },
    /// A write without `Authorization: Bearer TOKEN` while an admin token is set.
    #[error("this request changes norms and needs the admin token: send `Authorization: Bearer TOKEN`")]
    Unauthenticated,
    /// A write with a token that is not the admin token.
    #[error("the token sent is not the admin token")]
    Forbidden,
    /// The norm store cannot be read: decisions fail closed.
    #[error("the norms cannot be read, so no decision is made: {0}")]
    NormsUnavailable(String),
    /// The norm store failed while curating norms (locked, gone, corrupt); nothing was changed.
    #[error("the norm store is unavailable: {0}")]
    StoreUnavailable(String),
    #[error("internal error: {0}")]
    Internal(String),
}

impl Error {
    pub fn invalid(field: impl Into<String>, detail: impl Into<String>) -> Error {
        Error::Invalid {
            field: field.into(),
            detail: detail.into(),
        }
    }

    /// The single place where a failure becomes an HTTP status and a problem type (slug, title).
    pub fn codes(&self) -> (StatusCode, &'static str, &'static str) {
        match self {
            Error::MalformedBody { .. } => (StatusCode::BAD_REQUEST, "malformed-body", "Malformed request body"),
            Error::Invalid { .. } => (StatusCode::UNPROCESSABLE_ENTITY, "invalid-field", "Invalid field"),
            Error::UnsupportedMediaType { .. } => (
                StatusCode::UNSUPPORTED_MEDIA_TYPE,
                "unsupported-media-type",
                "Unsupported media type",
            ),
            Error::NotFound { .. } => (StatusCode::NOT_FOUND, "not-found", "Not found"),
            Error::MethodNotAllowed => (
                StatusCode::METHOD_NOT_ALLOWED,
                "method-not-allowed",
                "Method not allowed",
            ),
            Error::PayloadTooLarge { .. } => (StatusCode::PAYLOAD_TOO_LARGE, "payload-too-large", "Payload too large"),
            Error::Unauthenticated => (StatusCode::UNAUTHORIZED, "unauthenticated", "Unauthenticated"),
            Error::Forbidden => (StatusCode::FORBIDDEN, "forbidden", "Forbidden"),
            Error::NormsUnavailable(_) => (
                StatusCode::SERVICE_UNAVAILABLE,
                "norms-unavailable",
                "Norms unavailable",
            ),
            Error::StoreUnavailable(_) => (
                StatusCode::SERVICE_UNAVAILABLE,
                "store-unavailable",
                "Norm store unavailable",
            ),
            Error::Internal(_) => (StatusCode::INTERNAL_SERVER_ERROR, "internal", "Internal error"),
        }
    }

    fn field(&self) -> Option<&str> {
        match self {
            Error::Invalid { field, .. } => Some(field),
            _ => None,
        }
    }
}

impl From<EngineError> for Error {
    fn from(e: EngineError) -> Self {
        match e {
            EngineError::TooManyReadings { .. } => Error::invalid("/directive", e.to_string()),
        }
    }
}

impl From<StoreError> for Error {
    fn from(e: StoreError) -> Self {
        Error::StoreUnavailable(e.0)
    }
}

/// RFC 9457 problem details.
#[derive(Serialize)]
pub struct Problem<'a> {
    #[serde(rename = "type")]
    pub kind: String,
    pub title: &'a str,
    pub status: u16,
    pub detail: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub field: Option<&'a str>,
}

pub const PROBLEM_JSON: &str = "application/problem+json";

impl IntoResponse for Error {
    fn into_response(self) -> Response {
        let (status, slug, title) = self.codes();
        match &self {
            Error::Internal(_) | Error::NormsUnavailable(_) | Error::StoreUnavailable(_) => {
                tracing::error!(error = %self, "request failed")
            }
            _ => tracing::debug!(error = %self, "request rejected"),
        }
        let detail = match &self {
            // Internal details stay in the log; the client learns only that it was ours.
            Error::Internal(_) => "the service failed; the error is logged".to_owned(),
            Error::Invalid { detail, .. } => detail.clone(),
            other => other.to_string(),
        };
        let body = Problem {
            kind: format!("/problems/{slug}"),
            title,
            status: status.as_u16(),
            detail,
            field: self.field(),
        };
        let mut response = (status, axum::Json(body)).into_response();
        response
            .headers_mut()
            .insert(header::CONTENT_TYPE, HeaderValue::from_static(PROBLEM_JSON));
        if matches!(self, Error::Unauthenticated) {
            response
                .headers_mut()
                .insert(header::WWW_AUTHENTICATE, HeaderValue::from_static("Bearer"));
        }
        if matches!(self, Error::NormsUnavailable(_) | Error::StoreUnavailable(_)) {
            response
                .headers_mut()
                .insert(header::RETRY_AFTER, HeaderValue::from_static("1"));
        }
        response
    }
}
