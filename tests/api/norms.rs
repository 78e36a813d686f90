//! The norms API: create, list, get, delete; canonical terms; persistence; visibility across
//! processes sharing one database.

use reqwest::StatusCode;
use serde_json::{Value, json};

use crate::helpers::{KeepAsking, Options, assert_problem, get_vase, spawn_app, spawn_on};

#[tokio::test]
async fn a_norm_is_stored_canonical_listed_fetched_and_deleted() {
    let app = spawn_app().await;
    let response = app
        .post("/v1/norms", &json!({"kind": "forbidden_state", "state": "holding( self , X:physobj )", "when": ["fragile( X )"], "severity": 4, "context": "hospital", "note": "no fragile things in hand"}))
        .await;
    assert_eq!(response.status(), StatusCode::CREATED);
    let location = response.headers()["location"].to_str().unwrap().to_owned();
    let created: Value = response.json().await.unwrap();
    let id = created["id"].as_i64().unwrap();
    assert_eq!(location, format!("/v1/norms/{id}"));
    assert_eq!(
        created,
        json!({"id": id, "revision": 1, "kind": "forbidden_state", "state": "holding(self,X)", "when": ["fragile(X)"],
               "severity": 4, "context": "hospital", "note": "no fragile things in hand"})
    );
    let defaulted = app
        .post("/v1/norms", &json!({"kind": "forbidden_action", "action": "destroy"}))
        .await;
    let defaulted: Value = defaulted.json().await.unwrap();
    assert_eq!(defaulted["severity"], 3);
    assert_eq!(defaulted["when"], json!([]));
    assert!(defaulted.get("context").is_none());

    assert_eq!(app.norms().await, vec![created.clone(), defaulted.clone()]);
    let fetched: Value = app.get(&format!("/v1/norms/{id}")).await.json().await.unwrap();
    assert_eq!(fetched, created);

    assert_eq!(
        app.delete(&format!("/v1/norms/{id}")).await.status(),
        StatusCode::NO_CONTENT
    );
    assert_problem(app.get(&format!("/v1/norms/{id}")).await, StatusCode::NOT_FOUND, None).await;
    assert_problem(
        app.delete(&format!("/v1/norms/{id}")).await,
        StatusCode::NOT_FOUND,
        None,
    )
    .await;
    assert_problem(app.get("/v1/norms/not-a-number").await, StatusCode::NOT_FOUND, None).await;
    assert_eq!(app.norms().await, vec![defaulted]);
}

#[tokio::test]
async fn ids_are_never_reused_after_a_delete() {
    let app = spawn_app().await;
    let first = app
        .add_norm(&json!({"kind": "forbidden_action", "action": "steal"}))
        .await;
    assert_eq!(
        app.delete(&format!("/v1/norms/{first}")).await.status(),
        StatusCode::NO_CONTENT
    );
    let second = app
        .add_norm(&json!({"kind": "forbidden_action", "action": "steal"}))
        .await;
    assert!(second > first);
}

#[tokio::test]
async fn norms_survive_a_restart() {
    let app = spawn_app().await;
    let dir = app.dir.clone();
    app.add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
        .await;
    let before = app.norms().await;
    app.stop().await;

    let again = spawn_on(dir, Options::default()).await;
    assert_eq!(again.norms().await, before);
    let answer = again.clarify(&get_vase()).await;
    assert_eq!(answer["decision"], "assume");
    assert_eq!(answer["goal"], "did(self,get(object4))");
}

#[tokio::test]
async fn a_change_on_one_process_is_seen_by_the_very_next_request_on_another() {
    let one = spawn_app().await;
    let other = spawn_on(one.dir.clone(), Options::default()).await;

    // Nothing forbidden yet: both vases may be got, so the robot asks.
    assert_eq!(other.clarify(&get_vase()).await["decision"], "ask");

    let id = one
        .add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
        .await;
    let answer = other.clarify(&get_vase()).await;
    assert_eq!(answer["decision"], "assume");
    assert_eq!(answer["goal"], "did(self,get(object4))");
    assert_eq!(answer["interpretations"][0]["reasons"][0]["norm_id"], id);

    assert_eq!(
        other.delete(&format!("/v1/norms/{id}")).await.status(),
        StatusCode::NO_CONTENT
    );
    let answer = one.clarify(&get_vase()).await;
    assert_eq!(answer["decision"], "ask");
    assert_eq!(answer["norm_version"], 2);
}

