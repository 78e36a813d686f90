//! Web conventions: the served OpenAPI document, the probes, `/version`, CORS, and a norm set
//! merged rather than replaced (REST and gRPC).

use reqwest::StatusCode;
use reqwest::header::{
    ACCESS_CONTROL_ALLOW_CREDENTIALS, ACCESS_CONTROL_ALLOW_HEADERS, ACCESS_CONTROL_ALLOW_ORIGIN,
    ACCESS_CONTROL_EXPOSE_HEADERS, ORIGIN,
};
use scruple::transport::cors::CorsOrigins;
use scruple::transport::grpc::pb;
use scruple::transport::grpc::pb::norms_client::NormsClient;
use serde_json::{Value, json};
use tonic::Code;

use crate::grpc::{channel, norm_request};
use crate::helpers::{TestApp, assert_problem, spawn_app, spawn_tweaked};

#[tokio::test]
async fn the_served_document_is_the_checked_one_and_the_probes_and_version_answer() {
    let app = spawn_app().await;
    let served = app.get("/openapi.json").await;
    assert_eq!(served.status(), StatusCode::OK);
    assert_eq!(served.headers()["content-type"], "application/json");
    let checked = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/openapi/openapi.json")).unwrap();
    assert_eq!(
        served.text().await.unwrap(),
        checked,
        "GET /openapi.json is openapi/openapi.json"
    );

    for probe in ["/livez", "/readyz", "/healthz"] {
        let answer = app.get(probe).await;
        assert_eq!(answer.status(), StatusCode::OK, "{probe}");
        assert_eq!(
            answer.json::<Value>().await.unwrap(),
            json!({"status": "ok"}),
            "{probe}"
        );
    }

    let version: Value = app.get("/version").await.json().await.unwrap();
    assert_eq!(version["version"], env!("CARGO_PKG_VERSION"));
    let newest = std::fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/migrations/sqlite"))
        .unwrap()
        .filter_map(|e| e.unwrap().file_name().to_str()?.split('_').next()?.parse::<i64>().ok())
        .max()
        .unwrap();
    assert_eq!(version["schema_version"], newest, "the newest SQLite migration");
    // A checkout knows its commit; a build given none says null, never an empty string.
    match &version["commit"] {
        Value::String(commit) => assert!(!commit.is_empty() && commit.bytes().all(|b| b.is_ascii_hexdigit())),
        other => assert_eq!(other, &Value::Null),
    }
    app.stop().await;
}

#[tokio::test]
async fn liveness_holds_while_the_store_is_gone_and_readiness_says_so() {
    let app = spawn_app().await;
    std::fs::remove_file(&app.db_path).unwrap();
    // Readiness follows the last read of the store (at most a second old); a clarify reads it.
    let mut ready = StatusCode::OK;
    for _ in 0..40 {
        let _ = app.post("/v1/clarify", &crate::helpers::get_vase()).await;
        ready = app.get("/readyz").await.status();
        if ready != StatusCode::OK {
            break;
        }
        tokio::time::sleep(std::time::Duration::from_millis(100)).await;
    }
    assert_eq!(ready, StatusCode::SERVICE_UNAVAILABLE, "/readyz reports the lost store");
    assert_eq!(app.get("/healthz").await.status(), StatusCode::SERVICE_UNAVAILABLE);
    assert_eq!(
        app.get("/livez").await.status(),
        StatusCode::OK,
        "the process still answers"
    );
    app.stop().await;
}

fn preflight(app: &TestApp, origin: &str) -> reqwest::RequestBuilder {
    app.client
        .request(reqwest::Method::OPTIONS, app.url("/v1/clarify"))
        .header(ORIGIN, origin)
        .header("access-control-request-method", "POST")
        .header("access-control-request-headers", "content-type,authorization")
}

