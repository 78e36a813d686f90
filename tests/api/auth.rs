//! Tokens: writes need a write token (401 without, 403 wrong or read-only); reads need one once
//! reader tokens are configured; clarify and check never do; secrets never reach a log.

use reqwest::StatusCode;
use serde_json::json;

use crate::helpers::{Options, assert_problem, get_vase, spawn_tweaked, spawn_with};
use scruple::transport::auth::LabelledSecret;

#[tokio::test]
async fn writes_need_the_admin_token_and_reads_do_not() {
    let app = spawn_with(Options {
        admin_token: Some("s3cret-admin-token".into()),
        ..Options::default()
    })
    .await;
    let norm = json!({"kind": "forbidden_action", "action": "destroy"});

    let response = app.post("/v1/norms", &norm).await;
    assert_eq!(
        response.headers().get("www-authenticate").map(|v| v.to_str().unwrap()),
        Some("Bearer")
    );
    assert_problem(response, StatusCode::UNAUTHORIZED, None).await;
    let wrong = app
        .client
        .post(app.url("/v1/norms"))
        .bearer_auth("guess")
        .json(&norm)
        .send()
        .await
        .unwrap();
    assert_problem(wrong, StatusCode::FORBIDDEN, None).await;
    let basic = app
        .client
        .post(app.url("/v1/norms"))
        .basic_auth("admin", Some("s3cret-admin-token"))
        .json(&norm)
        .send()
        .await
        .unwrap();
    assert_problem(basic, StatusCode::UNAUTHORIZED, None).await;
    // The token is checked before the body: a bad norm without a token is still 401.
    let bad = app.post("/v1/norms", &json!({"kind": "nonsense"})).await;
    assert_problem(bad, StatusCode::UNAUTHORIZED, None).await;
    assert!(app.norms().await.is_empty(), "nothing stored without the token");

    let created = app
        .client
        .post(app.url("/v1/norms"))
        .bearer_auth("s3cret-admin-token")
        .json(&norm)
        .send()
        .await
        .unwrap();
    assert_eq!(created.status(), StatusCode::CREATED);
    let id = created.json::<serde_json::Value>().await.unwrap()["id"]
        .as_i64()
        .unwrap();

    assert_eq!(app.norms().await.len(), 1, "listing is open");
    assert_eq!(app.get(&format!("/v1/norms/{id}")).await.status(), StatusCode::OK);
    assert_eq!(
        app.post("/v1/clarify", &get_vase()).await.status(),
        StatusCode::OK,
        "clarify is open"
    );

    let path = format!("/v1/norms/{id}");
    assert_problem(app.delete(&path).await, StatusCode::UNAUTHORIZED, None).await;
    let wrong = app
        .client
        .delete(app.url(&path))
        .bearer_auth("guess")
        .send()
        .await
        .unwrap();
    assert_problem(wrong, StatusCode::FORBIDDEN, None).await;
    assert_eq!(app.norms().await.len(), 1);
    let deleted = app
        .client
        .delete(app.url(&path))
        .bearer_auth("s3cret-admin-token")
        .send()
        .await
        .unwrap();
    assert_eq!(deleted.status(), StatusCode::NO_CONTENT);
    assert!(app.norms().await.is_empty());
}

fn labelled(label: &str, secret: &str) -> LabelledSecret {
    LabelledSecret {
        label: label.to_owned(),
        secret: secret.to_owned(),
    }
}

