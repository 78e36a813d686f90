//! The problems the connection layer answers itself, before (or instead of) a handler: a head
//! hyper cannot parse, one that is too long, and a head or body that does not arrive in time.
//!
//! Owns: writing them, as a raw response on the socket or as a handler's answer. Their status,
//! type and title come from the one error table (`error::Error`). Must not: map a failure to a
//! status itself.

use axum::http::{HeaderValue, StatusCode, Version, header};
use axum::response::{IntoResponse, Response};

use crate::error::{Error, PROBLEM_JSON, Problem};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Protocol {
    /// Not HTTP/1.1 as RFC 9112 writes it: a bad request line, header, Content-Length or
    /// Transfer-Encoding.
    BadRequest,
    UriTooLong,
    HeadersTooLarge,
    /// The head or the body did not arrive within its timeout.
    RequestTimeout,
}

impl Protocol {
    /// The failure in the one error table (`error::Error::codes`).
    fn error(self, detail: String) -> Error {
        match self {
            Protocol::BadRequest => Error::BadRequest { detail },
            Protocol::UriTooLong => Error::UriTooLong { detail },
            Protocol::HeadersTooLarge => Error::HeadersTooLarge { detail },
            Protocol::RequestTimeout => Error::RequestTimeout { detail },
        }
    }

    pub fn status(self) -> StatusCode {
        StatusCode::from_u16(self.error(String::new()).row().http).unwrap_or(StatusCode::BAD_REQUEST)
    }

    pub fn problem(self, detail: impl Into<String>) -> Problem {
        self.error(detail.into()).problem()
    }

    /// A handler's answer. On HTTP/1 the connection closes after it: whatever the client sent
    /// after the fault cannot be trusted to start a request.
    pub fn response(self, detail: impl Into<String>, version: Version) -> Response {
        let mut response = (self.status(), axum::Json(self.problem(detail))).into_response();
        let headers = response.headers_mut();
        headers.insert(header::CONTENT_TYPE, HeaderValue::from_static(PROBLEM_JSON));
        if version <= Version::HTTP_11 {
            headers.insert(header::CONNECTION, HeaderValue::from_static("close"));
        }
        response
    }

    /// A whole HTTP/1.1 response, to write on the socket where hyper would have answered with
    /// an empty body; the connection is closed after it.
    pub fn raw(self, detail: impl Into<String>) -> Vec<u8> {
        let body = serde_json::to_vec(&self.problem(detail)).unwrap_or_default();
        let status = self.status();
        let mut bytes = format!(
            "HTTP/1.1 {} {}\r\ncontent-type: {PROBLEM_JSON}\r\ncontent-length: {}\r\nconnection: close\r\n\r\n",
            status.as_u16(),
            status.canonical_reason().unwrap_or(""),
            body.len()
        )
        .into_bytes();
        bytes.extend_from_slice(&body);
        bytes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_raw_problem_is_a_whole_response_with_the_problem_shape() {
        let bytes = Protocol::UriTooLong.raw("the request target is longer than 8192 bytes");
        let text = String::from_utf8(bytes).unwrap();
        let (head, body) = text.split_once("\r\n\r\n").unwrap();
        assert!(head.starts_with("HTTP/1.1 414 URI Too Long\r\n"), "{head}");
        assert!(head.contains("content-type: application/problem+json"));
        assert!(head.contains(&format!("content-length: {}", body.len())));
        let problem: serde_json::Value = serde_json::from_str(body).unwrap();
        assert_eq!(problem["type"], "/problems/uri-too-long");
        assert_eq!(problem["status"], 414);
        assert!(problem.get("field").is_none());
    }
}
