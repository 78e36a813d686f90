//! The playground: one page, its script and its style sheet, compiled into the binary.
//!
//! Owns: serving those three assets with their content types, caching and security headers.
//! Must not: read files at run time, call `core`, or give the page any way in but the public REST
//! API; the page is a client like any other, so what it shows is what a client would get.

use axum::http::{HeaderValue, header};
use axum::response::{IntoResponse, Response};

const INDEX_HTML: &str = include_str!("../../../playground/index.html");
const APP_JS: &str = include_str!("../../../playground/app.js");
const STYLE_CSS: &str = include_str!("../../../playground/style.css");

/// The page loads nothing but its own script and style sheet and talks only to this origin, so a
/// strict policy costs it nothing and keeps a pasted scene from ever running as code.
const CONTENT_SECURITY_POLICY: &str = "default-src 'none'; script-src 'self'; style-src 'self'; \
     connect-src 'self'; img-src 'self' data:; base-uri 'none'; form-action 'none'; frame-ancestors 'none'";

/// `no-cache`: the assets change with the binary but their URLs do not, so a browser must
/// revalidate rather than pair a new page with an old script.
fn asset(body: &'static str, content_type: &'static str) -> Response {
    let mut response = body.into_response();
    let headers = response.headers_mut();
    headers.insert(header::CONTENT_TYPE, HeaderValue::from_static(content_type));
    headers.insert(header::CACHE_CONTROL, HeaderValue::from_static("no-cache"));
    headers.insert(header::X_CONTENT_TYPE_OPTIONS, HeaderValue::from_static("nosniff"));
    headers.insert(
        header::CONTENT_SECURITY_POLICY,
        HeaderValue::from_static(CONTENT_SECURITY_POLICY),
    );
    response
}

#[utoipa::path(get, path = "/", tag = "playground",
    summary = "The playground: draw a scene, manage norms and ask for a decision from a browser",
    responses((status = 200, description = "The playground page", content_type = "text/html")))]
pub async fn index() -> Response {
    asset(INDEX_HTML, "text/html; charset=utf-8")
}

#[utoipa::path(get, path = "/playground/app.js", tag = "playground",
    summary = "The playground's script",
    responses((status = 200, description = "The script, a plain ES module", content_type = "text/javascript")))]
pub async fn script() -> Response {
    asset(APP_JS, "text/javascript; charset=utf-8")
}

#[utoipa::path(get, path = "/playground/style.css", tag = "playground",
    summary = "The playground's style sheet",
    responses((status = 200, description = "The style sheet", content_type = "text/css")))]
pub async fn style() -> Response {
    asset(STYLE_CSS, "text/css; charset=utf-8")
}
