//! Two `scruple serve` processes on loopback, one PostgreSQL database: a norm changed through
//! replica A is enforced by replica B on its very next request, also after B restarts, and the
//! other way round; and two replicas started at the same moment on a fresh database both come
//! up on one schema, on PostgreSQL and on a SQLite file.

use std::process::Stdio;

use reqwest::StatusCode;
use serde_json::{Value, json};

use crate::backends::PgDatabase;
use crate::helpers::{KeepAsking, Served, get_vase, serve_binary, try_serve_binary};

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
/// together), so that both find the database without a schema. `Err` names each start that
/// failed and what it said; a replica that did come up is then stopped with the failure.
fn start_two_at_once(database_url: &str) -> Result<[Replica; 2], String> {
    let together = std::sync::Barrier::new(2);
    let [a, b] = std::thread::scope(|scope| {
        let start = || {
            together.wait();
            try_serve_binary(database_url).map(|served| Replica {
                base: format!("http://{}", served.addr),
                served,
            })
        };
        let (a, b) = (scope.spawn(start), scope.spawn(start));
        [
            a.join().expect("replica A's start"),
            b.join().expect("replica B's start"),
        ]
    });
    match (a, b) {
        (Ok(a), Ok(b)) => Ok([a, b]),
        (a, b) => Err([("A", a.err()), ("B", b.err())]
            .into_iter()
            .filter_map(|(name, failed)| failed.map(|e| format!("{name} did not start: {e}")))
            .collect::<Vec<_>>()
            .join("; ")),
    }
}

/// What `_sqlx_migrations` says: how many migrations are recorded, and how many of those failed.
async fn migrations_recorded(database_url: &str) -> (usize, i64) {
    use sqlx::Connection;
    const SQL: &str = "SELECT count(*), coalesce(sum(CASE WHEN success THEN 0 ELSE 1 END), 0) FROM _sqlx_migrations";
    let (recorded, failed): (i64, i64) = if scruple::storage::is_postgres(database_url) {
        let mut connection = sqlx::PgConnection::connect(database_url).await.unwrap();
        sqlx::query_as(SQL).fetch_one(&mut connection).await.unwrap()
    } else {
        let mut connection = sqlx::SqliteConnection::connect(database_url).await.unwrap();
        sqlx::query_as(SQL).fetch_one(&mut connection).await.unwrap()
    };
    (recorded as usize, failed)
}

