//! Beyond the paper: too many readings, many forbidden readings, follow-up answers, the natural
//! style, and roles. The paper's own cases stay exact under default options (paper_demo.rs).

use reqwest::StatusCode;
use serde_json::{Value, json};

use crate::helpers::{assert_problem, get_vase, lab_scene, paper_demo, spawn_app};

fn cup(i: usize) -> Value {
    json!({"id": format!("cup{i}"), "type": "cup", "position": [0.4, -0.3 + 0.05 * i as f64, 0.8]})
}

fn plate(i: usize) -> Value {
    json!({"id": format!("plate{i}"), "type": "plate", "position": [0.5, -0.3 + 0.05 * i as f64, 0.76]})
}

/// A scene of `cups` identical cups and `plates` identical plates, all within reach.
pub(crate) fn kitchen(cups: usize, plates: usize) -> Value {
    let mut objects: Vec<Value> = (0..cups).map(cup).collect();
    objects.extend((0..plates).map(plate));
    json!({"agent": {"id": "self", "position": [0, 0, 0.75], "reach": 0.9}, "objects": objects})
}

pub(crate) fn request(action: &str, types: &[&str], scene: Value) -> Value {
    let arguments: Vec<Value> = types.iter().map(|t| json!({"type": t})).collect();
    json!({"directive": {"action": action, "arguments": arguments}, "scene": scene})
}

async fn with_paper_norms() -> crate::helpers::TestApp {
    let app = spawn_app().await;
    for norm in paper_demo()["norms"].as_array().unwrap() {
        app.add_norm(norm).await;
    }
    app
}

#[tokio::test]
async fn evenly_spread_readings_beyond_the_limit_name_the_ambiguous_words() {
    let app = spawn_app().await;
    let answer = app.clarify(&request("get", &["cup"], kitchen(7, 0))).await;
    assert_eq!(answer["decision"], "ask");
    assert_eq!(answer["utterance"], "I do not know which cup you mean.");
    assert_eq!(answer["speech_act"], "want_know(self,which(cup))");
    assert_eq!(answer["offered"], json!([]));
    assert_eq!(
        answer["interpretations"].as_array().unwrap().len(),
        7,
        "all were simulated"
    );
    assert!(answer.get("limits").is_none());

    // Raising the limit names them all again.
    let mut asked = request("get", &["cup"], kitchen(7, 0));
    asked["options"] = json!({"max_spoken": 7});
    let answer = app.clarify(&asked).await;
    assert_eq!(answer["offered"].as_array().unwrap().len(), 7);
}

#[tokio::test]
async fn scored_readings_beyond_the_limit_name_the_likeliest_permissible_ones_and_something_else() {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(cup0))"}))
        .await;
    let bindings: Vec<Value> = (0..8)
        .map(|i| json!({"id": format!("cup{i}"), "score": 1.0 - 0.1 * i as f64}))
        .collect();
    let body = json!({"directive": {"form": "did(self,get(X))", "bindings": {"X": bindings}}, "scene": kitchen(8, 0)});
    let answer = app.clarify(&body).await;
    assert_eq!(answer["decision"], "ask");
    // cup0 is the likeliest but forbidden: never named.
    assert_eq!(
        answer["utterance"],
        "Do you mean that you want me to get the cup (cup1) or that you want me to get the cup (cup2) or that you want me to get the cup (cup3) or something else?"
    );
    assert_eq!(
        answer["offered"],
        json!(["did(self,get(cup1))", "did(self,get(cup2))", "did(self,get(cup3))"])
    );
    assert_eq!(
        answer["speech_act"],
        "want_know(self,mean(human,or(did(self,get(cup1)),did(self,get(cup2)),did(self,get(cup3)),something_else)))"
    );
}

