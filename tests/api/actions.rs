//! The action library over the API: seeded defaults, verbs added and replaced as data, several
//! methods per verb, validation, the admin token, and failing closed on a broken library.

use reqwest::StatusCode;
use scruple::engine::Library;
use scruple::transport::grpc::pb;
use serde_json::{Value, json};

use crate::helpers::{Options, TestApp, assert_problem, lab_scene, raw_sql_on, spawn_app, spawn_on, spawn_with};

async fn put(app: &TestApp, name: &str, verb: &Value) -> reqwest::Response {
    app.client
        .put(app.url(&format!("/v1/actions/{name}")))
        .json(verb)
        .send()
        .await
        .unwrap()
}

fn request(action: &str, types: &[&str], scene: Value) -> Value {
    let arguments: Vec<Value> = types.iter().map(|t| json!({"type": t})).collect();
    json!({"directive": {"action": action, "arguments": arguments}, "scene": scene})
}

fn boxes(facts: &[&str]) -> Value {
    json!({"agent": {"position": [0, 0, 0.75], "reach": 0.9},
           "objects": [{"id": "box1", "type": "box", "position": [0.5, 0, 0.8]}],
           "facts": facts})
}

#[tokio::test]
async fn a_fresh_store_holds_the_contracts_default_library() {
    let app = spawn_app().await;
    let listed: Vec<Value> = app.get("/v1/actions").await.json().await.unwrap();
    let expected: Vec<Value> = Library::default_library()
        .verbs()
        .into_iter()
        .map(|def| serde_json::to_value(def.to_input()).unwrap())
        .collect();
    assert_eq!(listed, expected, "the migration seeds exactly the built-in library");
    let put_verb: Value = app.get("/v1/actions/put").await.json().await.unwrap();
    assert_eq!(
        put_verb,
        json!({"name": "put", "parameters": ["X", "Y"], "joiner": "on", "distinct": true, "methods": [{"steps": ["get(X)", "itself"],
               "reach": ["X", "Y"], "place": ["X", "Y"], "adds": ["on(X,Y)"], "removes": ["holding(self,X)"]}],
               "words": ["put", "place", "set", "position"], "joiners": ["on", "onto", "in", "into", "upon", "inside"]})
    );
    let get_verb: Value = app.get("/v1/actions/get").await.json().await.unwrap();
    assert_eq!(get_verb["words"], json!(["get", "grab", "take", "pick up", "fetch"]));
    let give_verb: Value = app.get("/v1/actions/give").await.json().await.unwrap();
    assert_eq!(give_verb["words"], json!(["give", "hand", "pass", "bring"]));
    let heat_verb: Value = app.get("/v1/actions/heat").await.json().await.unwrap();
    assert_eq!(heat_verb["implied"], json!({"Y": ["heater(Y)"]}));
    assert_problem(app.get("/v1/actions/juggle").await, StatusCode::NOT_FOUND, None).await;
}

