//! The coherence contract across OS processes (CONTRACT, "Norms": a change is seen "by every
//! request that starts after the change was acknowledged to its writer", on any process sharing
//! the database): two `scruple serve` processes on one store, a SQLite file or a PostgreSQL
//! database, both with a versions lease five times the default and both kept busy (so each
//! always holds a fresh lease), and writers on both at once.
//!
//! Each writer owns one cup. It forbids getting its cup through one process and, once that is
//! acknowledged, asks both processes; then it lifts the norm through the other process and asks
//! both again. Every answer must already reflect the acknowledged change, whatever the other
//! writers are committing meanwhile. A write acknowledged before every process's lease taken
//! before its commit has run out (a write that waited the default lease, or none) fails here.

use std::process::Stdio;

use reqwest::{Client, StatusCode};
use serde_json::{Value, json};

use crate::backends::PgDatabase;
use crate::helpers::{KeepAsking, Served, http_client, serve_binary};

/// Five times the default lease (50 ms): a writer that waits the default instead is caught.
const LEASE_MS: &str = "250";
const WRITERS: usize = 4;
const ROUNDS: usize = 4;

/// A cup per writer, each within reach.
fn cups() -> Value {
    let objects: Vec<Value> = (0..WRITERS)
        .map(|w| {
            json!({"id": format!("cup{w}"), "type": "cup", "position": [0.4, -0.3 + 0.2 * w as f64, 0.8],
                   "shape": {"cylinder": {"radius": 0.04, "half_height": 0.05}}})
        })
        .collect();
    json!({"agent": {"position": [0, 0, 0.75], "reach": 0.9}, "objects": objects})
}

/// "Get cupW" at `base`: its answer.
async fn get_cup(client: &Client, base: &str, writer: usize) -> Value {
    let request =
        json!({"directive": {"action": "get", "arguments": [{"id": format!("cup{writer}")}]}, "scene": cups()});
    let response = client
        .post(format!("{base}/v1/clarify"))
        .json(&request)
        .send()
        .await
        .unwrap();
    assert_eq!(response.status(), StatusCode::OK);
    response.json().await.unwrap()
}

/// One writer's rounds: writes through `bases[0]` and `bases[1]` in turn, asking both after
/// every acknowledgement.
async fn write_and_ask(writer: usize, bases: [String; 2]) {
    let client = http_client();
    let [one, other] = &bases;
    for round in 0..ROUNDS {
        let norm = json!({"kind": "forbidden_state", "state": format!("did(self,get(cup{writer}))")});
        let created = client.post(format!("{one}/v1/norms")).json(&norm).send().await.unwrap();
        assert_eq!(created.status(), StatusCode::CREATED);
        let created: Value = created.json().await.unwrap();
        for base in [other, one] {
            let answer = get_cup(&client, base, writer).await;
            let at = format!("writer {writer}, round {round}, {base} after the create");
            assert_eq!(answer["decision"], "refuse", "{at}: {answer}");
            assert_eq!(
                answer["interpretations"][0]["reasons"][0]["norm_id"], created["id"],
                "{at}: {answer}"
            );
            assert!(
                answer["norm_version"].as_i64() >= created["revision"].as_i64(),
                "{at}: decided under version {} before the write's {}",
                answer["norm_version"],
                created["revision"]
            );
        }
        let deleted = client
            .delete(format!("{other}/v1/norms/{}", created["id"]))
            .send()
            .await
            .unwrap();
        assert_eq!(deleted.status(), StatusCode::NO_CONTENT);
        for base in [one, other] {
            let answer = get_cup(&client, base, writer).await;
            let at = format!("writer {writer}, round {round}, {base} after the delete");
            assert_eq!(answer["decision"], "comply", "{at}: {answer}");
        }
    }
}

/// Two processes on `database_url`, busy, with writers through both at once.
async fn writers_on_two_busy_processes(database_url: &str) {
    let start = || serve_binary(database_url, &["--versions-lease-ms", LEASE_MS], &[], Stdio::inherit());
    let processes: [Served; 2] = [start(), start()];
    let bases = processes.each_ref().map(|p| format!("http://{}", p.addr));
    let busy = bases.each_ref().map(|base| KeepAsking::at(base));
    let writers: Vec<_> = (0..WRITERS)
        .map(|writer| {
            let [a, b] = bases.clone();
            // Half the writers write through each process first.
            let order = if writer % 2 == 0 { [a, b] } else { [b, a] };
            tokio::spawn(write_and_ask(writer, order))
        })
        .collect();
    for writer in writers {
        writer
            .await
            .expect("a writer's every answer reflected its acknowledged change");
    }
    for asking in busy {
        assert!(asking.stop().await > 20, "both processes were kept busy");
    }
    for process in processes {
        assert!(process.terminate().success());
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn on_sqlite_every_acknowledged_change_is_seen_at_once_by_both_busy_processes() {
    let dir = tempfile::tempdir().unwrap();
    let url = format!("sqlite://{}", dir.path().join("shared.db").display());
    writers_on_two_busy_processes(&url).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn on_postgresql_every_acknowledged_change_is_seen_at_once_by_both_busy_processes() {
    let database = PgDatabase::create().await;
    writers_on_two_busy_processes(&database.url).await;
}
