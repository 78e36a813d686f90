//! Answers unchanged: every request of `tests/golden/corpus.jsonl` (made by
//! `tests/golden/make_corpus.py`) is answered by the server, each on a fresh store after its
//! setup; the clarify requests marked `replay` by `scruple replay --out` with the setup's norms;
//! and those marked `grpc` over gRPC. The outputs must equal their golden files
//! (`server.jsonl`, `replay.jsonl`, `grpc.jsonl`) byte for byte, and a server on PostgreSQL must
//! give `server.jsonl` too. An entry's `server` may set an admin token and a body limit. The
//! golden files were made before the code was reshaped and committed on their own, so a diff of
//! them is a change of behaviour. `SCRUPLE_BLESS=1 cargo test --test api golden` (exactly `1`)
//! rewrites them, for a change of behaviour that is meant.

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

/// A server for one entry on a fresh store (a fresh SQLite file, or the PostgreSQL database at
/// `database_url`, fresh), after the entry's setup (each step must succeed).
async fn set_up(entry: &Value, database_url: Option<String>) -> TestApp {
    let server = &entry["server"];
    let app = spawn_with(Options {
        admin_token: server["admin_token"].as_str().map(str::to_owned),
        max_body_bytes: server["max_body_bytes"]
            .as_u64()
            .map_or(DEFAULT_MAX_BODY_BYTES, |n| n as usize),
        tweak: database_url.map(|url| -> crate::helpers::Tweak { Box::new(move |c| c.database_url = url) }),
    })
    .await;
    for step in entry["setup"].as_array().unwrap() {
        let (status, body) = send(&app, step).await;
        assert!(
            (200..300).contains(&status),
            "{}: setup {step} answered {status} {body}",
            entry["id"]
        );
    }
    app
}

/// One entry's answer over REST, on a fresh store.
async fn answer(entry: &Value, database_url: Option<String>) -> Value {
    let app = set_up(entry, database_url).await;
    let (status, body) = send(&app, &entry["request"]).await;
    app.stop().await;
    json!({"id": entry["id"], "status": status, "body": body})
}

/// Fields added to the response messages after the corpus was blessed, as their `Debug` form
/// prints them when empty. Proto3 sends no bytes for an empty repeated field, so an answer that
/// leaves them empty is, on the wire, the answer the corpus holds: they are left out of the
/// text compared, and a non-empty one still shows (and fails) as a change.
const ADDED_EMPTY: &[&str] = &[", steps: [], purposes: []"];

/// One entry's answer over gRPC, on a fresh store set up over REST: the status code, and the
/// response message in full (its `Debug` form: every field, in the proto's order; no response
/// message has a map, so the text is stable; [`ADDED_EMPTY`] aside) or the status's message
/// and field.
async fn answer_over_grpc(entry: &Value) -> Value {
    use scruple::transport::grpc::pb::clarifier_client::ClarifierClient;
    use scruple::transport::grpc::pb::norms_client::NormsClient;
    let app = set_up(entry, None).await;
    let channel = crate::grpc::channel(&app).await;
    let request = &entry["request"];
    let answer = match (request["method"].as_str(), request["path"].as_str()) {
        (Some("POST"), Some("/v1/clarify")) => ClarifierClient::new(channel)
            .clarify(crate::grpc::clarify_request(&request["body"]))
            .await
            .map(|r| format!("{:?}", r.into_inner())),
        (Some("POST"), Some("/v1/norms")) => NormsClient::new(channel)
            .create_norm(crate::grpc::norm_request(&request["body"]))
            .await
            .map(|r| format!("{:?}", r.into_inner())),
        other => panic!("{}: no gRPC call for {other:?}", entry["id"]),
    };
    app.stop().await;
    match answer {
        Ok(message) => {
            let message = ADDED_EMPTY.iter().fold(message, |m, empty| m.replace(empty, ""));
            json!({"id": entry["id"], "code": "Ok", "message": message})
        }
        Err(status) => json!({"id": entry["id"], "code": format!("{:?}", status.code()), "error": status.message(),
                              "field": status.metadata().get("field").map(|f| f.to_str().unwrap())}),
    }
}

/// The entries marked `grpc`, over gRPC: their answers must equal `grpc.jsonl`.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn grpc_gives_the_golden_answers() {
    let entries: Vec<Value> = corpus().into_iter().filter(|e| e["grpc"] == true).collect();
    assert!(entries.len() >= 40, "{} entries over gRPC", entries.len());
    let turns = Arc::new(tokio::sync::Semaphore::new(8));
    let tasks: Vec<_> = entries
        .into_iter()
        .map(|entry| {
            let turns = turns.clone();
            tokio::spawn(async move {
                let _turn = turns.acquire_owned().await.unwrap();
                answer_over_grpc(&entry).await
            })
        })
        .collect();
    let mut answers = Vec::with_capacity(tasks.len());
    for task in tasks {
        answers.push(task.await.expect("an entry is answered over gRPC"));
    }
    against_golden("grpc.jsonl", &answers);
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

