//! Several steps in one directive over HTTP and gRPC: in words and structured (`steps` with
//! back-references), the parse of each step, purposes, follow-up answers to a task's question,
//! limits on the task as a whole, and every fault of a structured task named by its field.

use reqwest::StatusCode;
use scruple::transport::grpc::pb::clarifier_client::ClarifierClient;
use serde_json::{Value, json};

use crate::grpc::{as_rest_json, channel, clarify_request};
use crate::helpers::{TestApp, assert_problem, paper_demo, spawn_app};

async fn with_paper_norms() -> TestApp {
    let app = spawn_app().await;
    for norm in paper_demo()["norms"].as_array().unwrap() {
        app.add_norm(norm).await;
    }
    app
}

/// A red mug and a blue mug, a sink, a plate and a vase.
fn kitchen() -> Value {
    json!({"agent": {"position": [0, 0, 0.75], "reach": 0.9}, "objects": [
        {"id": "m1", "type": "mug", "attributes": {"color": "red"}, "position": [0.5, 0.1, 0.8]},
        {"id": "m2", "type": "mug", "attributes": {"color": "blue"}, "position": [0.5, 0.3, 0.8]},
        {"id": "s1", "type": "sink", "position": [0.6, -0.2, 0.8]},
        {"id": "p1", "type": "plate", "position": [0.5, -0.3, 0.8]},
        {"id": "v1", "type": "vase", "properties": ["fragile"], "position": [0.6, 0.4, 0.85]}]})
}

fn said(text: &str) -> Value {
    json!({"directive": {"text": text}, "scene": kitchen()})
}

fn structured(steps: Value) -> Value {
    json!({"directive": {"steps": steps}, "scene": kitchen()})
}

#[tokio::test]
async fn a_task_in_words_asks_about_whole_tasks_and_shows_each_step() {
    let app = with_paper_norms().await;
    let answer = app.clarify(&said("Please take the mug and put it in the sink")).await;
    assert_eq!(answer["decision"], "ask", "{answer}");
    assert_eq!(
        answer["utterance"],
        "Do you mean that you want me to get the blue mug and put it in the sink or that you want me to get the red \
         mug and put it in the sink?"
    );
    assert_eq!(
        answer["offered"],
        json!(["did(self,and(get(m2),put(m2,s1)))", "did(self,and(get(m1),put(m1,s1)))"])
    );
    let parse = &answer["parse"];
    assert_eq!(parse["form"], "want(human,did(self,and(get(X),put(X,Y))))");
    assert_eq!(parse["steps"][0]["form"], "get(X)");
    assert_eq!(parse["steps"][1]["form"], "put(X,Y)");
    assert_eq!(
        parse["steps"][1]["references"][0],
        json!({"words": "it", "candidates": ["m1", "m2"]})
    );
    assert_eq!(
        parse["steps"][1]["pronouns"],
        json!([{"words": "it", "argument": 0, "bound_to": "step", "step": 0, "step_argument": 0}])
    );
    // The answer to the question picks a whole task.
    let mut follow = said("Please take the mug and put it in the sink");
    follow["answer"] = json!({"text": "the red one"});
    let answer = app.clarify(&follow).await;
    assert_eq!(answer["decision"], "comply", "{answer}");
    assert_eq!(answer["goal"], "did(self,and(get(m1),put(m1,s1)))");
    follow["answer"] = json!({"choice": 0});
    assert_eq!(app.clarify(&follow).await["goal"], "did(self,and(get(m2),put(m2,s1)))");
}

#[tokio::test]
async fn a_structured_task_is_the_task_its_words_are() {
    let app = with_paper_norms().await;
    let steps = json!([
        {"action": "get", "arguments": [{"type": "mug", "attributes": {"color": "red"}}]},
        {"action": "put", "arguments": [{"step": 0, "argument": 0}, {"type": "sink"}], "joiner": "in"}]);
    let answer = app.clarify(&structured(steps)).await;
    let words = app.clarify(&said("Get the red mug and put it in the sink.")).await;
    assert_eq!(answer["decision"], "comply", "{answer}");
    assert_eq!(answer["goal"], "did(self,and(get(m1),put(m1,s1)))");
    for key in ["decision", "goal", "utterance", "interpretations", "speech_act"] {
        assert_eq!(answer[key], words[key], "{key}");
    }
    assert!(
        answer.get("parse").is_none(),
        "a structured task has no parse: {answer}"
    );
    // One step structured keeps did(self,A).
    let one = app
        .clarify(&structured(json!([{"action": "get", "arguments": [{"id": "p1"}]}])))
        .await;
    assert_eq!(one["goal"], "did(self,get(p1))");
}

