//! When the norms cannot be read (a table dropped, a row corrupt, the file deleted, replaced or not
//! a database; a PostgreSQL database gone), clarify answers 503 and never complies or assumes;
//! writes refused on a lock leave nothing behind. A corrupt row and a lock held by another
//! session are tried on PostgreSQL as on SQLite.

use reqwest::StatusCode;
use serde_json::json;
use sqlx::sqlite::SqliteConnectOptions;
use sqlx::{ConnectOptions, Connection};

use crate::helpers::{assert_problem, get_vase, spawn_app};

async fn tamper(app: &crate::helpers::TestApp, sql: &str) {
    let mut connection = SqliteConnectOptions::new()
        .filename(&app.db_path)
        .connect()
        .await
        .expect("open the database");
    sqlx::raw_sql(sqlx::AssertSqlSafe(sql.to_owned()))
        .execute(&mut connection)
        .await
        .expect("tamper");
    connection.close().await.unwrap();
    crate::helpers::after_the_lease().await;
}

/// The next clarify answers 503, and its detail says how the file is not the one opened.
async fn clarify_fails_closed(app: &crate::helpers::TestApp, how: &str) {
    let problem = assert_problem(
        app.post("/v1/clarify", &get_vase()).await,
        StatusCode::SERVICE_UNAVAILABLE,
        None,
    )
    .await;
    assert!(problem["detail"].as_str().unwrap().contains(how), "{problem}");
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
async fn a_stored_norm_the_rules_refuse_fails_closed_naming_the_norm_and_the_field() {
    let destroy = json!({"directive": {"action": "destroy", "arguments": [{"type": "mug"}]}, "scene": crate::helpers::lab_scene()});
    // Each row parses as terms and lists, as the reader before the shared validation took it;
    // NormInput::validate refuses it, so decisions stop until it is mended.
    for (tamper_sql, field) in [
        (
            "UPDATE norms SET roles_json = '[\"owner\"]', exempt_roles_json = '[\"owner\"]'",
            "/exempt_roles",
        ),
        ("UPDATE norms SET term = 'X'", "/action"),
        ("UPDATE norms SET roles_json = '[\"not a role!\"]'", "/roles/0"),
    ] {
        let app = spawn_app().await;
        app.add_norm(&json!({"kind": "forbidden_action", "action": "destroy"}))
            .await;
        tamper(
            &app,
            &format!("{tamper_sql}; UPDATE norm_set SET version = version + 1"),
        )
        .await;
        let problem = assert_problem(
            app.post("/v1/clarify", &destroy).await,
            StatusCode::SERVICE_UNAVAILABLE,
            None,
        )
        .await;
        let detail = problem["detail"].as_str().unwrap_or_default();
        assert!(
            detail.contains("norm 1") && detail.contains(field),
            "{tamper_sql}: {detail}"
        );
    }
}

#[tokio::test]
async fn health_is_ok_once_the_store_is_open() {
    let app = spawn_app().await;
    let response = app.get("/healthz").await;
    assert_eq!(response.status(), StatusCode::OK);
}

#[tokio::test]
async fn a_database_file_deleted_under_the_service_fails_closed_instead_of_writing_into_the_void() {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
        .await;
    for suffix in ["", "-wal", "-shm"] {
        let mut path = app.db_path.clone().into_os_string();
        path.push(suffix);
        let _ = std::fs::remove_file(path);
    }
    clarify_fails_closed(&app, "is gone").await;
    let norm = json!({"kind": "forbidden_action", "action": "destroy"});
    assert_problem(
        app.post("/v1/norms", &norm).await,
        StatusCode::SERVICE_UNAVAILABLE,
        None,
    )
    .await;
    assert_problem(app.get("/healthz").await, StatusCode::SERVICE_UNAVAILABLE, None).await;
}

#[tokio::test]
async fn a_database_file_replaced_under_the_service_fails_closed() {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
        .await;
    // Someone restores an old copy over the live file: its norms are not the ones acknowledged.
    let copy = app.dir.path().join("copy.db");
    std::fs::copy(&app.db_path, &copy).unwrap();
    std::fs::rename(&copy, &app.db_path).unwrap();
    clarify_fails_closed(&app, "replaced").await;
}

/// The directory the file is in swapped for one holding a copy (a restore by directory) fails
/// closed on the next request; a file made beside the database changes nothing; and once the
/// original directory is back, decisions go on under the file opened.
#[tokio::test]
async fn a_database_directory_swapped_under_the_service_fails_closed_and_one_put_back_is_served() {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
        .await;
    std::fs::write(app.dir.path().join("notes.txt"), b"beside the database").unwrap();
    assert_eq!(app.clarify(&get_vase()).await["decision"], "assume");

    let live = app.dir.path().to_owned();
    let (staged, away) = (live.with_extension("staged"), live.with_extension("away"));
    std::fs::create_dir(&staged).unwrap();
    std::fs::copy(&app.db_path, staged.join("scruple.db")).unwrap();
    std::fs::rename(&live, &away).unwrap();
    std::fs::rename(&staged, &live).unwrap();
    clarify_fails_closed(&app, "replaced").await;

    std::fs::rename(&live, &staged).unwrap();
    std::fs::rename(&away, &live).unwrap();
    std::fs::remove_dir_all(&staged).unwrap();
    assert_eq!(app.clarify(&get_vase()).await["decision"], "assume");
}

/// In WAL mode another process's write lock never blocks reading the committed norms, so
/// decisions go on under them (the norms in force are known); a write waits out the busy timeout
/// and is refused with 503, writing nothing.
#[tokio::test]
async fn a_write_lock_held_by_another_process_refuses_writes_and_keeps_deciding_under_committed_norms() {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
        .await;
    let mut holder = SqliteConnectOptions::new()
        .filename(&app.db_path)
        .connect()
        .await
        .expect("open the database");
    sqlx::query("BEGIN IMMEDIATE").execute(&mut holder).await.unwrap();
    sqlx::query("UPDATE norm_set SET version = version + 1")
        .execute(&mut holder)
        .await
        .unwrap();
    assert_eq!(app.clarify(&get_vase()).await["decision"], "assume");
    let norm = json!({"kind": "forbidden_action", "action": "destroy"});
    let refused = app.post("/v1/norms", &norm).await;
    assert_eq!(refused.headers().get("retry-after").unwrap(), "1");
    assert_problem(refused, StatusCode::SERVICE_UNAVAILABLE, None).await;
    sqlx::query("ROLLBACK").execute(&mut holder).await.unwrap();
    holder.close().await.unwrap();
    assert_eq!(app.norms().await.len(), 1, "the refused write left nothing behind");
}

#[tokio::test]
async fn the_service_refuses_to_start_on_a_file_that_is_not_a_database() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("corrupt.db");
    std::fs::write(&path, vec![0x5a_u8; 8192]).unwrap();
    let config = scruple::app::Config::new("127.0.0.1:0", format!("sqlite://{}", path.display()));
    let error = scruple::app::Application::build(config)
        .await
        .err()
        .expect("a corrupt file must not start a service that would decide without norms");
    assert!(error.to_string().contains("not a database"), "{error}");
}

