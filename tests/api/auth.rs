//! `--admin-token`: writes need it (401 without, 403 wrong); reads and clarify stay open.

use reqwest::StatusCode;
use serde_json::json;

use crate::helpers::{Options, assert_problem, get_vase, spawn_with};

#[tokio::test]
async fn writes_need_the_admin_token_and_reads_do_not() {
    let app = spawn_with(Options {
        admin_token: Some("s3cret".into()),
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
        .basic_auth("admin", Some("s3cret"))
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
        .bearer_auth("s3cret")
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
        .bearer_auth("s3cret")
        .send()
        .await
        .unwrap();
    assert_eq!(deleted.status(), StatusCode::NO_CONTENT);
    assert!(app.norms().await.is_empty());
}
