//! Operator limits: each answers with a clear problem naming the limit (or, for the deadline, a
//! dialogue answer saying it was hit), and back-pressure refuses with 503 + Retry-After rather
//! than collapsing, while the defaults serve 128 concurrent clients without one refusal.

use std::time::Duration;

use reqwest::StatusCode;
use serde_json::{Value, json};
use tokio::io::AsyncWriteExt;

use crate::beyond::{kitchen, request};
use crate::helpers::{TestApp, assert_problem, get_vase, lab_scene, spawn_app, spawn_tweaked};
use scruple::engine::term::TermLimits;

#[tokio::test]
async fn a_scene_over_the_object_limit_is_refused_naming_the_limit() {
    let app = spawn_tweaked(|c| c.limits.max_objects = 3).await;
    let problem = assert_problem(
        app.post("/v1/clarify", &get_vase()).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/scene/objects"),
    )
    .await;
    assert!(
        problem["detail"].as_str().unwrap().contains("--max-objects"),
        "{problem}"
    );
    let check = json!({"scene": lab_scene(), "steps": ["get(object4)"]});
    assert_problem(
        app.post("/v1/check", &check).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/scene/objects"),
    )
    .await;
}

#[tokio::test]
async fn terms_deeper_or_longer_than_the_limits_are_refused_with_their_field() {
    let app = spawn_tweaked(|c| c.limits.terms = TermLimits { depth: 3, len: 40 }).await;
    let mut deep = get_vase();
    deep["directive"] = json!({"form": "want(human,did(self,get(f(X))))", "bindings": {"X": ["object3"]}});
    let problem = assert_problem(
        app.post("/v1/clarify", &deep).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/directive/form"),
    )
    .await;
    assert!(
        problem["detail"].as_str().unwrap().contains("at most 3 deep"),
        "{problem}"
    );
    let mut long = get_vase();
    long["scene"]["facts"] = json!([format!("owned(object3,{})", "a".repeat(40))]);
    let problem = assert_problem(
        app.post("/v1/clarify", &long).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/scene/facts/0"),
    )
    .await;
    assert!(
        problem["detail"].as_str().unwrap().contains("longer than 40 bytes"),
        "{problem}"
    );
    // Within the limits, the same service decides as usual.
    assert_eq!(app.clarify(&get_vase()).await["decision"], "ask");
}

#[tokio::test]
async fn the_operators_default_deadline_is_said_when_hit_and_longer_asks_are_refused() {
    let app = spawn_tweaked(|c| {
        c.limits.default_deadline_ms = 1;
        c.limits.max_deadline_ms = 5_000;
    })
    .await;
    let answer = app.clarify(&request("put", &["cup", "plate"], kitchen(100, 100))).await;
    assert_eq!(answer["limits"]["reason"], "deadline", "{}", answer["limits"]);
    let mut greedy = get_vase();
    greedy["options"] = json!({"deadline_ms": 5_001});
    let problem = assert_problem(
        app.post("/v1/clarify", &greedy).await,
        StatusCode::UNPROCESSABLE_ENTITY,
        Some("/options/deadline_ms"),
    )
    .await;
    assert!(problem["detail"].as_str().unwrap().contains("1..=5000"), "{problem}");
}

/// Holds one turn of the service: a request whose headers are in but whose body never ends.
async fn hold_a_turn(app: &TestApp) -> tokio::net::TcpStream {
    let addr = app.base.strip_prefix("http://").unwrap();
    let mut stream = tokio::net::TcpStream::connect(addr).await.unwrap();
    let head = format!(
        "POST /v1/clarify HTTP/1.1\r\nhost: {addr}\r\ncontent-type: application/json\r\ncontent-length: 1000\r\n\r\n{{"
    );
    stream.write_all(head.as_bytes()).await.unwrap();
    stream
}

/// Sends "Get the vase." until the answer is not 200 (the held turn needs a moment to be taken).
async fn first_refusal(app: &TestApp) -> reqwest::Response {
    for _ in 0..100 {
        let response = app.post("/v1/clarify", &get_vase()).await;
        if response.status() != StatusCode::OK {
            return response;
        }
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    panic!("no request was refused while the only turn was held");
}

#[tokio::test]
async fn past_the_queue_requests_are_refused_with_503_and_retry_after_while_probes_still_answer() {
    let app = spawn_tweaked(|c| {
        c.admission.max_concurrent = 1;
        c.admission.max_queued = 0;
    })
    .await;
    let _held = hold_a_turn(&app).await;
    let refused = first_refusal(&app).await;
    assert_eq!(refused.headers().get("retry-after").unwrap(), "1");
    let problem = assert_problem(refused, StatusCode::SERVICE_UNAVAILABLE, None).await;
    assert_eq!(problem["type"], "/problems/overloaded");
    assert_eq!(
        app.get("/healthz").await.status(),
        StatusCode::OK,
        "probes are never queued"
    );
    // gRPC callers get UNAVAILABLE, not an HTTP error their client cannot read.
    let channel = tonic::transport::Channel::from_shared(app.base.clone())
        .unwrap()
        .connect()
        .await
        .unwrap();
    let mut norms = scruple::transport::grpc::pb::norms_client::NormsClient::new(channel);
    let status = norms
        .list_norms(scruple::transport::grpc::pb::ListNormsRequest {})
        .await
        .unwrap_err();
    assert_eq!(status.code(), tonic::Code::Unavailable);
    assert_eq!(status.metadata().get("retry-after").unwrap(), "1");
}

#[tokio::test]
async fn a_queued_request_waits_its_turn_then_gives_up_after_the_queue_timeout() {
    let app = spawn_tweaked(|c| {
        c.admission.max_concurrent = 1;
        c.admission.max_queued = 8;
        c.admission.queue_timeout = Duration::from_millis(200);
    })
    .await;
    let held = hold_a_turn(&app).await;
    let started = std::time::Instant::now();
    let refused = first_refusal(&app).await;
    let waited = started.elapsed();
    assert!(waited >= Duration::from_millis(200), "{waited:?}");
    // Far below the default queue timeout (10 s): the configured 200 ms is the one in force.
    assert!(waited < Duration::from_secs(5), "{waited:?}");
    assert_problem(refused, StatusCode::SERVICE_UNAVAILABLE, None).await;
    // Once the turn is free again, queued work goes through.
    drop(held);
    let mut served = false;
    for _ in 0..50 {
        if app.post("/v1/clarify", &get_vase()).await.status() == StatusCode::OK {
            served = true;
            break;
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    assert!(served, "the service recovers once the held request goes away");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn with_the_defaults_128_concurrent_clients_are_all_served() {
    let app = std::sync::Arc::new(spawn_app().await);
    app.add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
        .await;
    let mut clients = Vec::new();
    for _ in 0..128 {
        let app = app.clone();
        clients.push(tokio::spawn(async move {
            // One connection per client, as 128 robots would have.
            let client = crate::helpers::http_client();
            let mut statuses = Vec::new();
            for _ in 0..4 {
                let response = client
                    .post(app.url("/v1/clarify"))
                    .json(&get_vase())
                    .send()
                    .await
                    .unwrap();
                statuses.push(response.status());
                let answer: Value = response.json().await.unwrap();
                assert_eq!(answer["decision"], "assume");
            }
            statuses
        }));
    }
    for client in clients {
        assert!(client.await.unwrap().iter().all(|s| *s == StatusCode::OK));
    }
}
