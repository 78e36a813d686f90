//! Bad input gets problem+json naming the field; nothing is stored; the service stays up.

use reqwest::StatusCode;
use serde_json::{Value, json};

use crate::helpers::{Options, assert_problem, get_vase, lab_scene, spawn_app, spawn_with};

/// Applies `edit` to a valid "Get the vase." request.
fn vase_with(edit: impl FnOnce(&mut Value)) -> Value {
    let mut request = get_vase();
    edit(&mut request);
    request
}

#[tokio::test]
async fn bad_clarify_requests_name_the_field_at_fault() {
    let app = spawn_app().await;
    let cases: Vec<(&str, Value, &str)> = vec![
        (
            "missing scene",
            vase_with(|r| drop(r.as_object_mut().unwrap().remove("scene"))),
            "/scene",
        ),
        (
            "missing directive",
            vase_with(|r| drop(r.as_object_mut().unwrap().remove("directive"))),
            "/directive",
        ),
        (
            "missing agent",
            vase_with(|r| drop(r["scene"].as_object_mut().unwrap().remove("agent"))),
            "/scene/agent",
        ),
        (
            "reach of the wrong type",
            vase_with(|r| r["scene"]["agent"]["reach"] = json!("far")),
            "/scene/agent/reach",
        ),
        (
            "negative reach",
            vase_with(|r| r["scene"]["agent"]["reach"] = json!(-1)),
            "/scene/agent/reach",
        ),
        (
            "duplicate object ids",
            vase_with(|r| r["scene"]["objects"][1]["id"] = json!("object1")),
            "/scene/objects/1/id",
        ),
        (
            "a position of two numbers",
            vase_with(|r| r["scene"]["objects"][0]["position"] = json!([0, 1])),
            "/scene/objects/0/position",
        ),
        (
            "a negative radius",
            vase_with(|r| r["scene"]["objects"][2]["shape"]["cylinder"]["radius"] = json!(-0.1)),
            "/scene/objects/2/shape/cylinder/radius",
        ),
        (
            "a cuboid of no depth",
            vase_with(|r| r["scene"]["objects"][0]["shape"]["cuboid"]["half_extents"][2] = json!(0)),
            "/scene/objects/0/shape/cuboid/half_extents/2",
        ),
        (
            "an unknown shape",
            vase_with(|r| r["scene"]["objects"][0]["shape"] = json!({"cone": {"radius": 1}})),
            "/scene/objects/0/shape",
        ),
        (
            "a rotation that is not unit",
            vase_with(|r| r["scene"]["objects"][0]["rotation"] = json!([0, 0, 0, 2])),
            "/scene/objects/0/rotation",
        ),
        (
            "a type that is not a name",
            vase_with(|r| r["scene"]["objects"][0]["type"] = json!("Note Book")),
            "/scene/objects/0/type",
        ),
        (
            "a scene fact with a variable",
            vase_with(|r| r["scene"]["facts"] = json!(["on(X,table)"])),
            "/scene/facts/0",
        ),
        (
            "an unparsable scene fact",
            vase_with(|r| r["scene"]["facts"] = json!(["on(a,"])),
            "/scene/facts/0",
        ),
        (
            "an id not in the scene",
            vase_with(|r| r["directive"]["arguments"] = json!([{"id": "object9"}])),
            "/directive/arguments/0/id",
        ),
        (
            "a reference with id and type",
            vase_with(|r| r["directive"]["arguments"] = json!([{"id": "object3", "type": "vase"}])),
            "/directive/arguments/0",
        ),
        (
            "an empty reference",
            vase_with(|r| r["directive"]["arguments"] = json!([{}])),
            "/directive/arguments/0",
        ),
        (
            "a misspelt reference member",
            vase_with(|r| r["directive"]["arguments"] = json!([{"typ": "vase"}])),
            "/directive/arguments/0/typ",
        ),
        (
            "both action and form",
            vase_with(|r| r["directive"]["form"] = json!("did(self,get(X))")),
            "/directive",
        ),
        (
            "neither action nor form nor text",
            vase_with(|r| r["directive"] = json!({"arguments": []})),
            "/directive",
        ),
        (
            "words over the length limit",
            vase_with(|r| r["directive"] = json!({"text": "get the vase ".repeat(80)})),
            "/directive/text",
        ),
        (
            "a focus on no object of the scene",
            vase_with(|r| r["focus"] = json!(["object9"])),
            "/focus/0",
        ),
        (
            "an unparsable form",
            json!({"directive": {"form": "did(self,get(X)", "bindings": {"X": ["object3"]}}, "scene": lab_scene()}),
            "/directive/form",
        ),
        (
            "a binding not in the scene",
            json!({"directive": {"form": "did(self,get(X))", "bindings": {"X": ["object3", "object9"]}}, "scene": lab_scene()}),
            "/directive/bindings/X/1",
        ),
        (
            "a scored binding not in the scene",
            json!({"directive": {"form": "did(self,get(X))", "bindings": {"X": [{"id": "object9", "score": 0.5}]}}, "scene": lab_scene()}),
            "/directive/bindings/X/0/id",
        ),
        (
            "a binding for no variable",
            json!({"directive": {"form": "did(self,get(X))", "bindings": {"X": ["object3"], "Y": ["object4"]}}, "scene": lab_scene()}),
            "/directive/bindings/Y",
        ),
        (
            "a variable with no bindings",
            json!({"directive": {"form": "did(self,put(X,Y))", "bindings": {"X": ["object3"]}}, "scene": lab_scene()}),
            "/directive/bindings/Y",
        ),
        (
            "a negative score",
            json!({"directive": {"form": "did(self,get(X))", "bindings": {"X": [{"id": "object3", "score": -1}]}}, "scene": lab_scene()}),
            "/directive/bindings/X/0/score",
        ),
        (
            "an action by someone else",
            json!({"directive": {"form": "did(bob,get(X))", "bindings": {"X": ["object3"]}}, "scene": lab_scene()}),
            "/directive/form",
        ),
        (
            "an unknown strategy",
            vase_with(|r| r["options"] = json!({"strategy": "cautious"})),
            "/options/strategy",
        ),
        (
            "an unknown option",
            vase_with(|r| r["options"] = json!({"stratgy": "moral"})),
            "/options/stratgy",
        ),
        (
            "a speaker that is not a name",
            vase_with(|r| r["speaker"] = json!("Dr Smith")),
            "/speaker",
        ),
        (
            "a misspelt top-level member",
            vase_with(|r| r["optoins"] = json!({"strategy": "reflexive"})),
            "/optoins",
        ),
        ("an empty context", vase_with(|r| r["context"] = json!("")), "/context"),
        ("not an object", json!(42), ""),
    ];
    for (name, request, field) in cases {
        let response = app.post("/v1/clarify", &request).await;
        assert_eq!(response.status(), StatusCode::UNPROCESSABLE_ENTITY, "{name}");
        let problem = assert_problem(response, StatusCode::UNPROCESSABLE_ENTITY, None).await;
        assert_eq!(problem["field"].as_str(), Some(field), "{name}: {problem}");
    }
    // Still up and still right.
    assert_eq!(app.clarify(&get_vase()).await["decision"], "ask");
}