/// A fresh PostgreSQL store is seeded with the same verbs as a fresh SQLite one (their own
/// migrations seed and amend them): the same answer byte for byte, and the same stored
/// definitions, member for member.
#[tokio::test]
async fn a_fresh_postgresql_store_holds_the_same_default_library_as_sqlite() {
    let sqlite = spawn_app().await;
    let database = crate::backends::PgDatabase::create().await;
    let url = database.url.clone();
    let postgres = crate::helpers::spawn_tweaked(move |c| c.database_url = url).await;
    let answers = [
        sqlite.get("/v1/actions").await.text().await.unwrap(),
        postgres.get("/v1/actions").await.text().await.unwrap(),
    ];
    assert_eq!(answers[0], answers[1], "GET /v1/actions, SQLite then PostgreSQL");
    let listed: Vec<Value> = serde_json::from_str(&answers[0]).unwrap();
    assert_eq!(listed.len(), Library::default_library().verbs().len());

    // The stored rows, parsed: PostgreSQL's JSON functions reorder and space the text.
    let stored_sqlite: Vec<(String, String)> = {
        use sqlx::{ConnectOptions, Connection};
        let mut connection = sqlx::sqlite::SqliteConnectOptions::new()
            .filename(&sqlite.db_path)
            .connect()
            .await
            .unwrap();
        let rows = sqlx::query_as("SELECT name, definition FROM actions")
            .fetch_all(&mut connection)
            .await
            .unwrap();
        connection.close().await.unwrap();
        rows
    };
    let stored_postgres: Vec<(String, String)> = {
        use sqlx::Connection;
        let mut connection = sqlx::PgConnection::connect(&database.url).await.unwrap();
        let rows = sqlx::query_as("SELECT name, definition FROM actions")
            .fetch_all(&mut connection)
            .await
            .unwrap();
        connection.close().await.unwrap();
        rows
    };
    // Sorted here: the two databases' collations may order names differently.
    let parsed = |rows: Vec<(String, String)>| -> Vec<(String, Value)> {
        let mut parsed: Vec<(String, Value)> = rows
            .into_iter()
            .map(|(name, text)| (name, serde_json::from_str(&text).unwrap()))
            .collect();
        parsed.sort_by(|a, b| a.0.cmp(&b.0));
        parsed
    };
    assert_eq!(parsed(stored_sqlite), parsed(stored_postgres));
    sqlite.stop().await;
    postgres.stop().await;
}

#[tokio::test]
async fn a_word_names_one_verb_only_and_a_clash_writes_nothing() {
    let app = spawn_app().await;
    let clutch = json!({"parameters": ["X"], "methods": [{"reach": ["X"]}], "words": ["seize", "Grab"]});
    let problem = assert_problem(
        put(&app, "clutch", &clutch).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/words/1"),
    )
    .await;
    let detail = problem["detail"].as_str().unwrap();
    assert!(detail.contains("`grab`") && detail.contains("`get`"), "{detail}");
    assert_problem(app.get("/v1/actions/clutch").await, StatusCode::NOT_FOUND, None).await;
    // Its own words, normalised, are kept; giving `get` new words frees the old ones.
    let clutch = json!({"parameters": ["X"], "methods": [{"reach": ["X"]}], "words": ["Seize", "clutch  at"]});
    assert_eq!(put(&app, "clutch", &clutch).await.status(), StatusCode::CREATED);
    let stored: Value = app.get("/v1/actions/clutch").await.json().await.unwrap();
    assert_eq!(stored["words"], json!(["seize", "clutch at"]));
    let lone = json!({"parameters": ["X"], "methods": [{}], "joiners": ["on"]});
    assert_problem(
        put(&app, "wave", &lone).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/joiners"),
    )
    .await;
}

#[tokio::test]
async fn verb_words_round_trip_over_grpc() {
    let app = spawn_app().await;
    let channel = tonic::transport::Channel::from_shared(app.base.clone())
        .unwrap()
        .connect()
        .await
        .unwrap();
    let mut client = pb::actions_client::ActionsClient::new(channel);
    let listed = client
        .list_actions(pb::ListActionsRequest {})
        .await
        .unwrap()
        .into_inner();
    let put_verb = listed
        .actions
        .iter()
        .find(|a| a.name.as_deref() == Some("put"))
        .unwrap();
    assert_eq!(put_verb.joiners, ["on", "onto", "in", "into", "upon", "inside"]);
    assert_eq!(put_verb.words, ["put", "place", "set", "position"]);
}

