//! Crash safety: norm writes streamed at a real `scruple serve`, SIGKILLed at random moments;
//! after every restart each write acknowledged before the kill is present, word for word, and
//! the database passes SQLite's integrity check. `SCRUPLE_CRASH_ITERATIONS` (default 20) sets
//! how many kills.

use std::path::Path;
use std::process::Stdio;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use reqwest::StatusCode;
use serde_json::{Value, json};
use sqlx::sqlite::SqliteConnectOptions;
use sqlx::{ConnectOptions, Connection};

use crate::helpers::{Served, serve_binary};

fn start(db: &Path) -> Served {
    serve_binary(&format!("sqlite://{}", db.display()), &[], &[], Stdio::null())
}

/// xorshift: kill moments that differ per iteration yet repeat from run to run.
fn next(state: &mut u64) -> u64 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    *state
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn every_acknowledged_write_survives_sigkill_at_random_moments() {
    let iterations: usize = std::env::var("SCRUPLE_CRASH_ITERATIONS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20);
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("crash.db");
    let acknowledged: Arc<Mutex<Vec<(i64, String)>>> = Arc::default();
    let client = crate::helpers::http_client();
    let mut random = 0x9e37_79b9_7f4a_7c15_u64;
    let mut killed_mid_stream = 0;
    for iteration in 0..iterations {
        let mut served = start(&db);
        let addr = served.addr.clone();
        let so_far = acknowledged.lock().unwrap().clone();
        check_all_present(&client, &addr, &so_far).await;

        // Four writers stream norms until the process dies under them.
        let mut writers = Vec::new();
        for writer in 0..4 {
            let client = client.clone();
            let addr = addr.clone();
            let acknowledged = acknowledged.clone();
            writers.push(tokio::spawn(async move {
                for n in 0.. {
                    let note = format!("i{iteration}-w{writer}-n{n}");
                    let norm = json!({"kind": "forbidden_action", "action": "destroy", "note": note});
                    let Ok(response) = client.post(format!("http://{addr}/v1/norms")).json(&norm).send().await else {
                        return n;
                    };
                    if response.status() != StatusCode::CREATED {
                        return n;
                    }
                    let Ok(body) = response.json::<Value>().await else {
                        return n;
                    };
                    acknowledged.lock().unwrap().push((body["id"].as_i64().unwrap(), note));
                }
                unreachable!()
            }));
        }
        tokio::time::sleep(Duration::from_millis(20 + next(&mut random) % 180)).await;
        served.child.kill().expect("SIGKILL");
        served.child.wait().unwrap();
        for writer in writers {
            if writer.await.unwrap() > 0 {
                killed_mid_stream += 1;
            }
        }
    }
    let mut served = start(&db);
    let acknowledged: Vec<(i64, String)> = acknowledged.lock().unwrap().clone();
    check_all_present(&client, &served.addr, &acknowledged).await;
    served.child.kill().unwrap();
    served.child.wait().unwrap();
    assert!(killed_mid_stream > 0, "the writers were writing when the kills came");
    assert!(
        acknowledged.len() > iterations,
        "{} writes acknowledged",
        acknowledged.len()
    );

    let mut connection = SqliteConnectOptions::new().filename(&db).connect().await.unwrap();
    let check: String = sqlx::query_scalar("PRAGMA integrity_check")
        .fetch_one(&mut connection)
        .await
        .unwrap();
    assert_eq!(check, "ok");
    let audited: i64 = sqlx::query_scalar("SELECT count(*) FROM audit WHERE operation = 'create'")
        .fetch_one(&mut connection)
        .await
        .unwrap();
    let stored: i64 = sqlx::query_scalar("SELECT count(*) FROM norms")
        .fetch_one(&mut connection)
        .await
        .unwrap();
    assert_eq!(audited, stored, "a norm and its audit entry commit together");
    connection.close().await.unwrap();
    eprintln!(
        "crash test: {iterations} kills, {} acknowledged writes verified, {stored} stored",
        acknowledged.len()
    );
}

async fn check_all_present(client: &reqwest::Client, addr: &str, acknowledged: &[(i64, String)]) {
    let norms: Vec<Value> = client
        .get(format!("http://{addr}/v1/norms"))
        .send()
        .await
        .unwrap()
        .json()
        .await
        .unwrap();
    let stored: std::collections::HashMap<i64, &str> = norms
        .iter()
        .map(|n| (n["id"].as_i64().unwrap(), n["note"].as_str().unwrap()))
        .collect();
    for (id, note) in acknowledged {
        assert_eq!(
            stored.get(id).copied(),
            Some(note.as_str()),
            "acknowledged norm {id} was lost"
        );
    }
}
