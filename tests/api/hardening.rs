//! Regressions from the hostile pass: each test pins one finding of the hardening issue, as a
//! user of the API sees it (status codes, problem fields, decisions, persisted state).

use reqwest::StatusCode;
use serde_json::{Value, json};
use sqlx::sqlite::SqliteConnectOptions;
use sqlx::{ConnectOptions, Connection};

use crate::helpers::{Options, TestApp, assert_problem, lab_scene, spawn_app, spawn_on};

async fn sql(app: &TestApp, statements: &'static str) {
    let mut connection = SqliteConnectOptions::new()
        .filename(&app.db_path)
        .connect()
        .await
        .expect("open the database");
    sqlx::raw_sql(statements)
        .execute(&mut connection)
        .await
        .expect("the SQL runs");
    connection.close().await.unwrap();
}

async fn put_json(app: &TestApp, path: &str, body: &Value) -> reqwest::Response {
    app.client.put(app.url(path)).json(body).send().await.unwrap()
}

/// Finding 1: an id beyond 2^53 − 1 in an import answered 200 and then every create failed
/// with "database or disk is full", even after a delete and a restart.
#[tokio::test]
async fn an_import_with_an_id_beyond_2_pow_53_is_refused_and_creating_still_works() {
    let app = spawn_app().await;
    for id in [9_223_372_036_854_775_807_i64, 9_007_199_254_740_992, 0, -1] {
        let body = json!({"norms": [
            {"kind": "forbidden_action", "action": "steal"},
            {"id": id, "kind": "forbidden_action", "action": "x"},
        ]});
        let problem = assert_problem(
            put_json(&app, "/v1/norm-set", &body).await,
            StatusCode::UNPROCESSABLE_ENTITY,
            Some("/norms/1/id"),
        )
        .await;
        assert!(
            problem["detail"].as_str().unwrap().contains("9007199254740991"),
            "{problem}"
        );
    }
    let largest = json!({"norms": [{"id": 9_007_199_254_740_991_i64, "kind": "forbidden_action", "action": "x"}]});
    assert_eq!(put_json(&app, "/v1/norm-set", &largest).await.status(), StatusCode::OK);
    let created = app
        .post("/v1/norms", &json!({"kind": "forbidden_action", "action": "steal"}))
        .await;
    assert_eq!(
        created.status(),
        StatusCode::CREATED,
        "creating works after the largest id"
    );
}

/// Finding 1, stored data: a store an older build let reach the end of the id range is
/// renumbered by a migration, and creating works again.
#[tokio::test]
async fn a_store_whose_ids_ran_past_the_range_is_migrated_and_can_create_again() {
    let app = spawn_app().await;
    let dir = app.dir.clone();
    let kept = app
        .add_norm(&json!({"kind": "forbidden_action", "action": "destroy"}))
        .await;
    app.stop().await;
    // As an older build left it: a norm at the last i64, the sequence exhausted, and the new
    // migration not yet applied.
    let probe = spawn_on(dir.clone(), Options::default()).await;
    sql(
        &probe,
        "INSERT INTO norms (id, kind, term, revision) VALUES (9223372036854775807, 'forbidden_action', 'steal', 1);
         UPDATE sqlite_sequence SET seq = 9223372036854775807 WHERE name = 'norms';
         DELETE FROM _sqlx_migrations WHERE version = 20261201000001;",
    )
    .await;
    probe.stop().await;

    let app = spawn_on(dir, Options::default()).await;
    let ids: Vec<i64> = app.norms().await.iter().map(|n| n["id"].as_i64().unwrap()).collect();
    assert_eq!(
        ids,
        vec![kept, kept + 1],
        "the norm beyond the range is renumbered after the others"
    );
    let steal = &app.norms().await[1];
    assert_eq!(steal["action"], "steal");
    let created = app
        .add_norm(&json!({"kind": "forbidden_action", "action": "get"}))
        .await;
    assert_eq!(created, kept + 2);
}

