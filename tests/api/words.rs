//! Directives in words over HTTP: what the words were read as, pronouns with `focus`, objects'
//! names, follow-up answers in words, and words that are not a directive.

use reqwest::StatusCode;
use serde_json::{Value, json};

use crate::helpers::{TestApp, assert_problem, lab_scene, paper_demo, spawn_app};

async fn with_paper_norms() -> TestApp {
    let app = spawn_app().await;
    for norm in paper_demo()["norms"].as_array().unwrap() {
        app.add_norm(norm).await;
    }
    app
}

fn said(text: &str) -> Value {
    json!({"directive": {"text": text}, "scene": lab_scene()})
}

#[tokio::test]
async fn the_answer_shows_what_the_words_were_read_as() {
    let app = with_paper_norms().await;
    let answer = app
        .clarify(&said(
            "Robot, would you mind putting the mug onto the green notebook now?",
        ))
        .await;
    assert_eq!(answer["decision"], "comply", "{answer}");
    assert_eq!(answer["goal"], "did(self,put(object5,object2))");
    assert_eq!(
        answer["parse"],
        json!({"act": "indirect_request", "addressee": "robot", "form": "want(human,did(self,put(X,Y)))",
               "references": [{"words": "the mug", "candidates": ["object5"]},
                              {"words": "the green notebook", "candidates": ["object2"]}],
               "ignored": ["now"]})
    );
    // A structured directive carries no parse: its text is only echoed.
    let structured = app.clarify(&crate::helpers::get_vase()).await;
    assert!(structured.get("parse").is_none(), "{structured}");
}

#[tokio::test]
async fn a_word_the_scene_does_not_know_is_said_back_never_guessed() {
    let app = with_paper_norms().await;
    let answer = app.clarify(&said("Get the wet mug.")).await;
    assert_eq!(answer["decision"], "unresolved");
    assert_eq!(answer["utterance"], "I do not know what you mean by the wet mug.");
    assert_eq!(
        answer["parse"]["references"],
        json!([{"words": "the wet mug", "candidates": []}])
    );
    assert!(answer["goal"].is_null());
}

#[tokio::test]
async fn a_pronoun_is_the_first_object_in_focus_and_without_focus_nothing() {
    let app = with_paper_norms().await;
    let mut request = said("Can you get it?");
    let without = app.clarify(&request).await;
    assert_eq!(without["decision"], "unresolved", "{without}");
    request["focus"] = json!(["object4", "object3"]);
    let with = app.clarify(&request).await;
    assert_eq!(with["decision"], "comply", "{with}");
    assert_eq!(with["goal"], "did(self,get(object4))");
    request["focus"] = json!(["object3"]);
    // The fragile vase may not be got: the pronoun does not make it acceptable.
    assert_eq!(app.clarify(&request).await["decision"], "refuse");
}

#[tokio::test]
async fn an_objects_names_are_nouns_for_it() {
    let app = with_paper_norms().await;
    let mut request = said("Hand me the coffee cup.");
    request["scene"]["objects"][4]["names"] = json!(["Coffee Cup", "drink"]);
    let answer = app.clarify(&request).await;
    assert_eq!(answer["goal"], "did(self,give(object5,human))", "{answer}");
    request["scene"]["objects"][4]["names"] = json!(["coffee-cup!"]);
    assert_problem(
        app.post("/v1/clarify", &request).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/scene/objects/4/names/0"),
    )
    .await;
}

#[tokio::test]
async fn follow_up_answers_in_words_are_decided_afresh() {
    let app = with_paper_norms().await;
    let mut request = said("Get the notebook.");
    assert_eq!(app.clarify(&request).await["decision"], "ask");
    for (text, goal) in [
        ("the red one", "did(self,get(object1))"),
        ("the first one", "did(self,get(object2))"),
    ] {
        request["answer"] = json!({"text": text});
        let answer = app.clarify(&request).await;
        assert_eq!(answer["goal"], goal, "{text}: {answer}");
    }
    let mut confirm = said("Get the vase.");
    confirm["options"] = json!({"single_permissible": "confirm"});
    assert_eq!(app.clarify(&confirm).await["decision"], "confirm");
    confirm["answer"] = json!({"text": "yes"});
    let yes = app.clarify(&confirm).await;
    assert_eq!(
        (yes["decision"].as_str(), yes["goal"].as_str()),
        (Some("comply"), Some("did(self,get(object4))"))
    );
    confirm["answer"] = json!({"text": "no"});
    let no = app.clarify(&confirm).await;
    assert_eq!(no["decision"], "cancelled", "{no}");
    assert_eq!(no["utterance"], "Okay, I will not.");
    assert!(no["goal"].is_null() && no["offered"] == json!([]), "{no}");
    request["answer"] = json!({"text": "yes"});
    assert_eq!(
        app.clarify(&request).await["decision"],
        "not_understood",
        "yes answers no question to confirm"
    );
    request["answer"] = json!({"text": "x".repeat(1001)});
    assert_problem(
        app.post("/v1/clarify", &request).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/answer/text"),
    )
    .await;
}

#[tokio::test]
async fn words_that_are_not_a_directive_are_a_200_not_understood() {
    let app = with_paper_norms().await;
    for (text, unclear) in [
        ("What color is the mug?", "question"),
        ("Don't destroy the notebook.", "negated"),
        (
            "Get the mug and get the mug and get the mug and get the mug and get the mug and get the mug and get \
             the mug and get the mug and get the mug.",
            "several",
        ),
        ("colorless green ideas", "unplaced"),
        ("Pepper, please.", "empty"),
    ] {
        let answer = app.clarify(&said(text)).await;
        assert_eq!(answer["decision"], "not_understood", "{text}: {answer}");
        assert_eq!(answer["parse"]["unclear"], unclear, "{text}");
        assert!(answer["goal"].is_null());
        assert_eq!(answer["interpretations"], json!([]));
        assert_eq!(answer["offered"], json!([]));
        assert_eq!(answer["speech_act"], format!("want_know(self,meaning({unclear}))"));
    }
    assert_eq!(
        app.clarify(&said("colorless green ideas")).await["utterance"],
        "I did not understand \"colorless green ideas\"."
    );
}
