//! Regressions from the second hostile pass (issue 50), over HTTP as a robot frontend sees them:
//! words that narrow, negate, add a step or state a purpose are never dropped; an id or a word
//! matches what was written; reading words and describing readings end at the deadline; an
//! answer can take a question back.

use std::time::{Duration, Instant};

use serde_json::{Value, json};

use crate::helpers::{TestApp, lab_scene, paper_demo, spawn_app};

async fn with_paper_norms() -> TestApp {
    let app = spawn_app().await;
    for norm in paper_demo()["norms"].as_array().unwrap() {
        app.add_norm(norm).await;
    }
    app
}

fn said(text: &str, scene: Value) -> Value {
    json!({"directive": {"text": text}, "scene": scene})
}

/// One red cup, one red notebook and a fork, as the hostile pass had them.
fn red_things() -> Value {
    json!({"agent": {"position": [0, 0, 0.75], "reach": 0.9}, "objects": [
        {"id": "cup1", "type": "cup", "attributes": {"color": "red"}, "position": [0.5, 0, 0.8]},
        {"id": "notebook1", "type": "notebook", "attributes": {"color": "red"}, "position": [0.5, 0.2, 0.76]},
        {"id": "fork1", "type": "fork", "position": [0.5, 0.4, 0.76]},
        {"id": "vase1", "type": "vase", "position": [0.5, -0.2, 0.8]},
        {"id": "mug1", "type": "mug", "position": [0.4, -0.2, 0.8]}]})
}

#[tokio::test]
async fn narrowing_and_negating_words_after_a_reference_are_never_dropped() {
    let app = with_paper_norms().await;
    for text in [
        "Get the cup, blue one.",
        "Get the cup, not red.",
        "Get the cup now, the blue one.",
        "Get the notebook for me, not the red one.",
        "Get the cup, don't.",
        // The cup is to the right of the fork, seen from the agent: read, never dropped.
        "Get the cup to the left of the fork",
    ] {
        let answer = app.clarify(&said(text, red_things())).await;
        assert!(answer["goal"].is_null(), "{text}: {answer}");
        let decision = answer["decision"].as_str().unwrap();
        assert!(["unresolved", "not_understood"].contains(&decision), "{text}: {answer}");
        assert!(answer["parse"]["addressee"].is_null(), "{text}: {answer}");
    }
}

#[tokio::test]
async fn a_purpose_or_a_step_that_could_be_forbidden_is_never_obeyed() {
    let app = with_paper_norms().await;
    // A purpose the norms forbid is read and refused; a step with nothing to act on makes the
    // whole not understood. Neither is ever obeyed in part.
    for (text, decision) in [
        ("Grab the mug to smash the vase.", "refuse"),
        ("Grab the mug, then smash.", "not_understood"),
        ("Grab the mug and smash the vase.", "refuse"),
    ] {
        let answer = app.clarify(&said(text, red_things())).await;
        assert_eq!(answer["decision"], decision, "{text}: {answer}");
        assert!(answer["goal"].is_null());
    }
    let answer = app
        .clarify(&said("Grab the mug to smash the vase.", red_things()))
        .await;
    assert_eq!(
        answer["utterance"],
        "I cannot get the mug to destroy the vase because destroy is forbidden action."
    );
    assert_eq!(answer["interpretations"][0]["reasons"][0]["kind"], "forbidden_purpose");
    assert_eq!(answer["parse"]["purposes"][0]["words"], "to smash the vase");
    assert_eq!(answer["parse"]["purposes"][0]["form"], "destroy(Y)");
}

#[tokio::test]
async fn a_vocative_or_please_after_a_pronoun_leaves_the_directive_whole() {
    let app = with_paper_norms().await;
    for text in ["Grab it, Pepper.", "Grab it, please."] {
        let mut request = said(text, lab_scene());
        request["focus"] = json!(["object5"]);
        let answer = app.clarify(&request).await;
        assert_eq!(answer["goal"], "did(self,get(object5))", "{text}: {answer}");
    }
}

