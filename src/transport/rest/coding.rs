//! `Content-Encoding` of a request body (RFC 9110 §8.4): `identity` is no coding, `gzip` is
//! decoded, anything else is refused with 415 naming the coding, never read as JSON.
//!
//! Owns: the codings accepted and their decoding under the body limit, which holds for the
//! decoded size too (a small gzip bomb is a 413). Must not: read the body itself.

use std::io::Read;

use axum::http::{HeaderMap, HeaderValue, header};
use axum::response::{IntoResponse, Response};
use bytes::Bytes;

use crate::error::Error;

/// What `Accept-Encoding` names on a 415 for a coding (RFC 9110 §12.5.3).
const ACCEPTED: &str = "gzip, identity";

/// How a request body is coded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coding {
    Identity,
    Gzip,
}

/// A coding this service does not decode: 415, with the codings it does.
#[derive(Debug)]
pub struct Unsupported(String);

impl IntoResponse for Unsupported {
    fn into_response(self) -> Response {
        let mut response = Error::UnsupportedMediaType { detail: self.0 }.into_response();
        response
            .headers_mut()
            .insert(header::ACCEPT_ENCODING, HeaderValue::from_static(ACCEPTED));
        response
    }
}

fn unsupported(detail: String) -> Unsupported {
    Unsupported(detail)
}

/// The coding of the body, from every `Content-Encoding` line (codings listed in the order
/// applied). One gzip layer at most: each would be decoded in full, so a stack of them would
/// multiply the work of one request.
pub fn of(headers: &HeaderMap) -> Result<Coding, Unsupported> {
    let mut coding = Coding::Identity;
    for value in headers.get_all(header::CONTENT_ENCODING) {
        let text = value
            .to_str()
            .map_err(|_| unsupported("a Content-Encoding that is not text".to_owned()))?;
        for name in text.split(',').map(str::trim).filter(|n| !n.is_empty()) {
            if name.eq_ignore_ascii_case("identity") {
                continue;
            }
            let gzip = name.eq_ignore_ascii_case("gzip") || name.eq_ignore_ascii_case("x-gzip");
            if !gzip {
                let shown: String = name.chars().take(64).collect();
                return Err(unsupported(format!(
                    "Content-Encoding `{shown}` is not supported: send the body as gzip or without a coding"
                )));
            }
            if coding == Coding::Gzip {
                return Err(unsupported("one gzip coding at most".to_owned()));
            }
            coding = Coding::Gzip;
        }
    }
    Ok(coding)
}

/// The body as sent, decoded; no more than `limit` bytes once decoded (413 beyond), and a body
/// that is not valid gzip is a 400.
pub fn decode(coding: Coding, body: Bytes, limit: usize) -> Result<Bytes, Error> {
    match coding {
        Coding::Identity => Ok(body),
        Coding::Gzip => {
            let mut decoded = Vec::new();
            let mut decoder = flate2::read::MultiGzDecoder::new(&body[..]).take(limit as u64 + 1);
            decoder.read_to_end(&mut decoded).map_err(|e| Error::MalformedBody {
                detail: format!("the gzip body cannot be decoded: {e}"),
            })?;
            if decoded.len() > limit {
                return Err(Error::PayloadTooLarge { limit });
            }
            Ok(Bytes::from(decoded))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn headers(values: &[&str]) -> HeaderMap {
        let mut map = HeaderMap::new();
        for v in values {
            map.append(header::CONTENT_ENCODING, HeaderValue::from_str(v).unwrap());
        }
        map
    }

    #[test]
    fn identity_and_one_gzip_are_taken_and_anything_else_is_415() {
        assert_eq!(of(&headers(&[])).unwrap(), Coding::Identity);
        assert_eq!(of(&headers(&["identity"])).unwrap(), Coding::Identity);
        assert_eq!(of(&headers(&["GZip"])).unwrap(), Coding::Gzip);
        assert_eq!(of(&headers(&["identity", "x-gzip"])).unwrap(), Coding::Gzip);
        for refused in [&["bogus"][..], &["gzip, br"], &["gzip", "gzip"]] {
            let response = of(&headers(refused)).unwrap_err().into_response();
            assert_eq!(response.status(), 415, "{refused:?}");
            assert_eq!(response.headers()[header::ACCEPT_ENCODING], ACCEPTED);
        }
    }

    #[test]
    fn the_limit_holds_for_the_decoded_size() {
        let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        encoder.write_all(&[b'x'; 10_000]).unwrap();
        let gzip = Bytes::from(encoder.finish().unwrap());
        assert_eq!(decode(Coding::Gzip, gzip.clone(), 10_000).unwrap().len(), 10_000);
        assert!(matches!(
            decode(Coding::Gzip, gzip, 9_999),
            Err(Error::PayloadTooLarge { limit: 9_999 })
        ));
        assert!(matches!(
            decode(Coding::Gzip, Bytes::from_static(b"{}"), 10),
            Err(Error::MalformedBody { .. })
        ));
    }
}
