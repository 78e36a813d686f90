//! References by relation, order and number over HTTP and gRPC: the README's "References"
//! examples decided as it says, structured `relations` equal to the words, the agent's
//! rotation turning left and right, and every fault of a structured relation named by field.

use reqwest::StatusCode;
use scruple::transport::grpc::pb::clarifier_client::ClarifierClient;
use serde_json::{Value, json};

use crate::grpc::{as_rest_json, channel, clarify_request};
use crate::helpers::{assert_problem, spawn_app};

/// The README's room: a table with two cups and a fork on it, a cup in a box (by `facts`), two
/// boxes of different sizes.
pub(crate) fn room() -> Value {
    json!({"agent": {"position": [0, 0, 0.75], "reach": 1.2},
     "objects": [
       {"id": "table1", "type": "table", "position": [0.7, 0, 0.4], "shape": {"cuboid": {"half_extents": [0.3, 0.5, 0.4]}}},
       {"id": "cup1", "type": "cup", "position": [0.7, 0.1, 0.85], "shape": {"cylinder": {"radius": 0.04, "half_height": 0.05}}},
       {"id": "cup2", "type": "cup", "position": [0.7, -0.3, 0.85], "shape": {"cylinder": {"radius": 0.04, "half_height": 0.05}}},
       {"id": "cup3", "type": "cup", "position": [0.3, -0.6, 0.3], "shape": {"cylinder": {"radius": 0.05, "half_height": 0.07}}},
       {"id": "fork1", "type": "fork", "position": [0.7, 0.2, 0.805], "shape": {"cuboid": {"half_extents": [0.08, 0.01, 0.005]}}},
       {"id": "box1", "type": "box", "position": [0.4, 0.6, 0.1], "shape": {"cuboid": {"half_extents": [0.1, 0.1, 0.1]}}},
       {"id": "box2", "type": "box", "position": [0.4, -0.9, 0.1], "shape": {"cuboid": {"half_extents": [0.2, 0.2, 0.1]}}}],
     "facts": ["in(cup3,box2)"]})
}

fn said(text: &str) -> Value {
    json!({"directive": {"text": text}, "scene": room()})
}

fn cup_with(relations: Value) -> Value {
    json!({"directive": {"action": "get", "arguments": [{"type": "cup", "relations": relations}]}, "scene": room()})
}

#[tokio::test]
async fn the_readmes_references_are_decided_as_it_says() {
    let app = spawn_app().await;
    for (text, goal) in [
        ("Get the cup on the table next to the fork.", "did(self,get(cup1))"),
        ("Get the cup in the box.", "did(self,get(cup3))"),
        ("Get the biggest box.", "did(self,get(box2))"),
        ("Get the second cup from the left.", "did(self,get(cup2))"),
        ("Get the cup that is not on the table.", "did(self,get(cup3))"),
    ] {
        let answer = app.clarify(&said(text)).await;
        assert_eq!(answer["decision"], "comply", "{text}: {answer}");
        assert_eq!(answer["goal"], goal, "{text}");
    }
    let answer = app.clarify(&said("Get the heaviest box.")).await;
    assert_eq!(answer["decision"], "unresolved");
    assert_eq!(
        answer["utterance"],
        "I cannot tell which box is the heaviest: I do not know how heavy every box is."
    );
    // Look-alikes are told apart by a landmark, then a position; no id is spoken.
    let answer = app.clarify(&said("Get the cup.")).await;
    assert_eq!(answer["decision"], "ask");
    assert_eq!(
        answer["utterance"],
        "Do you mean that you want me to get the cup in the box or that you want me to get the cup near the fork \
         or that you want me to get the right cup on the table?"
    );
    // Each of those words, said back, is the one object it was said of.
    for (words, goal) in [
        ("Get the cup in the box.", "did(self,get(cup3))"),
        ("Get the cup near the fork.", "did(self,get(cup1))"),
        ("Get the right cup on the table.", "did(self,get(cup2))"),
    ] {
        assert_eq!(app.clarify(&said(words)).await["goal"], goal, "{words}");
    }
    // A landmark said as "it" is the object in focus; with none, nothing.
    let mut next_to_it = said("Get the cup next to it.");
    assert_eq!(app.clarify(&next_to_it).await["decision"], "unresolved");
    next_to_it["focus"] = json!(["fork1"]);
    assert_eq!(app.clarify(&next_to_it).await["goal"], "did(self,get(cup1))");
    // A bare ordinal is not guessed.
    let answer = app.clarify(&said("Get the second cup.")).await;
    assert_eq!(answer["decision"], "unresolved");
    assert_eq!(answer["goal"], Value::Null);
}

#[tokio::test]
async fn structured_relations_decide_as_the_words_over_rest_and_grpc() {
    let app = spawn_app().await;
    let structured = cup_with(json!([
        {"relation": "on", "to": {"type": "table"}},
        {"relation": "near", "to": {"type": "fork"}}]));
    let rest = app.clarify(&structured).await;
    assert_eq!(rest["decision"], "comply", "{rest}");
    assert_eq!(rest["goal"], "did(self,get(cup1))");
    let words = app.clarify(&said("Get the cup on the table next to the fork.")).await;
    assert_eq!(words["goal"], rest["goal"]);
    // Nested: the cup in a box that is to the right of the table (seen from the agent).
    let nested = cup_with(json!([{"relation": "in", "to": {"type": "box", "relations": [
        {"relation": "right_of", "to": {"id": "table1"}}]}}]));
    assert_eq!(app.clarify(&nested).await["goal"], "did(self,get(cup3))");
    let mut clarifier = ClarifierClient::new(channel(&app).await);
    for body in [structured, nested, said("Get the cup."), said("Get the heaviest box.")] {
        let grpc = as_rest_json(
            clarifier
                .clarify(clarify_request(&body))
                .await
                .expect("gRPC")
                .into_inner(),
        );
        assert_eq!(grpc, app.clarify(&body).await, "{body}");
    }
    let bad = cup_with(json!([{"relation": "atop", "to": {"type": "table"}}]));
    let status = clarifier.clarify(clarify_request(&bad)).await.unwrap_err();
    assert_eq!(status.code(), tonic::Code::InvalidArgument);
    assert_eq!(
        status.metadata().get("field").unwrap(),
        "/directive/arguments/0/relations/0/relation"
    );
}