#[tokio::test]
async fn more_readings_than_may_be_simulated_is_a_dialogue_answer_not_an_error() {
    let app = spawn_app().await;
    let mut body = request("put", &["cup", "plate"], kitchen(20, 20));
    body["options"] = json!({"max_readings": 100});
    let answer = app.clarify(&body).await;
    assert_eq!(answer["decision"], "ask");
    assert_eq!(answer["utterance"], "I do not know which cup and which plate you mean.");
    assert_eq!(
        answer["limits"],
        json!({"reason": "too_many_readings", "readings": 400, "simulated": 0})
    );
    assert_eq!(answer["interpretations"], json!([]));
    assert_eq!(answer["goal"], Value::Null);
}

#[tokio::test]
async fn a_deadline_hit_is_said_and_nothing_unsimulated_is_offered() {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_action", "action": "put(X,Y)", "when": ["cup(X)"]}))
        .await;
    let mut body = request("put", &["cup", "plate"], kitchen(100, 100));
    body["options"] = json!({"deadline_ms": 1});
    let answer = app.clarify(&body).await;
    let limits = &answer["limits"];
    assert_eq!(limits["reason"], "deadline", "{limits}");
    assert_eq!(limits["readings"], 10_000);
    // The deadline counts from the request's arrival, so even the first batch may be cut.
    let simulated = limits["simulated"].as_u64().unwrap();
    assert!(simulated < 10_000, "{limits}");
    assert_eq!(answer["interpretations"].as_array().unwrap().len() as u64, simulated);
    // Every simulated reading is forbidden, so nothing is offered: the ambiguous words are named.
    assert_eq!(answer["decision"], "ask");
    assert_eq!(answer["utterance"], "I do not know which cup and which plate you mean.");
    assert_eq!(answer["offered"], json!([]));
}

#[tokio::test]
async fn many_forbidden_readings_and_one_permissible_confirm_above_the_ratio() {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_state", "state": "holding(self,X)", "when": ["fragile(X)"]}))
        .await;
    let mut objects: Vec<Value> = (0..3)
        .map(|i| {
            let color = ["red", "green", "blue"][i];
            json!({"id": format!("v{i}"), "type": "vase", "properties": ["fragile"], "attributes": {"color": color},
                   "position": [0.5, 0.1 * i as f64, 0.8]})
        })
        .collect();
    objects.push(json!({"id": "v3", "type": "vase", "attributes": {"color": "white"}, "position": [0.5, 0.3, 0.8]}));
    let scene = json!({"agent": {"position": [0, 0, 0.75], "reach": 0.9}, "objects": objects});
    let mut body = request("get", &["vase"], scene);
    // Off by default: Algorithm 1 assumes.
    assert_eq!(app.clarify(&body).await["decision"], "assume");
    body["options"] = json!({"confirm_above_ratio": 0.8});
    assert_eq!(
        app.clarify(&body).await["decision"],
        "assume",
        "3 of 4 is not above 0.8"
    );
    body["options"] = json!({"confirm_above_ratio": 0.5});
    let answer = app.clarify(&body).await;
    assert_eq!(answer["decision"], "confirm");
    assert_eq!(answer["goal"], Value::Null);
    assert_eq!(answer["offered"], json!(["did(self,get(v3))"]));
    assert!(answer["utterance"].as_str().unwrap().starts_with("Do you want me to get the white vase? I cannot get the fragile blue vase because holding the fragile blue vase is forbidden."));
}

