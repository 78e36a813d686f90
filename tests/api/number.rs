//! Number over HTTP and gRPC: the README's plural examples decided as it says, structured
//! `count`/`all` equal to the words, and every fault of them named by its field.

use reqwest::StatusCode;
use scruple::transport::grpc::pb::clarifier_client::ClarifierClient;
use serde_json::{Value, json};

use crate::grpc::{as_rest_json, channel, clarify_request};
use crate::helpers::{assert_problem, spawn_app};
use crate::references::room;

fn said(text: &str) -> Value {
    json!({"directive": {"text": text}, "scene": room()})
}

fn cups(extra: Value) -> Value {
    let mut cup = json!({"type": "cup"});
    for (key, value) in extra.as_object().expect("an object") {
        cup[key] = value.clone();
    }
    json!({"directive": {"action": "get", "arguments": [cup]}, "scene": room()})
}

#[tokio::test]
async fn the_readmes_plurals_are_decided_as_it_says() {
    let app = spawn_app().await;
    let answer = app.clarify(&said("Get the cups on the table.")).await;
    assert_eq!(answer["decision"], "comply", "{answer}");
    assert_eq!(answer["goal"], "did(self,and(get(cup1),get(cup2)))");
    let answer = app.clarify(&said("Get both cups.")).await;
    assert_eq!(answer["decision"], "unresolved");
    assert_eq!(
        answer["utterance"],
        "I cannot tell which two cups you mean: I see three."
    );
    let answer = app.clarify(&said("Get two cups.")).await;
    assert_eq!(answer["decision"], "assume");
    assert_eq!(
        answer["utterance"],
        "I am assuming you want me to get the cup near the fork and the cup in the box."
    );
    let answer = app
        .clarify(&said(
            "Get the cups on the table and put them in the box to the left of the table.",
        ))
        .await;
    assert_eq!(
        answer["goal"], "did(self,and(get(cup1),get(cup2),put(cup1,box1),put(cup2,box1)))",
        "{answer}"
    );
    let answer = app.clarify(&said("Get the cups except the one in the box.")).await;
    assert_eq!(answer["goal"], "did(self,and(get(cup1),get(cup2)))", "{answer}");
}

#[tokio::test]
async fn structured_count_and_all_decide_as_the_words_over_rest_and_grpc() {
    let app = spawn_app().await;
    let pairs = [
        (cups(json!({"all": true})), "Get the cups."),
        (cups(json!({"all": true, "count": 2})), "Get both cups."),
        (cups(json!({"count": 2})), "Get two cups."),
        (
            cups(json!({"all": true, "relations": [{"relation": "on", "to": {"type": "table"}}]})),
            "Get the cups on the table.",
        ),
    ];
    let mut clarifier = ClarifierClient::new(channel(&app).await);
    for (structured, text) in pairs {
        let rest = app.clarify(&structured).await;
        let words = app.clarify(&said(text)).await;
        for key in ["decision", "goal", "utterance", "offered"] {
            assert_eq!(rest[key], words[key], "{text}: {key}");
        }
        let grpc = as_rest_json(
            clarifier
                .clarify(clarify_request(&structured))
                .await
                .expect("gRPC")
                .into_inner(),
        );
        assert_eq!(grpc, rest, "{structured}");
    }
    // In a step: every cup, then each put in the small box.
    let steps = json!({"directive": {"steps": [
        {"action": "get", "arguments": [{"type": "cup", "all": true}]},
        {"action": "put", "arguments": [{"step": 0, "argument": 0}, {"id": "box1"}], "joiner": "in"}]},
        "scene": room()});
    let answer = app.clarify(&steps).await;
    assert_eq!(
        answer["goal"], "did(self,and(get(cup1),get(cup2),get(cup3),put(cup1,box1),put(cup2,box1),put(cup3,box1)))",
        "{answer}"
    );
    let bad = cups(json!({"count": 0}));
    let status = clarifier.clarify(clarify_request(&bad)).await.unwrap_err();
    assert_eq!(status.code(), tonic::Code::InvalidArgument);
    assert_eq!(status.metadata().get("field").unwrap(), "/directive/arguments/0/count");
}

#[tokio::test]
async fn every_fault_of_count_and_all_is_named_by_its_field() {
    let app = spawn_app().await;
    let cases = [
        (cups(json!({"count": 0})), "/directive/arguments/0/count"),
        (cups(json!({"count": 33})), "/directive/arguments/0/count"),
        (
            json!({"directive": {"action": "get", "arguments": [{"id": "cup1", "all": true}]}, "scene": room()}),
            "/directive/arguments/0/all",
        ),
        (
            cups(json!({"relations": [{"relation": "on", "to": {"type": "table", "count": 1}}]})),
            "/directive/arguments/0/relations/0/to/count",
        ),
        (
            json!({"directive": {"action": "put", "arguments": [{"type": "cup", "all": true}, {"type": "box", "all": true}]},
                   "scene": room()}),
            "/directive/arguments/1",
        ),
        (
            json!({"directive": {"steps": [
                {"action": "get", "arguments": [{"type": "cup", "all": true}]},
                {"action": "put", "arguments": [{"step": 0, "argument": 0}, {"type": "box", "count": 1}]}]},
                "scene": room()}),
            "/directive/steps/1/arguments/1",
        ),
        (
            json!({"directive": {"steps": [
                {"action": "get", "arguments": [{"type": "cup"}]},
                {"action": "get", "arguments": [{"step": 0, "argument": 0, "all": true}]}]},
                "scene": room()}),
            "/directive/steps/1/arguments/0",
        ),
        (
            json!({"directive": {"action": "get", "arguments": [{"type": "cup"}]}, "scene": room(),
                   "answer": {"reference": {"type": "cup", "count": 1}}}),
            "/answer/reference/count",
        ),
    ];
    for (body, field) in cases {
        let response = app.post("/v1/clarify", &body).await;
        assert_problem(response, StatusCode::UNPROCESSABLE_ENTITY, Some(field)).await;
    }
    // `count` must be a whole number.
    let response = app.post("/v1/clarify", &cups(json!({"count": -1}))).await;
    assert_eq!(response.status(), StatusCode::UNPROCESSABLE_ENTITY);
}