/// Two replicas started together on `database_url` both come up on one schema: both healthy,
/// each of the `migrations` recorded once and applied, one seeded library, and one norm set (a
/// norm added through A is enforced by B; it stays there, so a second pair on the same store
/// meets it). `Err` when either did not start.
async fn both_come_up_on_one_schema(database_url: &str, migrations: usize) -> Result<[Replica; 2], String> {
    let replicas = start_two_at_once(database_url)?;
    let client = crate::helpers::http_client();
    let mut libraries = Vec::new();
    for replica in &replicas {
        let health = client.get(format!("{}/healthz", replica.base)).send().await.unwrap();
        assert_eq!(health.status(), StatusCode::OK);
        let library = client.get(format!("{}/v1/actions", replica.base)).send().await.unwrap();
        libraries.push(library.text().await.unwrap());
    }
    assert_eq!(libraries[0], libraries[1]);
    let seeded: Vec<Value> = serde_json::from_str(&libraries[0]).unwrap();
    assert_eq!(seeded.len(), scruple::engine::Library::default_library().verbs().len());
    assert_eq!(migrations_recorded(database_url).await, (migrations, 0));
    let [a, b] = &replicas;
    let created = client
        .post(format!("{}/v1/norms", a.base))
        .json(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
        .send()
        .await
        .unwrap();
    assert_eq!(created.status(), StatusCode::CREATED);
    assert_eq!(b.decide(&client).await["decision"], "assume");
    Ok(replicas)
}

/// How many migrations a backend's folder holds.
fn migrations_in(backend: &str) -> usize {
    let folder = format!("{}/migrations/{backend}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_dir(folder).unwrap().count()
}

/// Two replicas of a new deployment start together on one fresh database: both come up (the
/// migrations run once, under their advisory lock, while the other waits), each migration is
/// recorded once, and both serve one seeded library and one norm set.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_replicas_started_at_once_on_a_fresh_database_both_come_up_on_one_schema() {
    for attempt in 0..2 {
        let database = PgDatabase::create().await;
        let replicas = both_come_up_on_one_schema(&database.url, migrations_in("postgres"))
            .await
            .unwrap_or_else(|e| panic!("attempt {attempt}: {e}"));
        replicas.into_iter().for_each(Replica::stop);
    }
}

/// Finding: two processes started together on a new SQLite file both applied the migrations
/// (sqlx's SQLite migrator takes no lock), and one of them failed to start in most tries
/// ("UNIQUE constraint failed: _sqlx_migrations.version", "duplicate column name: roles_json",
/// "table norms already exists"). The migrations now run under SQLite's write lock, so the
/// second waits for the first and finds them applied. Ten rounds on ten new files, each
/// followed by two processes started together on the file just migrated (a restart of both):
/// every start comes up on one schema, and the norm the first pair stored is still in force.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_processes_started_at_once_on_a_new_sqlite_file_both_come_up_on_one_schema() {
    const ROUNDS: usize = 10;
    let client = crate::helpers::http_client();
    let mut failed = Vec::new();
    for round in 0..ROUNDS {
        let dir = tempfile::tempdir().unwrap();
        let url = format!("sqlite://{}", dir.path().join("scruple.db").display());
        match both_come_up_on_one_schema(&url, migrations_in("sqlite")).await {
            Ok(replicas) => replicas.into_iter().for_each(Replica::stop),
            Err(e) => {
                failed.push(format!("round {round}, new file: {e}"));
                continue;
            }
        }
        match start_two_at_once(&url) {
            Ok(replicas) => {
                for replica in &replicas {
                    assert_eq!(replica.decide(&client).await["decision"], "assume", "round {round}");
                }
                assert_eq!(migrations_recorded(&url).await, (migrations_in("sqlite"), 0));
                replicas.into_iter().for_each(Replica::stop);
            }
            Err(e) => failed.push(format!("round {round}, migrated file: {e}")),
        }
    }
    assert!(
        failed.is_empty(),
        "{} of {ROUNDS} rounds had a start fail:\n{}",
        failed.len(),
        failed.join("\n")
    );
}

/// A start that cannot have the database's write lock to migrate it (another process holds it:
/// here the test's own connection) waits for it as a writer does, 5 s, and then fails naming the
/// database: it never hangs, and never serves on a schema it could not check. Once the lock is
/// let go, a start comes up on the same file.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_start_kept_from_the_write_lock_fails_after_a_bounded_wait_naming_the_database() {
    use sqlx::Connection;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("held.db");
    let url = format!("sqlite://{}", path.display());
    Replica::start(&url).stop();
    let mut holder = sqlx::SqliteConnection::connect(&url).await.unwrap();
    sqlx::query("BEGIN IMMEDIATE").execute(&mut holder).await.unwrap();
    let began = std::time::Instant::now();
    let refused = try_serve_binary(&url).err().expect("no start while the lock is held");
    let waited = began.elapsed();
    assert!(
        refused.contains(&format!("{}: another process kept the database locked", path.display())),
        "{refused}"
    );
    let bounds = std::time::Duration::from_millis(4_500)..std::time::Duration::from_secs(15);
    assert!(bounds.contains(&waited), "waited {waited:?}");
    sqlx::query("ROLLBACK").execute(&mut holder).await.unwrap();
    holder.close().await.unwrap();
    Replica::start(&url).stop();
}