#[tokio::test]
async fn follow_up_answers_are_re_resolved_and_re_simulated() {
    let app = with_paper_norms().await;
    let notebook = request("get", &["notebook"], lab_scene());
    let question = app.clarify(&notebook).await;
    assert_eq!(
        question["offered"],
        json!(["did(self,get(object2))", "did(self,get(object1))"])
    );

    let cases = [
        (json!({"choice": 1}), "did(self,get(object1))"),
        (json!({"choice": 0}), "did(self,get(object2))"),
        (json!({"id": "object1"}), "did(self,get(object1))"),
        (
            json!({"reference": {"attributes": {"color": "green"}}}),
            "did(self,get(object2))",
        ),
    ];
    for (answer, goal) in cases {
        let mut follow_up = notebook.clone();
        follow_up["answer"] = answer.clone();
        let decided = app.clarify(&follow_up).await;
        assert_eq!(decided["decision"], "comply", "{answer}");
        assert_eq!(decided["goal"], goal, "{answer}");
        assert_eq!(decided["utterance"], "Okay.");
    }

    // An answer that picks a forbidden reading is refused with its reason, whatever was said before.
    let mut fragile = get_vase();
    fragile["answer"] = json!({"reference": {"properties": ["fragile"]}});
    let decided = app.clarify(&fragile).await;
    assert_eq!(decided["decision"], "refuse");
    assert_eq!(
        decided["utterance"],
        "I cannot get the fragile vase because it requires a forbidden state."
    );

    // A confirmation is answered with choice 0.
    let mut confirmed = get_vase();
    confirmed["options"] = json!({"single_permissible": "confirm"});
    confirmed["answer"] = json!({"choice": 0});
    let decided = app.clarify(&confirmed).await;
    assert_eq!(
        (decided["decision"].as_str(), decided["goal"].as_str()),
        (Some("comply"), Some("did(self,get(object4))"))
    );

    // An answer naming something none of the readings involves.
    let mut mug = notebook.clone();
    mug["answer"] = json!({"id": "object5"});
    let decided = app.clarify(&mug).await;
    assert_eq!(decided["decision"], "unresolved");
    assert_eq!(decided["utterance"], "I do not know what you mean by the mug.");

    // Nothing to choose from, or a choice out of range: the client's error, naming the field.
    let mut nothing = request("destroy", &["notebook"], lab_scene());
    nothing["answer"] = json!({"choice": 0});
    assert_problem(
        app.post("/v1/clarify", &nothing).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/answer"),
    )
    .await;
    let mut far = notebook.clone();
    far["answer"] = json!({"choice": 2});
    assert_problem(
        app.post("/v1/clarify", &far).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/answer/choice"),
    )
    .await;
}

#[tokio::test]
async fn the_service_never_trusts_an_earlier_question() {
    let app = spawn_app().await;
    let notebook = request("get", &["notebook"], lab_scene());
    assert_eq!(app.clarify(&notebook).await["offered"].as_array().unwrap().len(), 2);
    // A curator forbids the red notebook between the question and the answer.
    app.add_norm(&json!({"kind": "forbidden_action", "action": "get(object1)"}))
        .await;
    let mut follow_up = notebook.clone();
    follow_up["answer"] = json!({"id": "object1"});
    let decided = app.clarify(&follow_up).await;
    assert_eq!(decided["decision"], "refuse");
    assert_eq!(
        decided["utterance"],
        "I cannot get the red notebook because get is forbidden action."
    );
}