#[tokio::test]
async fn a_mark_inside_a_word_and_an_id_match_exactly_what_was_written() {
    let app = with_paper_norms().await;
    let bottles = json!({"agent": {"position": [0, 0, 0.75], "reach": 0.9}, "objects": [
        {"id": "b15", "type": "bottle", "attributes": {"volume": "15"}, "position": [0.5, 0, 0.8]},
        {"id": "b1_5", "type": "bottle", "attributes": {"volume": "1.5"}, "position": [0.5, 0.1, 0.8]},
        {"id": "d1", "type": "drpepper", "position": [0.5, 0.2, 0.8]}]});
    let answer = app.clarify(&said("Get the 1.5 bottle.", bottles.clone())).await;
    assert_eq!(answer["goal"], "did(self,get(b1_5))", "{answer}");
    let answer = app.clarify(&said("Get the dr.pepper.", bottles)).await;
    assert_eq!(answer["decision"], "unresolved", "{answer}");
    let cups = json!({"agent": {"position": [0, 0, 0.75], "reach": 0.9}, "objects": [
        {"id": "c.1", "type": "cup", "position": [0.5, 0, 0.8]},
        {"id": "c1", "type": "cup", "position": [0.5, 0.1, 0.8]},
        {"id": "cA", "type": "cup", "position": [0.5, 0.2, 0.8]},
        {"id": "ca", "type": "cup", "position": [0.5, 0.3, 0.8]}]});
    for id in ["c.1", "cA"] {
        let mut request = said("Get the cup.", cups.clone());
        request["answer"] = json!({"text": id});
        let answer = app.clarify(&request).await;
        assert_eq!(answer["goal"], format!("did(self,get({id}))"), "{id}: {answer}");
    }
}

#[tokio::test]
async fn the_robot_says_which_words_it_did_not_understand() {
    let app = with_paper_norms().await;
    let mut request = said("Get the mug pls.", lab_scene());
    request["options"] = json!({"style": "natural"});
    let answer = app.clarify(&request).await;
    assert_eq!(answer["utterance"], "I do not understand \"pls\" in \"the mug pls\".");
    request["directive"]["text"] = json!("Get the second notebook.");
    let answer = app.clarify(&request).await;
    assert_eq!(
        answer["utterance"],
        "I do not understand \"second\" in \"the second notebook\"."
    );
}

#[tokio::test]
async fn never_mind_cancels_and_a_new_directive_is_decided_afresh() {
    let app = with_paper_norms().await;
    let mut request = said("Get the notebook.", lab_scene());
    request["answer"] = json!({"text": "never mind"});
    let answer = app.clarify(&request).await;
    assert_eq!(answer["decision"], "cancelled", "{answer}");
    assert_eq!(answer["utterance"], "Okay, I will not.");
    assert!(answer["goal"].is_null());
    request["answer"] = json!({"text": "Get the vase."});
    let answer = app.clarify(&request).await;
    assert_eq!(answer["decision"], "assume", "{answer}");
    assert_eq!(answer["goal"], "did(self,get(object4))");
}

#[tokio::test]
async fn direction_controls_are_not_echoed() {
    let app = with_paper_norms().await;
    let answer = app.clarify(&said("What is \u{202e}the mug?", lab_scene())).await;
    let utterance = answer["utterance"].as_str().unwrap();
    assert!(!utterance.contains('\u{202e}'), "{utterance:?}");
}