#[tokio::test]
async fn an_older_store_gains_the_default_words_and_a_curators_words_are_kept() {
    let app = spawn_app().await;
    let dir = app.dir.clone();
    let get_words = json!({"parameters": ["X"], "methods": [{"reach": ["X"], "grasp": ["X"], "adds": ["holding(self,X)"]}], "words": ["obtain"]});
    assert_eq!(put(&app, "get", &get_words).await.status(), StatusCode::OK);
    app.stop().await;
    // As an older build left it: the seeded verbs without words, and the migration not applied.
    let db_path = dir.path().join("scruple.db");
    raw_sql_on(
        &db_path,
        "UPDATE actions SET definition = json_remove(definition, '$.words', '$.joiners') WHERE name <> 'get';
         DELETE FROM _sqlx_migrations WHERE version = 20261201000003;",
    )
    .await
    .unwrap();
    let app = spawn_on(dir, Options::default()).await;
    let put_verb: Value = app.get("/v1/actions/put").await.json().await.unwrap();
    assert_eq!(put_verb["words"], json!(["put", "place", "set", "position"]));
    assert_eq!(
        put_verb["joiners"],
        json!(["on", "onto", "in", "into", "upon", "inside"])
    );
    let get_verb: Value = app.get("/v1/actions/get").await.json().await.unwrap();
    assert_eq!(get_verb["words"], json!(["obtain"]), "a verb that has words keeps them");
}

#[tokio::test]
async fn a_new_verb_is_simulated_with_its_preconditions_and_effects() {
    let app = spawn_app().await;
    let open = json!({"parameters": ["X"], "methods": [{"reach": ["X"], "preconditions": ["closed(X)"], "adds": ["open(X)"], "removes": ["closed(X)"]}]});
    let response = put(&app, "unseal", &open).await;
    assert_eq!(response.status(), StatusCode::CREATED);
    let stored: Value = response.json().await.unwrap();
    assert_eq!(
        stored["methods"][0]["steps"],
        json!(["itself"]),
        "itself is made explicit"
    );

    let closed = app
        .clarify(&request("unseal", &["box"], boxes(&["closed(box1)"])))
        .await;
    assert_eq!(closed["decision"], "comply");
    assert_eq!(closed["library_version"], 2);
    let already = app.clarify(&request("unseal", &["box"], boxes(&[]))).await;
    assert_eq!(already["decision"], "refuse");
    assert_eq!(
        already["utterance"],
        "I cannot unseal the box because the box is not closed."
    );
    assert_eq!(
        already["interpretations"][0]["reasons"][0],
        json!({"kind": "precondition", "detail": "closed(box1)", "words": "the box is not closed"})
    );

    // Replacing it: 200, and the very next request uses the new definition.
    let no_precondition = json!({"parameters": ["X"], "methods": [{"adds": ["open(X)"]}]});
    assert_eq!(put(&app, "unseal", &no_precondition).await.status(), StatusCode::OK);
    let answer = app.clarify(&request("unseal", &["box"], boxes(&[]))).await;
    assert_eq!(
        (answer["decision"].as_str(), answer["library_version"].as_i64()),
        (Some("comply"), Some(3))
    );

    // A forbidden state entered by the new verb's effects is caught like any other.
    app.add_norm(&json!({"kind": "forbidden_state", "state": "open(X)", "when": ["box(X)"]}))
        .await;
    let answer = app.clarify(&request("unseal", &["box"], boxes(&[]))).await;
    assert_eq!(
        answer["utterance"],
        "I cannot unseal the box because the box being open is forbidden."
    );
}

