//! What an operator sees: Prometheus metrics at `/metrics`, a request id on every response (the
//! caller's, or a fresh one), and JSON logs that carry it but keep the human's words and the
//! speaker out unless `--log-utterances` is on.

use reqwest::StatusCode;
use serde_json::{Value, json};

use crate::helpers::{get_vase, serve_binary, spawn_app};

/// The value of the sample with exactly these labels, if the exposition has it.
fn sample(text: &str, name_and_labels: &str) -> Option<f64> {
    text.lines()
        .find_map(|line| line.strip_prefix(name_and_labels)?.strip_prefix(' ')?.parse().ok())
}

#[tokio::test]
async fn metrics_count_requests_decisions_readings_and_cache_use() {
    let app = spawn_app().await;
    app.add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
        .await;
    for _ in 0..3 {
        assert_eq!(app.clarify(&get_vase()).await["decision"], "assume");
    }
    assert_eq!(app.get("/v1/norms/999").await.status(), StatusCode::NOT_FOUND);
    assert_eq!(app.get("/nowhere/42").await.status(), StatusCode::NOT_FOUND);

    let response = app.get("/metrics").await;
    assert_eq!(response.status(), StatusCode::OK);
    let content_type = response.headers()["content-type"].to_str().unwrap().to_owned();
    assert!(
        content_type.starts_with("application/openmetrics-text"),
        "{content_type}"
    );
    let text = response.text().await.unwrap();
    let value = |s: &str| sample(&text, s).unwrap_or_else(|| panic!("no sample {s} in\n{text}"));
    assert_eq!(
        value(r#"scruple_http_requests_total{route="/v1/clarify",method="POST",status="200"}"#),
        3.0
    );
    assert_eq!(
        value(r#"scruple_http_requests_total{route="/v1/norms",method="POST",status="201"}"#),
        1.0
    );
    // A route template, never the raw path; an unknown path is one label, whatever it was.
    assert_eq!(
        value(r#"scruple_http_requests_total{route="/v1/norms/{id}",method="GET",status="404"}"#),
        1.0
    );
    assert_eq!(
        value(r#"scruple_http_requests_total{route="unmatched",method="GET",status="404"}"#),
        1.0
    );
    assert!(!text.contains("/v1/norms/999") && !text.contains("nowhere"));
    assert_eq!(
        value(r#"scruple_http_request_duration_seconds_count{route="/v1/clarify",method="POST"}"#),
        3.0
    );
    assert_eq!(value(r#"scruple_decisions_total{kind="assume"}"#), 3.0);
    assert_eq!(value("scruple_readings_simulated_count"), 3.0);
    assert_eq!(
        value("scruple_readings_simulated_sum"),
        6.0,
        "two vases, two readings each time"
    );
    // The first decision compiles the norm set; the next two reuse it.
    assert_eq!(
        value(r#"scruple_knowledge_cache_total{cache="norms",outcome="refresh"}"#),
        1.0
    );
    assert_eq!(
        value(r#"scruple_knowledge_cache_total{cache="norms",outcome="hit"}"#),
        2.0
    );
    assert_eq!(value("scruple_overloaded_total"), 0.0);
    assert!(text.trim_end().ends_with("# EOF"));
}

/// A request counts one lookup a cache, whichever way it got its knowledge: also the request
/// that finds the lease past three quarters of its time and reads the versions again ahead of
/// its end (it once counted the lease's hit and the read's outcome both).
#[tokio::test]
async fn a_request_that_reads_ahead_of_the_lease_counts_one_lookup_a_cache() {
    let lease = std::time::Duration::from_millis(400);
    let app = crate::helpers::spawn_tweaked(move |config| config.lease = lease).await;
    app.add_norm(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
        .await;
    let body = get_vase();
    assert_eq!(app.clarify(&body).await["decision"], "assume");
    // The first request's read began before this instant: the second comes at least 80% of
    // the lease after it, past the three quarters that make a read ahead due.
    let after = std::time::Instant::now();
    tokio::time::sleep_until((after + lease.mul_f64(0.8)).into()).await;
    assert_eq!(app.clarify(&body).await["decision"], "assume");
    let text = app.get("/metrics").await.text().await.unwrap();
    for cache in ["norms", "library"] {
        let count = |outcome: &str| {
            sample(
                &text,
                &format!(r#"scruple_knowledge_cache_total{{cache="{cache}",outcome="{outcome}"}}"#),
            )
            .unwrap_or(0.0)
        };
        assert_eq!(count("hit") + count("refresh"), 2.0, "{cache}: two requests\n{text}");
    }
}

#[tokio::test]
async fn every_response_carries_a_request_id_and_a_callers_id_is_echoed() {
    let app = spawn_app().await;
    let fresh = app.post("/v1/clarify", &get_vase()).await;
    let id = fresh.headers()["x-request-id"].to_str().unwrap().to_owned();
    assert_eq!(id.len(), 36, "a UUID: {id}");
    let other = app.get("/healthz").await;
    assert_ne!(other.headers()["x-request-id"].to_str().unwrap(), id);
    let echoed = app
        .client
        .post(app.url("/v1/clarify"))
        .header("x-request-id", "robot-7-utterance-42")
        .json(&get_vase())
        .send()
        .await
        .unwrap();
    assert_eq!(echoed.headers()["x-request-id"], "robot-7-utterance-42");
    // Errors carry it too.
    let problem = app.get("/v1/norms/abc").await;
    assert!(problem.headers().contains_key("x-request-id"));
}

/// Runs the binary with JSON logs at debug, sends one spoken directive, returns the log lines
/// and the request id the answer carried.
async fn json_log_of_one_decision(extra: &[&str]) -> (Vec<Value>, String) {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("log.jsonl");
    let mut args = vec!["--log-format", "json"];
    args.extend_from_slice(extra);
    let served = serve_binary(
        &format!("sqlite://{}", dir.path().join("db").display()),
        &args,
        &[("RUST_LOG", "scruple=debug,tower_http=debug")],
        std::fs::File::create(&log).unwrap().into(),
    );
    let addr = served.addr.clone();
    let mut body = get_vase();
    body["speaker"] = json!("dr_whistler");
    body["directive"]["text"] = json!("Get the vase, please.");
    let response = crate::helpers::http_client()
        .post(format!("http://{addr}/v1/clarify"))
        .json(&body)
        .send()
        .await
        .unwrap();
    assert_eq!(response.status(), StatusCode::OK);
    let id = response.headers()["x-request-id"].to_str().unwrap().to_owned();
    served.terminate();
    let lines = std::fs::read_to_string(&log)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("not a JSON log line ({e}): {l}")))
        .collect();
    (lines, id)
}

#[tokio::test]
async fn json_logs_carry_the_request_id_and_keep_words_and_speakers_out() {
    let (lines, id) = json_log_of_one_decision(&[]).await;
    let decided = lines
        .iter()
        .find(|l| l["fields"]["message"] == "decided")
        .unwrap_or_else(|| panic!("no decision line in {lines:?}"));
    assert_eq!(decided["span"]["request_id"], id.as_str());
    assert_eq!(decided["fields"]["decision"], "ask");
    let all = serde_json::to_string(&lines).unwrap();
    assert!(
        !all.contains("Get the vase") && !all.contains("dr_whistler"),
        "personal data in the log"
    );
}

/// Plain-text logs filtered on the request span's fields: every line of the requests the filter
/// picks (the answer's included), none of the others, with the span's fields as before.
#[tokio::test]
async fn a_log_filter_on_the_request_spans_fields_picks_those_requests_whole() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("log.txt");
    let served = serve_binary(
        &format!("sqlite://{}", dir.path().join("db").display()),
        &[],
        &[("RUST_LOG", "warn,[request{path=/v1/check}]=debug")],
        std::fs::File::create(&log).unwrap().into(),
    );
    let client = crate::helpers::http_client();
    let clarified = client
        .post(format!("http://{}/v1/clarify", served.addr))
        .json(&get_vase())
        .send()
        .await
        .unwrap();
    assert_eq!(clarified.status(), StatusCode::OK);
    let checked = client
        .post(format!("http://{}/v1/check", served.addr))
        .json(&json!({}))
        .send()
        .await
        .unwrap();
    assert_eq!(checked.status(), StatusCode::UNPROCESSABLE_ENTITY);
    let id = checked.headers()["x-request-id"].to_str().unwrap().to_owned();
    served.terminate();
    let text = std::fs::read_to_string(&log).unwrap();
    let span = format!("request{{method=POST path=/v1/check request_id={id}}}: ");
    let of_check: Vec<&str> = text.lines().filter(|l| l.contains(&span)).collect();
    assert!(
        of_check.iter().any(|l| l.contains("request rejected")),
        "no rejection line in {text}"
    );
    assert!(
        of_check.iter().any(|l| l.contains("answered status=422")),
        "no answer line in {text}"
    );
    assert!(
        !text.contains("/v1/clarify"),
        "a request the filter leaves out was logged: {text}"
    );
}

#[tokio::test]
async fn log_utterances_puts_the_words_and_the_speaker_in_the_decision_line() {
    let (lines, _) = json_log_of_one_decision(&["--log-utterances"]).await;
    let decided = lines.iter().find(|l| l["fields"]["message"] == "decided").unwrap();
    assert_eq!(decided["fields"]["text"], "Get the vase, please.");
    assert_eq!(decided["fields"]["speaker"], "dr_whistler");
    assert!(
        decided["fields"]["utterance"]
            .as_str()
            .unwrap()
            .starts_with("Do you mean")
    );
}

/// Label values come from bounded sets whatever a client sends: a method outside the standard
/// nine is `other`, and a gRPC content type on a REST path never makes the raw path a label.
#[tokio::test]
async fn made_up_methods_and_paths_do_not_grow_the_metrics() {
    // The hostile pass found it on the binary: this runs the binary.
    let dir = tempfile::tempdir().unwrap();
    let served = serve_binary(
        &format!("sqlite://{}", dir.path().join("metrics.db").display()),
        &[],
        &[],
        std::process::Stdio::null(),
    );
    let client = crate::helpers::http_client();
    let url = |path: &str| format!("http://{}{path}", served.addr);
    for i in 0..50 {
        let method = reqwest::Method::from_bytes(format!("M{i}XXXX").as_bytes()).unwrap();
        let response = client.request(method, url("/")).send().await.unwrap();
        assert!(response.status().is_client_error(), "{}", response.status());
    }
    for i in 0..20 {
        let _ = client
            .post(url(&format!("/v1/norms/{}", 90_000 + i)))
            .header("content-type", "application/grpc")
            .body("x")
            .send()
            .await
            .unwrap();
    }
    let text = client.get(url("/metrics")).send().await.unwrap().text().await.unwrap();
    assert!(!text.contains("XXXX"), "a made-up method became a label:\n{text}");
    assert!(!text.contains("/v1/norms/900"), "a raw path became a label:\n{text}");
    let others: Vec<&str> = text
        .lines()
        .filter(|l| l.starts_with("scruple_http_requests_total{") && l.contains(r#"method="other""#))
        .collect();
    assert_eq!(others.len(), 1, "one series for every made-up method: {others:?}");
    assert!(others[0].ends_with(" 50"), "{}", others[0]);
    let methods: std::collections::BTreeSet<&str> = text
        .lines()
        .filter_map(|l| l.split("method=\"").nth(1)?.split('"').next())
        .collect();
    let known = [
        "GET", "HEAD", "POST", "PUT", "DELETE", "PATCH", "OPTIONS", "CONNECT", "TRACE", "other",
    ];
    assert!(methods.iter().all(|m| known.contains(m)), "{methods:?}");
    let statuses: std::collections::BTreeSet<&str> = text
        .lines()
        .filter_map(|l| l.split("status=\"").nth(1)?.split('"').next())
        .collect();
    assert!(
        statuses.iter().all(|s| s.parse::<u16>().is_ok() || *s == "other"),
        "{statuses:?}"
    );
    let status = tokio::task::spawn_blocking(move || served.terminate()).await.unwrap();
    assert_eq!(status.code(), Some(0));
}