#[tokio::test]
async fn the_natural_style_words_every_decision_kind() {
    let app = spawn_app().await;
    let destroy = app
        .add_norm(&json!({"kind": "forbidden_action", "action": "destroy"}))
        .await;
    app.add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))", "severity": 2}))
        .await;
    let natural = |mut body: Value| {
        body["options"] = json!({"style": "natural"});
        body
    };
    let mut far = lab_scene();
    far["objects"][4]["position"] = json!([3.0, 0.0, 0.8]);
    let cases = [
        (
            "comply",
            request("get", &["mug"], lab_scene()),
            "Okay, I will get the mug.",
        ),
        (
            "refuse",
            request("destroy", &["mug"], lab_scene()),
            "I won't destroy the mug: destroying things is not allowed.",
        ),
        (
            "refuse, unable",
            request("get", &["mug"], far),
            "I can't get the mug: the mug is out of my reach.",
        ),
        (
            "refuse, unknown verb",
            request("juggle", &["mug"], lab_scene()),
            "I can't juggle the mug: I don't know how to juggle.",
        ),
        (
            "ask",
            request("get", &["notebook"], lab_scene()),
            "Do you want me to get the green notebook or the red notebook?",
        ),
        (
            "ask which",
            request("get", &["cup"], kitchen(7, 0)),
            "Which cup do you mean?",
        ),
        (
            "assume",
            request("get", &["vase"], lab_scene()),
            "I'll get the plastic vase. Sorry, I'd rather not get the fragile vase: it would lead to a state I am not allowed to bring about.",
        ),
        (
            "explain",
            request("destroy", &["notebook"], lab_scene()),
            "I won't destroy either notebook: destroying things is not allowed.",
        ),
        (
            "unresolved",
            request("get", &["spoon"], lab_scene()),
            "I can't find the spoon here.",
        ),
    ];
    for (name, body, utterance) in cases {
        let answer = app.clarify(&natural(body)).await;
        assert_eq!(answer["utterance"], utterance, "{name}");
    }
    let mut confirm = natural(request("get", &["vase"], lab_scene()));
    confirm["options"]["single_permissible"] = json!("confirm");
    assert_eq!(
        app.clarify(&confirm).await["utterance"],
        "Should I get the plastic vase? Sorry, I'd rather not get the fragile vase: it would lead to a state I am not allowed to bring about."
    );

    // Severity sets the firmness: the same refusal under a grave norm.
    app.delete(&format!("/v1/norms/{destroy}")).await;
    app.add_norm(&json!({"kind": "forbidden_action", "action": "destroy", "severity": 5}))
        .await;
    let answer = app.clarify(&natural(request("destroy", &["mug"], lab_scene()))).await;
    assert_eq!(
        answer["utterance"],
        "I will not destroy the mug. Destroying things is forbidden."
    );
    let answer = app
        .clarify(&natural(request("destroy", &["notebook"], lab_scene())))
        .await;
    assert_eq!(
        answer["utterance"],
        "I will not destroy either notebook. Destroying things is forbidden."
    );
    // The decision is the same in both styles; only the words differ.
    assert_eq!(answer["decision"], "explain");
    // Three or more are "any of" them, in the plural the words path reads ("knives").
    let knives: Vec<Value> = (0..3)
        .map(|i| json!({"id": format!("knife{i}"), "type": "kitchen_knife", "position": [0.5, 0.1 * i as f64, 0.8]}))
        .collect();
    let scene = json!({"agent": {"position": [0, 0, 0.75], "reach": 0.9}, "objects": knives});
    let answer = app
        .clarify(&natural(request("destroy", &["kitchen_knife"], scene)))
        .await;
    assert_eq!(
        answer["utterance"],
        "I will not destroy any of the kitchen knives. Destroying things is forbidden."
    );
}

#[tokio::test]
async fn reasons_carry_their_words_in_the_requests_style() {
    let app = with_paper_norms().await;
    let answer = app.clarify(&request("destroy", &["mug"], lab_scene())).await;
    assert_eq!(
        answer["interpretations"][0]["reasons"][0]["words"],
        "destroy is forbidden action"
    );
    let mut natural = request("destroy", &["mug"], lab_scene());
    natural["options"] = json!({"style": "natural"});
    let answer = app.clarify(&natural).await;
    assert_eq!(
        answer["interpretations"][0]["reasons"][0]["words"],
        "destroying any object is forbidden"
    );
}

#[tokio::test]
async fn roles_with_context_select_the_norms_in_force() {
    let app = spawn_app().await;
    // "Only the owner may have the cash box taken."
    let norm = app
        .post(
            "/v1/norms",
            &json!({"kind": "forbidden_action", "action": "steal", "exempt_roles": ["owner"]}),
        )
        .await;
    assert_eq!(norm.status(), StatusCode::CREATED);
    let norm: Value = norm.json().await.unwrap();
    assert_eq!(norm["exempt_roles"], json!(["owner"]));
    // A norm only for children, only in the hospital.
    app.add_norm(&json!({"kind": "forbidden_action", "action": "get", "roles": ["child"], "context": "hospital"}))
        .await;

    let office = paper_demo()["scenes"]["office"].clone();
    let mut steal = request("steal", &["cash_box"], office);
    assert_eq!(app.clarify(&steal).await["decision"], "explain");
    steal["speaker_roles"] = json!(["owner"]);
    assert_eq!(app.clarify(&steal).await["decision"], "ask");

    let mut get = request("get", &["mug"], lab_scene());
    let cases = [
        (json!(["child"]), "hospital", "refuse"),
        (json!(["child"]), "default", "comply"),
        (json!(["nurse"]), "hospital", "comply"),
        (json!([]), "hospital", "comply"),
    ];
    for (roles, context, decision) in cases {
        get["speaker_roles"] = roles.clone();
        get["context"] = json!(context);
        assert_eq!(app.clarify(&get).await["decision"], decision, "{roles} in {context}");
    }
}