#[tokio::test]
async fn a_reading_is_acceptable_when_any_method_is_and_otherwise_carries_every_methods_reasons() {
    let app = spawn_app().await;
    let tidy = json!({"parameters": ["X"], "methods": [{"steps": ["get(X)"]}, {"steps": ["pointTo(X)"]}]});
    assert_eq!(put(&app, "tidy", &tidy).await.status(), StatusCode::CREATED);
    app.add_norm(&json!({"kind": "forbidden_action", "action": "get(X)", "when": ["fragile(X)"]}))
        .await;

    let answer = app.clarify(&request("tidy", &["vase"], lab_scene())).await;
    // The plastic vase by the first method; the fragile one by the second (pointing only).
    assert_eq!(answer["decision"], "ask");
    let plans: Vec<&Value> = answer["interpretations"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| &i["plan"])
        .collect();
    assert_eq!(
        plans,
        [
            &json!(["pointTo(object3)", "tidy(object3)"]),
            &json!(["get(object4)", "tidy(object4)"])
        ]
    );

    let pointing = app
        .add_norm(&json!({"kind": "forbidden_action", "action": "pointTo"}))
        .await;
    let answer = app.clarify(&request("tidy", &["vase"], lab_scene())).await;
    assert_eq!(answer["decision"], "assume");
    let kinds: Vec<(&str, &str)> = answer["interpretations"][0]["reasons"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| (r["kind"].as_str().unwrap(), r["detail"].as_str().unwrap()))
        .collect();
    assert_eq!(
        kinds,
        [
            ("forbidden_action", "get(object3)"),
            ("forbidden_action", "pointTo(object3)")
        ]
    );
    assert_eq!(
        answer["utterance"],
        "I am assuming you want me to tidy the plastic vase. I cannot tidy the fragile vase because getting the fragile vase is forbidden."
    );
    assert!(pointing > 0);
}

#[tokio::test]
async fn bad_verbs_name_their_field_and_store_nothing() {
    let app = spawn_app().await;
    let cases = [
        (
            "open",
            json!({"parameters": ["X"], "methods": [{"adds": ["open(Y)"]}]}),
            "/methods/0/adds/0",
        ),
        ("open", json!({"parameters": ["x"], "methods": [{}]}), "/parameters/0"),
        ("open", json!({"parameters": ["X"], "methods": []}), "/methods"),
        ("open", json!({"parameters": ["X"]}), "/methods"),
        (
            "open",
            json!({"name": "shut", "parameters": ["X"], "methods": [{}]}),
            "/name",
        ),
        (
            "open",
            json!({"parameters": ["X"], "methods": [{"steps": ["open(X)"]}]}),
            "/methods/0/steps/0",
        ),
        (
            "open",
            json!({"parameters": ["X"], "methods": [{"reach": ["Y"]}]}),
            "/methods/0/reach/0",
        ),
        (
            "open",
            json!({"parameters": ["X"], "methods": [{"stesp": ["get(X)"]}]}),
            "/methods/0/stesp",
        ),
        ("Open", json!({"parameters": ["X"], "methods": [{}]}), "/name"),
    ];
    for (name, verb, field) in cases {
        assert_problem(
            put(&app, name, &verb).await,
            StatusCode::UNPROCESSABLE_ENTITY,
            Some(field),
        )
        .await;
    }
    // A loop through the library: carry calls fetch calls carry.
    let fetch = json!({"parameters": ["X"], "methods": [{"steps": ["carry(X)"]}]});
    assert_eq!(put(&app, "fetch", &fetch).await.status(), StatusCode::CREATED);
    let carry = json!({"parameters": ["X"], "methods": [{"steps": ["fetch(X)"]}]});
    let problem = assert_problem(put(&app, "carry", &carry).await, StatusCode::UNPROCESSABLE_ENTITY, None).await;
    let detail = problem["detail"].as_str().unwrap();
    assert!(
        detail.contains("call back into the verb") && detail.contains("fetch →") && detail.contains("carry →"),
        "{problem}"
    );
    assert_problem(app.get("/v1/actions/carry").await, StatusCode::NOT_FOUND, None).await;
    assert_eq!(
        app.get("/v1/actions").await.json::<Vec<Value>>().await.unwrap().len(),
        Library::default_library().verbs().len() + 1
    );
}