/// Smaller finding: a "Hospital" norm did not apply to a "hospital" request, which was then
/// complied with. Contexts and roles are matched normalised, however they were sent or stored.
#[tokio::test]
async fn contexts_and_roles_match_whatever_their_case_and_spacing() {
    let app = spawn_app().await;
    let norm = app
        .add_norm(
            &json!({"kind": "forbidden_action", "action": "get", "context": " Hospital Ward ", "roles": ["Visitor"]}),
        )
        .await;
    let stored: Value = app.get(&format!("/v1/norms/{norm}")).await.json().await.unwrap();
    assert_eq!(stored["context"], "hospital_ward");
    assert_eq!(stored["roles"], json!(["visitor"]));
    let request = |context: &str, role: &str| {
        json!({
            "directive": {"action": "get", "arguments": [{"type": "mug"}]},
            "scene": lab_scene(),
            "context": context,
            "speaker_roles": [role],
        })
    };
    for (context, role) in [
        ("hospital_ward", "visitor"),
        ("HOSPITAL   ward", "VISITOR"),
        ("hospital_ward", " visitor"),
    ] {
        assert_eq!(
            app.clarify(&request(context, role)).await["decision"],
            "refuse",
            "{context} / {role}"
        );
    }
    assert_eq!(app.clarify(&request("hospital", "visitor")).await["decision"], "comply");

    // Stored under the old rules, as written then: read normalised, so still in force.
    sql(&app, "UPDATE norms SET context = 'Hospital Ward', roles_json = '[\"Visitor\"]'; UPDATE norm_set SET version = version + 1;").await;
    assert_eq!(
        app.clarify(&request("hospital_ward", "visitor")).await["decision"],
        "refuse"
    );
    assert_eq!(app.norms().await[0]["context"], "hospital_ward");
}

/// Finding: a norm's `context` kept invisible characters ("ward" + U+200B was stored and then
/// applied to no request anyone could type), while roles refused them. Contexts and roles now
/// follow one rule, wherever they come from: a norm, an import, a request, a check, gRPC; the
/// refusal is a 422 naming the field, and nothing is stored.
#[tokio::test]
async fn a_context_with_invisible_or_control_characters_is_refused_as_a_role_is() {
    use scruple::transport::grpc::pb::clarifier_client::ClarifierClient;
    use scruple::transport::grpc::pb::norms_client::NormsClient;

    let app = spawn_app().await;
    let channel = crate::grpc::channel(&app).await;
    let (mut norms, mut clarifier) = (NormsClient::new(channel.clone()), ClarifierClient::new(channel));
    for context in [
        "ward\u{200b}",
        "\u{202e}ward",
        "wa\u{0}rd",
        "ward\u{feff}",
        "ward\u{1b}[0m",
    ] {
        let norm = json!({"kind": "forbidden_action", "action": "get", "context": context});
        assert_problem(
            app.post("/v1/norms", &norm).await,
            StatusCode::UNPROCESSABLE_ENTITY,
            Some("/context"),
        )
        .await;
        let status = norms.create_norm(crate::grpc::norm_request(&norm)).await.unwrap_err();
        assert_eq!(status.code(), tonic::Code::InvalidArgument, "{context:?}");
        assert_eq!(status.metadata().get("field").unwrap(), "/context");
        assert_problem(
            put_json(&app, "/v1/norm-set", &json!({"norms": [norm]})).await,
            StatusCode::UNPROCESSABLE_ENTITY,
            Some("/norms/0/context"),
        )
        .await;
        let request = json!({
            "directive": {"action": "get", "arguments": [{"type": "mug"}]},
            "scene": lab_scene(),
            "context": context,
        });
        assert_problem(
            app.post("/v1/clarify", &request).await,
            StatusCode::UNPROCESSABLE_ENTITY,
            Some("/context"),
        )
        .await;
        let status = clarifier
            .clarify(crate::grpc::clarify_request(&request))
            .await
            .unwrap_err();
        assert_eq!(status.code(), tonic::Code::InvalidArgument, "{context:?}");
        assert_eq!(status.metadata().get("field").unwrap(), "/context");
        let check = json!({"scene": lab_scene(), "steps": ["get(object5)"], "context": context});
        assert_problem(
            app.post("/v1/check", &check).await,
            StatusCode::UNPROCESSABLE_ENTITY,
            Some("/context"),
        )
        .await;
    }
    assert!(app.norms().await.is_empty(), "nothing was stored");

    // A context stored before the rule (by hand, or by an older build) applies nowhere: it
    // fails closed, naming the norm and the field, rather than being silently passed over.
    app.add_norm(&json!({"kind": "forbidden_action", "action": "get", "context": "ward"}))
        .await;
    sql(
        &app,
        "UPDATE norms SET context = 'ward' || char(8203); UPDATE norm_set SET version = version + 1;",
    )
    .await;
    crate::helpers::after_the_lease().await;
    let request = json!({
        "directive": {"action": "get", "arguments": [{"type": "mug"}]},
        "scene": lab_scene(),
        "context": "ward",
    });
    let problem = assert_problem(
        app.post("/v1/clarify", &request).await,
        StatusCode::SERVICE_UNAVAILABLE,
        None,
    )
    .await;
    let detail = problem["detail"].as_str().unwrap_or_default();
    assert!(detail.contains("norm 1") && detail.contains("/context"), "{detail}");
}

