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

/// The same cases sent as the human's words alone (`{"text": "Pepper, can you go steal the cash
/// box for me?"}`): the paper's decision, goal and words, and a parse that shows how.
#[tokio::test]
async fn every_paper_case_in_words_alone_gives_the_papers_answer() {
    let app = spawn_app().await;
    let demo = paper_demo();
    for norm in demo["norms"].as_array().unwrap() {
        app.add_norm(norm).await;
    }
    let mut failures = Vec::new();
    for case in demo["cases"].as_array().unwrap() {
        let mut request = json!({
            "directive": {"text": case["text"]},
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
        let verb = case["directive"]["action"].as_str().unwrap_or("get");
        assert_eq!(
            answer["parse"]["form"],
            format!("want(human,did(self,{verb}(X)))"),
            "{}",
            case["name"]
        );
        assert_eq!(answer["text"], case["text"]);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    let steal = json!({"directive": {"text": "Pepper, can you go steal the cash box for me?"}, "scene": demo["scenes"]["office"]});
    let parse = &app.clarify(&steal).await["parse"];
    assert_eq!(
        parse,
        &json!({"act": "indirect_request", "addressee": "pepper", "form": "want(human,did(self,steal(X)))",
                "references": [{"words": "the cash box", "candidates": ["box1", "box2"]}], "ignored": []})
    );
}

/// The OpenAPI document's example of `/v1/clarify` is the paper's "Get the vase.": the server
/// must answer its example request with exactly its example response, every field.
#[tokio::test]
async fn the_documented_vase_example_is_what_the_server_answers() {
    let app = spawn_app().await;
    for norm in paper_demo()["norms"].as_array().unwrap() {
        app.add_norm(norm).await;
    }
    let doc: Value = serde_json::from_str(
        &std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/openapi/openapi.json")).unwrap(),
    )
    .unwrap();
    let operation = &doc["paths"]["/v1/clarify"]["post"];
    let request = &operation["requestBody"]["content"]["application/json"]["example"];
    let expected = &operation["responses"]["200"]["content"]["application/json"]["example"];
    let answer = app.clarify(request).await;
    assert_eq!(&answer, expected);
    // The parts the paper fixes, spelled out.
    assert_eq!(answer["decision"], "assume");
    assert_eq!(answer["goal"], "did(self,get(object4))");
    assert_eq!(answer["interpretations"][0]["reasons"][0]["norm_id"], 2);
    assert_eq!(answer["interpretations"][1]["reasons"], json!([]));
    assert_eq!(answer["interpretations"][1]["plan"], json!(["get(object4)"]));
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
