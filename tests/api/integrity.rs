//! The norm store keeps every acknowledged write: replace with If-Match (412 when stale, no lost
//! update under concurrent curators), export and import round-trip, and an audit trail of every
//! change with the label of the token that made it.

use reqwest::StatusCode;
use serde_json::{Value, json};

use crate::helpers::{TestApp, assert_problem, get_vase, spawn_app, spawn_tweaked};
use scruple::app::Secret;
use scruple::transport::auth::LabelledSecret;

fn etag(response: &reqwest::Response) -> String {
    response
        .headers()
        .get("etag")
        .expect("an ETag")
        .to_str()
        .unwrap()
        .to_owned()
}

async fn put(app: &TestApp, path: &str, if_match: Option<&str>, body: &Value) -> reqwest::Response {
    let mut request = app.client.put(app.url(path)).json(body);
    if let Some(tag) = if_match {
        request = request.header("if-match", tag);
    }
    request.send().await.unwrap()
}

#[tokio::test]
async fn a_norm_is_replaced_in_place_and_a_stale_if_match_is_refused_with_412() {
    let app = spawn_app().await;
    let created = app
        .post(
            "/v1/norms",
            &json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}),
        )
        .await;
    assert_eq!(created.status(), StatusCode::CREATED);
    let first = etag(&created);
    let body: Value = created.json().await.unwrap();
    assert_eq!(first, format!("\"{}\"", body["revision"]));
    let id = body["id"].as_i64().unwrap();
    assert_eq!(app.clarify(&get_vase()).await["decision"], "assume");

    // Replace it: the fragile vase becomes gettable, the plastic one forbidden.
    let path = format!("/v1/norms/{id}");
    let plastic = json!({"kind": "forbidden_state", "state": "did(self,get(object4))", "severity": 4});
    let replaced = put(&app, &path, Some(&first), &plastic).await;
    assert_eq!(replaced.status(), StatusCode::OK);
    let second = etag(&replaced);
    assert_ne!(first, second);
    let stored: Value = replaced.json().await.unwrap();
    assert_eq!(
        (stored["id"].as_i64(), &stored["state"]),
        (Some(id), &json!("did(self,get(object4))"))
    );
    let decision = app.clarify(&get_vase()).await;
    assert_eq!(decision["decision"], "assume");
    assert_eq!(
        decision["goal"], "did(self,get(object3))",
        "the next decision uses the replaced norm"
    );

    // A curator still holding the first revision is refused, and nothing changes.
    let stale = put(
        &app,
        &path,
        Some(&first),
        &json!({"kind": "forbidden_action", "action": "get"}),
    )
    .await;
    let problem = assert_problem(stale, StatusCode::PRECONDITION_FAILED, None).await;
    assert_eq!(problem["type"], "/problems/stale-revision");
    let now = app.get(&path).await;
    assert_eq!(etag(&now), second);
    assert_eq!(now.json::<Value>().await.unwrap()["state"], "did(self,get(object4))");

    // Delete is conditional the same way; an unreadable tag matches nothing.
    let delete = |tag: &'static str| app.client.delete(app.url(&path)).header("if-match", tag).send();
    assert_eq!(delete("\"1\"").await.unwrap().status(), StatusCode::PRECONDITION_FAILED);
    assert_eq!(
        delete("garbage").await.unwrap().status(),
        StatusCode::PRECONDITION_FAILED
    );
    let gone = app
        .client
        .delete(app.url(&path))
        .header("if-match", &second)
        .send()
        .await
        .unwrap();
    assert_eq!(gone.status(), StatusCode::NO_CONTENT);
    assert_problem(put(&app, &path, None, &plastic).await, StatusCode::NOT_FOUND, None).await;
}

