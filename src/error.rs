//! The one error type of the service and the one table that turns it into what a client sees.
//!
//! Owns: every failure a request can end in and the one table of what each shows (HTTP status,
//! gRPC code, problem type, public detail, field, retry, log level).
//! Must not: grow a second mapping anywhere else (transports read `Error::row`), or import the
//! store or a transport.

use serde::Serialize;

use crate::engine::clarify::EngineError;
use crate::engine::input::Invalid;

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
    /// A verb other verbs call in their methods: removing it would leave them failing at that
    /// step. `callers` is the list as written ("`put` and `fetch`"); nothing was changed.
    #[error("verb `{verb}` is called by {callers}: change or remove them first")]
    VerbInUse { verb: String, callers: String },
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

/// Everything a client is shown of a failure, and how it is logged: one row per variant of
/// [`Error`], all columns decided in one place ([`Error::row`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Row {
    /// The HTTP status.
    pub http: u16,
    /// The gRPC status code, by its number in the gRPC specification (see [`grpc`]).
    pub grpc: i32,
    /// The problem type's last path segment: `/problems/{slug}`.
    pub slug: &'static str,
    pub title: &'static str,
    /// What the client is told; internal details stay in the log.
    pub detail: String,
    /// A JSON Pointer into the request at the member at fault.
    pub field: Option<String>,
    /// Seconds to wait before retrying, for failures that pass.
    pub retry_after_s: Option<u64>,
    pub log: Log,
}

/// How a failure is logged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Log {
    /// The service's own fault or the store's: at error, with the whole message.
    Error,
    /// The caller's: at debug, with its type and field only (the detail may echo the caller's
    /// input: a speaker id, a word).
    Debug,
}

/// gRPC status codes as the gRPC specification numbers them; transports turn them into their
/// own type.
pub mod grpc {
    pub const INVALID_ARGUMENT: i32 = 3;
    pub const DEADLINE_EXCEEDED: i32 = 4;
    pub const NOT_FOUND: i32 = 5;
    pub const PERMISSION_DENIED: i32 = 7;
    pub const RESOURCE_EXHAUSTED: i32 = 8;
    pub const FAILED_PRECONDITION: i32 = 9;
    pub const UNIMPLEMENTED: i32 = 12;
    pub const INTERNAL: i32 = 13;
    pub const UNAVAILABLE: i32 = 14;
    pub const UNAUTHENTICATED: i32 = 16;
}

impl Error {
    pub fn invalid(field: impl Into<String>, detail: impl Into<String>) -> Error {
        Error::Invalid {
            field: field.into(),
            detail: detail.into(),
        }
    }

    /// The single place where a failure becomes what a client sees and what the log says. Both
    /// transports and the offline CLI read it; it has no catch-all arm, so a new variant does
    /// not compile until every column is decided for it.
    pub fn row(&self) -> Row {
        use grpc::*;
        let shown = || self.to_string();
        #[rustfmt::skip]
        let (http, grpc, slug, title, detail, field, retry_after_s, log) = match self {
            Error::MalformedBody { .. } => (400, INVALID_ARGUMENT, "malformed-body", "Malformed request body", shown(), None, None, Log::Debug),
            Error::Invalid { field, detail } => (422, INVALID_ARGUMENT, "invalid-field", "Invalid field", detail.clone(), Some(field.clone()), None, Log::Debug),
            Error::UnsupportedMediaType { .. } => (415, INVALID_ARGUMENT, "unsupported-media-type", "Unsupported media type", shown(), None, None, Log::Debug),
            Error::NotFound { .. } => (404, NOT_FOUND, "not-found", "Not found", shown(), None, None, Log::Debug),
            Error::NoRoute => (404, UNIMPLEMENTED, "no-route", "No such route", shown(), None, None, Log::Debug),
            Error::MethodNotAllowed => (405, UNIMPLEMENTED, "method-not-allowed", "Method not allowed", shown(), None, None, Log::Debug),
            Error::PayloadTooLarge { .. } => (413, RESOURCE_EXHAUSTED, "payload-too-large", "Payload too large", shown(), None, None, Log::Debug),
            Error::Unauthenticated => (401, UNAUTHENTICATED, "unauthenticated", "Unauthenticated", shown(), None, None, Log::Debug),
            Error::Forbidden(_) => (403, PERMISSION_DENIED, "forbidden", "Forbidden", shown(), None, None, Log::Debug),
            Error::Stale { .. } => (412, FAILED_PRECONDITION, "stale-revision", "Stale revision", shown(), None, None, Log::Debug),
            Error::VerbInUse { .. } => (409, FAILED_PRECONDITION, "verb-in-use", "Verb in use", shown(), None, None, Log::Debug),
            Error::Overloaded { retry_after_s } => (503, UNAVAILABLE, "overloaded", "Overloaded", shown(), None, Some(*retry_after_s), Log::Debug),
            Error::NormsUnavailable(_) => (503, UNAVAILABLE, "norms-unavailable", "Norms unavailable", shown(), None, Some(1), Log::Error),
            Error::StoreUnavailable(_) => (503, UNAVAILABLE, "store-unavailable", "Norm store unavailable", shown(), None, Some(1), Log::Error),
            Error::Internal(_) => (500, INTERNAL, "internal", "Internal error", "the service failed; the error is logged".to_owned(), None, None, Log::Error),
            Error::BadRequest { .. } => (400, INVALID_ARGUMENT, "bad-request", "Bad request", shown(), None, None, Log::Debug),
            Error::UriTooLong { .. } => (414, INVALID_ARGUMENT, "uri-too-long", "URI too long", shown(), None, None, Log::Debug),
            Error::HeadersTooLarge { .. } => (431, RESOURCE_EXHAUSTED, "headers-too-large", "Request header fields too large", shown(), None, None, Log::Debug),
            Error::RequestTimeout { .. } => (408, DEADLINE_EXCEEDED, "request-timeout", "Request timeout", shown(), None, None, Log::Debug),
        };
        Row {
            http,
            grpc,
            slug,
            title,
            detail,
            field,
            retry_after_s,
            log,
        }
    }

    /// Writes the failure to the log, at the level its row says.
    pub fn log(&self, row: &Row) {
        match row.log {
            Log::Error => tracing::error!(error = %self, "request failed"),
            Log::Debug => tracing::debug!(problem = row.slug, field = row.field.as_deref(), "request rejected"),
        }
    }
}

/// A constructor's fault is a 422 naming the field.
impl From<Invalid> for Error {
    fn from(e: Invalid) -> Self {
        Error::Invalid {
            field: e.field,
            detail: e.message,
        }
    }
}

impl From<EngineError> for Error {
    fn from(e: EngineError) -> Self {
        match e {
            EngineError::BadChoice { .. } => Error::invalid("/answer/choice", e.to_string()),
            EngineError::NothingAsked { .. } | EngineError::AskedWhich { .. } => {
                Error::invalid("/answer", e.to_string())
            }
            EngineError::BadJoiner { .. } => Error::invalid("/directive/joiner", e.to_string()),
        }
    }
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
        let row = self.row();
        Problem {
            kind: format!("/problems/{}", row.slug),
            title: row.title.to_owned(),
            status: row.http,
            detail: row.detail,
            field: row.field,
        }
    }
}
