//! Soft norms over HTTP and gRPC: "should" and "should not" choose among the acceptable
//! readings, are shown with their score and words, pass a check with their reason, and survive
//! an older store's upgrade.

use reqwest::StatusCode;
use scruple::transport::grpc::pb::clarifier_client::ClarifierClient;
use scruple::transport::grpc::pb::norms_client::NormsClient;
use serde_json::{Value, json};

use crate::grpc::{as_rest_json, channel, clarify_request, norm_request};
use crate::helpers::{Options, assert_problem, raw_sql_on, spawn_app, spawn_on};

/// The serving tray of README's example: a clean and a dirty mug.
fn tray(dirty_too: bool, clean: usize) -> Value {
    let mut objects = Vec::new();
    for (n, color) in ["blue", "red"].iter().take(clean).enumerate() {
        objects.push(
            json!({"id": format!("mug{}", n + 1), "type": "mug", "properties": ["clean"],
                            "attributes": {"color": color}, "position": [0.5, 0.1 + 0.1 * n as f64, 0.8]}),
        );
    }
    if dirty_too {
        objects.push(json!({"id": "mug9", "type": "mug", "properties": ["dirty"],
                            "attributes": {"color": "green"}, "position": [0.5, -0.1, 0.8]}));
    }
    json!({"agent": {"id": "self", "position": [0, 0, 0.75], "reach": 0.9}, "objects": objects})
}

fn serving_norm() -> Value {
    json!({"kind": "discouraged_action", "action": "get(X)", "when": ["dirty(X)"], "context": "serving",
           "severity": 2, "note": "one serves with clean things"})
}

fn get_me_the_mug(scene: Value) -> Value {
    json!({"directive": {"text": "Get me the mug."}, "scene": scene, "context": "serving"})
}

#[tokio::test]
async fn serving_gives_the_clean_mug_and_says_why_not_the_dirty_one() {
    let app = spawn_app().await;
    let id = app.add_norm(&serving_norm()).await;
    let stored: Value = app.get(&format!("/v1/norms/{id}")).await.json().await.unwrap();
    assert_eq!(stored["kind"], "discouraged_action");
    assert_eq!(stored["severity"], 2);

    let answer = app.clarify(&get_me_the_mug(tray(true, 1))).await;
    assert_eq!(answer["decision"], "assume", "{answer}");
    assert_eq!(answer["goal"], "did(self,get(mug1))");
    assert_eq!(
        answer["utterance"],
        "I am assuming you want me to get the clean mug. I would rather not get the dirty mug because the dirty mug is dirty."
    );
    let dirty = &answer["interpretations"][1];
    assert_eq!(dirty["permissible"], true);
    assert_eq!(dirty["feasible"], true);
    assert_eq!(dirty["norm_score"], -2);
    assert_eq!(
        dirty["reasons"],
        json!([{"kind": "discouraged_action", "detail": "get(mug9)", "norm_id": id, "severity": 2,
                "words": "the dirty mug is dirty"}])
    );
    assert!(
        answer["interpretations"][0].get("norm_score").is_none(),
        "0 is left out: {answer}"
    );

    // Two clean and a dirty one: which clean one; the dirty one is never offered.
    let answer = app.clarify(&get_me_the_mug(tray(true, 2))).await;
    assert_eq!(answer["decision"], "ask");
    assert_eq!(
        answer["utterance"],
        "Do you mean that you want me to get the clean blue mug or that you want me to get the clean red mug?"
    );
    assert_eq!(answer["offered"], json!(["did(self,get(mug1))", "did(self,get(mug2))"]));

    // Only the dirty mug: handed over, saying so.
    let answer = app.clarify(&get_me_the_mug(tray(true, 0))).await;
    assert_eq!(answer["decision"], "comply");
    assert_eq!(answer["utterance"], "Okay, although the mug is dirty.");

    // The control condition: today's question.
    let mut ignoring = get_me_the_mug(tray(true, 1));
    ignoring["options"] = json!({"soft_norms": "ignore"});
    let answer = app.clarify(&ignoring).await;
    assert_eq!(answer["decision"], "ask");
    assert!(answer["interpretations"][1]["reasons"].as_array().unwrap().is_empty());
    ignoring["options"] = json!({"soft_norms": "sometimes"});
    let problem = assert_problem(
        app.post("/v1/clarify", &ignoring).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/options/soft_norms"),
    )
    .await;
    assert!(problem["detail"].as_str().unwrap().contains("rank"), "{problem}");
}