/// PostgreSQL down (here: the database dropped and every connection to it terminated): clarify
/// answers 503 rather than deciding without norms, once the lease on the versions read before
/// the drop has run out (README, "Several replicas on PostgreSQL"). Until then the norms read
/// under it still hold; without the wait, the test passed only when the drop itself outlasted
/// the lease.
#[tokio::test]
async fn a_postgresql_database_gone_fails_closed() {
    let database = crate::backends::PgDatabase::create().await;
    let url = database.url.clone();
    let app = crate::helpers::spawn_tweaked(move |c| c.database_url = url).await;
    app.add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
        .await;
    assert_eq!(app.clarify(&get_vase()).await["decision"], "assume");
    drop(database);
    crate::helpers::after_the_lease().await;
    let problem = assert_problem(
        app.post("/v1/clarify", &get_vase()).await,
        StatusCode::SERVICE_UNAVAILABLE,
        None,
    )
    .await;
    assert!(problem.get("decision").is_none());
    assert_problem(app.get("/healthz").await, StatusCode::SERVICE_UNAVAILABLE, None).await;
}

/// A server on a fresh PostgreSQL database, and the database.
async fn on_postgresql() -> (crate::helpers::TestApp, crate::backends::PgDatabase) {
    let database = crate::backends::PgDatabase::create().await;
    let url = database.url.clone();
    let app = crate::helpers::spawn_tweaked(move |c| c.database_url = url).await;
    (app, database)
}