#[tokio::test]
async fn cors_is_off_by_default_and_a_listed_origin_is_answered_with_credentials() {
    let off = spawn_app().await;
    let refused = preflight(&off, "https://app.example").send().await.unwrap();
    assert_eq!(
        refused.status(),
        StatusCode::METHOD_NOT_ALLOWED,
        "no CORS: OPTIONS is not a method here"
    );
    assert!(refused.headers().get(ACCESS_CONTROL_ALLOW_ORIGIN).is_none());
    off.stop().await;

    let listed = ["https://App.example".to_owned(), "http://localhost:5173".to_owned()];
    let origins = CorsOrigins::parse(&listed).unwrap();
    let app = spawn_tweaked(move |config| config.cors = origins).await;
    let answered = preflight(&app, "https://app.example").send().await.unwrap();
    assert_eq!(answered.status(), StatusCode::OK);
    let headers = answered.headers();
    assert_eq!(headers[ACCESS_CONTROL_ALLOW_ORIGIN], "https://app.example");
    assert_eq!(headers[ACCESS_CONTROL_ALLOW_CREDENTIALS], "true");
    let allowed = headers[ACCESS_CONTROL_ALLOW_HEADERS].to_str().unwrap();
    assert!(
        allowed.contains("authorization") && allowed.contains("content-type"),
        "{allowed}"
    );

    // The actual request from that page carries the origin back, and exposes the ETag.
    let set = app
        .client
        .get(app.url("/v1/norm-set"))
        .header(ORIGIN, "http://localhost:5173");
    let set = set.send().await.unwrap();
    assert_eq!(set.headers()[ACCESS_CONTROL_ALLOW_ORIGIN], "http://localhost:5173");
    let exposed = set.headers()[ACCESS_CONTROL_EXPOSE_HEADERS].to_str().unwrap();
    assert!(exposed.contains("etag"), "{exposed}");

    // Another page gets no grant: its browser refuses the answer.
    let other = preflight(&app, "https://evil.example").send().await.unwrap();
    assert!(other.headers().get(ACCESS_CONTROL_ALLOW_ORIGIN).is_none());
    app.stop().await;
}

#[tokio::test]
async fn the_wildcard_origin_never_allows_credentials() {
    let app = spawn_tweaked(|config| config.cors = Some(CorsOrigins::Any)).await;
    let answered = preflight(&app, "https://anyone.example").send().await.unwrap();
    assert_eq!(answered.status(), StatusCode::OK);
    assert_eq!(answered.headers()[ACCESS_CONTROL_ALLOW_ORIGIN], "*");
    assert!(answered.headers().get(ACCESS_CONTROL_ALLOW_CREDENTIALS).is_none());
    let decided = app
        .client
        .post(app.url("/v1/clarify"))
        .header(ORIGIN, "https://anyone.example");
    let decided = decided.json(&crate::helpers::get_vase()).send().await.unwrap();
    assert_eq!(decided.status(), StatusCode::OK);
    assert_eq!(decided.headers()[ACCESS_CONTROL_ALLOW_ORIGIN], "*");
    app.stop().await;
}

async fn put_set(app: &TestApp, body: &Value) -> reqwest::Response {
    app.client.put(app.url("/v1/norm-set")).json(body).send().await.unwrap()
}