#[tokio::test]
async fn bad_norms_name_the_field_and_store_nothing() {
    let app = spawn_app().await;
    let cases: Vec<(&str, Value, &str)> = vec![
        ("no kind", json!({"action": "destroy"}), "/kind"),
        (
            "an unknown kind",
            json!({"kind": "forbidden_thought", "action": "destroy"}),
            "/kind",
        ),
        (
            "an unparsable action",
            json!({"kind": "forbidden_action", "action": "get(X"}),
            "/action",
        ),
        (
            "a bare variable",
            json!({"kind": "forbidden_action", "action": "X"}),
            "/action",
        ),
        ("no state", json!({"kind": "forbidden_state"}), "/state"),
        (
            "an unparsable condition",
            json!({"kind": "forbidden_state", "state": "holding(self,X)", "when": ["fragile(X"]}),
            "/when/0",
        ),
        (
            "severity too high",
            json!({"kind": "forbidden_action", "action": "destroy", "severity": 6}),
            "/severity",
        ),
        (
            "severity too low",
            json!({"kind": "forbidden_action", "action": "destroy", "severity": 0}),
            "/severity",
        ),
        (
            "severity in words",
            json!({"kind": "forbidden_action", "action": "destroy", "severity": "high"}),
            "/severity",
        ),
        (
            "a misspelt member",
            json!({"kind": "forbidden_state", "state": "holding(self,X)", "wehn": ["fragile(X)"]}),
            "/wehn",
        ),
        (
            "when is not a list",
            json!({"kind": "forbidden_state", "state": "holding(self,X)", "when": "fragile(X)"}),
            "/when",
        ),
        (
            "both action and state",
            json!({"kind": "forbidden_action", "action": "get", "state": "p(a)"}),
            "/state",
        ),
    ];
    for (name, norm, field) in cases {
        let response = app.post("/v1/norms", &norm).await;
        let problem = assert_problem(response, StatusCode::UNPROCESSABLE_ENTITY, None).await;
        assert_eq!(problem["field"].as_str(), Some(field), "{name}: {problem}");
    }
    assert!(app.norms().await.is_empty(), "nothing is stored");
}

#[tokio::test]
async fn malformed_bodies_are_400_and_wrong_media_types_415() {
    let app = spawn_app().await;
    for path in ["/v1/clarify", "/v1/norms"] {
        for body in ["{", "", "{\"kind\": }", "{} trailing"] {
            let response = app
                .client
                .post(app.url(path))
                .header("content-type", "application/json")
                .body(body)
                .send()
                .await
                .unwrap();
            assert_problem(response, StatusCode::BAD_REQUEST, None).await;
        }
        let response = app
            .client
            .post(app.url(path))
            .header("content-type", "text/plain")
            .body("{}")
            .send()
            .await
            .unwrap();
        assert_problem(response, StatusCode::UNSUPPORTED_MEDIA_TYPE, None).await;
    }
    assert!(app.norms().await.is_empty());
}