#[tokio::test]
async fn replace_refuses_a_body_naming_another_norm_or_invalid_fields_and_writes_nothing() {
    let app = spawn_app().await;
    let id = app
        .add_norm(&json!({"kind": "forbidden_action", "action": "destroy"}))
        .await;
    let path = format!("/v1/norms/{id}");
    let other = json!({"id": id + 1, "kind": "forbidden_action", "action": "steal"});
    assert_problem(
        put(&app, &path, None, &other).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/id"),
    )
    .await;
    let bad = json!({"kind": "forbidden_action", "action": "steal", "severity": 9});
    assert_problem(
        put(&app, &path, None, &bad).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/severity"),
    )
    .await;
    assert_eq!(app.norms().await[0]["action"], "destroy");
    // A create may not choose its id.
    let chosen = json!({"id": 99, "kind": "forbidden_action", "action": "steal"});
    assert_problem(
        app.post("/v1/norms", &chosen).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/id"),
    )
    .await;
}

/// 8 curators each make 500 read-modify-write increments of one counter (in the norm's note),
/// retrying on 412: with If-Match, every increment survives.
#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn eight_concurrent_writers_lose_no_update() {
    const WRITERS: usize = 8;
    const UPDATES: usize = 500;
    let app = std::sync::Arc::new(spawn_app().await);
    let id = app
        .add_norm(&json!({"kind": "forbidden_action", "action": "destroy", "note": "0"}))
        .await;
    let path = format!("/v1/norms/{id}");
    let mut writers = Vec::new();
    for _ in 0..WRITERS {
        let app = app.clone();
        let path = path.clone();
        writers.push(tokio::spawn(async move {
            let mut refused = 0usize;
            for _ in 0..UPDATES {
                loop {
                    let current = app.get(&path).await;
                    assert_eq!(current.status(), StatusCode::OK);
                    let tag = etag(&current);
                    let norm: Value = current.json().await.unwrap();
                    let count: u64 = norm["note"].as_str().unwrap().parse().unwrap();
                    let next =
                        json!({"kind": "forbidden_action", "action": "destroy", "note": (count + 1).to_string()});
                    let written = put(&app, &path, Some(&tag), &next).await;
                    match written.status() {
                        StatusCode::OK => break,
                        StatusCode::PRECONDITION_FAILED => refused += 1,
                        other => panic!("unexpected {other}: {}", written.text().await.unwrap()),
                    }
                }
            }
            refused
        }));
    }
    let mut refused = 0;
    for writer in writers {
        refused += writer.await.unwrap();
    }
    let norm: Value = app.get(&path).await.json().await.unwrap();
    assert_eq!(
        norm["note"],
        (WRITERS * UPDATES).to_string(),
        "{refused} stale writes were refused"
    );
    // Every acknowledged update is in the audit trail too.
    let mut replaced = 0;
    let mut after = 0;
    loop {
        let page: Value = app
            .get(&format!("/v1/audit?after={after}&limit=1000"))
            .await
            .json()
            .await
            .unwrap();
        let entries = page["entries"].as_array().unwrap();
        if entries.is_empty() {
            break;
        }
        replaced += entries.iter().filter(|e| e["operation"] == "replace").count();
        after = page["next_after"].as_i64().unwrap();
    }
    assert_eq!(replaced, WRITERS * UPDATES);
}