fn cups(colours: &[&str]) -> Value {
    let objects: Vec<Value> = colours
        .iter()
        .enumerate()
        .map(|(i, colour)| {
            json!({"id": format!("c{}", i + 1), "type": "cup", "attributes": {"color": colour},
                   "position": [0.4, 0.1 * i as f64, 0.8]})
        })
        .collect();
    json!({"agent": {"position": [0, 0, 0.75], "reach": 0.9}, "objects": objects})
}

fn put_cup_on_cup(scene: Value) -> Value {
    json!({"directive": {"action": "put", "arguments": [{"type": "cup"}, {"type": "cup"}]}, "scene": scene})
}

/// Finding 7: "Put the cup on the cup" with one cup was obeyed (`put(c1,c1)`).
#[tokio::test]
async fn an_object_is_never_put_on_itself() {
    let app = spawn_app().await;
    let one = app.clarify(&put_cup_on_cup(cups(&["red"]))).await;
    assert_eq!(one["decision"], "refuse");
    assert_eq!(one["goal"], Value::Null);
    assert_eq!(
        one["utterance"],
        "I cannot put the cup on the cup because the cup cannot be put on itself."
    );
    assert_eq!(one["interpretations"][0]["reasons"][0]["kind"], "same_object");
    assert_eq!(one["interpretations"][0]["reasons"][0]["detail"], "c1");

    let two = app.clarify(&put_cup_on_cup(cups(&["red", "blue"]))).await;
    assert_eq!(two["decision"], "ask");
    assert_eq!(two["offered"], json!(["did(self,put(c2,c1))", "did(self,put(c1,c2))"]));
    assert_eq!(
        two["utterance"],
        "Do you mean that you want me to put the blue cup on the red cup or that you want me to put the red cup on the blue cup?"
    );

    let check = app
        .post("/v1/check", &json!({"scene": cups(&["red"]), "steps": ["put(c1,c1)"]}))
        .await;
    let check: Value = check.json().await.unwrap();
    assert_eq!(check["permitted"], false);
    assert_eq!(check["steps"][0]["reasons"][0]["kind"], "same_object");

    // `distinct` is the verb's to declare, over the API; it needs two parameters.
    let put: Value = app.get("/v1/actions/put").await.json().await.unwrap();
    assert_eq!(put["distinct"], true);
    let stack = json!({"parameters": ["X", "Y"], "joiner": "on", "distinct": true, "methods": [{"reach": ["X", "Y"]}]});
    assert_eq!(
        put_json(&app, "/v1/actions/stack", &stack).await.status(),
        StatusCode::CREATED
    );
    let mut request = put_cup_on_cup(cups(&["red"]));
    request["directive"]["action"] = json!("stack");
    let stacked = app.clarify(&request).await;
    assert_eq!(
        stacked["utterance"],
        "I cannot stack the cup on the cup because the cup cannot be stacked on itself."
    );
    let lone = json!({"parameters": ["X"], "distinct": true, "methods": [{}]});
    assert_problem(
        put_json(&app, "/v1/actions/lone", &lone).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/distinct"),
    )
    .await;
}

