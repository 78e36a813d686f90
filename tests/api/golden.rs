//! Answers unchanged: every request of `tests/golden/corpus.jsonl` (made by
//! `tests/golden/make_corpus.py`) is answered by the server, each on a fresh store after its
//! setup, and the clarify requests marked `replay` by `scruple replay --out` with the setup's
//! norms; both outputs must equal their golden files (`server.jsonl`, `replay.jsonl`) byte for
//! byte. An entry's `server` may set an admin token and a body limit. The golden files were made before the code was reshaped and committed on their own, so
//! a diff of them is a change of behaviour. `SCRUPLE_BLESS=1 cargo test --test api golden`
//! (exactly `1`) rewrites them, for a change of behaviour that is meant.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde_json::{Value, json};

use scruple::app::DEFAULT_MAX_BODY_BYTES;

use crate::helpers::{Options, TestApp, spawn_with};

fn golden_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

fn corpus() -> Vec<Value> {
    let text = std::fs::read_to_string(golden_dir().join("corpus.jsonl")).expect("tests/golden/corpus.jsonl");
    text.lines()
        .map(|l| serde_json::from_str(l).expect("a corpus line is JSON"))
        .collect()
}

async fn send(app: &TestApp, request: &Value) -> (u16, Value) {
    let method = reqwest::Method::from_bytes(request["method"].as_str().unwrap().as_bytes()).unwrap();
    let mut builder = app.client.request(method, app.url(request["path"].as_str().unwrap()));
    if let Some(headers) = request["headers"].as_object() {
        for (name, value) in headers {
            builder = builder.header(name, value.as_str().unwrap());
        }
    }
    if let Some(raw) = request["raw"].as_str() {
        builder = builder.body(raw.to_owned());
    } else if !request["body"].is_null() {
        builder = builder.json(&request["body"]);
    }
    let response = builder.send().await.expect("the request is answered");
    let status = response.status().as_u16();
    let text = response.text().await.unwrap();
    let body = serde_json::from_str(&text).unwrap_or(Value::String(text));
    (status, body)
}

/// One entry on a fresh store: its setup (each must succeed), then its request.
async fn answer(entry: Value) -> Value {
    let server = &entry["server"];
    let app = spawn_with(Options {
        admin_token: server["admin_token"].as_str().map(str::to_owned),
        max_body_bytes: server["max_body_bytes"]
            .as_u64()
            .map_or(DEFAULT_MAX_BODY_BYTES, |n| n as usize),
        ..Options::default()
    })
    .await;
    let id = entry["id"].as_str().unwrap().to_owned();
    for step in entry["setup"].as_array().unwrap() {
        let (status, body) = send(&app, step).await;
        assert!(
            (200..300).contains(&status),
            "{id}: setup {step} answered {status} {body}"
        );
    }
    let (status, body) = send(&app, &entry["request"]).await;
    app.stop().await;
    json!({"id": id, "status": status, "body": body})
}

fn lines(values: &[Value]) -> String {
    values.iter().map(|v| format!("{v}\n")).collect()
}

/// Whether the golden files are rewritten rather than compared: only when `SCRUPLE_BLESS` is
/// exactly `1`. Any other value (`0`, empty, `false`) compares, as one would read it.
fn blessing(value: Option<&std::ffi::OsStr>) -> bool {
    value.is_some_and(|v| v == "1")
}

#[test]
fn only_scruple_bless_1_rewrites_the_golden_files() {
    assert!(blessing(Some("1".as_ref())));
    for value in ["0", "", "false", "no", " 1", "1 ", "01", "yes", "true"] {
        assert!(!blessing(Some(value.as_ref())), "SCRUPLE_BLESS={value:?} blesses");
    }
    assert!(!blessing(None));
}