#[tokio::test]
async fn bad_options_answers_and_roles_name_their_field() {
    let app = spawn_app().await;
    let with = |edit: &dyn Fn(&mut Value)| {
        let mut body = get_vase();
        edit(&mut body);
        body
    };
    let cases: Vec<(Value, &str)> = vec![
        (
            with(&|b| b["options"] = json!({"max_spoken": 1})),
            "/options/max_spoken",
        ),
        (
            with(&|b| b["options"] = json!({"max_readings": 0})),
            "/options/max_readings",
        ),
        (
            with(&|b| b["options"] = json!({"deadline_ms": 0})),
            "/options/deadline_ms",
        ),
        (
            with(&|b| b["options"] = json!({"confirm_above_ratio": 1.5})),
            "/options/confirm_above_ratio",
        ),
        (with(&|b| b["options"] = json!({"style": "pirate"})), "/options/style"),
        (
            with(&|b| b["answer"] = json!({"choice": 0, "id": "object3"})),
            "/answer",
        ),
        (with(&|b| b["answer"] = json!({"id": "object9"})), "/answer/id"),
        (
            with(&|b| b["speaker_roles"] = json!(["head nurse!"])),
            "/speaker_roles/0",
        ),
    ];
    for (body, field) in cases {
        assert_problem(
            app.post("/v1/clarify", &body).await,
            StatusCode::UNPROCESSABLE_ENTITY,
            Some(field),
        )
        .await;
    }
    let norms: Vec<(Value, &str)> = vec![
        (
            json!({"kind": "forbidden_action", "action": "steal", "roles": ["a/b"]}),
            "/roles/0",
        ),
        (
            json!({"kind": "forbidden_action", "action": "steal", "roles": ["owner"], "exempt_roles": ["owner"]}),
            "/exempt_roles",
        ),
    ];
    for (norm, field) in norms {
        assert_problem(
            app.post("/v1/norms", &norm).await,
            StatusCode::UNPROCESSABLE_ENTITY,
            Some(field),
        )
        .await;
    }
    assert!(app.norms().await.is_empty());
}

