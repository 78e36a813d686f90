//! Cross-origin requests from browsers (`--cors-origin`): which origins may call the REST API
//! from a page, and the preflight answer. Off unless configured.
//!
//! Must not: allow credentials with the wildcard origin, or take an origin a browser would never
//! send (a path, a trailing slash, a scheme other than http or https): it would silently match
//! nothing.

use std::time::Duration;

use axum::http::{HeaderName, HeaderValue, Method, Uri, header};
use tower_http::cors::{AllowOrigin, CorsLayer};

use super::observe::REQUEST_ID;

/// How long a browser may keep a preflight's answer.
const PREFLIGHT_MAX_AGE: Duration = Duration::from_secs(600);

/// The origins a browser page may call from: any (`*`), or a list.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum CorsOrigins {
    /// Any origin; never with credentials.
    Any,
    /// Exactly these, each `scheme://host[:port]` in lower case; credentials allowed.
    List(Vec<String>),
}

impl CorsOrigins {
    /// Reads `--cors-origin` values: `*` alone, or origins such as `https://app.example` or
    /// `http://localhost:5173`. Empty: `None` (CORS off). The error names the value at fault.
    pub fn parse(values: &[String]) -> Result<Option<CorsOrigins>, String> {
        let values: Vec<&str> = values.iter().map(|v| v.trim()).filter(|v| !v.is_empty()).collect();
        if values.is_empty() {
            return Ok(None);
        }
        if values.contains(&"*") {
            return match values.as_slice() {
                ["*"] => Ok(Some(CorsOrigins::Any)),
                _ => Err("--cors-origin: `*` allows every origin, so it cannot be listed with others".to_owned()),
            };
        }
        let mut origins = Vec::with_capacity(values.len());
        for value in values {
            let origin = origin(value).map_err(|why| format!("--cors-origin `{}`: {why}", value.escape_debug()))?;
            if !origins.contains(&origin) {
                origins.push(origin);
            }
        }
        Ok(Some(CorsOrigins::List(origins)))
    }

    /// The layer answering preflights and marking answers for these origins. Credentials
    /// (cookies, and a browser's own HTTP authentication) only with a list: a bearer token in
    /// `Authorization` needs none, so the wildcard still serves a page that sends one.
    pub fn layer(&self) -> CorsLayer {
        let layer = CorsLayer::new()
            .allow_methods([Method::GET, Method::POST, Method::PUT, Method::DELETE])
            .allow_headers([
                header::AUTHORIZATION,
                header::CONTENT_TYPE,
                header::IF_MATCH,
                REQUEST_ID,
            ])
            .expose_headers([
                header::ETAG,
                header::LOCATION,
                header::RETRY_AFTER,
                REQUEST_ID,
                HeaderName::from_static("www-authenticate"),
            ])
            .max_age(PREFLIGHT_MAX_AGE);
        match self {
            CorsOrigins::Any => layer.allow_origin(AllowOrigin::any()),
            CorsOrigins::List(origins) => {
                let values = origins.iter().filter_map(|o| HeaderValue::from_str(o).ok());
                layer.allow_origin(AllowOrigin::list(values)).allow_credentials(true)
            }
        }
    }
}

/// An origin as a browser sends it in `Origin`: `scheme://host[:port]`, lower case.
fn origin(value: &str) -> Result<String, &'static str> {
    let uri: Uri = value
        .parse()
        .map_err(|_| "not an origin: write it as scheme://host[:port], e.g. https://app.example")?;
    let scheme = uri
        .scheme_str()
        .ok_or("no scheme: write it as https://host or http://host")?;
    let scheme = scheme.to_ascii_lowercase();
    if scheme != "http" && scheme != "https" {
        return Err("a browser origin's scheme is http or https");
    }
    let authority = uri.authority().ok_or("no host")?;
    if authority.as_str().contains('@') {
        return Err("an origin carries no user name or password");
    }
    if uri
        .path_and_query()
        .is_some_and(|p| p.as_str() != "/" && !p.as_str().is_empty())
        || value.ends_with('/')
    {
        return Err("an origin has no path, not even a trailing `/` (browsers send none)");
    }
    Ok(format!("{scheme}://{}", authority.as_str().to_ascii_lowercase()))
}

#[cfg(test)]
mod tests {
    use super::CorsOrigins;

    fn parse(values: &[&str]) -> Result<Option<CorsOrigins>, String> {
        CorsOrigins::parse(&values.iter().map(|v| (*v).to_owned()).collect::<Vec<_>>())
    }

    #[test]
    fn origins_are_read_as_a_browser_sends_them_and_mistakes_are_named() {
        assert_eq!(parse(&[]), Ok(None));
        assert_eq!(parse(&["*"]), Ok(Some(CorsOrigins::Any)));
        assert_eq!(
            parse(&["HTTPS://App.Example", "http://localhost:5173", "https://app.example"]),
            Ok(Some(CorsOrigins::List(vec![
                "https://app.example".to_owned(),
                "http://localhost:5173".to_owned()
            ])))
        );
        let refused = |values: &[&str], why: &str| {
            let error = parse(values).unwrap_err();
            assert!(error.contains(why), "{values:?}: {error}");
        };
        refused(&["*", "https://a.example"], "cannot be listed with others");
        refused(&["https://app.example/"], "no path");
        refused(&["https://app.example/ui"], "no path");
        refused(&["app.example"], "scheme");
        refused(&["ftp://app.example"], "http or https");
        refused(&["https://user@app.example"], "user name");
        refused(&["not an origin"], "not an origin");
    }
}
