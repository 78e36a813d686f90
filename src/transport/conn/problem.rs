//! The problems the connection layer answers itself, before (or instead of) a handler: a head
//! hyper cannot parse, one that is too long, and a head or body that does not arrive in time.
//!
//! Owns: their status, type, title and body, in the shape of `error::Problem`, for a raw write
//! on the socket and for a handler's answer alike. Must not: grow into a second error table:
//! these are only the failures no handler ever sees (see the report for the variants `Error`
//! could take over).

use axum::http::{HeaderValue, StatusCode, Version, header};
use axum::response::{IntoResponse, Response};

use crate::error::{PROBLEM_JSON, Problem};

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
    pub fn status(self) -> StatusCode {
        match self {
            Protocol::BadRequest => StatusCode::BAD_REQUEST,
            Protocol::UriTooLong => StatusCode::URI_TOO_LONG,
            Protocol::HeadersTooLarge => StatusCode::REQUEST_HEADER_FIELDS_TOO_LARGE,
            Protocol::RequestTimeout => StatusCode::REQUEST_TIMEOUT,
        }
    }

    fn slug_and_title(self) -> (&'static str, &'static str) {
        match self {
            Protocol::BadRequest => ("bad-request", "Bad request"),
            Protocol::UriTooLong => ("uri-too-long", "URI too long"),
            Protocol::HeadersTooLarge => ("headers-too-large", "Request header fields too large"),
            Protocol::RequestTimeout => ("request-timeout", "Request timeout"),
        }
    }

    pub fn problem(self, detail: impl Into<String>) -> Problem {
        let (slug, title) = self.slug_and_title();
        Problem {
            kind: format!("/problems/{slug}"),
            title: title.to_owned(),
            status: self.status().as_u16(),
            detail: detail.into(),
            field: None,
        }
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