#[tokio::test]
async fn checks_while_acting_use_the_norms_in_force_now_and_carry_effects_between_steps() {
    let app = with_paper_norms().await;
    let check = |steps: Value| json!({"scene": lab_scene(), "steps": steps});
    let post = |body: Value| {
        let app = &app;
        async move {
            let response = app.post("/v1/check", &body).await;
            assert_eq!(response.status(), StatusCode::OK, "{body}");
            response.json::<Value>().await.unwrap()
        }
    };

    let ok = post(check(json!(["get(object4)"]))).await;
    assert_eq!(ok["permitted"], true);
    assert_eq!(ok["utterance"], "Okay.");
    assert_eq!(ok["steps"][0]["plan"], json!(["get(object4)"]));
    assert_eq!(ok["norm_version"], 3);

    let fragile = post(check(json!(["get(object4)", "get(object3)"]))).await;
    assert_eq!(fragile["permitted"], false);
    assert_eq!(fragile["steps"][0]["permissible"], true);
    assert_eq!(fragile["steps"][1]["reasons"][0]["kind"], "forbidden_state");
    assert_eq!(
        fragile["utterance"],
        "I cannot get the fragile vase because it requires a forbidden state."
    );

    // Effects carry over: destroying what the robot holds is forbidden, and the get before it
    // is what makes it held.
    app.add_norm(&json!({"kind": "forbidden_action", "action": "smash(X)", "when": ["holding(self,X)"]}))
        .await;
    let alone = post(check(json!(["smash(object5)"]))).await;
    assert_eq!(alone["steps"][0]["permissible"], true, "not held yet: only unknown");
    assert_eq!(alone["steps"][0]["reasons"][0]["kind"], "unknown_action");
    let held = post(check(json!(["get(object5)", "smash(object5)"]))).await;
    assert_eq!(held["steps"][1]["permissible"], false);
    // The norm holds only while the mug is held: it is said so, never as "smash is forbidden".
    assert_eq!(
        held["steps"][1]["reasons"][0]["words"],
        "smashing the mug is forbidden when I am holding the mug"
    );

    // A norm added partway through is in force for the next check.
    app.add_norm(&json!({"kind": "forbidden_action", "action": "get(object4)"}))
        .await;
    let now = post(check(json!(["get(object4)"]))).await;
    assert_eq!(now["permitted"], false);
    assert_eq!(now["norm_version"], 5);

    let mut natural = check(json!(["get(object3)"]));
    natural["options"] = json!({"style": "natural"});
    assert_eq!(
        post(natural).await["utterance"],
        "I can't go on to get the fragile vase: the fragile vase may not be got."
    );

    for (steps, field) in [
        (json!([]), "/steps"),
        (json!(["get(X)"]), "/steps/0"),
        (json!(["get(object4)", "get("]), "/steps/1"),
    ] {
        assert_problem(
            app.post("/v1/check", &check(steps)).await,
            StatusCode::UNPROCESSABLE_ENTITY,
            Some(field),
        )
        .await;
    }
}

fn geometry_scene(agent_extra: Value, objects: Value) -> Value {
    let mut agent = json!({"id": "self", "position": [0, 0, 0.75], "reach": 0.9});
    for (k, v) in agent_extra.as_object().unwrap() {
        agent[k] = v.clone();
    }
    json!({"agent": agent, "objects": objects})
}

