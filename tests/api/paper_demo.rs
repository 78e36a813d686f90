//! Every case of `../shared/scenarios/paper-demo.json`, over HTTP, word for word.

use serde_json::{Value, json};

use crate::helpers::{paper_demo, spawn_app};

#[tokio::test]
async fn every_paper_case_gives_the_papers_decision_goal_and_words() {
    let app = spawn_app().await;
    let demo = paper_demo();
    for norm in demo["norms"].as_array().unwrap() {
        app.add_norm(norm).await;
    }
    let cases = demo["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 10, "the paper's example and experiment have 10 cases");
    let mut failures = Vec::new();
    for case in cases {
        let mut directive = case["directive"].clone();
        directive["text"] = case["text"].clone();
        let mut request = json!({
            "directive": directive,
            "scene": demo["scenes"][case["scene"].as_str().unwrap()].clone(),
        });
        if let Some(options) = case.get("options") {
            request["options"] = options.clone();
        }
        let answer = app.clarify(&request).await;
        for (key, expected) in case["expect"].as_object().unwrap() {
            if &answer[key] != expected {
                failures.push(format!("{}: {key} was {} not {}", case["name"], answer[key], expected));
            }
        }
        assert_eq!(answer["text"], case["text"], "the human's words are echoed");
        // The safety invariant, on the paper's own cases: nothing forbidden is the goal.
        if let Some(goal) = answer["goal"].as_str() {
            let chosen = answer["interpretations"]
                .as_array()
                .unwrap()
                .iter()
                .find(|i| i["action"] == goal)
                .expect("the goal is one of the readings");
            assert_eq!(chosen["permissible"], Value::Bool(true));
            assert_eq!(chosen["feasible"], Value::Bool(true));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[tokio::test]
async fn get_the_vase_carries_every_reading_with_reasons_plan_and_norm_version() {
    let app = spawn_app().await;
    let demo = paper_demo();
    let mut ids = Vec::new();
    for norm in demo["norms"].as_array().unwrap() {
        ids.push(app.add_norm(norm).await);
    }
    let answer = app.clarify(&crate::helpers::get_vase()).await;
    assert_eq!(
        answer,
        json!({
            "decision": "assume",
            "utterance": "I am assuming you want me to get the plastic vase. I cannot get the fragile vase because it requires a forbidden state.",
            "speech_act": "assume(self,mean(human,did(self,get(object4))))",
            "goal": "did(self,get(object4))",
            "interpretations": [
                {"action": "did(self,get(object3))", "description": "the fragile vase", "permissible": false,
                 "feasible": true, "reasons": [{"kind": "forbidden_state", "detail": "did(self,get(object3))",
                 "norm_id": ids[1], "severity": 3, "words": "it requires a forbidden state"}],
                 "plan": ["get(object3)"], "score": 1.0},
                {"action": "did(self,get(object4))", "description": "the plastic vase", "permissible": true,
                 "feasible": true, "reasons": [], "plan": ["get(object4)"], "score": 1.0}
            ],
            "offered": ["did(self,get(object4))"],
            "norm_version": 3,
            "library_version": 1,
            "text": "Get the vase."
        })
    );
}

#[tokio::test]
async fn the_same_request_gives_the_same_bytes() {
    let app = spawn_app().await;
    for norm in paper_demo()["norms"].as_array().unwrap() {
        app.add_norm(norm).await;
    }
    let mut bodies = Vec::new();
    for _ in 0..3 {
        let response = app.post("/v1/clarify", &crate::helpers::get_vase()).await;
        bodies.push(response.bytes().await.unwrap());
    }
    assert!(bodies.windows(2).all(|w| w[0] == w[1]));
}