/// Finding 3.1: 11 objects with 100 long properties each and a 490-word reference took 19-47 s
/// against a 500-1,000 ms deadline. The bound is far below that and above any debug build's
/// honest time.
#[tokio::test]
async fn long_words_over_long_properties_end_by_the_deadline() {
    let app = with_paper_norms().await;
    // Each object is "x", and phrases of 40 to 59 x's: every word of the reference is an
    // adjective, and at every word each length of phrase is worth looking up.
    let property = |i: usize, j: usize| match j {
        0 => "x".to_owned(),
        _ => format!("{}p{i}_{j}", "x_".repeat(40 + j % 20)),
    };
    let objects: Vec<Value> = (0..11)
        .map(|i| {
            let properties: Vec<String> = (0..100).map(|j| property(i, j)).collect();
            json!({"id": format!("o{i}"), "type": "thing", "properties": properties, "position": [0.5, 0, 0.8]})
        })
        .collect();
    let words = vec!["x"; 480].join(" ");
    let mut request = said(
        &format!("Get the {words} thing."),
        json!({"agent": {"position": [0, 0, 0.75], "reach": 0.9}, "objects": objects}),
    );
    request["options"] = json!({"deadline_ms": 500});
    let started = Instant::now();
    let answer = app.clarify(&request).await;
    assert!(started.elapsed() < Duration::from_secs(8), "{:?}", started.elapsed());
    assert!(answer["goal"].is_null(), "{answer}");
}

/// Finding 3.2: describing 10,000 cups to sort them ran before the `max_readings` check and
/// never asked the deadline (12-16 s for a `too_many_readings` answer).
#[tokio::test]
async fn too_many_readings_are_refused_before_anything_is_described() {
    let app = with_paper_norms().await;
    let objects: Vec<Value> = (0..10_000)
        .map(|i| {
            let properties: Vec<String> = (0..12).map(|j| format!("p{}", (i * 7 + j * 13) % 5_000)).collect();
            json!({"id": format!("c{i}"), "type": "cup", "properties": properties, "position": [0.5, 0, 0.8]})
        })
        .collect();
    let scene = json!({"agent": {"position": [0, 0, 0.75], "reach": 0.9}, "objects": objects});
    let put = json!({"directive": {"action": "put", "arguments": [{"type": "cup"}, {"type": "cup"}]},
                     "scene": scene.clone(), "options": {"deadline_ms": 1000}});
    let started = Instant::now();
    let answer = app.clarify(&put).await;
    assert_eq!(answer["limits"]["reason"], "too_many_readings", "{}", answer["limits"]);
    assert!(started.elapsed() < Duration::from_secs(8), "{:?}", started.elapsed());
    let get = json!({"directive": {"action": "get", "arguments": [{"type": "cup"}]},
                     "scene": scene, "options": {"deadline_ms": 1000}});
    let started = Instant::now();
    let answer = app.clarify(&get).await;
    assert!(started.elapsed() < Duration::from_secs(8), "{:?}", started.elapsed());
    assert!(answer["goal"].is_null() || answer["limits"].is_null(), "{answer}");
}

/// Finding 3.3: an indefinite cut short by the deadline was assumed on a partial view (the first
/// mug, not the one a norm prefers). Whatever the deadline leaves, a decision made with readings
/// unsimulated neither assumes nor obeys.
#[tokio::test]
async fn an_indefinite_is_never_assumed_on_a_partial_view() {
    let app = with_paper_norms().await;
    app.add_norm(&json!({"kind": "preferred_state", "state": "holding(self,X)", "when": ["clean(X)"], "severity": 3}))
        .await;
    let objects: Vec<Value> = (0..6_000)
        .map(|i| {
            let properties = if i == 5_999 { json!(["clean"]) } else { json!([]) };
            json!({"id": format!("m{i:05}"), "type": "mug", "properties": properties, "position": [0.5, 0, 0.8]})
        })
        .collect();
    let request = json!({"directive": {"text": "Get a mug."},
        "scene": {"agent": {"position": [0, 0, 0.75], "reach": 0.9}, "objects": objects},
        "options": {"deadline_ms": 10}});
    let answer = app.clarify(&request).await;
    if answer["limits"].is_null() {
        assert_eq!(answer["goal"], "did(self,get(m05999))", "{}", answer["utterance"]);
    } else {
        assert!(answer["goal"].is_null(), "{} {}", answer["decision"], answer["limits"]);
        assert!(
            ["ask", "not_understood"].contains(&answer["decision"].as_str().unwrap()),
            "{}",
            answer["decision"]
        );
    }
}