#[tokio::test]
async fn a_merge_replaces_what_it_names_adds_the_rest_and_keeps_every_other_norm() {
    let app = spawn_app().await;
    let kept = app
        .add_norm(&json!({"kind": "forbidden_action", "action": "destroy"}))
        .await;
    let named = app
        .add_norm(&json!({"kind": "forbidden_action", "action": "steal"}))
        .await;
    let before: Value = app.get("/v1/norm-set").await.json().await.unwrap();
    let kept_before = before["norms"][0].clone();

    let merged = put_set(
        &app,
        &json!({"mode": "merge", "norms": [
            {"id": named, "kind": "forbidden_action", "action": "steal", "severity": 5},
            {"kind": "forbidden_state", "state": "did(self,get(object3))"}
        ]}),
    )
    .await;
    assert_eq!(merged.status(), StatusCode::OK);
    let merged: Value = merged.json().await.unwrap();
    let norms = merged["norms"].as_array().unwrap();
    assert_eq!(norms.len(), 3, "{merged}");
    assert_eq!(norms[0], kept_before, "the norm not named is kept, revision and all");
    assert_eq!(norms[1]["id"], named);
    assert_eq!(norms[1]["severity"], 5, "the named norm is replaced");
    assert!(norms[2]["id"].as_i64().unwrap() > named, "the new norm gets a fresh id");
    assert_eq!(norms[0]["id"], kept);
    let version = merged["version"].as_i64().unwrap();
    assert_eq!(version, before["version"].as_i64().unwrap() + 1);

    // Merging nothing changes nothing: no new version.
    let nothing: Value = put_set(&app, &json!({"mode": "merge", "norms": []}))
        .await
        .json()
        .await
        .unwrap();
    assert_eq!(nothing["version"], version);
    assert_eq!(nothing["norms"], merged["norms"]);

    // Replace, the default, still makes the set exactly what is sent.
    let replaced: Value = put_set(
        &app,
        &json!({"norms": [{"kind": "forbidden_action", "action": "destroy"}]}),
    )
    .await
    .json()
    .await
    .unwrap();
    assert_eq!(replaced["norms"].as_array().unwrap().len(), 1);

    // A mode that is not one, or a stale precondition: nothing changes.
    let wrong = put_set(&app, &json!({"mode": "append", "norms": []})).await;
    let problem = assert_problem(wrong, StatusCode::UNPROCESSABLE_ENTITY, Some("/mode")).await;
    assert!(
        problem["detail"].as_str().unwrap().contains("`replace` or `merge`"),
        "{problem}"
    );
    let stale = app
        .client
        .put(app.url("/v1/norm-set"))
        .header("if-match", format!("\"{version}\""))
        .json(&json!({"mode": "merge", "norms": [{"kind": "forbidden_action", "action": "steal"}]}))
        .send()
        .await
        .unwrap();
    assert_eq!(stale.status(), StatusCode::PRECONDITION_FAILED);
    let after: Value = app.get("/v1/norm-set").await.json().await.unwrap();
    assert_eq!(after["norms"], replaced["norms"]);
    app.stop().await;
}

#[tokio::test]
async fn grpc_merges_alike_and_names_a_bad_mode() {
    let app = spawn_app().await;
    let mut norms = NormsClient::new(channel(&app).await);
    let kept = app
        .add_norm(&json!({"kind": "forbidden_action", "action": "destroy"}))
        .await;
    let merged = norms
        .import_norms(pb::ImportNormsRequest {
            norms: vec![pb::ImportedNorm {
                id: None,
                norm: Some(norm_request(&json!({"kind": "forbidden_action", "action": "steal"}))),
            }],
            mode: Some("merge".to_owned()),
            ..Default::default()
        })
        .await
        .unwrap()
        .into_inner();
    let ids: Vec<i64> = merged.norms.iter().map(|n| n.id).collect();
    assert_eq!(ids.len(), 2);
    assert_eq!(ids[0], kept);

    // An empty merge needs no `clear` and empties nothing.
    let same = norms
        .import_norms(pb::ImportNormsRequest {
            mode: Some("merge".to_owned()),
            ..Default::default()
        })
        .await
        .unwrap()
        .into_inner();
    assert_eq!(same.version, merged.version);
    assert_eq!(same.norms.len(), 2);

    let bad = norms
        .import_norms(pb::ImportNormsRequest {
            mode: Some("append".to_owned()),
            ..Default::default()
        })
        .await
        .unwrap_err();
    assert_eq!(bad.code(), Code::InvalidArgument);
    assert_eq!(bad.metadata().get("field").and_then(|v| v.to_str().ok()), Some("/mode"));
    let clear = norms
        .import_norms(pb::ImportNormsRequest {
            mode: Some("merge".to_owned()),
            clear: true,
            ..Default::default()
        })
        .await
        .unwrap_err();
    assert_eq!(clear.code(), Code::InvalidArgument);
    let after: Value = app.get("/v1/norm-set").await.json().await.unwrap();
    assert_eq!(after["norms"].as_array().unwrap().len(), 2, "nothing changed");
    app.stop().await;
}

#[test]
fn a_cors_origin_a_browser_would_never_send_is_a_usage_error_naming_the_flag() {
    for (origin, why) in [
        ("https://app.example/", "no path"),
        ("*,https://app.example", "cannot be listed with others"),
    ] {
        let out = crate::support::scruple()
            .args(["serve", "--listen", "127.0.0.1:0", "--database-url", "sqlite::memory:"])
            .env("SCRUPLE_CORS_ORIGINS", origin)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "a usage error: {origin}: {stderr}");
        assert!(
            stderr.contains("--cors-origin") && stderr.contains(why),
            "{origin}: {stderr}"
        );
    }
}