#[tokio::test]
async fn a_forbidden_step_or_purpose_is_refused_whole() {
    let app = with_paper_norms().await;
    for text in [
        "Get the plate and smash the vase.",
        "Get the plate to smash the vase.",
        "Get the plate so I can break the vase.",
    ] {
        let answer = app.clarify(&said(text)).await;
        assert_eq!(answer["decision"], "refuse", "{text}: {answer}");
        assert!(answer["goal"].is_null());
    }
    let answer = app.clarify(&said("Get the plate to smash the vase.")).await;
    assert_eq!(
        answer["utterance"],
        "I cannot get the plate to destroy the vase because destroy is forbidden action."
    );
    assert_eq!(answer["interpretations"][0]["reasons"][0]["kind"], "forbidden_purpose");
    assert_eq!(
        answer["speech_act"],
        "cannot(did(self,get(p1)),because(forbiddenPurpose(destroy(v1))))"
    );
}

#[tokio::test]
async fn limits_apply_to_the_task_as_a_whole_and_never_act() {
    let app = with_paper_norms().await;
    let mut request = said("Get the mug and put it in the sink and get the mug.");
    request["options"] = json!({"max_readings": 3});
    let answer = app.clarify(&request).await;
    assert_eq!(answer["limits"]["reason"], "too_many_readings", "{answer}");
    assert_eq!(answer["limits"]["readings"], 4);
    assert!(answer["goal"].is_null());
    assert_eq!(answer["interpretations"], json!([]));
}

#[tokio::test]
async fn every_fault_of_a_structured_task_is_named_by_its_field() {
    let app = spawn_app().await;
    let get_mug = json!({"action": "get", "arguments": [{"type": "mug"}]});
    for (steps, field) in [
        (json!([]), "/directive/steps"),
        (
            json!([
                get_mug, get_mug, get_mug, get_mug, get_mug, get_mug, get_mug, get_mug, get_mug
            ]),
            "/directive/steps",
        ),
        (
            json!([{"action": "Get!", "arguments": []}]),
            "/directive/steps/0/action",
        ),
        (
            json!([{"action": "get", "arguments": [{"step": 0, "argument": 0}]}]),
            "/directive/steps/0/arguments/0/step",
        ),
        (
            json!([get_mug, {"action": "get", "arguments": [{"step": 1, "argument": 0}]}]),
            "/directive/steps/1/arguments/0/step",
        ),
        (
            json!([get_mug, {"action": "get", "arguments": [{"step": 0, "argument": 1}]}]),
            "/directive/steps/1/arguments/0/argument",
        ),
        (
            json!([get_mug, {"action": "get", "arguments": [{"step": 0}]}]),
            "/directive/steps/1/arguments/0/argument",
        ),
        (
            json!([get_mug, {"action": "get", "arguments": [{"step": 0, "argument": 0, "type": "mug"}]}]),
            "/directive/steps/1/arguments/0",
        ),
        (
            json!([{"action": "get", "arguments": [{"id": "nope"}]}]),
            "/directive/steps/0/arguments/0/id",
        ),
        (
            json!([{"action": "put", "arguments": [{"type": "mug"}, {"type": "sink"}], "joiner": "In Side"}]),
            "/directive/steps/0/joiner",
        ),
    ] {
        assert_problem(
            app.post("/v1/clarify", &structured(steps.clone())).await,
            StatusCode::UNPROCESSABLE_ENTITY,
            Some(field),
        )
        .await;
    }
    // `steps` beside `action`, or `arguments` beside `steps`.
    let mut both = structured(json!([get_mug]));
    both["directive"]["action"] = json!("get");
    assert_problem(
        app.post("/v1/clarify", &both).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/directive"),
    )
    .await;
    let mut beside = structured(json!([get_mug]));
    beside["directive"]["arguments"] = json!([]);
    assert_problem(
        app.post("/v1/clarify", &beside).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/directive/arguments"),
    )
    .await;
    // A joiner the verb does not take.
    let bad = structured(json!([{"action": "put", "arguments": [{"id": "m1"}, {"id": "s1"}], "joiner": "with"}]));
    assert_problem(
        app.post("/v1/clarify", &bad).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        None,
    )
    .await;
}

#[tokio::test]
async fn tasks_give_the_same_answer_over_grpc_as_over_rest() {
    let app = with_paper_norms().await;
    let mut clarifier = ClarifierClient::new(channel(&app).await);
    for body in [
        said("Get the mug and put it in the sink."),
        said("Get the red mug. Put it on the plate."),
        said("Get the plate to smash the vase."),
        said("I need the plate."),
        structured(json!([
            {"action": "get", "arguments": [{"type": "mug"}]},
            {"action": "put", "arguments": [{"step": 0, "argument": 0}, {"id": "s1"}], "joiner": "in"}])),
    ] {
        let rest = app.clarify(&body).await;
        let grpc = as_rest_json(
            clarifier
                .clarify(clarify_request(&body))
                .await
                .expect("gRPC")
                .into_inner(),
        );
        assert_eq!(grpc, rest, "{body}");
    }
    let bad = structured(json!([{"action": "get", "arguments": [{"step": 0, "argument": 0}]}]));
    let status = clarifier.clarify(clarify_request(&bad)).await.unwrap_err();
    assert_eq!(status.code(), tonic::Code::InvalidArgument);
    assert_eq!(
        status.metadata().get("field").unwrap(),
        "/directive/steps/0/arguments/0/step"
    );
}