#[tokio::test]
async fn grasp_payload_clearance_and_placing_are_checked_when_the_request_gives_what_they_need() {
    let app = spawn_app().await;
    let cylinder = |r: f64, h: f64| json!({"cylinder": {"radius": r, "half_height": h}});
    let objects = json!([
        {"id": "cup1", "type": "cup", "position": [0.6, 0.0, 0.8], "shape": cylinder(0.04, 0.05), "mass": 0.3},
        {"id": "pot1", "type": "pot", "position": [0.5, 0.4, 0.85], "shape": cylinder(0.15, 0.1), "mass": 1.5},
        {"id": "box1", "type": "box", "position": [0.4, -0.5, 0.8], "shape": {"cuboid": {"half_extents": [0.05, 0.05, 0.05]}}, "mass": 5.0},
        {"id": "wall1", "type": "wall", "position": [0.3, 0.0, 0.8], "shape": {"cuboid": {"half_extents": [0.01, 0.2, 0.2]}}},
        {"id": "saucer1", "type": "saucer", "position": [0.5, -0.2, 0.76], "shape": cylinder(0.03, 0.005)},
        {"id": "tray1", "type": "tray", "position": [0.5, 0.2, 0.76], "shape": {"cuboid": {"half_extents": [0.2, 0.15, 0.01]}}},
        {"id": "ball1", "type": "ball", "position": [0.3, 0.6, 0.8], "shape": {"ball": {"radius": 0.1}}}
    ]);
    let robot = json!({"gripper_aperture": 0.1, "payload": 2.0, "gripper_size": 0.02});
    let scene = geometry_scene(robot, objects.clone());
    let cases = [
        (
            "get",
            vec!["pot"],
            "refuse",
            "I cannot get the pot because the pot is too wide to grasp.",
            "too_wide",
        ),
        (
            "get",
            vec!["box"],
            "refuse",
            "I cannot get the box because the box is too heavy.",
            "too_heavy",
        ),
        (
            "get",
            vec!["cup"],
            "refuse",
            "I cannot get the cup because the wall is in the way.",
            "blocked",
        ),
        ("pointTo", vec!["cup"], "comply", "Okay.", ""),
        ("destroy", vec!["pot"], "comply", "Okay.", ""),
        (
            "put",
            vec!["box", "saucer"],
            "refuse",
            "I cannot put the box on the saucer because the box is too heavy.",
            "too_heavy",
        ),
        (
            "put",
            vec!["ball", "tray"],
            "refuse",
            "I cannot put the ball on the tray because the ball is too wide to grasp.",
            "too_wide",
        ),
    ];
    for (verb, types, decision, utterance, kind) in cases {
        let answer = app.clarify(&request(verb, &types, scene.clone())).await;
        assert_eq!(answer["decision"], decision, "{verb} {types:?}");
        assert_eq!(answer["utterance"], utterance, "{verb} {types:?}");
        if !kind.is_empty() {
            assert_eq!(
                answer["interpretations"][0]["reasons"][0]["kind"], kind,
                "{verb} {types:?}"
            );
        }
    }

    // Placing: a cup does not fit on a saucer narrower than itself, fits on a tray, never on a ball.
    let mut open = objects.clone();
    open.as_array_mut().unwrap().retain(|o| o["id"] != "wall1");
    let scene = geometry_scene(json!({"gripper_aperture": 0.1}), open);
    let saucer = app.clarify(&request("put", &["cup", "saucer"], scene.clone())).await;
    assert_eq!(
        saucer["utterance"],
        "I cannot put the cup on the saucer because there is no room for the cup on the saucer."
    );
    assert_eq!(
        saucer["interpretations"][0]["reasons"][0]["detail"],
        "no room for cup1 on saucer1"
    );
    assert_eq!(
        saucer["speech_act"],
        "cannot(did(self,put(cup1,saucer1)),because(noRoom(cup1,saucer1)))"
    );
    assert_eq!(
        app.clarify(&request("put", &["cup", "tray"], scene.clone())).await["decision"],
        "comply"
    );
    let on_ball = app.clarify(&request("put", &["cup", "ball"], scene.clone())).await;
    assert_eq!(on_ball["interpretations"][0]["reasons"][0]["kind"], "no_room");

    // Without the agent's measures the same scene is judged on reach alone, as the contract's are.
    let plain = geometry_scene(json!({}), objects);
    for (verb, types) in [("get", vec!["pot"]), ("get", vec!["box"]), ("get", vec!["cup"])] {
        assert_eq!(
            app.clarify(&request(verb, &types, plain.clone())).await["decision"],
            "comply",
            "{verb} {types:?}"
        );
    }
    // And the paper's lab stays clear with a gripper: nothing there stands in the way.
    let mut lab = lab_scene();
    lab["agent"]["gripper_size"] = json!(0.02);
    lab["agent"]["gripper_aperture"] = json!(0.3);
    let answer = app.clarify(&request("get", &["vase"], lab)).await;
    assert_eq!(answer["decision"], "ask");
}

#[tokio::test]
async fn geometry_reasons_have_natural_words_too() {
    let app = spawn_app().await;
    let scene = geometry_scene(
        json!({"gripper_aperture": 0.1, "payload": 1.0}),
        json!([{"id": "box1", "type": "box", "position": [0.4, 0, 0.8], "shape": {"cuboid": {"half_extents": [0.2, 0.2, 0.2]}}, "mass": 3}]),
    );
    let mut body = request("get", &["box"], scene);
    body["options"] = json!({"style": "natural"});
    let answer = app.clarify(&body).await;
    assert_eq!(
        answer["utterance"],
        "I can't get the box: the box is too wide for my gripper."
    );
    let words: Vec<&str> = answer["interpretations"][0]["reasons"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["words"].as_str().unwrap())
        .collect();
    assert_eq!(
        words,
        [
            "the box is too wide for my gripper",
            "the box is too heavy for me to lift"
        ]
    );
}