#[tokio::test]
async fn every_fault_of_a_structured_relation_is_named_by_its_field() {
    let app = spawn_app().await;
    let cases = [
        (
            cup_with(json!([{"relation": "atop", "to": {"type": "table"}}])),
            "/directive/arguments/0/relations/0/relation",
        ),
        (
            cup_with(json!([{"relation": "on", "to": {}}])),
            "/directive/arguments/0/relations/0/to",
        ),
        (
            cup_with(json!([{"relation": "on", "to": {"id": "nowhere"}}])),
            "/directive/arguments/0/relations/0/to/id",
        ),
        (
            cup_with(json!([{"relation": "on", "to": {"type": "table", "relations": [
                {"relation": "near", "to": {"type": "Fork!"}}]}}])),
            "/directive/arguments/0/relations/0/to/relations/0/to/type",
        ),
        (
            json!({"directive": {"action": "get", "arguments": [{"id": "cup1", "type": "cup",
                "relations": [{"relation": "on", "to": {"type": "table"}}]}]}, "scene": room()}),
            "/directive/arguments/0",
        ),
    ];
    for (body, field) in cases {
        let response = app.post("/v1/clarify", &body).await;
        assert_problem(response, StatusCode::UNPROCESSABLE_ENTITY, Some(field)).await;
    }
    // Nine relations, nested, are more than a reference may carry.
    let mut to = json!({"type": "table"});
    for _ in 0..9 {
        to = json!({"type": "table", "relations": [{"relation": "near", "to": to}]});
    }
    let response = app
        .post("/v1/clarify", &cup_with(json!([{"relation": "on", "to": to}])))
        .await;
    let problem = assert_problem(response, StatusCode::UNPROCESSABLE_ENTITY, None).await;
    assert!(
        problem["detail"].as_str().unwrap().contains("at most 8 relations"),
        "{problem}"
    );
    // A missing `relation` or `to` is refused by the schema, naming the field.
    let response = app
        .post("/v1/clarify", &cup_with(json!([{"to": {"type": "table"}}])))
        .await;
    assert_eq!(response.status(), StatusCode::UNPROCESSABLE_ENTITY);
}

#[tokio::test]
async fn the_agents_rotation_turns_left_and_right() {
    let app = spawn_app().await;
    let mut turned = room();
    // Half a turn about z: the agent looks along -x, and its left is -y.
    turned["agent"]["rotation"] = json!([0.0, 0.0, 1.0, 0.0]);
    let ask = |scene: Value| json!({"directive": {"text": "Get the leftmost cup."}, "scene": scene});
    assert_eq!(app.clarify(&ask(room())).await["goal"], "did(self,get(cup1))");
    assert_eq!(app.clarify(&ask(turned.clone())).await["goal"], "did(self,get(cup3))");
    turned["agent"]["rotation"] = json!([0.0, 0.0, 3.0, 0.0]);
    let response = app.post("/v1/clarify", &ask(turned)).await;
    assert_problem(
        response,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/scene/agent/rotation"),
    )
    .await;
}

/// A two-argument verb whose words hold two joiners is read both ways: the way whose references
/// all name something here is the reading, and when both do, the robot says it cannot tell
/// rather than choose.
#[tokio::test]
async fn a_joiner_that_could_part_the_words_twice_is_read_the_way_the_scene_fits() {
    let app = spawn_app().await;
    // "the box on the table" names nothing: the cup in the box goes on the table.
    let answer = app.clarify(&said("Put the cup in the box on the table.")).await;
    assert_eq!(answer["decision"], "comply", "{answer}");
    assert_eq!(answer["goal"], "did(self,put(cup3,table1))");
    let words: Vec<&Value> = (answer["parse"]["references"].as_array().unwrap().iter())
        .map(|r| &r["words"])
        .collect();
    assert_eq!(words, [&json!("the cup in the box"), &json!("the table")]);
    // "the table in the box" names nothing: the fork goes in one of the boxes.
    let answer = app.clarify(&said("Put the fork on the table in the box.")).await;
    assert_eq!(answer["decision"], "ask", "{answer}");
    let actions: Vec<&str> = (answer["interpretations"].as_array().unwrap().iter())
        .map(|i| i["action"].as_str().unwrap())
        .collect();
    assert_eq!(actions, ["did(self,put(fork1,box1))", "did(self,put(fork1,box2))"]);
    // Neither way names everything: the first way says what it could not find.
    let answer = app.clarify(&said("Put the cup on the plate in the bowl.")).await;
    assert_eq!(answer["decision"], "unresolved", "{answer}");
    assert_eq!(answer["goal"], Value::Null);
    // With a box on the table, both ways name objects: not guessed.
    let mut both = said("Put the cup in the box on the table.");
    both["scene"]["facts"] = json!(["in(cup3,box2)", "on(box1,table1)"]);
    let answer = app.clarify(&both).await;
    assert_eq!(answer["decision"], "not_understood", "{answer}");
    assert_eq!(answer["parse"]["unclear"], "ambiguous");
    assert_eq!(
        answer["utterance"],
        "I can read \"Put the cup in the box on the table\" in more than one way here; please say it another way."
    );
    assert_eq!(answer["goal"], Value::Null);
}