/// The lease on the stored versions never hides an acknowledged change: the other process
/// answers a steady stream of requests (so its lease is always fresh), and each change made
/// through one is enforced by the other's first request after the acknowledgement, every time.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn every_acknowledged_change_is_seen_at_once_by_a_busy_other_process() {
    let one = spawn_app().await;
    let other = spawn_on(one.dir.clone(), Options::default()).await;
    let busy = KeepAsking::at(&other.base);
    for round in 0..25 {
        let id = one
            .add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
            .await;
        let answer = other.clarify(&get_vase()).await;
        assert_eq!(answer["decision"], "assume", "round {round}: {answer}");
        assert_eq!(
            one.delete(&format!("/v1/norms/{id}")).await.status(),
            StatusCode::NO_CONTENT
        );
        let answer = other.clarify(&get_vase()).await;
        assert_eq!(answer["decision"], "ask", "round {round}: {answer}");
    }
    assert!(busy.stop().await > 50, "the other process was kept busy");
}

#[tokio::test]
async fn context_norms_apply_only_to_requests_in_that_context() {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_action", "action": "get", "context": "hospital"}))
        .await;
    let mut request = json!({
        "directive": {"action": "get", "arguments": [{"type": "mug"}]},
        "scene": crate::helpers::lab_scene(),
    });
    assert_eq!(app.clarify(&request).await["decision"], "comply");
    request["context"] = json!("hospital");
    let answer = app.clarify(&request).await;
    assert_eq!(answer["decision"], "refuse");
    assert_eq!(
        answer["utterance"],
        "I cannot get the mug because getting the mug is forbidden in the hospital context."
    );
}

#[tokio::test]
async fn when_conditions_are_checked_against_the_scene() {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_state", "state": "holding(self,X)", "when": ["fragile(X)"]}))
        .await;
    let answer = app.clarify(&get_vase()).await;
    assert_eq!(answer["decision"], "assume");
    assert_eq!(answer["goal"], "did(self,get(object4))");
    assert_eq!(
        answer["interpretations"][0]["reasons"][0]["detail"],
        "holding(self,object3)"
    );
}

/// Refresh ahead: once three quarters of the lease have run, the next request reads the stored
/// versions again, so a change made behind the service's back (not acknowledged by it, so only
/// promised within the lease) shows before the lease runs out, and no request waits for the
/// read at its end. Under the lease the change is not seen yet (so what shows it later is the
/// read ahead, not a read on every request); the request at 80% of the lease answers from the
/// store, not the lease.
///
/// Which side of those instants a request falls on depends on how fast the machine answers, so
/// each is measured, never assumed: a try whose requests did not all fall where the check needs
/// them (a stalled machine) starts again on a fresh service with a longer lease, and the test
/// fails only if none does. Every check is made on the try that counts; none is skipped.
#[tokio::test]
async fn the_versions_are_read_again_before_the_lease_runs_out() {
    let mut tries = Vec::new();
    for lease_ms in [400, 600, 900] {
        match held_then_read_ahead(std::time::Duration::from_millis(lease_ms)).await {
            Ok(()) => return,
            Err(why) => tries.push(format!("{lease_ms} ms: {why}")),
        }
    }
    panic!("no try fell where the checks need it:\n{}", tries.join("\n"));
}

/// One try with `lease`: `Err` says which instant fell outside its window.
async fn held_then_read_ahead(lease: std::time::Duration) -> Result<(), String> {
    use std::time::{Duration, Instant};
    let app = crate::helpers::spawn_tweaked(move |config| config.lease = lease).await;
    // The write drops this process's lease, so the next request reads.
    app.add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
        .await;
    let body = get_vase();
    // The lease is taken between these two instants.
    let before = Instant::now();
    assert_eq!(app.clarify(&body).await["decision"], "assume");
    let after = Instant::now();
    crate::helpers::raw_sql_on(
        &app.db_path,
        "DELETE FROM norms; UPDATE norm_set SET version = version + 1",
    )
    .await
    .unwrap();
    let stale = app.clarify(&body).await;
    let stale_by = before.elapsed();
    // Nothing reads the store again before three quarters of the lease after `before` (the
    // read ahead) or a second after it (the readiness probe, when no request has read).
    let window = lease.mul_f64(0.75).min(Duration::from_secs(1));
    if stale_by >= window {
        app.stop().await;
        return Err(format!("the request under the lease ended {stale_by:?} after the read"));
    }
    assert_eq!(
        stale["decision"], "assume",
        "under the lease, a change behind the service's back is not seen yet"
    );
    tokio::time::sleep_until((after + lease.mul_f64(0.8)).into()).await;
    let sent = before.elapsed();
    let fresh = app.clarify(&body).await;
    // Sent before the lease ran out and before the probe could read: only the read ahead
    // can have seen the change.
    if sent >= lease.min(Duration::from_secs(1)) {
        app.stop().await;
        return Err(format!(
            "the request at 80% of the lease was sent {sent:?} after the read"
        ));
    }
    assert_eq!(fresh["decision"], "ask", "{fresh}");
    assert_eq!(app.clarify(&body).await["decision"], "ask");
    app.stop().await;
    Ok(())
}