/// PostgreSQL's twin of the corrupt and refused rows above: whatever is wrong with a stored
/// norm, decisions stop (503, no decision) rather than go on without it.
#[tokio::test]
async fn a_corrupt_norm_row_on_postgresql_fails_closed_rather_than_being_skipped() {
    let destroy = json!({"directive": {"action": "destroy", "arguments": [{"type": "mug"}]}, "scene": crate::helpers::lab_scene()});
    for (tamper_sql, says) in [
        ("UPDATE norms SET term = 'destroy('", "norm 1"),
        ("UPDATE norms SET term = 'X'", "/action"),
        ("UPDATE norms SET roles_json = '[\"not a role!\"]'", "/roles/0"),
    ] {
        let (app, database) = on_postgresql().await;
        app.add_norm(&json!({"kind": "forbidden_action", "action": "destroy"}))
            .await;
        assert_eq!(app.clarify(&destroy).await["decision"], "refuse");
        database
            .execute(&format!("{tamper_sql}; UPDATE norm_set SET version = version + 1"))
            .await
            .unwrap();
        crate::helpers::after_the_lease().await;
        let problem = assert_problem(
            app.post("/v1/clarify", &destroy).await,
            StatusCode::SERVICE_UNAVAILABLE,
            None,
        )
        .await;
        assert!(problem.get("decision").is_none(), "{problem}");
        let detail = problem["detail"].as_str().unwrap_or_default();
        assert!(detail.contains(says), "{tamper_sql}: {detail}");
        app.stop().await;
    }
}

/// PostgreSQL's twin of the SQLite write lock: another session holding the norm set's version
/// row makes a write wait out the lock timeout and answer 503 with Retry-After, writing
/// nothing, while decisions go on under the committed norms (readers take no row lock).
#[tokio::test]
async fn a_row_lock_held_by_another_postgresql_session_refuses_writes_and_keeps_deciding() {
    let (app, database) = on_postgresql().await;
    app.add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
        .await;
    let mut holder = sqlx::PgConnection::connect(&database.url).await.unwrap();
    sqlx::raw_sql("BEGIN; SELECT version FROM norm_set WHERE id = 1 FOR UPDATE")
        .execute(&mut holder)
        .await
        .unwrap();
    assert_eq!(app.clarify(&get_vase()).await["decision"], "assume");
    let norm = json!({"kind": "forbidden_action", "action": "destroy"});
    let refused = app.post("/v1/norms", &norm).await;
    assert_eq!(
        refused.headers().get("retry-after").map(|v| v.to_str().unwrap()),
        Some("1")
    );
    assert_problem(refused, StatusCode::SERVICE_UNAVAILABLE, None).await;
    assert_eq!(app.clarify(&get_vase()).await["decision"], "assume");
    sqlx::raw_sql("ROLLBACK").execute(&mut holder).await.unwrap();
    holder.close().await.unwrap();
    assert_eq!(app.norms().await.len(), 1, "the refused write left nothing behind");
    app.stop().await;
}
