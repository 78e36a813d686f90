//! People in a scene over HTTP and gRPC: a curator's `give` and a norm on the recipient's role,
//! the same answer by name, role, "me" and id, a person never handled, `/v1/check` seeing
//! roles, and every fault of a person named by its field.

use reqwest::StatusCode;
use scruple::transport::grpc::pb::clarifier_client::ClarifierClient;
use serde_json::{Value, json};

use crate::grpc::{as_rest_json, channel, clarify_request};
use crate::helpers::{TestApp, assert_problem, spawn_app};

/// A kitchen with one knife and a cup; Bob is a child, Alice a parent, a visitor stands 3 m away.
fn kitchen() -> Value {
    json!({"agent": {"position": [0, 0, 0.75], "reach": 1.2},
     "objects": [
       {"id": "knife1", "type": "knife", "position": [0.5, 0, 0.8]},
       {"id": "cup1", "type": "cup", "position": [0.5, 0.2, 0.8]}],
     "people": [
       {"id": "bob", "names": ["Bob"], "roles": ["child"], "position": [0.6, 0.3, 0.8]},
       {"id": "alice", "names": ["Alice"], "roles": ["parent"], "position": [0.7, -0.3, 0.8]},
       {"id": "guest", "roles": ["visitor"], "position": [3, 0, 0.8]}]})
}

fn said(text: &str) -> Value {
    json!({"directive": {"text": text}, "scene": kitchen()})
}

/// The default `give` (its method declares the recipient a person); no knives for children.
async fn household() -> TestApp {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_action", "action": "give(X,P)", "when": ["knife(X)", "role(P,child)"]}))
        .await;
    app
}

#[tokio::test]
async fn a_norm_on_the_recipients_role_is_not_bypassed_by_naming_them_otherwise() {
    let app = household().await;
    let refusal = "I cannot give the knife to Bob because giving the knife to Bob is forbidden when Bob is a child.";
    let mut me = said("Give the knife to me.");
    me["speaker"] = json!("bob");
    let by_id =
        json!({"directive": {"action": "give", "arguments": [{"type": "knife"}, {"id": "bob"}]}, "scene": kitchen()});
    for body in [
        said("Give the knife to Bob."),
        said("Give the knife to the child."),
        me,
        by_id,
    ] {
        let answer = app.clarify(&body).await;
        assert_eq!(answer["decision"], "refuse", "{body}: {answer}");
        // Spoken to Bob, Bob is "you".
        let refusal = match body["speaker"] == "bob" {
            true => refusal.replace("to Bob", "to you").replace("Bob is", "you are"),
            false => refusal.to_owned(),
        };
        assert_eq!(answer["utterance"], refusal);
        assert_eq!(answer["interpretations"][0]["reasons"][0]["kind"], "forbidden_action");
    }
    let answer = app.clarify(&said("Give the knife to Alice.")).await;
    assert_eq!(answer["goal"], "did(self,give(knife1,alice))", "{answer}");
    // The speaker's roles make the speaker a child too.
    let mut alice_as_child = said("Give the knife to me.");
    alice_as_child["speaker"] = json!("alice");
    alice_as_child["speaker_roles"] = json!(["child"]);
    assert_eq!(app.clarify(&alice_as_child).await["decision"], "refuse");
    // A speaker who is not among the people is handed things all the same: they come for them
    // ("bring" and "hand me" leave the recipient to the speaker), and are spoken "you".
    for text in [
        "Give the cup to me.",
        "Bring the cup.",
        "Hand me the cup.",
        "I need the cup.",
    ] {
        let answer = app.clarify(&said(text)).await;
        assert_eq!(
            (&answer["decision"], &answer["goal"]),
            (&json!("comply"), &json!("did(self,give(cup1,human))")),
            "{text}: {answer}"
        );
    }
    let answer = app.clarify(&said("Hand me the knife.")).await;
    assert_eq!(answer["goal"], "did(self,give(knife1,human))", "{answer}");
    let mut child = said("Hand me the knife.");
    child["speaker_roles"] = json!(["child"]);
    let answer = app.clarify(&child).await;
    assert_eq!(
        answer["utterance"],
        "I cannot give the knife to you because giving the knife to you is forbidden when you are a child.",
        "{answer}"
    );
    // The same over gRPC.
    let mut clarifier = ClarifierClient::new(channel(&app).await);
    for body in [said("Give the knife to Bob."), said("Point to the person.")] {
        let grpc = as_rest_json(
            clarifier
                .clarify(clarify_request(&body))
                .await
                .expect("gRPC")
                .into_inner(),
        );
        assert_eq!(grpc, app.clarify(&body).await, "{body}");
    }
    // A plan checked while acting sees the roles as well.
    let check = json!({"scene": kitchen(), "steps": ["give(knife1,bob)"]});
    let response = app.post("/v1/check", &check).await;
    assert_eq!(response.status(), StatusCode::OK);
    let body: Value = response.json().await.unwrap();
    assert_eq!(body["permitted"], false, "{body}");
}