/// Finding 3.6: a reference of only `{"properties": []}` or `{"attributes": {}}` was "any object"
/// over REST and INVALID_ARGUMENT over gRPC: one rule, a 422 naming the reference.
#[tokio::test]
async fn a_reference_that_says_nothing_is_refused_as_grpc_refuses_it() {
    let app = with_paper_norms().await;
    for reference in [
        json!({"properties": []}),
        json!({"attributes": {}}),
        json!({"properties": [], "attributes": {}}),
        json!({}),
    ] {
        let body = json!({"directive": {"action": "get", "arguments": [reference]}, "scene": lab_scene()});
        crate::helpers::assert_problem(
            app.post("/v1/clarify", &body).await,
            reqwest::StatusCode::UNPROCESSABLE_ENTITY,
            Some("/directive/arguments/0"),
        )
        .await;
    }
    let body =
        json!({"directive": {"action": "get", "arguments": [{"properties": ["fragile"]}]}, "scene": lab_scene()});
    assert_eq!(app.clarify(&body).await["decision"], "refuse");
}

/// Finding 3.8: words were admitted as if they could have every pair of objects for readings:
/// 64 clients of "Get the plastic vase." on 200 objects got up to 178 503s where the same
/// request structured got none. Words in a small scene are read first and admitted by what they
/// name.
#[tokio::test]
async fn words_are_admitted_by_the_readings_they_give() {
    let app = with_paper_norms().await;
    let mut objects: Vec<Value> = (0..198)
        .map(|i| json!({"id": format!("b{i}"), "type": "box", "position": [0.5, 0.001 * i as f64, 0.8]}))
        .collect();
    objects
        .push(json!({"id": "v1", "type": "vase", "attributes": {"material": "plastic"}, "position": [0.5, 0.3, 0.8]}));
    objects.push(json!({"id": "v2", "type": "vase", "properties": ["fragile"], "position": [0.5, 0.4, 0.8]}));
    let request = said(
        "Get the plastic vase.",
        json!({"agent": {"position": [0, 0, 0.75], "reach": 0.9}, "objects": objects}),
    );
    let mut clients = Vec::new();
    for _ in 0..64 {
        let (client, url, request) = (app.client.clone(), app.url("/v1/clarify"), request.clone());
        clients.push(tokio::spawn(async move {
            let mut refused = 0;
            for _ in 0..5 {
                let response = client.post(&url).json(&request).send().await.unwrap();
                refused += usize::from(response.status() == reqwest::StatusCode::SERVICE_UNAVAILABLE);
            }
            refused
        }));
    }
    let mut refused = 0;
    for client in clients {
        refused += client.await.unwrap();
    }
    assert_eq!(refused, 0, "words for one reading were refused as overload");
}

/// Finding 3.10: `snatch` could take "grabbed" while "grab" names `get`, and "the" was taken as
/// a verb's word and "and" as a joiner. Over REST, each is a 422 naming the word's field, and
/// nothing is stored.
#[tokio::test]
async fn verb_words_that_clash_once_inflected_or_are_the_grammars_are_refused() {
    let app = spawn_app().await;
    for (name, verb, field) in [
        (
            "snatch",
            json!({"parameters": ["X"], "methods": [{}], "words": ["grabbed"]}),
            "/words/0",
        ),
        (
            "odd",
            json!({"parameters": ["X"], "methods": [{}], "words": ["the thing"]}),
            "/words/0",
        ),
        (
            "fling",
            json!({"parameters": ["X", "Y"], "methods": [{}], "words": ["fling"], "joiners": ["and"]}),
            "/joiners/0",
        ),
    ] {
        let response = app
            .client
            .put(app.url(&format!("/v1/actions/{name}")))
            .json(&verb)
            .send()
            .await
            .unwrap();
        crate::helpers::assert_problem(response, reqwest::StatusCode::UNPROCESSABLE_ENTITY, Some(field)).await;
        assert_eq!(
            app.get(&format!("/v1/actions/{name}")).await.status(),
            reqwest::StatusCode::NOT_FOUND
        );
    }
}
