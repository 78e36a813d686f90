//! Processes sharing one store with different `--versions-lease-ms`: a write through the one
//! with the shortest lease is still seen by the very next request on the one with the longest,
//! on a SQLite file and on PostgreSQL, and the wait goes back down once that process has left.

use std::process::Stdio;
use std::time::{Duration, Instant};

use reqwest::StatusCode;
use serde_json::{Value, json};

use crate::backends::PgDatabase;
use crate::helpers::{KeepAsking, Served, get_vase, serve_binary};

/// The longer lease: long enough that a stale answer could not hide in the timing.
const LONG_MS: u64 = 2_000;

/// A server process, killed if the test ends (or fails) before it is stopped.
struct Running(Option<Served>);

impl std::ops::Deref for Running {
    type Target = Served;

    fn deref(&self) -> &Served {
        self.0.as_ref().expect("running")
    }
}

impl Running {
    /// SIGTERM, then its exit status once it has drained.
    async fn terminate(mut self) -> std::process::ExitStatus {
        let served = self.0.take().expect("running");
        tokio::task::spawn_blocking(move || served.terminate()).await.unwrap()
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        if let Some(mut served) = self.0.take() {
            let _ = served.child.kill();
            let _ = served.child.wait();
        }
    }
}

fn start(database_url: &str, lease_ms: u64) -> Running {
    Running(Some(serve_binary(
        database_url,
        &["--versions-lease-ms", &lease_ms.to_string()],
        &[],
        Stdio::inherit(),
    )))
}

async fn decide(client: &reqwest::Client, served: &Served) -> Value {
    let response = client
        .post(format!("http://{}/v1/clarify", served.addr))
        .json(&get_vase())
        .send()
        .await
        .unwrap();
    assert_eq!(response.status(), StatusCode::OK);
    response.json().await.unwrap()
}

/// Adds the paper's vase norm through `served`; its id and how long the acknowledgement took.
async fn forbid_the_fragile_vase(client: &reqwest::Client, served: &Served) -> (i64, Duration) {
    let began = Instant::now();
    let created = client
        .post(format!("http://{}/v1/norms", served.addr))
        .json(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
        .send()
        .await
        .unwrap();
    let took = began.elapsed();
    assert_eq!(created.status(), StatusCode::CREATED);
    (created.json::<Value>().await.unwrap()["id"].as_i64().unwrap(), took)
}

/// A at lease 0 acknowledged in milliseconds while B, at 2,000, kept answering under the norms
/// it had read: every request B began in the next two seconds decided under the old version.
/// Every writer now waits out the longest lease of any process serving the store.
async fn a_short_lease_writer_waits_out_the_long_lease_of_another_process(database_url: &str) {
    let a = start(database_url, 0);
    let b = start(database_url, LONG_MS);
    let client = crate::helpers::http_client();
    let busy = KeepAsking::at(&format!("http://{}", b.addr));
    assert_eq!(decide(&client, &b).await["decision"], "ask");

    let (id, took) = forbid_the_fragile_vase(&client, &a).await;
    let decided = decide(&client, &b).await;
    assert_eq!(decided["decision"], "assume", "B after A's acknowledgement: {decided}");
    assert!(
        took >= Duration::from_millis(LONG_MS),
        "A acknowledged after {took:?}, inside B's lease"
    );
    let deleted = client
        .delete(format!("http://{}/v1/norms/{id}", a.addr))
        .send()
        .await
        .unwrap();
    assert_eq!(deleted.status(), StatusCode::NO_CONTENT);
    assert_eq!(decide(&client, &b).await["decision"], "ask");
    assert!(busy.stop().await > 10, "B was kept busy");

    // B drains and leaves: A's writes no longer wait for a lease nobody holds.
    assert!(b.terminate().await.success());
    let (_, took) = forbid_the_fragile_vase(&client, &a).await;
    assert!(took < Duration::from_millis(LONG_MS / 2), "A still waited {took:?}");
    assert!(a.terminate().await.success());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn on_sqlite_a_short_lease_writer_waits_out_another_process_long_lease() {
    let dir = tempfile::tempdir().unwrap();
    let url = format!("sqlite://{}", dir.path().join("shared.db").display());
    a_short_lease_writer_waits_out_the_long_lease_of_another_process(&url).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn on_postgresql_a_short_lease_writer_waits_out_another_replica_long_lease() {
    let database = PgDatabase::create().await;
    a_short_lease_writer_waits_out_the_long_lease_of_another_process(&database.url).await;
}