#[tokio::test]
async fn a_person_is_a_referent_never_an_object_to_handle() {
    let app = household().await;
    for (text, decision, utterance) in [
        (
            "Get Bob.",
            "refuse",
            "I cannot get Bob because Bob is a person, not an object to handle.",
        ),
        (
            "Put the cup on Alice.",
            "refuse",
            "I cannot put the cup on Alice because Alice is a person, not an object to handle.",
        ),
        (
            "Give the cup to the knife.",
            "refuse",
            "I cannot give the cup to the knife because the knife is not a person.",
        ),
        (
            "Give the cup to the visitor.",
            "refuse",
            "I cannot give the cup to the visitor because the visitor is out of reach.",
        ),
        ("Point to Bob.", "comply", "Okay."),
        (
            "Point to the person.",
            "ask",
            "Do you mean that you want me to point to Alice or that you want me to point to Bob or that you want me to \
             point to the visitor?",
        ),
    ] {
        let answer = app.clarify(&said(text)).await;
        assert_eq!(answer["decision"], decision, "{text}: {answer}");
        assert_eq!(answer["utterance"], utterance, "{text}");
    }
    let answer = app.clarify(&said("Get Bob.")).await;
    assert_eq!(answer["interpretations"][0]["reasons"][0]["kind"], "person");
    assert_eq!(
        answer["speech_act"],
        "cannot(did(self,get(bob)),because(isPerson(bob)))"
    );
}

#[tokio::test]
async fn every_fault_of_a_person_is_named_by_its_field() {
    let app = spawn_app().await;
    let with = |person: Value| {
        let mut scene = kitchen();
        scene["people"] = json!([person]);
        json!({"directive": {"text": "Point to Bob."}, "scene": scene})
    };
    let cases = [
        (with(json!({"id": "cup1", "position": [0, 0, 0]})), "/scene/people/0/id"),
        (with(json!({"id": "Bob!", "position": [0, 0, 0]})), "/scene/people/0/id"),
        (
            with(json!({"id": "bob", "names": ["Bob 2"], "position": [0, 0, 0]})),
            "/scene/people/0/names/0",
        ),
        (
            with(json!({"id": "bob", "roles": ["child!"], "position": [0, 0, 0]})),
            "/scene/people/0/roles/0",
        ),
    ];
    for (body, field) in cases {
        let response = app.post("/v1/clarify", &body).await;
        assert_problem(response, StatusCode::UNPROCESSABLE_ENTITY, Some(field)).await;
    }
    // A person without a position, or with a field the contract does not name ("role" for
    // "roles" would drop a norm's condition silently), is refused by the schema.
    for person in [
        json!({"id": "bob"}),
        json!({"id": "bob", "role": "child", "position": [0, 0, 0]}),
    ] {
        let response = app.post("/v1/clarify", &with(person)).await;
        assert_eq!(response.status(), StatusCode::UNPROCESSABLE_ENTITY);
    }
    // Over gRPC, a position that is not three numbers is named as REST names it.
    let mut clarifier = ClarifierClient::new(channel(&app).await);
    let status = (clarifier
        .clarify(clarify_request(&with(json!({"id": "bob", "position": [0, 0]}))))
        .await)
        .unwrap_err();
    assert_eq!(status.code(), tonic::Code::InvalidArgument);
    assert_eq!(status.metadata().get("field").unwrap(), "/scene/people/0/position");
    // A name with a character that turns the text is echoed escaped, never as sent.
    let response = app
        .post(
            "/v1/clarify",
            &with(json!({"id": "bob", "names": ["\u{202e}evil"], "position": [0, 0, 0]})),
        )
        .await;
    let problem = assert_problem(
        response,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/scene/people/0/names/0"),
    )
    .await;
    let detail = problem["detail"].as_str().unwrap();
    assert!(
        detail.contains("\\u{202e}evil") && !detail.contains('\u{202e}'),
        "{detail}"
    );
}