#[tokio::test]
async fn removing_a_verb_makes_its_readings_unknown_and_writes_need_the_token() {
    let app = spawn_with(Options {
        admin_token: Some("t0ken-0123456789ab".into()),
        ..Options::default()
    })
    .await;
    let verb = json!({"parameters": ["X"], "methods": [{}]});
    assert_problem(put(&app, "wave", &verb).await, StatusCode::UNAUTHORIZED, None).await;
    let wrong = app
        .client
        .put(app.url("/v1/actions/wave"))
        .bearer_auth("nope")
        .json(&verb)
        .send()
        .await
        .unwrap();
    assert_problem(wrong, StatusCode::FORBIDDEN, None).await;
    assert_problem(app.delete("/v1/actions/get").await, StatusCode::UNAUTHORIZED, None).await;
    assert_eq!(
        app.clarify(&request("get", &["mug"], lab_scene())).await["decision"],
        "comply"
    );

    // `put` and the household verbs call `get`: they go first.
    for verb in ["put", "give", "heat", "discard", "pour", "cut", "get"] {
        let deleted = app
            .client
            .delete(app.url(&format!("/v1/actions/{verb}")))
            .bearer_auth("t0ken-0123456789ab")
            .send()
            .await
            .unwrap();
        assert_eq!(deleted.status(), StatusCode::NO_CONTENT, "{verb}");
    }
    let answer = app.clarify(&request("get", &["mug"], lab_scene())).await;
    assert_eq!(
        answer["utterance"],
        "I cannot get the mug because I do not know how to get."
    );
    let again = app
        .client
        .delete(app.url("/v1/actions/get"))
        .bearer_auth("t0ken-0123456789ab")
        .send()
        .await
        .unwrap();
    assert_problem(again, StatusCode::NOT_FOUND, None).await;

    // Over gRPC: the same library, the same token rule.
    let channel = tonic::transport::Channel::from_shared(app.base.clone())
        .unwrap()
        .connect()
        .await
        .unwrap();
    let mut actions = pb::actions_client::ActionsClient::new(channel);
    let listed = actions
        .list_actions(pb::ListActionsRequest {})
        .await
        .unwrap()
        .into_inner()
        .actions;
    assert_eq!(
        listed.iter().map(|a| a.name.clone().unwrap()).collect::<Vec<_>>(),
        [
            "clean",
            "close",
            "destroy",
            "open",
            "pointTo",
            "steal",
            "switchOff",
            "switchOn"
        ]
    );
    let status = actions
        .put_action(pb::PutActionRequest {
            name: "wave".into(),
            action: Some(pb::Action {
                parameters: vec!["X".into()],
                methods: vec![pb::Method::default()],
                ..Default::default()
            }),
        })
        .await
        .unwrap_err();
    assert_eq!(status.code(), tonic::Code::Unauthenticated);
    let mut authorised = tonic::Request::new(pb::PutActionRequest {
        name: "get".into(),
        action: Some(pb::Action {
            parameters: vec!["X".into()],
            methods: vec![pb::Method {
                reach: vec!["X".into()],
                adds: vec!["holding(self,X)".into()],
                ..Default::default()
            }],
            ..Default::default()
        }),
    });
    authorised
        .metadata_mut()
        .insert("authorization", "Bearer t0ken-0123456789ab".parse().unwrap());
    assert!(actions.put_action(authorised).await.unwrap().into_inner().created);
    assert_eq!(
        app.clarify(&request("get", &["mug"], lab_scene())).await["decision"],
        "comply"
    );
}

#[tokio::test]
async fn another_process_sees_a_verb_change_on_its_next_request() {
    let one = spawn_app().await;
    let other = spawn_on(one.dir.clone(), Options::default()).await;
    assert_eq!(
        other.clarify(&request("wave", &["mug"], lab_scene())).await["decision"],
        "refuse"
    );
    assert_eq!(
        put(&one, "wave", &json!({"parameters": ["X"], "methods": [{}]}))
            .await
            .status(),
        StatusCode::CREATED
    );
    assert_eq!(
        other.clarify(&request("wave", &["mug"], lab_scene())).await["decision"],
        "comply"
    );
}