/// Finding 11: verbs of 65 to 128 bytes could be used in a clarify but never defined (PUT
/// answered 404). One bound, 64 bytes, everywhere a verb is named.
#[tokio::test]
async fn a_verb_name_is_at_most_64_bytes_wherever_it_is_named() {
    let app = spawn_app().await;
    let longest = "v".repeat(64);
    let over = "v".repeat(65);
    let verb = json!({"parameters": ["X"], "methods": [{}]});
    assert_eq!(
        put_json(&app, &format!("/v1/actions/{longest}"), &verb).await.status(),
        StatusCode::CREATED
    );
    let problem = assert_problem(
        put_json(&app, &format!("/v1/actions/{over}"), &verb).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/name"),
    )
    .await;
    assert!(problem["detail"].as_str().unwrap().contains("64 bytes"), "{problem}");
    let scene = lab_scene();
    let cases = [
        (
            json!({"directive": {"action": over, "arguments": [{"type": "mug"}]}, "scene": scene}),
            "/directive/action",
        ),
        (
            json!({"directive": {"form": format!("did(self,{over}(X))"), "bindings": {"X": ["object5"]}}, "scene": scene}),
            "/directive/form",
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
    let check = json!({"scene": scene, "steps": ["get(object5)", format!("{over}(object5)")]});
    assert_problem(
        app.post("/v1/check", &check).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/steps/1"),
    )
    .await;
    let used = json!({"directive": {"action": longest, "arguments": [{"type": "mug"}]}, "scene": scene});
    assert_eq!(app.clarify(&used).await["decision"], "comply");
}

/// Finding 12: with five cups and `max_readings: 4`, the answer "c2" was ignored and the robot
/// asked again. The answer narrows the readings before the limit applies.
#[tokio::test]
async fn a_follow_up_narrows_the_readings_before_max_readings_applies() {
    let app = spawn_app().await;
    let scene = cups(&["red", "blue", "green", "white", "black"]);
    let mut request = json!({
        "directive": {"action": "get", "arguments": [{"type": "cup"}]},
        "scene": scene,
        "options": {"max_readings": 4},
    });
    let asked = app.clarify(&request).await;
    assert_eq!(asked["limits"]["reason"], "too_many_readings");
    request["answer"] = json!({"id": "c2"});
    let answered = app.clarify(&request).await;
    assert_eq!(answered["decision"], "comply");
    assert_eq!(answered["goal"], "did(self,get(c2))");
    assert_eq!(answered["limits"], Value::Null);
    // Putting a cup on a cup: "the blue one" keeps the 9 readings that involve c2 (5 + 5 − 1,
    // c2 on itself among them, which is infeasible): within 9, but not within 4.
    let mut put = put_cup_on_cup(scene.clone());
    put["options"] = json!({"max_readings": 9});
    put["answer"] = json!({"reference": {"attributes": {"color": "blue"}}});
    let narrowed = app.clarify(&put).await;
    assert_eq!(narrowed["limits"], Value::Null, "{narrowed}");
    assert_eq!(narrowed["interpretations"].as_array().unwrap().len(), 9);
    assert_eq!(narrowed["decision"], "ask");
    put["options"] = json!({"max_readings": 4});
    assert_eq!(app.clarify(&put).await["limits"]["reason"], "too_many_readings");
}

/// Wording: "`self` or `self`" when the agent is `self`.
#[tokio::test]
async fn a_form_for_another_agent_names_the_agent_once() {
    let app = spawn_app().await;
    let body =
        json!({"directive": {"form": "did(pepper,get(X))", "bindings": {"X": ["object5"]}}, "scene": lab_scene()});
    let problem = assert_problem(
        app.post("/v1/clarify", &body).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/directive/form"),
    )
    .await;
    assert_eq!(problem["detail"], "did(A,...) must name the agent: `self`");
}

/// Wording: inputs that produced empty or repeated words ("I cannot  because _ is forbidden
/// action.", "which cup and which cup") get sentences or clear errors.
#[tokio::test]
async fn no_answer_speaks_empty_or_repeated_words() {
    let app = spawn_app().await;
    let norm = json!({"kind": "forbidden_action", "action": "_"});
    assert_problem(
        app.post("/v1/norms", &norm).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/action"),
    )
    .await;
    let verb = json!({"parameters": ["X"], "methods": [{}]});
    assert_problem(
        put_json(&app, "/v1/actions/_", &verb).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/name"),
    )
    .await;
    let mut blank = json!({"directive": {"action": "get", "arguments": [{"type": "_"}]}, "scene": lab_scene()});
    assert_problem(
        app.post("/v1/clarify", &blank).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/directive/arguments/0/type"),
    )
    .await;
    blank["scene"]["objects"][0]["type"] = json!("__");
    blank["directive"]["arguments"][0]["type"] = json!("vase");
    assert_problem(
        app.post("/v1/clarify", &blank).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/scene/objects/0/type"),
    )
    .await;

    let mut put = put_cup_on_cup(cups(&["red", "blue", "green"]));
    put["options"] = json!({"max_readings": 4});
    let asked = app.clarify(&put).await;
    assert_eq!(
        asked["utterance"],
        "I do not know which cup and which other cup you mean."
    );
    put["options"]["style"] = json!("natural");
    assert_eq!(
        app.clarify(&put).await["utterance"],
        "Which cup and which other cup do you mean?"
    );
}

/// A library that costs as much as the expansion bound allows per reading: `a2` tries 8 methods
/// of 4 `a1` steps, each of 8 methods of 4 `a0` steps, and `a0` never can be done, so every
/// method is tried. `pair(X,Y)` does `a2` on each of two objects.
async fn store_costly_library(app: &TestApp) {
    let a0 = json!({"parameters": ["X"], "methods": [{"preconditions": ["never(X)"]}]});
    assert_eq!(put_json(app, "/v1/actions/a0", &a0).await.status(), StatusCode::CREATED);
    let over = |callee: &str| {
        let method = json!({"steps": [format!("{callee}(X)"), format!("{callee}(X)"), format!("{callee}(X)"), format!("{callee}(X)")]});
        json!({"parameters": ["X"], "methods": vec![method; 8]})
    };
    assert_eq!(
        put_json(app, "/v1/actions/a1", &over("a0")).await.status(),
        StatusCode::CREATED
    );
    assert_eq!(
        put_json(app, "/v1/actions/a2", &over("a1")).await.status(),
        StatusCode::CREATED
    );
    let pair = json!({"parameters": ["X", "Y"], "methods": [{"steps": ["a2(X)", "a2(Y)"]}]});
    assert_eq!(
        put_json(app, "/v1/actions/pair", &pair).await.status(),
        StatusCode::CREATED
    );
}

/// `pair` over every two of 60 cups, with [`store_costly_library`]: 3,600 readings of 2,577
/// steps each, far more work than any deadline here allows.
fn costly_pairs(deadline_ms: u64) -> Value {
    json!({
        "directive": {"action": "pair", "arguments": [{"type": "cup"}, {"type": "cup"}]},
        "scene": many_cups(60),
        "options": {"deadline_ms": deadline_ms},
    })
}

/// The `scruple_simulations_in_flight` line of a scrape of `/metrics` (empty if there is none).
async fn in_flight_line(app: &TestApp) -> String {
    let metrics = app.get("/metrics").await.text().await.unwrap();
    (metrics.lines())
        .find(|l| l.starts_with("scruple_simulations_in_flight "))
        .unwrap_or_default()
        .to_owned()
}

fn many_cups(n: usize) -> Value {
    let colours: Vec<String> = (0..n).map(|i| format!("c{i}")).collect();
    let refs: Vec<&str> = colours.iter().map(String::as_str).collect();
    cups(&refs)
}

/// Finding 3: a verb whose plan explodes ignored the deadline (26-32 s for `deadline_ms: 100`,
/// a 192 MB body); `/v1/check` had no deadline at all. A verb may expand to at most 10,000
/// steps (checked when it is stored), and both calls stop at their deadline with `limits`.
#[tokio::test]
async fn expansion_is_bounded_when_stored_and_stops_at_the_deadline() {
    // The service's own default deadline is longer than the client waits (20 s), so only the
    // deadlines the requests carry can answer them in time.
    let app = crate::helpers::spawn_tweaked(|c| c.limits.default_deadline_ms = 30_000).await;
    store_costly_library(&app).await;
    let method = json!({"steps": ["a2(X)", "a2(X)", "a2(X)", "a2(X)"]});
    let a3 = json!({"parameters": ["X"], "methods": vec![method; 8]});
    let problem = assert_problem(
        put_json(&app, "/v1/actions/a3", &a3).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/methods/0"),
    )
    .await;
    assert!(
        problem["detail"].as_str().unwrap().contains("at most 10000"),
        "{problem}"
    );
    assert_eq!(
        app.get("/v1/actions/a3").await.status(),
        StatusCode::NOT_FOUND,
        "nothing was stored"
    );

    // 3,600 readings of 2,577 steps each: far more than 300 ms of work.
    let request = costly_pairs(300);
    let client = reqwest::Client::builder()
        .timeout(std::time::Duration::from_secs(20))
        .build()
        .unwrap();
    let answer: Value = client
        .post(app.url("/v1/clarify"))
        .json(&request)
        .send()
        .await
        .expect("answered well before 20 s")
        .json()
        .await
        .unwrap();
    assert_eq!(answer["limits"]["reason"], "deadline", "{}", answer["limits"]);
    assert_eq!(answer["goal"], Value::Null);
    assert!(answer["limits"]["simulated"].as_u64().unwrap() < 3600);

    // One reading cut short mid-plan: refused, saying why, never obeyed.
    let one = json!({
        "directive": {"action": "pair", "arguments": [{"id": "c1"}, {"id": "c2"}]},
        "scene": many_cups(2),
        "options": {"deadline_ms": 1},
    });
    let refused = app.clarify(&one).await;
    if refused["limits"] != Value::Null {
        assert_eq!(refused["decision"], "refuse");
        assert!(
            refused["utterance"]
                .as_str()
                .unwrap()
                .ends_with("because I could not finish checking it in time."),
            "{refused}"
        );
        assert_eq!(
            refused["interpretations"][0]["reasons"]
                .as_array()
                .unwrap()
                .last()
                .unwrap()["kind"],
            "unfinished"
        );
    }

    let steps: Vec<String> = (0..1000)
        .map(|i| format!("pair(c{},c{})", i % 60 + 1, (i + 1) % 60 + 1))
        .collect();
    let check = json!({"scene": many_cups(60), "steps": steps, "options": {"deadline_ms": 300}});
    let checked: Value = client
        .post(app.url("/v1/check"))
        .json(&check)
        .send()
        .await
        .expect("answered")
        .json()
        .await
        .unwrap();
    assert_eq!(checked["permitted"], false);
    assert_eq!(checked["limits"]["reason"], "deadline", "{}", checked["limits"]);
    assert_eq!(checked["limits"]["readings"], 1000);
    assert!(checked["limits"]["simulated"].as_u64().unwrap() < 1000);
}

/// Finding 4: two costly requests whose clients left after a second kept both cores busy for a
/// minute, and `/healthz` took 31.8 s meanwhile. A client that goes away cancels its decision.
#[tokio::test]
async fn a_client_that_leaves_cancels_its_decision_and_health_answers_meanwhile() {
    let app = spawn_app().await;
    store_costly_library(&app).await;
    let request = costly_pairs(60000);
    let impatient = reqwest::Client::builder()
        .timeout(std::time::Duration::from_millis(500))
        .build()
        .unwrap();
    let left: Vec<_> = (0..4)
        .map(|_| {
            let (client, url, body) = (impatient.clone(), app.url("/v1/clarify"), request.clone());
            tokio::spawn(async move { client.post(url).json(&body).send().await })
        })
        .collect();
    let started = std::time::Instant::now();
    let mut gave_up = 0;
    for handle in left {
        match handle.await.unwrap() {
            Err(_) => gave_up += 1,
            // Past one costly simulation per core, the rest are refused at once.
            Ok(response) => assert_eq!(response.status(), StatusCode::SERVICE_UNAVAILABLE),
        }
    }
    assert!(gave_up >= 1, "some client gave up before an answer");
    // The abandoned simulations stop (they would have run to their 60 s deadline).
    let mut in_flight = String::new();
    for _ in 0..100 {
        in_flight = in_flight_line(&app).await;
        if in_flight == "scruple_simulations_in_flight 0" {
            break;
        }
        tokio::time::sleep(std::time::Duration::from_millis(50)).await;
    }
    assert_eq!(
        in_flight, "scruple_simulations_in_flight 0",
        "abandoned work still runs"
    );
    // Health answers, and a decision gets a turn again.
    let health = app
        .client
        .get(app.url("/healthz"))
        .timeout(std::time::Duration::from_secs(5))
        .send()
        .await;
    assert_eq!(health.expect("health answers under load").status(), StatusCode::OK);
    let small = json!({"directive": {"action": "get", "arguments": [{"id": "c1"}]}, "scene": many_cups(2)});
    let answer = app
        .client
        .post(app.url("/v1/clarify"))
        .json(&small)
        .timeout(std::time::Duration::from_secs(10))
        .send()
        .await;
    assert_eq!(answer.expect("a small decision is made").status(), StatusCode::OK);
    assert!(
        started.elapsed() < std::time::Duration::from_secs(30),
        "the abandoned work did not run to its 60 s deadline"
    );
}

/// Admission by cost: a flood of heavy requests (9.3 million simulated steps each) takes fewer
/// turns than there are cores, so a request of middling cost (about 1,300 steps) is still
/// decided while they run, instead of being refused as overload behind them.
#[tokio::test]
async fn heavy_requests_leave_a_core_to_a_request_of_middling_cost() {
    let cores = std::thread::available_parallelism().map_or(2, usize::from);
    if cores < 2 {
        eprintln!("one core: nothing to leave free; skipped");
        return;
    }
    let app = spawn_app().await;
    store_costly_library(&app).await;
    let heavy = costly_pairs(4000);
    // One more heavy request than there are cores: without the heavy lane they would hold
    // every turn.
    let flood: Vec<_> = (0..=cores)
        .map(|_| {
            let (client, url, body) = (app.client.clone(), app.url("/v1/clarify"), heavy.clone());
            tokio::spawn(async move { client.post(url).json(&body).send().await.unwrap().status() })
        })
        .collect();
    let mut running = false;
    for _ in 0..200 {
        running = (in_flight_line(&app).await)
            .strip_prefix("scruple_simulations_in_flight ")
            .is_some_and(|n| n.trim() != "0");
        if running {
            break;
        }
        tokio::time::sleep(std::time::Duration::from_millis(10)).await;
    }
    assert!(running, "the heavy requests never started");
    let middling = json!({
        "directive": {"action": "a2", "arguments": [{"id": "c1"}]},
        "scene": many_cups(2),
    });
    let response = app
        .client
        .post(app.url("/v1/clarify"))
        .json(&middling)
        .send()
        .await
        .unwrap();
    assert_eq!(response.status(), StatusCode::OK, "{}", response.text().await.unwrap());
    let statuses: Vec<StatusCode> = joined(flood).await;
    assert!(
        statuses.contains(&StatusCode::OK),
        "a heavy request was decided: {statuses:?}"
    );
    assert!(
        statuses.contains(&StatusCode::SERVICE_UNAVAILABLE),
        "past the heavy turns, the rest were refused at once: {statuses:?}"
    );
}

async fn joined(handles: Vec<tokio::task::JoinHandle<StatusCode>>) -> Vec<StatusCode> {
    let mut statuses = Vec::new();
    for handle in handles {
        statuses.push(handle.await.unwrap());
    }
    statuses
}

/// Finding 10: well-formed JSON of the wrong shape was called malformed (400, no field), a
/// repeated key pointed at the whole document, a bad audit query was "malformed JSON".
#[tokio::test]
async fn well_formed_json_of_the_wrong_shape_is_a_422_naming_the_member() {
    let app = spawn_app().await;
    let with = |edit: &dyn Fn(&mut Value)| {
        let mut body = json!({"directive": {"action": "get", "arguments": [{"type": "cup"}]}, "scene": cups(&["red"])});
        edit(&mut body);
        body
    };
    let cases: Vec<(Value, &str)> = vec![
        (
            with(&|b| b["scene"]["objects"][0]["position"] = json!([0.4, 0.1, 0.8, 1.0])),
            "/scene/objects/0/position",
        ),
        (
            with(&|b| b["scene"]["agent"]["position"] = json!([0, 0])),
            "/scene/agent/position",
        ),
        (
            with(&|b| b["scene"]["objects"][0]["shape"] = json!({})),
            "/scene/objects/0/shape",
        ),
        (
            with(&|b| {
                b["scene"]["objects"][0]["shape"] =
                    json!({"ball": {"radius": 0.1}, "cylinder": {"radius": 0.1, "half_height": 0.1}})
            }),
            "/scene/objects/0/shape",
        ),
        (
            with(&|b| b["scene"]["objects"][0]["rotation"] = json!([0, 0, 0, 1, 0])),
            "/scene/objects/0/rotation",
        ),
        (
            with(&|b| b["scene"]["objects"][0]["shape"] = json!({"cuboid": {"half_extents": [0.1, 0.1, 0.1, 0.1]}})),
            "/scene/objects/0/shape/cuboid/half_extents",
        ),
    ];
    for (body, field) in cases {
        let problem = assert_problem(
            app.post("/v1/clarify", &body).await,
            StatusCode::UNPROCESSABLE_ENTITY,
            Some(field),
        )
        .await;
        assert!(
            !problem["detail"].as_str().unwrap().contains("trailing characters"),
            "{problem}"
        );
    }
    let twice = r#"{"directive": {"action": "get", "arguments": [{"type": "cup"}]}, "directive": {"action": "get", "arguments": []}, "scene": {"agent": {"position": [0,0,0], "reach": 1}}}"#;
    let response = app
        .client
        .post(app.url("/v1/clarify"))
        .header("content-type", "application/json")
        .body(twice)
        .send()
        .await
        .unwrap();
    assert_problem(response, StatusCode::UNPROCESSABLE_ENTITY, Some("/directive")).await;
    for (query, field) in [
        ("after=abc", "/after"),
        ("limit=ten", "/limit"),
        ("after=1&limit=0", "/limit"),
    ] {
        assert_problem(
            app.get(&format!("/v1/audit?{query}")).await,
            StatusCode::UNPROCESSABLE_ENTITY,
            Some(field),
        )
        .await;
    }
    // Text that is not JSON stays a 400.
    let response = app
        .client
        .post(app.url("/v1/clarify"))
        .header("content-type", "application/json")
        .body("{} trailing")
        .send()
        .await
        .unwrap();
    assert_problem(response, StatusCode::BAD_REQUEST, None).await;
}

/// Finding 8: a malformed protobuf, a missing message or a bad compression flag answered
/// INTERNAL, an oversized message OUT_OF_RANGE.
#[tokio::test]
async fn grpc_requests_that_cannot_be_decoded_are_the_callers_fault() {
    let dir = tempfile::tempdir().unwrap();
    let served = crate::helpers::serve_binary(
        &format!("sqlite://{}", dir.path().join("grpc.db").display()),
        &["--max-body-bytes", "1024"],
        &[],
        std::process::Stdio::null(),
    );
    let url = format!("http://{}/scruple.v1.Clarifier/Clarify", served.addr);
    crate::support::install_ring();
    let h2 = reqwest::Client::builder().http2_prior_knowledge().build().unwrap();
    let frame = |flag: u8, len: u32, body: &[u8]| {
        let mut bytes = vec![flag];
        bytes.extend_from_slice(&len.to_be_bytes());
        bytes.extend_from_slice(body);
        bytes
    };
    let cases: Vec<(Vec<u8>, &str)> = vec![
        (frame(0, 3, &[0xff, 0xff, 0xff]), "3"),
        (Vec::new(), "3"),
        (frame(2, 0, &[]), "3"),
        (frame(0, 4096, &[0; 16]), "8"),
    ];
    for (body, code) in cases {
        let response = h2
            .post(&url)
            .header("content-type", "application/grpc")
            .header("te", "trailers")
            .body(body.clone())
            .send()
            .await
            .unwrap();
        let status = response
            .headers()
            .get("grpc-status")
            .map(|v| v.to_str().unwrap().to_owned());
        assert_eq!(status.as_deref(), Some(code), "{body:?}: {:?}", response.headers());
    }
    let status = tokio::task::spawn_blocking(move || served.terminate()).await.unwrap();
    assert_eq!(status.code(), Some(0));
}

/// Finding 14: with the norms table dropped, `/healthz` said 200 while clarify and writes said
/// 503. Readiness is the outcome of the last read of what a decision needs, on both transports.
#[tokio::test]
async fn health_says_what_a_decision_would_find() {
    use tonic_health::pb::health_check_response::ServingStatus;
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_action", "action": "destroy"}))
        .await;
    assert_eq!(app.get("/healthz").await.status(), StatusCode::OK);
    let channel = tonic::transport::Channel::from_shared(app.base.clone())
        .unwrap()
        .connect()
        .await
        .unwrap();
    let mut grpc = tonic_health::pb::health_client::HealthClient::new(channel);
    let grpc_status = |service: &str| tonic_health::pb::HealthCheckRequest {
        service: service.to_owned(),
    };
    sql(&app, "DROP TABLE norms; UPDATE norm_set SET version = version + 1;").await;
    // No request comes: the probe finds it within a second or so.
    for _ in 0..60 {
        if app.get("/healthz").await.status() != StatusCode::OK {
            break;
        }
        tokio::time::sleep(std::time::Duration::from_millis(50)).await;
    }
    let problem = assert_problem(app.get("/healthz").await, StatusCode::SERVICE_UNAVAILABLE, None).await;
    assert_eq!(problem["type"], "/problems/norms-unavailable");
    for service in ["", "scruple.v1.Clarifier"] {
        let answer = grpc.check(grpc_status(service)).await.unwrap().into_inner();
        assert_eq!(answer.status(), ServingStatus::NotServing, "{service:?}");
    }
    let destroy = json!({"directive": {"action": "destroy", "arguments": [{"id": "object3"}]}, "scene": lab_scene()});
    assert_problem(
        app.post("/v1/clarify", &destroy).await,
        StatusCode::SERVICE_UNAVAILABLE,
        None,
    )
    .await;
}

/// Finding: `/v1/audit?actor=alice` answered every entry, as if filtered by nobody: a member
/// the endpoint does not take was silently ignored. Each unknown or repeated member is a 422
/// naming it; the members it takes still work, percent-encoded or not.
#[tokio::test]
async fn an_audit_query_member_the_endpoint_does_not_take_is_a_422_naming_it() {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_action", "action": "destroy"}))
        .await;
    for (query, field) in [
        ("actor=alice", "/actor"),
        ("after=0&actor=alice", "/actor"),
        ("subject=norm&limit=5", "/subject"),
        ("after=0&after=1", "/after"),
        ("limit=5&limit=5", "/limit"),
        ("after", "/after"),
    ] {
        let problem = assert_problem(
            app.get(&format!("/v1/audit?{query}")).await,
            StatusCode::UNPROCESSABLE_ENTITY,
            Some(field),
        )
        .await;
        assert!(
            problem["detail"].as_str().unwrap_or_default().contains('`'),
            "{query}: the detail names it: {problem}"
        );
    }
    for query in ["", "after=0", "after=0&limit=5", "%61fter=0&limit=%35", "after=0&"] {
        let response = app.get(&format!("/v1/audit?{query}")).await;
        assert_eq!(response.status(), StatusCode::OK, "{query}");
        let page: Value = response.json().await.unwrap();
        assert_eq!(page["entries"].as_array().map(Vec::len), Some(1), "{query}");
    }
}