#[tokio::test]
async fn unknown_paths_and_methods_answer_problem_json() {
    let app = spawn_app().await;
    assert_problem(app.get("/v1/nothing").await, StatusCode::NOT_FOUND, None).await;
    assert_problem(app.get("/v1/clarify").await, StatusCode::METHOD_NOT_ALLOWED, None).await;
    let response = app
        .client
        .put(app.url("/v1/norms"))
        .json(&json!({}))
        .send()
        .await
        .unwrap();
    assert_problem(response, StatusCode::METHOD_NOT_ALLOWED, None).await;
}

#[tokio::test]
async fn a_body_over_the_limit_is_413() {
    let app = spawn_with(Options {
        max_body_bytes: 512,
        ..Options::default()
    })
    .await;
    let response = app.post("/v1/clarify", &get_vase()).await;
    let problem = assert_problem(response, StatusCode::PAYLOAD_TOO_LARGE, None).await;
    assert!(problem["detail"].as_str().unwrap().contains("512"), "{problem}");
    let small = json!({"kind": "forbidden_action", "action": "destroy"});
    assert_eq!(app.post("/v1/norms", &small).await.status(), StatusCode::CREATED);
}

#[tokio::test]
async fn references_that_match_nothing_are_unresolved_not_errors() {
    let app = spawn_app().await;
    let spoon = json!({"directive": {"action": "get", "arguments": [{"type": "spoon"}]}, "scene": lab_scene()});
    let answer = app.clarify(&spoon).await;
    assert_eq!(answer["decision"], "unresolved");
    assert_eq!(answer["utterance"], "I do not know what you mean by the spoon.");
    assert_eq!(answer["goal"], Value::Null);
    assert_eq!(answer["interpretations"], json!([]));

    let mut empty = get_vase();
    empty["scene"]["objects"] = json!([]);
    let answer = app.clarify(&empty).await;
    assert_eq!(answer["decision"], "unresolved");
    assert_eq!(answer["utterance"], "I do not know what you mean by the vase.");
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    use std::io::Write;
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    encoder.write_all(bytes).unwrap();
    encoder.finish().unwrap()
}

/// A gzip body is decoded (and the size limit applies to what it decodes to, so a zip bomb is
/// 413); `identity` is no coding; any other coding is 415 naming it, never read as JSON.
#[tokio::test]
async fn content_encodings_are_decoded_or_refused_by_name() {
    let app = spawn_with(Options {
        max_body_bytes: 64 * 1024,
        ..Options::default()
    })
    .await;
    let send = |coding: &'static str, body: Vec<u8>| {
        app.client
            .post(app.url("/v1/clarify"))
            .header("content-type", "application/json")
            .header("content-encoding", coding)
            .body(body)
            .send()
    };
    let plain = serde_json::to_vec(&get_vase()).unwrap();
    for coding in ["gzip", "x-gzip", "GZIP", "identity, gzip"] {
        let response = send(coding, gzip(&plain)).await.unwrap();
        assert_eq!(response.status(), StatusCode::OK, "{coding}");
        assert_eq!(response.json::<Value>().await.unwrap()["decision"], "ask");
    }
    assert_eq!(send("identity", plain.clone()).await.unwrap().status(), StatusCode::OK);

    let bomb = gzip(&vec![b' '; 10 * 1024 * 1024]);
    assert!(bomb.len() < 64 * 1024, "the bomb itself is under the limit");
    assert_problem(send("gzip", bomb).await.unwrap(), StatusCode::PAYLOAD_TOO_LARGE, None).await;
    assert_problem(
        send("gzip", plain.clone()).await.unwrap(),
        StatusCode::BAD_REQUEST,
        None,
    )
    .await;

    for coding in ["bogus", "br", "deflate", "gzip, bogus"] {
        let response = send(coding, plain.clone()).await.unwrap();
        let problem = assert_problem(response, StatusCode::UNSUPPORTED_MEDIA_TYPE, None).await;
        let named = coding.rsplit(", ").next().unwrap();
        assert!(
            problem["detail"].as_str().unwrap().contains(named),
            "{coding}: {problem}"
        );
    }
    // A norm body too, and nothing is stored from a refused one.
    let norm = serde_json::to_vec(&json!({"kind": "forbidden_action", "action": "destroy"})).unwrap();
    let refused = app
        .client
        .post(app.url("/v1/norms"))
        .header("content-type", "application/json")
        .header("content-encoding", "bogus")
        .body(norm.clone())
        .send()
        .await
        .unwrap();
    assert_eq!(refused.status(), StatusCode::UNSUPPORTED_MEDIA_TYPE);
    assert!(app.norms().await.is_empty());
    let created = app
        .client
        .post(app.url("/v1/norms"))
        .header("content-type", "application/json")
        .header("content-encoding", "gzip")
        .body(gzip(&norm))
        .send()
        .await
        .unwrap();
    assert_eq!(created.status(), StatusCode::CREATED);
}