#[tokio::test]
async fn an_unreadable_verb_in_the_store_fails_closed() {
    let app = spawn_app().await;
    let mut connection = {
        use sqlx::ConnectOptions;
        sqlx::sqlite::SqliteConnectOptions::new()
            .filename(&app.db_path)
            .connect()
            .await
            .unwrap()
    };
    sqlx::query("UPDATE actions SET definition = '{\"parameters\": [\"x\"]}' WHERE name = 'get'; UPDATE action_set SET version = version + 1")
        .execute(&mut connection)
        .await
        .unwrap();
    crate::helpers::after_the_lease().await;
    assert_problem(
        app.post("/v1/clarify", &request("get", &["mug"], lab_scene())).await,
        StatusCode::SERVICE_UNAVAILABLE,
        None,
    )
    .await;
}

/// Finding: `DELETE /v1/actions/get` succeeded while the default `put` calls `get` in its
/// method, so every `put` became infeasible at a step nobody asked about. A verb another verb
/// calls is refused with 409, naming the callers, over REST and gRPC; nothing changes (the
/// library version stays); once the callers are gone, it goes.
#[tokio::test]
async fn a_verb_another_verb_calls_is_not_removed_and_the_callers_are_named() {
    let app = spawn_app().await;
    let version = |app: &TestApp| {
        let url = app.url("/v1/clarify");
        let client = app.client.clone();
        async move {
            let body = request("get", &["mug"], lab_scene());
            let answer: Value = client.post(url).json(&body).send().await.unwrap().json().await.unwrap();
            answer["library_version"].as_i64().unwrap()
        }
    };
    let before = version(&app).await;
    // A second caller, by another arity's name: `fetch(X,Y)` calls `get(X)`.
    let fetch = json!({"parameters": ["X", "Y"], "methods": [{"steps": ["get(X)", "itself"]}]});
    assert_eq!(put(&app, "fetch", &fetch).await.status(), StatusCode::CREATED);
    let problem = assert_problem(app.delete("/v1/actions/get").await, StatusCode::CONFLICT, None).await;
    let detail = problem["detail"].as_str().unwrap_or_default();
    assert!(detail.contains("`put`") && detail.contains("`fetch`"), "{detail}");
    assert_eq!(problem["type"], "/problems/verb-in-use");
    assert_eq!(
        app.get("/v1/actions/get").await.status(),
        StatusCode::OK,
        "get is still there"
    );
    assert_eq!(
        version(&app).await,
        before + 1,
        "only the put of fetch moved the library"
    );

    let channel = crate::grpc::channel(&app).await;
    let mut actions = pb::actions_client::ActionsClient::new(channel);
    let status = actions
        .delete_action(pb::DeleteActionRequest { name: "get".into() })
        .await
        .unwrap_err();
    assert_eq!(status.code(), tonic::Code::FailedPrecondition);
    assert!(status.message().contains("`put`"), "{}", status.message());

    // The callers first, then the verb they called.
    for name in ["fetch", "put", "give", "heat", "discard", "pour", "cut", "get"] {
        let response = app.delete(&format!("/v1/actions/{name}")).await;
        assert_eq!(response.status(), StatusCode::NO_CONTENT, "{name}");
    }
    assert_problem(app.get("/v1/actions/get").await, StatusCode::NOT_FOUND, None).await;
}

