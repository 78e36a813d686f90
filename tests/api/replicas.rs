//! Two `scruple serve` processes on loopback, one PostgreSQL database: a norm changed through
//! replica A is enforced by replica B on its very next request, also after B restarts, and the
//! other way round; and two replicas started at the same moment on a fresh database both come
//! up on one schema.

use std::process::Stdio;

use reqwest::StatusCode;
use serde_json::{Value, json};

use crate::backends::PgDatabase;
use crate::helpers::{KeepAsking, Served, get_vase, serve_binary};

struct Replica {
    served: Served,
    base: String,
}

impl Replica {
    fn start(database_url: &str) -> Replica {
        let served = serve_binary(database_url, &[], &[], Stdio::inherit());
        Replica {
            base: format!("http://{}", served.addr),
            served,
        }
    }

    async fn decide(&self, client: &reqwest::Client) -> Value {
        let response = client
            .post(format!("{}/v1/clarify", self.base))
            .json(&get_vase())
            .send()
            .await
            .unwrap();
        assert_eq!(response.status(), StatusCode::OK);
        response.json().await.unwrap()
    }

    fn stop(self) {
        self.served.terminate();
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_change_through_one_replica_is_enforced_by_the_other_on_its_next_request() {
    let database = PgDatabase::create().await;
    let a = Replica::start(&database.url);
    let b = Replica::start(&database.url);
    let client = crate::helpers::http_client();
    // Warm B's cache under the empty norm set: both vases may be got, so it asks.
    assert_eq!(b.decide(&client).await["decision"], "ask");

    let norm = json!({"kind": "forbidden_state", "state": "did(self,get(object3))"});
    let created = client
        .post(format!("{}/v1/norms", a.base))
        .json(&norm)
        .send()
        .await
        .unwrap();
    assert_eq!(created.status(), StatusCode::CREATED);
    let id = created.json::<Value>().await.unwrap()["id"].as_i64().unwrap();
    // No wait, no notification: B's very next request reads the new version.
    let decided = b.decide(&client).await;
    assert_eq!(decided["decision"], "assume", "{decided}");
    assert_eq!(decided["goal"], "did(self,get(object4))");

    // B restarts and still enforces it; a delete through B reaches A at once.
    b.stop();
    let b = Replica::start(&database.url);
    assert_eq!(b.decide(&client).await["decision"], "assume");
    let deleted = client.delete(format!("{}/v1/norms/{id}", b.base)).send().await.unwrap();
    assert_eq!(deleted.status(), StatusCode::NO_CONTENT);
    assert_eq!(a.decide(&client).await["decision"], "ask");
    // Both list the same set and audit trail.
    let audit_a: Value = client
        .get(format!("{}/v1/audit", a.base))
        .send()
        .await
        .unwrap()
        .json()
        .await
        .unwrap();
    let audit_b: Value = client
        .get(format!("{}/v1/audit", b.base))
        .send()
        .await
        .unwrap()
        .json()
        .await
        .unwrap();
    assert_eq!(audit_a, audit_b);
    assert_eq!(audit_a["entries"].as_array().unwrap().len(), 2);
    a.stop();
    b.stop();
}

/// The lease on the stored versions, across replicas: B is kept busy (its lease always fresh),
/// and every change acknowledged by A is enforced by B's first request after it.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn every_change_acknowledged_by_one_replica_is_seen_at_once_by_a_busy_other() {
    let database = PgDatabase::create().await;
    let a = Replica::start(&database.url);
    let b = Replica::start(&database.url);
    let client = crate::helpers::http_client();
    let busy = KeepAsking::at(&b.base);
    for round in 0..20 {
        let created = client
            .post(format!("{}/v1/norms", a.base))
            .json(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
            .send()
            .await
            .unwrap();
        assert_eq!(created.status(), StatusCode::CREATED);
        let id = created.json::<Value>().await.unwrap()["id"].as_i64().unwrap();
        let decided = b.decide(&client).await;
        assert_eq!(decided["decision"], "assume", "round {round}: {decided}");
        let deleted = client.delete(format!("{}/v1/norms/{id}", a.base)).send().await.unwrap();
        assert_eq!(deleted.status(), StatusCode::NO_CONTENT);
        let decided = b.decide(&client).await;
        assert_eq!(decided["decision"], "ask", "round {round}: {decided}");
    }
    assert!(busy.stop().await > 40, "B was kept busy");
    a.stop();
    b.stop();
}

/// Starts two replicas on `database_url` at the same moment (each from its own thread, released
/// together), so that both find the database without a schema.
fn start_two_at_once(database_url: &str) -> [Replica; 2] {
    let together = std::sync::Barrier::new(2);
    std::thread::scope(|scope| {
        let start = || {
            together.wait();
            Replica::start(database_url)
        };
        let (a, b) = (scope.spawn(start), scope.spawn(start));
        [a.join().expect("replica A starts"), b.join().expect("replica B starts")]
    })
}

/// Two replicas of a new deployment start together on one fresh database: both come up (the
/// migrations run once, under their advisory lock, while the other waits), each migration is
/// recorded once, and both serve one seeded library and one norm set.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_replicas_started_at_once_on_a_fresh_database_both_come_up_on_one_schema() {
    let migrations = std::fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/migrations/postgres"))
        .unwrap()
        .count();
    let client = crate::helpers::http_client();
    for attempt in 0..2 {
        let database = PgDatabase::create().await;
        let replicas = start_two_at_once(&database.url);
        let mut libraries = Vec::new();
        for replica in &replicas {
            let health = client.get(format!("{}/healthz", replica.base)).send().await.unwrap();
            assert_eq!(health.status(), StatusCode::OK, "attempt {attempt}");
            let library = client.get(format!("{}/v1/actions", replica.base)).send().await.unwrap();
            libraries.push(library.text().await.unwrap());
        }
        assert_eq!(libraries[0], libraries[1], "attempt {attempt}");
        let seeded: Vec<Value> = serde_json::from_str(&libraries[0]).unwrap();
        assert_eq!(seeded.len(), scruple::engine::Library::default_library().verbs().len());
        let mut connection = <sqlx::PgConnection as sqlx::Connection>::connect(&database.url)
            .await
            .unwrap();
        let (recorded, all_applied): (i64, bool) =
            sqlx::query_as("SELECT count(*), bool_and(success) FROM _sqlx_migrations")
                .fetch_one(&mut connection)
                .await
                .unwrap();
        assert_eq!(
            (recorded as usize, all_applied),
            (migrations, true),
            "attempt {attempt}"
        );
        // One norm set: a norm through one is enforced by the other.
        let [a, b] = replicas;
        let created = client
            .post(format!("{}/v1/norms", a.base))
            .json(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
            .send()
            .await
            .unwrap();
        assert_eq!(created.status(), StatusCode::CREATED);
        assert_eq!(b.decide(&client).await["decision"], "assume", "attempt {attempt}");
        a.stop();
        b.stop();
    }
}