#[tokio::test]
async fn the_stronger_norm_wins_a_conflict() {
    let app = spawn_app().await;
    app.add_norm(
        &json!({"kind": "preferred_action", "action": "get(X)", "when": ["dirty(X)"],
                         "context": "tidying", "severity": 2}),
    )
    .await;
    app.add_norm(
        &json!({"kind": "preferred_action", "action": "get(X)", "when": ["broken(X)"],
                         "context": "tidying", "severity": 4, "note": "hazards first"}),
    )
    .await;
    let floor = json!({"agent": {"id": "self", "position": [0, 0, 0.75], "reach": 0.9},
        "objects": [{"id": "plate1", "type": "plate", "properties": ["broken"], "position": [0.5, 0.2, 0.1]},
                    {"id": "cup1", "type": "cup", "properties": ["dirty"], "position": [0.5, -0.2, 0.1]}],
        "facts": ["on(plate1,floor1)", "on(cup1,floor1)"]});
    let body = json!({"directive": {"form": "get(X)", "bindings": {"X": ["plate1", "cup1"]},
                                    "text": "Pick up the thing on the floor."},
                      "scene": floor, "context": "tidying"});
    let answer = app.clarify(&body).await;
    assert_eq!(answer["decision"], "assume", "{answer}");
    assert_eq!(answer["goal"], "did(self,get(plate1))");
    assert_eq!(
        answer["utterance"],
        "I am assuming you want me to get the plate. I would rather not get the cup because it is less preferred than getting the plate."
    );
    let scores: Vec<&Value> = (answer["interpretations"].as_array().unwrap().iter())
        .map(|i| &i["norm_score"])
        .collect();
    assert_eq!(scores, [&json!(2), &json!(4)]);
}

#[tokio::test]
async fn a_preferred_norm_never_rescues_a_forbidden_reading() {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "preferred_action", "action": "get(X)", "when": ["dirty(X)"], "severity": 5}))
        .await;
    app.add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(mug9))"}))
        .await;
    let answer = app
        .clarify(&json!({"directive": {"action": "get", "arguments": [{"type": "mug"}]}, "scene": tray(true, 1)}))
        .await;
    assert_eq!(answer["decision"], "assume");
    assert_eq!(answer["goal"], "did(self,get(mug1))");
    assert_eq!(
        answer["utterance"],
        "I am assuming you want me to get the clean mug. I cannot get the dirty mug because it requires a forbidden state."
    );
    let dirty = &answer["interpretations"][1];
    assert_eq!(dirty["permissible"], false);
    assert_eq!(dirty["norm_score"], 5, "the score is shown, and changes nothing");
}

#[tokio::test]
async fn a_check_permits_a_discouraged_step_with_its_reason() {
    let app = spawn_app().await;
    let id = app.add_norm(&serving_norm()).await;
    let body = json!({"scene": tray(true, 0), "steps": ["get(mug9)"], "context": "serving"});
    let answer: Value = app.post("/v1/check", &body).await.json().await.unwrap();
    assert_eq!(answer["permitted"], true, "{answer}");
    assert_eq!(answer["utterance"], "Okay, although the mug is dirty.");
    assert_eq!(answer["steps"][0]["permissible"], true);
    assert_eq!(answer["steps"][0]["reasons"][0]["kind"], "discouraged_action");
    assert_eq!(answer["steps"][0]["reasons"][0]["norm_id"], id);
}