/// Whether this run rewrites the golden files.
fn blessing_now() -> bool {
    blessing(std::env::var_os("SCRUPLE_BLESS").as_deref())
}

/// Compares with the golden file, or writes it under `SCRUPLE_BLESS=1`.
fn against_golden(name: &str, values: &[Value]) {
    if blessing_now() {
        std::fs::write(golden_dir().join(name), lines(values)).unwrap();
        return;
    }
    compare_with_golden(name, values);
}

/// Asserts that `values` are the golden file's lines, byte for byte.
fn compare_with_golden(name: &str, values: &[Value]) {
    let path = golden_dir().join(name);
    let text = lines(values);
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
            answer(&entry, None).await
        }));
    }
    let mut answers = Vec::with_capacity(tasks.len());
    for task in tasks {
        answers.push(task.await.expect("an entry is answered"));
    }
    against_golden("server.jsonl", &answers);
}

/// A PostgreSQL database that answers entries one after another, each on a fresh store:
/// creating and dropping a database per entry would take minutes, so instead every table is
/// emptied and given back the rows the migrations left (kept aside in schema `pristine`), its
/// identity sequences restarted. (The tables that have sequences start empty.)
struct PgSlot {
    database: crate::backends::PgDatabase,
    reset: String,
}

impl PgSlot {
    async fn new() -> PgSlot {
        use sqlx::Connection;
        let database = crate::backends::PgDatabase::create().await;
        let store = scruple::storage::PostgresStore::open(&database.url)
            .await
            .expect("the PostgreSQL store opens and migrates");
        store.pool().close().await;
        let mut connection = sqlx::PgConnection::connect(&database.url).await.unwrap();
        let tables: Vec<String> = sqlx::query_scalar(
            "SELECT tablename::text FROM pg_tables WHERE schemaname = 'public' \
             AND tablename <> '_sqlx_migrations' ORDER BY tablename",
        )
        .fetch_all(&mut connection)
        .await
        .unwrap();
        connection.close().await.unwrap();
        assert!(tables.len() >= 5, "the migrated tables: {tables:?}");
        let mut keep = String::from("CREATE SCHEMA pristine;");
        let mut reset = format!(
            "TRUNCATE {} RESTART IDENTITY;",
            tables
                .iter()
                .map(|t| format!("public.\"{t}\""))
                .collect::<Vec<_>>()
                .join(", ")
        );
        for table in &tables {
            keep += &format!("CREATE TABLE pristine.\"{table}\" AS TABLE public.\"{table}\";");
            reset +=
                &format!("INSERT INTO public.\"{table}\" OVERRIDING SYSTEM VALUE SELECT * FROM pristine.\"{table}\";");
        }
        database.execute(&keep).await.unwrap();
        PgSlot { database, reset }
    }

    /// The database's URL, its store fresh again.
    async fn fresh(&self) -> String {
        self.database.execute(&self.reset).await.unwrap();
        self.database.url.clone()
    }
}

/// The same answers from a server on PostgreSQL: the golden file is the one the SQLite store
/// gives, and the store a server runs on changes no byte of any answer. (Not while blessing,
/// which rewrites that file as this reads it: the next run compares.)
#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn the_server_gives_the_golden_answers_on_postgresql() {
    if blessing_now() {
        return;
    }
    let entries = corpus();
    let count = entries.len();
    let queue = Arc::new(std::sync::Mutex::new(
        entries
            .into_iter()
            .enumerate()
            .collect::<std::collections::VecDeque<_>>(),
    ));
    let answers = Arc::new(std::sync::Mutex::new(vec![Value::Null; count]));
    let workers: Vec<_> = (0..4)
        .map(|_| {
            let (queue, answers) = (queue.clone(), answers.clone());
            tokio::spawn(async move {
                let slot = PgSlot::new().await;
                loop {
                    let next = queue.lock().unwrap().pop_front();
                    let Some((index, entry)) = next else { break };
                    let answered = answer(&entry, Some(slot.fresh().await)).await;
                    answers.lock().unwrap()[index] = answered;
                }
            })
        })
        .collect();
    for worker in workers {
        worker.await.expect("every entry is answered on PostgreSQL");
    }
    let answers = std::mem::take(&mut *answers.lock().unwrap());
    compare_with_golden("server.jsonl", &answers);
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