#[tokio::test]
async fn an_export_imported_into_a_fresh_store_round_trips() {
    let source = spawn_app().await;
    source
        .add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))", "note": "fragile"}))
        .await;
    let doomed = source
        .add_norm(&json!({"kind": "forbidden_action", "action": "steal"}))
        .await;
    source
        .add_norm(
            &json!({"kind": "forbidden_action", "action": "destroy(X)", "when": ["owned(X,Y)"],
                          "context": "lab", "severity": 5, "roles": ["visitor"], "exempt_roles": ["owner"]}),
        )
        .await;
    assert_eq!(
        source.delete(&format!("/v1/norms/{doomed}")).await.status(),
        StatusCode::NO_CONTENT
    );
    let exported = source.get("/v1/norm-set").await;
    assert_eq!(exported.status(), StatusCode::OK);
    let exported: Value = exported.json().await.unwrap();
    assert_eq!(exported["norms"].as_array().unwrap().len(), 2);

    let target = spawn_app().await;
    target
        .add_norm(&json!({"kind": "forbidden_action", "action": "pointTo"}))
        .await;
    let imported = put(&target, "/v1/norm-set", None, &exported).await;
    assert_eq!(imported.status(), StatusCode::OK);
    let again: Value = target.get("/v1/norm-set").await.json().await.unwrap();
    let content = |set: &Value| -> Vec<Value> {
        set["norms"]
            .as_array()
            .unwrap()
            .iter()
            .map(|n| {
                let mut n = n.clone();
                n.as_object_mut().unwrap().remove("revision");
                n
            })
            .collect()
    };
    assert_eq!(
        content(&again),
        content(&exported),
        "ids and every field survive the round trip"
    );
    // The imported set is the one in force, and the replaced norm is gone.
    assert_eq!(target.clarify(&get_vase()).await["decision"], "assume");
    assert!(target.norms().await.iter().all(|n| n["action"] != "pointTo"));
    // A fresh norm gets an id above every imported one.
    let fresh = target
        .add_norm(&json!({"kind": "forbidden_action", "action": "pointTo"}))
        .await;
    assert!(fresh > exported["norms"][1]["id"].as_i64().unwrap());
}

#[tokio::test]
async fn an_import_with_one_bad_norm_or_a_stale_version_changes_nothing() {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_action", "action": "destroy"}))
        .await;
    let before: Value = app.get("/v1/norm-set").await.json().await.unwrap();
    let bad = json!({"norms": [
        {"kind": "forbidden_action", "action": "steal"},
        {"kind": "forbidden_state", "state": "did(self,get(object3)", "note": "unbalanced"},
    ]});
    assert_problem(
        put(&app, "/v1/norm-set", None, &bad).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/norms/1/state"),
    )
    .await;
    let twice = json!({"norms": [
        {"id": 4, "kind": "forbidden_action", "action": "steal"},
        {"id": 4, "kind": "forbidden_action", "action": "destroy"},
    ]});
    assert_problem(
        put(&app, "/v1/norm-set", None, &twice).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/norms/1/id"),
    )
    .await;
    let stale = put(&app, "/v1/norm-set", Some("\"0\""), &json!({"norms": []})).await;
    assert_problem(stale, StatusCode::PRECONDITION_FAILED, None).await;
    let after: Value = app.get("/v1/norm-set").await.json().await.unwrap();
    assert_eq!(after, before);
    // With the current ETag, an empty set clears every norm in one step.
    let tag = format!("\"{}\"", before["version"]);
    assert_eq!(
        put(&app, "/v1/norm-set", Some(&tag), &json!({"norms": []}))
            .await
            .status(),
        StatusCode::OK
    );
    assert!(app.norms().await.is_empty());
}