#[tokio::test]
async fn soft_norms_are_validated_as_the_forbidden_kinds_are() {
    let app = spawn_app().await;
    for (norm, field) in [
        (json!({"kind": "discouraged_action", "state": "dirty(X)"}), "/state"),
        (json!({"kind": "preferred_state", "action": "get"}), "/action"),
        (json!({"kind": "preferred_state"}), "/state"),
        (
            json!({"kind": "discouraged_action", "action": "get", "severity": 6}),
            "/severity",
        ),
        (json!({"kind": "should_not"}), "/kind"),
    ] {
        let response = app.post("/v1/norms", &norm).await;
        let problem = assert_problem(response, StatusCode::UNPROCESSABLE_ENTITY, Some(field)).await;
        if field == "/kind" {
            let detail = problem["detail"].as_str().unwrap();
            for kind in [
                "discouraged_action",
                "discouraged_state",
                "preferred_action",
                "preferred_state",
            ] {
                assert!(detail.contains(kind), "{detail}");
            }
        }
    }
    assert!(app.norms().await.is_empty(), "nothing was stored");
}

#[tokio::test]
async fn grpc_gives_the_same_soft_answer_as_rest() {
    let app = spawn_app().await;
    let channel = channel(&app).await;
    NormsClient::new(channel.clone())
        .create_norm(norm_request(&serving_norm()))
        .await
        .expect("a soft norm created over gRPC");
    let mut clarifier = ClarifierClient::new(channel);
    for scene in [tray(true, 1), tray(true, 2), tray(true, 0)] {
        let body = get_me_the_mug(scene);
        let rest = app.clarify(&body).await;
        let grpc = as_rest_json(clarifier.clarify(clarify_request(&body)).await.unwrap().into_inner());
        assert_eq!(grpc, rest);
    }
}

#[tokio::test]
async fn an_older_store_keeps_its_norms_and_ids_and_takes_soft_ones() {
    let app = spawn_app().await;
    let dir = app.dir.clone();
    let kept = app
        .add_norm(&json!({"kind": "forbidden_action", "action": "destroy", "note": "kept"}))
        .await;
    let gone = app
        .add_norm(&json!({"kind": "forbidden_action", "action": "steal"}))
        .await;
    assert_eq!(
        app.delete(&format!("/v1/norms/{gone}")).await.status(),
        StatusCode::NO_CONTENT
    );
    let before = app.norms().await;
    app.stop().await;
    // As an older build left it: the norms table with its check on the two forbidden kinds, and
    // the soft-norms migration not applied.
    let db_path = dir.path().join("scruple.db");
    raw_sql_on(
        &db_path,
        "CREATE TABLE norms_old (
             id INTEGER PRIMARY KEY AUTOINCREMENT,
             kind TEXT NOT NULL CHECK (kind IN ('forbidden_action', 'forbidden_state')),
             term TEXT NOT NULL, when_json TEXT NOT NULL DEFAULT '[]', context TEXT,
             severity INTEGER NOT NULL DEFAULT 3 CHECK (severity BETWEEN 1 AND 5), note TEXT,
             created_at TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now')),
             roles_json TEXT NOT NULL DEFAULT '[]', exempt_roles_json TEXT NOT NULL DEFAULT '[]',
             revision INTEGER NOT NULL DEFAULT 0);
         INSERT INTO norms_old SELECT * FROM norms;
         CREATE TEMP TABLE old_sequence AS SELECT seq FROM sqlite_sequence WHERE name = 'norms';
         DROP TABLE norms;
         ALTER TABLE norms_old RENAME TO norms;
         UPDATE sqlite_sequence SET seq = (SELECT seq FROM old_sequence) WHERE name = 'norms';
         DELETE FROM _sqlx_migrations WHERE version = 20261201000004;",
    )
    .await
    .unwrap();
    let refused = raw_sql_on(
        &db_path,
        "INSERT INTO norms (kind, term) VALUES ('discouraged_action', 'get')",
    )
    .await;
    assert!(refused.is_err(), "the older table refuses soft kinds");

    let app = spawn_on(dir, Options::default()).await;
    assert_eq!(app.norms().await, before, "every norm as it was");
    let soft = app.add_norm(&serving_norm()).await;
    assert!(soft > gone, "a deleted id is never reused ({soft} after {gone})");
    assert_eq!(app.norms().await.len(), 2);
    assert!(kept < gone);
}