#[tokio::test]
async fn reader_tokens_guard_reads_of_the_curated_state_but_never_decisions() {
    let app = spawn_tweaked(|c| {
        c.curator_tokens = vec![labelled("alice", "alice-secret-0123456789")];
        c.reader_tokens = vec![labelled("dashboard", "dashboard-secret-0123456789")];
    })
    .await;
    let norm = json!({"kind": "forbidden_state", "state": "did(self,get(object3))"});
    let send = |request: reqwest::RequestBuilder, token: Option<&str>| {
        let request = match token {
            Some(token) => request.bearer_auth(token),
            None => request,
        };
        request.send()
    };
    let reader = Some("dashboard-secret-0123456789");
    let curator = Some("alice-secret-0123456789");
    let created = send(app.client.post(app.url("/v1/norms")).json(&norm), curator)
        .await
        .unwrap();
    assert_eq!(created.status(), StatusCode::CREATED);
    let refused = send(app.client.post(app.url("/v1/norms")).json(&norm), reader)
        .await
        .unwrap();
    let problem = assert_problem(refused, StatusCode::FORBIDDEN, None).await;
    assert!(problem["detail"].as_str().unwrap().contains("may read"), "{problem}");
    for path in [
        "/v1/norms",
        "/v1/norms/1",
        "/v1/norm-set",
        "/v1/audit",
        "/v1/actions",
        "/v1/actions/get",
    ] {
        assert_problem(app.get(path).await, StatusCode::UNAUTHORIZED, None).await;
        let stranger = send(app.client.get(app.url(path)), Some("nobody-0123456789"))
            .await
            .unwrap();
        assert_problem(stranger, StatusCode::FORBIDDEN, None).await;
        for token in [reader, curator] {
            let read = send(app.client.get(app.url(path)), token).await.unwrap();
            assert_eq!(read.status(), StatusCode::OK, "{path}");
        }
    }
    let decision = app.clarify(&get_vase()).await;
    assert_eq!(decision["decision"], "assume", "a robot's decisions need no token");
}

/// Secrets must not reach logs even at the most verbose level, whether sent right or wrong.
#[tokio::test]
async fn tokens_never_reach_the_log() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("log.txt");
    let served = crate::helpers::serve_binary(
        &format!("sqlite://{}", dir.path().join("db").display()),
        &[],
        &[
            ("SCRUPLE_ADMIN_TOKEN", "admin-SECRET-in-env"),
            ("SCRUPLE_CURATOR_TOKENS", "carol=carol-SECRET-0123456789"),
            ("RUST_LOG", "trace"),
        ],
        std::fs::File::create(&log).unwrap().into(),
    );
    let addr = served.addr.clone();
    let client = crate::helpers::http_client();
    let norm = json!({"kind": "forbidden_action", "action": "destroy"});
    for token in ["admin-SECRET-in-env", "carol-SECRET-0123456789", "wrong-SECRET-guess"] {
        let _ = client
            .post(format!("http://{addr}/v1/norms"))
            .bearer_auth(token)
            .json(&norm)
            .send()
            .await
            .unwrap();
    }
    served.terminate();
    let text = std::fs::read_to_string(&log).unwrap();
    assert!(text.len() > 1000, "trace logging is on: {} bytes", text.len());
    assert!(!text.contains("SECRET"), "a secret reached the log");
}

/// RFC 9110 §11.1: the scheme is case-insensitive; the token itself is not.
#[tokio::test]
async fn the_bearer_scheme_is_matched_in_any_case() {
    let app = spawn_with(Options {
        admin_token: Some("s3cret-admin-token".into()),
        ..Options::default()
    })
    .await;
    let norm = json!({"kind": "forbidden_action", "action": "destroy"});
    for header in [
        "Bearer s3cret-admin-token",
        "bearer s3cret-admin-token",
        "BEARER s3cret-admin-token",
        "bEaReR   s3cret-admin-token",
    ] {
        let response = app
            .client
            .post(app.url("/v1/norms"))
            .header("authorization", header)
            .json(&norm)
            .send()
            .await
            .unwrap();
        assert_eq!(response.status(), StatusCode::CREATED, "{header}");
    }
    let wrong_case = app
        .client
        .post(app.url("/v1/norms"))
        .header("authorization", "Bearer S3CRET")
        .json(&norm)
        .send()
        .await
        .unwrap();
    assert_problem(wrong_case, StatusCode::FORBIDDEN, None).await;
    let no_space = app
        .client
        .post(app.url("/v1/norms"))
        .header("authorization", "Bearers3cret-admin-token")
        .json(&norm)
        .send()
        .await
        .unwrap();
    assert_problem(no_space, StatusCode::UNAUTHORIZED, None).await;
}
