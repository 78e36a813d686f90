//! `openapi/openapi.json` against the code and the running router: it cannot drift.

use std::path::{Path, PathBuf};

use reqwest::Method;
use serde_json::Value;

use crate::helpers::spawn_app;

fn manifest_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn checked_in() -> Value {
    let text = std::fs::read_to_string(manifest_dir().join("openapi/openapi.json")).expect("openapi/openapi.json");
    serde_json::from_str(&text).expect("openapi.json is JSON")
}

#[test]
fn the_checked_in_document_is_the_one_the_code_generates() {
    let generated: Value = serde_json::to_value(scruple::transport::rest::openapi()).unwrap();
    assert!(
        generated == checked_in(),
        "openapi/openapi.json is stale: regenerate it with `cargo run -- openapi > openapi/openapi.json`"
    );
    assert_eq!(generated["openapi"], "3.1.0");
}

#[test]
fn the_document_has_every_operation_of_the_contract() {
    let doc = checked_in();
    let mut operations: Vec<String> = Vec::new();
    for (path, item) in doc["paths"].as_object().unwrap() {
        for method in item.as_object().unwrap().keys() {
            operations.push(format!("{} {path}", method.to_uppercase()));
        }
    }
    operations.sort();
    assert_eq!(
        operations,
        [
            "DELETE /v1/actions/{name}",
            "DELETE /v1/norms/{id}",
            "GET /",
            "GET /healthz",
            "GET /livez",
            "GET /metrics",
            "GET /openapi.json",
            "GET /playground/app.js",
            "GET /playground/style.css",
            "GET /readyz",
            "GET /v1/actions",
            "GET /v1/actions/{name}",
            "GET /v1/audit",
            "GET /v1/norm-set",
            "GET /v1/norms",
            "GET /v1/norms/{id}",
            "GET /version",
            "POST /v1/check",
            "POST /v1/clarify",
            "POST /v1/norms",
            "PUT /v1/actions/{name}",
            "PUT /v1/norm-set",
            "PUT /v1/norms/{id}",
        ]
    );
}

/// Every documented operation reaches a handler on the live router (never the no-route fallback
/// nor 405).
#[tokio::test]
async fn every_documented_operation_is_routed() {
    let app = spawn_app().await;
    let doc = checked_in();
    for (path, item) in doc["paths"].as_object().unwrap() {
        for method in item.as_object().unwrap().keys() {
            let url = app.url(&path.replace("{id}", "1").replace("{name}", "get"));
            let method = Method::from_bytes(method.to_uppercase().as_bytes()).unwrap();
            let response = app
                .client
                .request(method.clone(), url)
                .header("content-type", "application/json")
                .body("{}")
                .send()
                .await
                .unwrap();
            let status = response.status();
            let body: Value = response.json().await.unwrap_or(Value::Null);
            assert_ne!(status, reqwest::StatusCode::METHOD_NOT_ALLOWED, "{method} {path}");
            assert_ne!(
                body["type"], "/problems/no-route",
                "{method} {path} is documented but not routed"
            );
        }
    }
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// Routes are registered only through `routes!(handler)`, which requires the handler's
/// `#[utoipa::path]` and puts it in the document; any other way of adding a route would be
/// undocumented, so it fails here.
#[test]
fn no_route_is_registered_around_the_document() {
    let mut files = Vec::new();
    rust_files(&manifest_dir().join("src"), &mut files);
    let forbidden = [".route(", ".route_service(", ".nest(", ".nest_service("];
    let mut found = Vec::new();
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        for (n, line) in text.lines().enumerate() {
            if forbidden.iter().any(|f| line.contains(f)) {
                found.push(format!("{}:{}: {}", file.display(), n + 1, line.trim()));
            }
        }
    }
    assert!(
        found.is_empty(),
        "routes registered without OpenAPI documentation:\n{}",
        found.join("\n")
    );
}