/// Finding: a plain list of norms (the offline CLI's `--norms` file) sent to `PUT
/// /v1/norm-set` answered "invalid type: map, expected i64" at `/0`, read as the set's members
/// in order. A list is taken as the set's `norms` (the CLI file imports as is); faults point
/// into the list as sent; any other shape says which two are wanted.
#[tokio::test]
async fn a_plain_list_of_norms_imports_as_a_norm_set() {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_action", "action": "steal"}))
        .await;
    let list = json!([
        {"kind": "forbidden_action", "action": "destroy"},
        {"kind": "forbidden_state", "state": "did(self,get(object3))", "note": "the fragile vase may not be got"},
    ]);
    let response = put(&app, "/v1/norm-set", None, &list).await;
    assert_eq!(response.status(), StatusCode::OK);
    let tag = etag(&response);
    let imported: Value = response.json().await.unwrap();
    let exported: Value = app.get("/v1/norm-set").await.json().await.unwrap();
    assert_eq!(imported, exported);
    assert_eq!(tag, format!("\"{}\"", exported["version"]));
    let norms = exported["norms"].as_array().unwrap();
    assert_eq!(norms.len(), 2, "the list replaced the set: {exported}");
    assert_eq!(norms[0]["action"], "destroy");
    assert_eq!(norms[1]["state"], "did(self,get(object3))");
    assert_eq!(app.clarify(&get_vase()).await["decision"], "assume");

    // A fault in the list points into the list; nothing changes.
    let bad = json!([
        {"kind": "forbidden_action", "action": "steal"},
        {"kind": "forbidden_action", "action": "steal", "severity": 9},
    ]);
    assert_problem(
        put(&app, "/v1/norm-set", None, &bad).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/1/severity"),
    )
    .await;
    let misspelt = json!([{"kind": "forbidden_action", "action": "steal", "wen": []}]);
    assert_problem(
        put(&app, "/v1/norm-set", None, &misspelt).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/0/wen"),
    )
    .await;
    assert_eq!(app.get("/v1/norm-set").await.json::<Value>().await.unwrap(), exported);

    // Neither a set nor a list: the answer says what is wanted.
    for body in [json!("norms"), json!(3), json!(null)] {
        let problem = assert_problem(
            put(&app, "/v1/norm-set", None, &body).await,
            StatusCode::UNPROCESSABLE_ENTITY,
            Some(""),
        )
        .await;
        let detail = problem["detail"].as_str().unwrap_or_default();
        assert!(
            detail.contains("\"norms\"") && detail.contains("list"),
            "{body}: {detail}"
        );
    }
}

#[tokio::test]
async fn the_audit_trail_says_when_what_and_which_token_for_every_change() {
    let app = spawn_tweaked(|config| {
        config.admin_token = Some(Secret("root-secret-0123456789".into()));
        config.curator_tokens = vec![LabelledSecret {
            label: "alice".into(),
            secret: "alice-secret-0123456789".into(),
        }];
    })
    .await;
    let as_token = |token: &'static str| move |request: reqwest::RequestBuilder| request.bearer_auth(token).send();
    let alice = as_token("alice-secret-0123456789");
    let admin = as_token("root-secret-0123456789");
    let norm = json!({"kind": "forbidden_action", "action": "destroy"});
    let created = alice(app.client.post(app.url("/v1/norms")).json(&norm)).await.unwrap();
    assert_eq!(created.status(), StatusCode::CREATED);
    let id = created.json::<Value>().await.unwrap()["id"].as_i64().unwrap();
    let severe = json!({"kind": "forbidden_action", "action": "destroy", "severity": 5});
    let replaced = admin(app.client.put(app.url(&format!("/v1/norms/{id}"))).json(&severe))
        .await
        .unwrap();
    assert_eq!(replaced.status(), StatusCode::OK);
    let verb = json!({"parameters": ["X"], "methods": [{"reach": ["X"], "adds": ["open(X)"]}]});
    assert_eq!(
        alice(app.client.put(app.url("/v1/actions/unseal")).json(&verb))
            .await
            .unwrap()
            .status(),
        StatusCode::CREATED
    );
    assert_eq!(
        admin(app.client.delete(app.url(&format!("/v1/norms/{id}"))))
            .await
            .unwrap()
            .status(),
        StatusCode::NO_CONTENT
    );

    let page: Value = app.get("/v1/audit").await.json().await.unwrap();
    let entries = page["entries"].as_array().unwrap();
    let summary: Vec<(&str, &str, &str, &str)> = entries
        .iter()
        .map(|e| {
            (
                e["actor"].as_str().unwrap(),
                e["subject"].as_str().unwrap(),
                e["operation"].as_str().unwrap(),
                e["target"].as_str().unwrap(),
            )
        })
        .collect();
    let target = id.to_string();
    assert_eq!(
        summary,
        vec![
            ("alice", "norm", "create", target.as_str()),
            ("admin", "norm", "replace", target.as_str()),
            ("alice", "action", "create", "unseal"),
            ("admin", "norm", "delete", target.as_str()),
        ]
    );
    assert_eq!(entries[1]["before"]["severity"], 3);
    assert_eq!(entries[1]["after"]["severity"], 5);
    assert!(entries[0].get("before").is_none() && entries[3].get("after").is_none());
    assert!(entries.iter().all(|e| e["at"].as_str().unwrap().ends_with('Z')));
    // Paging: after the second entry come the last two.
    let rest: Value = app
        .get(&format!("/v1/audit?after={}&limit=2", entries[1]["id"]))
        .await
        .json()
        .await
        .unwrap();
    assert_eq!(rest["entries"].as_array().unwrap().len(), 2);
    assert_eq!(rest["next_after"], entries[3]["id"]);
    assert_problem(
        app.get("/v1/audit?limit=0").await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/limit"),
    )
    .await;
    assert_problem(
        app.get("/v1/audit?after=x").await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/after"),
    )
    .await;
}

