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
    /// No route serves this path: distinct from a missing norm, so clients and the API drift
    /// test can tell the two apart.
    #[error("no route serves this path")]
    NoRoute,
    #[error("the method is not allowed here")]
    MethodNotAllowed,
    #[error("the body is larger than the limit of {limit} bytes")]
    PayloadTooLarge { limit: usize },
    /// No `Authorization: Bearer TOKEN` where tokens are configured and this request needs one.
    #[error("this request needs a token: send `Authorization: Bearer TOKEN`")]
    Unauthenticated,
    /// A token that is not configured, or one that may read but this request writes.
    #[error("{0}")]
    Forbidden(&'static str),
    /// A conditional write (`If-Match`, `expected_revision`) whose revision is no longer current;
    /// nothing was written.
    #[error("{what} has changed since revision {expected}; it is now at revision {current}: read it again and retry")]
    Stale {
        what: String,
        expected: String,
        current: i64,
    },
    /// Every worker is busy and the queue is full or waited too long: retry after a moment.
    #[error("the service is at its concurrency limit; retry after {retry_after_s} s")]
    Overloaded { retry_after_s: u64 },
    /// The norm store cannot be read: decisions fail closed.
    #[error("the norms cannot be read, so no decision is made: {0}")]
    NormsUnavailable(String),
    /// The norm store failed while curating norms (locked, gone, corrupt); nothing was changed.
    #[error("the norm store is unavailable: {0}")]
    StoreUnavailable(String),
    #[error("internal error: {0}")]
    Internal(String),
    /// Not HTTP as RFC 9112 writes it (a bad request line, header, length or coding; TLS bytes
    /// on the cleartext port): answered by the connection layer, no handler sees it.
    #[error("{detail}")]
    BadRequest { detail: String },
    #[error("{detail}")]
    UriTooLong { detail: String },
    #[error("{detail}")]
    HeadersTooLarge { detail: String },
    /// A head or a body did not arrive within its timeout.
    #[error("{detail}")]
    RequestTimeout { detail: String },
}

impl Error {
    pub fn invalid(field: impl Into<String>, detail: impl Into<String>) -> Error {
        Error::Invalid {
            field: field.into(),
            detail: detail.into(),
        }
    }

    /// The single place where a failure becomes an HTTP status, a gRPC code and a problem type
    /// (slug, title). Both transports read it; there is no wildcard arm.
    pub fn codes(&self) -> Codes {
        use tonic::Code;
        let (http, grpc, slug, title) = match self {
            Error::MalformedBody { .. } => (
                StatusCode::BAD_REQUEST,
                Code::InvalidArgument,
                "malformed-body",
                "Malformed request body",
            ),
            Error::Invalid { .. } => (
                StatusCode::UNPROCESSABLE_ENTITY,
                Code::InvalidArgument,
                "invalid-field",
                "Invalid field",
            ),
            Error::UnsupportedMediaType { .. } => (
                StatusCode::UNSUPPORTED_MEDIA_TYPE,
                Code::InvalidArgument,
                "unsupported-media-type",
                "Unsupported media type",
            ),
            Error::NotFound { .. } => (StatusCode::NOT_FOUND, Code::NotFound, "not-found", "Not found"),
            Error::NoRoute => (StatusCode::NOT_FOUND, Code::Unimplemented, "no-route", "No such route"),
            Error::MethodNotAllowed => (
                StatusCode::METHOD_NOT_ALLOWED,
                Code::Unimplemented,
                "method-not-allowed",
                "Method not allowed",
            ),
            Error::PayloadTooLarge { .. } => (
                StatusCode::PAYLOAD_TOO_LARGE,
                Code::ResourceExhausted,
                "payload-too-large",
                "Payload too large",
            ),
            Error::Unauthenticated => (
                StatusCode::UNAUTHORIZED,
                Code::Unauthenticated,
                "unauthenticated",
                "Unauthenticated",
            ),
            Error::Forbidden(_) => (StatusCode::FORBIDDEN, Code::PermissionDenied, "forbidden", "Forbidden"),
            Error::Stale { .. } => (
                StatusCode::PRECONDITION_FAILED,
                Code::FailedPrecondition,
                "stale-revision",
                "Stale revision",
            ),
            Error::Overloaded { .. } => (
                StatusCode::SERVICE_UNAVAILABLE,
                Code::Unavailable,
                "overloaded",
                "Overloaded",
            ),
            Error::NormsUnavailable(_) => (
                StatusCode::SERVICE_UNAVAILABLE,
                Code::Unavailable,
                "norms-unavailable",
                "Norms unavailable",
            ),
            Error::StoreUnavailable(_) => (
                StatusCode::SERVICE_UNAVAILABLE,
                Code::Unavailable,
                "store-unavailable",
                "Norm store unavailable",
            ),
            Error::Internal(_) => (
                StatusCode::INTERNAL_SERVER_ERROR,
                Code::Internal,
                "internal",
                "Internal error",
            ),
            Error::BadRequest { .. } => (
                StatusCode::BAD_REQUEST,
                Code::InvalidArgument,
                "bad-request",
                "Bad request",
            ),
            Error::UriTooLong { .. } => (
                StatusCode::URI_TOO_LONG,
                Code::InvalidArgument,
                "uri-too-long",
                "URI too long",
            ),
            Error::HeadersTooLarge { .. } => (
                StatusCode::REQUEST_HEADER_FIELDS_TOO_LARGE,
                Code::ResourceExhausted,
                "headers-too-large",
                "Request header fields too large",
            ),
            Error::RequestTimeout { .. } => (
                StatusCode::REQUEST_TIMEOUT,
                Code::DeadlineExceeded,
                "request-timeout",
                "Request timeout",
            ),
        };
        Codes {
            http,
            grpc,
            slug,
            title,
        }
    }

