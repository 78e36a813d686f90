//! When the norms cannot be read, clarify answers 503 and never complies or assumes.

use reqwest::StatusCode;
use serde_json::json;
use sqlx::sqlite::SqliteConnectOptions;
use sqlx::{ConnectOptions, Connection};

use crate::helpers::{assert_problem, get_vase, spawn_app};

async fn tamper(app: &crate::helpers::TestApp, sql: &'static str) {
    let mut connection = SqliteConnectOptions::new()
        .filename(&app.db_path)
        .connect()
        .await
        .expect("open the database");
    sqlx::query(sql).execute(&mut connection).await.expect("tamper");
    connection.close().await.unwrap();
}

#[tokio::test]
async fn a_missing_norm_table_fails_closed() {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
        .await;
    assert_eq!(app.clarify(&get_vase()).await["decision"], "assume");
    tamper(&app, "DROP TABLE norms; UPDATE norm_set SET version = version + 1").await;
    let problem = assert_problem(
        app.post("/v1/clarify", &get_vase()).await,
        StatusCode::SERVICE_UNAVAILABLE,
        None,
    )
    .await;
    assert!(problem.get("decision").is_none());
    // Curating fails the same way, and says the store is at fault, not the norm.
    let norm = json!({"kind": "forbidden_action", "action": "destroy"});
    assert_problem(
        app.post("/v1/norms", &norm).await,
        StatusCode::SERVICE_UNAVAILABLE,
        None,
    )
    .await;
    assert_problem(app.get("/v1/norms").await, StatusCode::SERVICE_UNAVAILABLE, None).await;
}

#[tokio::test]
async fn a_missing_version_table_fails_closed_and_health_says_so() {
    let app = spawn_app().await;
    tamper(&app, "DROP TABLE norm_set").await;
    assert_problem(
        app.post("/v1/clarify", &get_vase()).await,
        StatusCode::SERVICE_UNAVAILABLE,
        None,
    )
    .await;
    assert_problem(app.get("/healthz").await, StatusCode::SERVICE_UNAVAILABLE, None).await;
}

#[tokio::test]
async fn a_corrupt_norm_row_fails_closed_rather_than_being_skipped() {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_action", "action": "destroy"}))
        .await;
    // A norm the service cannot parse must not silently drop out of the set.
    tamper(
        &app,
        "UPDATE norms SET term = 'destroy(' ; UPDATE norm_set SET version = version + 1",
    )
    .await;
    let destroy = json!({"directive": {"action": "destroy", "arguments": [{"type": "mug"}]}, "scene": crate::helpers::lab_scene()});
    assert_problem(
        app.post("/v1/clarify", &destroy).await,
        StatusCode::SERVICE_UNAVAILABLE,
        None,
    )
    .await;
}

#[tokio::test]
async fn health_is_ok_once_the_store_is_open() {
    let app = spawn_app().await;
    let response = app.get("/healthz").await;
    assert_eq!(response.status(), StatusCode::OK);
}