/// Compares with the golden file, or writes it under `SCRUPLE_BLESS=1`.
fn against_golden(name: &str, values: &[Value]) {
    let path = golden_dir().join(name);
    let text = lines(values);
    if blessing(std::env::var_os("SCRUPLE_BLESS").as_deref()) {
        std::fs::write(&path, &text).unwrap();
        return;
    }
    let golden = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let changed: Vec<String> = golden
        .lines()
        .zip(text.lines())
        .filter(|(g, t)| g != t)
        .take(5)
        .map(|(g, t)| format!("golden: {g}\n   now: {t}"))
        .collect();
    assert!(
        changed.is_empty() && golden.lines().count() == text.lines().count(),
        "{name}: answers changed ({} lines golden, {} now):\n{}",
        golden.lines().count(),
        text.lines().count(),
        changed.join("\n")
    );
}

#[tokio::test]
async fn the_server_gives_the_golden_answers() {
    let entries = corpus();
    assert!(entries.len() >= 200, "the corpus has {} entries", entries.len());
    // Eight fresh stores at a time: a few seconds for the whole corpus.
    let turns = Arc::new(tokio::sync::Semaphore::new(8));
    let mut tasks = Vec::new();
    for entry in entries {
        let turns = turns.clone();
        tasks.push(tokio::spawn(async move {
            let _turn = turns.acquire_owned().await.unwrap();
            answer(entry).await
        }));
    }
    let mut answers = Vec::with_capacity(tasks.len());
    for task in tasks {
        answers.push(task.await.expect("an entry is answered"));
    }
    against_golden("server.jsonl", &answers);
}

/// Runs `scruple replay FILE --norms NORMS --out OUT` and returns the answers by id.
fn replay(dir: &Path, group: usize, norms: &Value, entries: &[&Value]) -> BTreeMap<String, Value> {
    let norms_file = dir.join(format!("norms-{group}.json"));
    std::fs::write(&norms_file, norms.to_string()).unwrap();
    let input = dir.join(format!("requests-{group}.jsonl"));
    let requests: Vec<Value> = entries
        .iter()
        .map(|e| json!({"id": e["id"], "request": e["request"]["body"]}))
        .collect();
    std::fs::write(&input, lines(&requests)).unwrap();
    let out = dir.join(format!("answers-{group}.jsonl"));
    let status = crate::support::scruple()
        .arg("replay")
        .arg(&input)
        .arg("--norms")
        .arg(&norms_file)
        .arg("--out")
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .expect("scruple replay runs");
    assert!(matches!(status.code(), Some(0 | 2)), "replay exited {status}");
    std::fs::read_to_string(&out)
        .unwrap()
        .lines()
        .map(|l| {
            let line: Value = serde_json::from_str(l).unwrap();
            let answer = if line["decision"].is_null() {
                line["error"].clone()
            } else {
                line["decision"].clone()
            };
            (line["id"].as_str().unwrap().to_owned(), answer)
        })
        .collect()
}

#[test]
fn replay_gives_the_golden_answers() {
    let entries = corpus();
    let replayed: Vec<&Value> = entries.iter().filter(|e| e["replay"] == true).collect();
    // Entries that share their norms are replayed together.
    let mut groups: BTreeMap<String, (Value, Vec<&Value>)> = BTreeMap::new();
    for entry in &replayed {
        let norms: Vec<Value> = entry["setup"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| {
                assert_eq!(s["path"], "/v1/norms", "a replayed entry's setup only adds norms");
                s["body"].clone()
            })
            .collect();
        let norms = Value::Array(norms);
        groups
            .entry(norms.to_string())
            .or_insert_with(|| (norms, Vec::new()))
            .1
            .push(entry);
    }
    let dir = tempfile::tempdir().unwrap();
    let mut by_id = BTreeMap::new();
    for (group, (norms, members)) in groups.values().enumerate() {
        by_id.extend(replay(dir.path(), group, norms, members));
    }
    let answers: Vec<Value> = replayed
        .iter()
        .map(|e| {
            let id = e["id"].as_str().unwrap();
            json!({"id": id, "answer": by_id.remove(id).unwrap_or_else(|| panic!("{id} was not replayed"))})
        })
        .collect();
    against_golden("replay.jsonl", &answers);
}