    /// What the client is told: internal details stay in the log.
    fn public_detail(&self) -> String {
        match self {
            Error::Internal(_) => "the service failed; the error is logged".to_owned(),
            Error::Invalid { detail, .. } => detail.clone(),
            other => other.to_string(),
        }
    }

    fn log(&self) {
        match self {
            Error::Internal(_) | Error::NormsUnavailable(_) | Error::StoreUnavailable(_) => {
                tracing::error!(error = %self, "request failed")
            }
            // The detail may echo the caller's input (a speaker id, a word): the type and the
            // field say enough to find the request by its id.
            _ => tracing::debug!(problem = self.codes().slug, field = self.field(), "request rejected"),
        }
    }

    /// Seconds a client should wait before retrying, for failures that pass.
    pub fn retry_after_s(&self) -> Option<u64> {
        match self {
            Error::NormsUnavailable(_) | Error::StoreUnavailable(_) => Some(1),
            Error::Overloaded { retry_after_s } => Some(*retry_after_s),
            _ => None,
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
            EngineError::BadChoice { .. } => Error::invalid("/answer/choice", e.to_string()),
            EngineError::NothingAsked { .. } => Error::invalid("/answer", e.to_string()),
        }
    }
}

impl From<StoreError> for Error {
    fn from(e: StoreError) -> Self {
        if e.busy {
            Error::Overloaded { retry_after_s: 1 }
        } else {
            Error::StoreUnavailable(e.detail)
        }
    }
}

/// How one failure shows on each transport.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Codes {
    pub http: StatusCode,
    pub grpc: tonic::Code,
    /// The problem type's last path segment: `/problems/{slug}`.
    pub slug: &'static str,
    pub title: &'static str,
}

/// RFC 9457 problem details: every 4xx and 5xx answer of the REST API.
#[derive(Clone, Debug, PartialEq, Serialize, utoipa::ToSchema)]
pub struct Problem {
    /// A URI reference naming the kind of problem, e.g. `/problems/invalid-field`.
    #[serde(rename = "type")]
    pub kind: String,
    pub title: String,
    /// The HTTP status, repeated.
    pub status: u16,
    /// What went wrong, for a person.
    pub detail: String,
    /// A JSON Pointer into the request body at the member at fault, when one is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub field: Option<String>,
}

pub const PROBLEM_JSON: &str = "application/problem+json";

impl Error {
    /// The problem body a client is shown: the REST answer's, and the offline CLI's report.
    pub fn problem(&self) -> Problem {
        let Codes { http, slug, title, .. } = self.codes();
        Problem {
            kind: format!("/problems/{slug}"),
            title: title.to_owned(),
            status: http.as_u16(),
            detail: self.public_detail(),
            field: self.field().map(str::to_owned),
        }
    }
}

impl IntoResponse for Error {
    fn into_response(self) -> Response {
        let http = self.codes().http;
        self.log();
        let body = self.problem();
        let mut response = (http, axum::Json(body)).into_response();
        response
            .headers_mut()
            .insert(header::CONTENT_TYPE, HeaderValue::from_static(PROBLEM_JSON));
        if matches!(self, Error::Unauthenticated) {
            response
                .headers_mut()
                .insert(header::WWW_AUTHENTICATE, HeaderValue::from_static("Bearer"));
        }
        if let Some(seconds) = self.retry_after_s() {
            response
                .headers_mut()
                .insert(header::RETRY_AFTER, HeaderValue::from(seconds));
        }
        response
    }
}

impl From<Error> for tonic::Status {
    /// The gRPC twin of the problem body: the code from the same table, the field (when one is
    /// at fault) leading the message and in the `field` metadata entry.
    fn from(error: Error) -> tonic::Status {
        let Codes { grpc, .. } = error.codes();
        error.log();
        let message = match error.field() {
            Some(field) => format!("{field}: {}", error.public_detail()),
            None => error.public_detail(),
        };
        let mut status = tonic::Status::new(grpc, message);
        if let Some(seconds) = error.retry_after_s() {
            status.metadata_mut().insert("retry-after", seconds.into());
        }
        if let Some(field) = error.field()
            && let Ok(value) = field.parse()
        {
            status.metadata_mut().insert("field", value);
        }
        status
    }
}