/// `implied` over the API: a curator's verb with an implied instrument is stored and read
/// back as written, decides with the argument left out, and every fault is a 422 naming the
/// member at fault, storing nothing.
#[tokio::test]
async fn an_implied_parameter_is_stored_checked_and_used() {
    let app = spawn_app().await;
    let sweep = json!({"parameters": ["X", "B"], "joiner": "with", "implied": {"B": ["broom(B)"]},
        "methods": [{"steps": ["itself"], "reach": ["X"], "preconditions": ["broom(B)"], "adds": ["swept(X)"]}],
        "words": ["sweep"], "joiners": ["with"]});
    let response = put(&app, "sweep", &sweep).await;
    assert_eq!(response.status(), StatusCode::CREATED);
    let stored: Value = app.get("/v1/actions/sweep").await.json().await.unwrap();
    assert_eq!(stored["implied"], json!({"B": ["broom(B)"]}));
    let floor = json!({"agent": {"position": [0, 0, 0.75], "reach": 0.9},
        "objects": [{"id": "floor1", "type": "floor", "position": [0.5, 0, 0.5]},
                    {"id": "broom1", "type": "broom", "position": [0.4, 0.2, 0.5]}]});
    let answer = app
        .clarify(&json!({"directive": {"text": "Sweep the floor."}, "scene": floor}))
        .await;
    assert_eq!(answer["goal"], "did(self,sweep(floor1,broom1))", "{answer}");
    let answer = app.clarify(&request("sweep", &["floor"], floor.clone())).await;
    assert_eq!(answer["goal"], "did(self,sweep(floor1,broom1))", "{answer}");
    let mut bare = floor.clone();
    bare["objects"].as_array_mut().unwrap().pop();
    let answer = app.clarify(&request("sweep", &["floor"], bare)).await;
    assert_eq!(answer["decision"], "unresolved", "{answer}");
    assert_eq!(answer["utterance"], "I do not see anything to sweep the floor with.");

    let before: Vec<Value> = app.get("/v1/actions").await.json().await.unwrap();
    for (implied, field) in [
        (json!({"Z": ["broom(Z)"]}), "/implied/Z"),
        // A key is one segment of the pointer, escaped.
        (json!({"a/b~": ["broom(B)"]}), "/implied/a~1b~0"),
        (json!({"X": ["floor(X)"]}), "/implied/X"),
        (json!({"B": []}), "/implied/B"),
        (json!({"B": ["near(B,X)"]}), "/implied/B/0"),
        (json!({"B": ["broom("]}), "/implied/B/0"),
        (json!({"B": ["B"]}), "/implied/B/0"),
    ] {
        let mut bad = sweep.clone();
        bad["implied"] = implied.clone();
        assert_problem(
            put(&app, "sweep", &bad).await,
            StatusCode::UNPROCESSABLE_ENTITY,
            Some(field),
        )
        .await;
    }
    // A parameter after an implied one must be implied too.
    let three = json!({"parameters": ["X", "B", "Y"], "implied": {"B": ["broom(B)"]}, "methods": [{}]});
    assert_problem(
        put(&app, "brush", &three).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/implied/B"),
    )
    .await;
    let after: Vec<Value> = app.get("/v1/actions").await.json().await.unwrap();
    assert_eq!(before, after, "a refused verb stores nothing");

    // The same verb over gRPC, implied facts and all.
    let channel = crate::grpc::channel(&app).await;
    let mut actions = pb::actions_client::ActionsClient::new(channel);
    let got = actions
        .get_action(pb::GetActionRequest { name: "sweep".into() })
        .await
        .unwrap()
        .into_inner();
    let implied = &got.implied;
    assert_eq!(implied["B"].facts, ["broom(B)"]);
    // A default (empty) message of facts, and a key that is no parameter: INVALID_ARGUMENT
    // naming the member, as REST names it; nothing stored.
    for (parameter, facts, field) in [
        ("B", vec![], "/implied/B"),
        ("", vec!["broom(B)".to_owned()], "/implied/"),
    ] {
        let mut action = got.clone();
        action.implied = [(parameter.to_owned(), pb::ImpliedFacts { facts })].into();
        let status = actions
            .put_action(pb::PutActionRequest {
                name: "sweep".into(),
                action: Some(action),
            })
            .await
            .unwrap_err();
        assert_eq!(status.code(), tonic::Code::InvalidArgument, "{parameter:?}");
        assert_eq!(status.metadata().get("field").unwrap(), field);
    }
    let after: Vec<Value> = app.get("/v1/actions").await.json().await.unwrap();
    assert_eq!(before, after, "a refused verb stores nothing");
}
