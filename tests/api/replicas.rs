//! Two `scruple serve` processes on loopback, one PostgreSQL database: a norm changed through
//! replica A is enforced by replica B on its very next request, also after B restarts, and the
//! other way round.

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