/// RFC 9110 §13.1.1: If-Match takes a list, any member of which may match, and compares strongly,
/// so a weak tag never matches a write; `*` matches any current norm.
#[tokio::test]
async fn if_match_takes_a_list_and_never_matches_a_weak_tag() {
    let app = spawn_app().await;
    let id = app
        .add_norm(&json!({"kind": "forbidden_action", "action": "destroy"}))
        .await;
    let path = format!("/v1/norms/{id}");
    let current = etag(&app.get(&path).await);
    let revision: i64 = current.trim_matches('"').parse().unwrap();
    let body = |action: &str| json!({"kind": "forbidden_action", "action": action});

    let weak = format!("W/{current}");
    let refused = put(&app, &path, Some(&weak), &body("steal")).await;
    assert_problem(refused, StatusCode::PRECONDITION_FAILED, None).await;
    assert_eq!(etag(&app.get(&path).await), current, "nothing written for a weak tag");

    let list = format!("\"{}\", {current}", revision + 100);
    let replaced = put(&app, &path, Some(&list), &body("steal")).await;
    assert_eq!(replaced.status(), StatusCode::OK, "{list}");
    let next = etag(&replaced);

    let neither = format!("\"{}\", W/{next}, \"{}\"", revision + 100, revision + 200);
    let refused = put(&app, &path, Some(&neither), &body("get")).await;
    assert_problem(refused, StatusCode::PRECONDITION_FAILED, None).await;

    let with_weak = format!("W/{next},{next}");
    assert_eq!(
        put(&app, &path, Some(&with_weak), &body("get")).await.status(),
        StatusCode::OK
    );
    assert_eq!(
        put(&app, &path, Some("*"), &body("point")).await.status(),
        StatusCode::OK
    );

    // The same rules for a delete and for the whole norm set.
    let current = etag(&app.get(&path).await);
    let weak_delete = app
        .client
        .delete(app.url(&path))
        .header("if-match", format!("W/{current}"))
        .send()
        .await
        .unwrap();
    assert_eq!(weak_delete.status(), StatusCode::PRECONDITION_FAILED);
    let set = app.get("/v1/norm-set").await;
    let version = etag(&set);
    let norms: Value = set.json().await.unwrap();
    let import = |tag: String| {
        app.client
            .put(app.url("/v1/norm-set"))
            .header("if-match", tag)
            .json(&json!({"norms": norms["norms"]}))
            .send()
    };
    assert_eq!(
        import(format!("W/{version}")).await.unwrap().status(),
        StatusCode::PRECONDITION_FAILED
    );
    assert_eq!(
        import(format!("\"999999\", {version}")).await.unwrap().status(),
        StatusCode::OK
    );
    let current = etag(&app.get(&path).await);
    let listed_delete = app
        .client
        .delete(app.url(&path))
        .header("if-match", format!("\"0\", {current}"))
        .send()
        .await
        .unwrap();
    assert_eq!(listed_delete.status(), StatusCode::NO_CONTENT);
}
