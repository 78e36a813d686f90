//! The same storage suite on both backends: SQLite (a fresh file) and PostgreSQL (a fresh
//! database on the server at `SCRUPLE_TEST_POSTGRES_URL`, default
//! `postgres://postgres@127.0.0.1:5432/postgres`; `.ci/run` starts it). Each test runs once per
//! backend; a PostgreSQL that cannot be reached fails the test, loudly.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use scruple::engine::action::ActionInput;
use scruple::engine::norms::{NormInput, NormSetMode, NormSpec};
use scruple::error::Error;
use scruple::storage::{NormStore, PostgresStore, SqliteStore, StoredAction, Write};
use sqlx::Connection;

/// The server's admin URL, where per-test databases are created.
pub fn postgres_admin_url() -> String {
    std::env::var("SCRUPLE_TEST_POSTGRES_URL").unwrap_or_else(|_| "postgres://postgres@127.0.0.1:5432/postgres".into())
}

/// A database of its own on the PostgreSQL server; dropped when the value is.
pub struct PgDatabase {
    pub url: String,
    name: String,
}

static NEXT: AtomicUsize = AtomicUsize::new(0);

impl PgDatabase {
    pub async fn create() -> PgDatabase {
        let admin = postgres_admin_url();
        let name = format!(
            "scruple_test_{}_{}",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        );
        let mut connection = sqlx::PgConnection::connect(&admin).await.unwrap_or_else(|e| {
            panic!("PostgreSQL at {admin} is needed for this test (set SCRUPLE_TEST_POSTGRES_URL): {e}")
        });
        for sql in [
            format!("DROP DATABASE IF EXISTS {name} WITH (FORCE)"),
            format!("CREATE DATABASE {name}"),
        ] {
            sqlx::raw_sql(sqlx::AssertSqlSafe(sql))
                .execute(&mut connection)
                .await
                .unwrap();
        }
        connection.close().await.unwrap();
        let (base, _) = admin.rsplit_once('/').expect("a URL ending in /database");
        PgDatabase {
            url: format!("{base}/{name}"),
            name,
        }
    }
}

impl PgDatabase {
    /// Runs `sql` straight on the database, as a hand edit or an older build would have.
    pub async fn execute(&self, sql: &str) -> Result<(), sqlx::Error> {
        let mut connection = sqlx::PgConnection::connect(&self.url).await?;
        sqlx::raw_sql(sqlx::AssertSqlSafe(sql.to_owned()))
            .execute(&mut connection)
            .await?;
        connection.close().await
    }
}

impl Drop for PgDatabase {
    fn drop(&mut self) {
        let admin = postgres_admin_url();
        let sql = format!("DROP DATABASE IF EXISTS {} WITH (FORCE)", self.name);
        // A drop runs outside any runtime the test may be ending; a thread of its own has one.
        let _ = std::thread::spawn(move || {
            let runtime = tokio::runtime::Builder::new_current_thread()
                .enable_all()
                .build()
                .ok()?;
            runtime.block_on(async {
                let mut connection = sqlx::PgConnection::connect(&admin).await.ok()?;
                sqlx::raw_sql(sqlx::AssertSqlSafe(sql))
                    .execute(&mut connection)
                    .await
                    .ok()
            })
        })
        .join();
    }
}

/// What keeps a backend alive for the length of a test.
enum Keep {
    Dir(#[allow(dead_code)] tempfile::TempDir),
    Database(#[allow(dead_code)] PgDatabase),
}

async fn sqlite() -> (Arc<dyn NormStore>, Keep) {
    let dir = tempfile::tempdir().unwrap();
    let url = format!("sqlite://{}", dir.path().join("store.db").display());
    (Arc::new(SqliteStore::open(&url).await.unwrap()), Keep::Dir(dir))
}

async fn postgres() -> (Arc<dyn NormStore>, Keep) {
    let database = PgDatabase::create().await;
    let store = PostgresStore::open(&database.url)
        .await
        .expect("the PostgreSQL store opens and migrates");
    (Arc::new(store), Keep::Database(database))
}

/// One test per backend, from one body taking the store.
macro_rules! on_both_backends {
    ($name:ident, $body:expr) => {
        mod $name {
            use super::*;

            #[tokio::test(flavor = "multi_thread", worker_threads = 4)]
            async fn sqlite() {
                let (store, _keep) = super::sqlite().await;
                ($body)(store).await;
            }

            #[tokio::test(flavor = "multi_thread", worker_threads = 4)]
            async fn postgres() {
                let (store, _keep) = super::postgres().await;
                ($body)(store).await;
            }
        }
    };
}

fn spec(kind: &str, term: &str) -> NormSpec {
    let mut input = NormInput {
        kind: Some(kind.into()),
        ..NormInput::default()
    };
    if kind.ends_with("_action") {
        input.action = Some(term.into());
    } else {
        input.state = Some(term.into());
    }
    input.validate().unwrap()
}

fn noted(note: &str) -> NormSpec {
    NormSpec {
        note: Some(note.into()),
        ..spec("forbidden_action", "destroy")
    }
}

on_both_backends!(
    norms_are_created_read_replaced_and_deleted_with_revisions,
    |store: Arc<dyn NormStore>| async move {
        let start = store.versions().await.unwrap();
        assert_eq!(start.norms, 0);
        let vase = spec("forbidden_state", "did(self,get(object3))");
        let first = store.create(&vase, "alice").await.unwrap();
        let second = store.create(&noted("x"), "alice").await.unwrap();
        assert!(second.id > first.id);
        assert_eq!(
            (first.revision, second.revision),
            (1, 2),
            "a revision is the set version of its write"
        );
        assert_eq!(store.get(first.id).await.unwrap().as_ref(), Some(&first));
        let (version, all) = store.load().await.unwrap();
        assert_eq!((version, all), (2, vec![first.clone(), second.clone()]));

        let replaced = store
            .replace(first.id, &noted("y"), Some(first.revision), "bob")
            .await
            .unwrap();
        let Write::Done(replaced) = replaced else {
            panic!("{replaced:?}")
        };
        assert_eq!((replaced.id, replaced.revision), (first.id, 3));
        let stale = store
            .replace(first.id, &vase, Some(first.revision), "bob")
            .await
            .unwrap();
        assert_eq!(stale, Write::Stale { current: 3 });
        assert_eq!(store.replace(999, &vase, None, "bob").await.unwrap(), Write::Missing);
        assert_eq!(
            store.delete(first.id, Some(1), "bob").await.unwrap(),
            Write::Stale { current: 3 }
        );
        assert_eq!(store.delete(first.id, Some(3), "bob").await.unwrap(), Write::Done(()));
        assert_eq!(store.delete(first.id, None, "bob").await.unwrap(), Write::Missing);
        assert_eq!(store.versions().await.unwrap().norms, 4, "refused writes move nothing");
        // A fresh id never reuses a deleted one.
        let third = store.create(&vase, "alice").await.unwrap();
        assert!(third.id > second.id);
    }
);

on_both_backends!(every_norm_kind_is_stored_and_read_back_as_it_was, |store: Arc<
    dyn NormStore,
>| async move {
    let kinds = [
        ("forbidden_action", "destroy"),
        ("forbidden_state", "holding(self,X)"),
        ("discouraged_action", "get(X)"),
        ("discouraged_state", "holding(self,X)"),
        ("preferred_action", "get(X)"),
        ("preferred_state", "on(X,tray1)"),
    ];
    let mut stored = Vec::new();
    for (kind, term) in kinds {
        let norm = NormSpec {
            severity: 2,
            when: vec![scruple::engine::term::Term::parse("dirty(X)").unwrap()],
            ..spec(kind, term)
        };
        let created = store.create(&norm, "alice").await.unwrap();
        assert_eq!(created.spec, norm, "{kind}");
        stored.push(created);
    }
    let (_, all) = store.load().await.unwrap();
    assert_eq!(all, stored, "each kind is read back as written");
});

on_both_backends!(
    an_import_replaces_the_set_keeping_ids_and_numbering_fresh_ones_above,
    |store: Arc<dyn NormStore>| async move {
        store.create(&noted("old"), "alice").await.unwrap();
        let current = store.versions().await.unwrap().norms;
        let stale = store
            .import(&[(None, noted("new"))], NormSetMode::Replace, Some(current + 5), "bob")
            .await
            .unwrap();
        assert_eq!(stale, Write::Stale { current });
        let norms = [
            (None, noted("fresh")),
            (Some(40), noted("forty")),
            (Some(7), noted("seven")),
        ];
        let Write::Done((version, after)) = store
            .import(&norms, NormSetMode::Replace, Some(current), "bob")
            .await
            .unwrap()
        else {
            panic!("the import was refused")
        };
        let ids: Vec<(i64, &str)> = after.iter().map(|n| (n.id, n.spec.note.as_deref().unwrap())).collect();
        assert_eq!(ids, vec![(7, "seven"), (40, "forty"), (41, "fresh")]);
        assert_eq!(store.load().await.unwrap(), (version, after));
        let next = store.create(&noted("next"), "alice").await.unwrap();
        assert!(next.id > 41, "fresh ids come after every imported one: {}", next.id);
    }
);

on_both_backends!(
    a_merge_replaces_the_norms_it_names_and_keeps_the_rest_with_their_revisions,
    |store: Arc<dyn NormStore>| async move {
        let kept = store.create(&noted("kept"), "alice").await.unwrap();
        let named = store.create(&noted("named"), "alice").await.unwrap();
        let norms = [
            (Some(named.id), noted("renamed")),
            (None, noted("fresh")),
            (Some(90), noted("ninety")),
        ];
        let Write::Done((version, after)) = store.import(&norms, NormSetMode::Merge, None, "bob").await.unwrap() else {
            panic!("the merge was refused")
        };
        let notes: Vec<(i64, &str)> = after.iter().map(|n| (n.id, n.spec.note.as_deref().unwrap())).collect();
        assert_eq!(
            notes,
            vec![(kept.id, "kept"), (named.id, "renamed"), (90, "ninety"), (91, "fresh")]
        );
        assert_eq!(after[0], kept, "a norm not named keeps its revision");
        assert!(after[1..].iter().all(|n| n.revision == version));
        let Write::Done((same, unchanged)) = store.import(&[], NormSetMode::Merge, None, "bob").await.unwrap() else {
            panic!("the empty merge was refused")
        };
        assert_eq!((same, &unchanged), (version, &after), "merging nothing changes nothing");
        assert_eq!(store.load().await.unwrap(), (version, after));
    }
);

on_both_backends!(every_change_is_audited_in_order_with_its_actor, |store: Arc<
    dyn NormStore,
>| async move {
    let norm = store.create(&noted("a"), "alice").await.unwrap();
    store.replace(norm.id, &noted("b"), None, "bob").await.unwrap();
    store.delete(norm.id, None, "carol").await.unwrap();
    store
        .import(&[(None, noted("c"))], NormSetMode::Replace, None, "dave")
        .await
        .unwrap();
    let entries = store.audit(0, 100).await.unwrap();
    let summary: Vec<(&str, &str, &str)> = entries
        .iter()
        .map(|e| (e.actor.as_str(), e.subject.as_str(), e.operation.as_str()))
        .collect();
    assert_eq!(
        summary,
        vec![
            ("alice", "norm", "create"),
            ("bob", "norm", "replace"),
            ("carol", "norm", "delete"),
            ("dave", "norm_set", "import"),
        ]
    );
    assert_eq!(entries[1].before.as_ref().unwrap()["note"], "a");
    assert_eq!(entries[1].after.as_ref().unwrap()["note"], "b");
    assert_eq!(entries.iter().map(|e| e.version).collect::<Vec<_>>(), vec![1, 2, 3, 4]);
    assert!(
        entries.iter().all(|e| e.at.len() == 24 && e.at.ends_with('Z')),
        "{:?}",
        entries[0].at
    );
    assert_eq!(store.audit(entries[1].id, 2).await.unwrap(), entries[2..4].to_vec());
});

on_both_backends!(
    verbs_are_put_refused_whole_and_deleted,
    |store: Arc<dyn NormStore>| async move {
        let (start, verbs) = store.load_actions().await.unwrap();
        let names: Vec<&str> = verbs.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            [
                "clean",
                "close",
                "cut",
                "destroy",
                "discard",
                "get",
                "give",
                "heat",
                "open",
                "pointTo",
                "pour",
                "put",
                "steal",
                "switchOff",
                "switchOn"
            ]
        );
        let open: ActionInput =
            serde_json::from_value(serde_json::json!({"parameters": ["X"], "methods": [{"adds": ["open(X)"]}]}))
                .unwrap();
        let accept_all = |_: &[StoredAction]| Ok(());
        assert!(
            store
                .put_action("unseal", &open, &accept_all, "alice")
                .await
                .unwrap()
                .unwrap(),
            "a new verb"
        );
        assert!(
            !store
                .put_action("unseal", &open, &accept_all, "alice")
                .await
                .unwrap()
                .unwrap(),
            "a replaced verb"
        );
        let refuse = |all: &[StoredAction]| -> Result<(), Error> {
            assert!(
                all.iter().any(|(n, _)| n == "reseal"),
                "the judge sees the library as it would be"
            );
            Err(Error::invalid("/methods", "refused"))
        };
        assert!(
            store
                .put_action("reseal", &open, &refuse, "alice")
                .await
                .unwrap()
                .is_err()
        );
        // A delete the judge refuses (another verb calls it) writes nothing either.
        let keep = |rest: &[StoredAction]| -> Result<(), Error> {
            assert!(
                !rest.iter().any(|(n, _)| n == "unseal"),
                "the judge sees the library without it"
            );
            Err(Error::invalid("", "refused"))
        };
        assert!(store.delete_action("unseal", &keep, "bob").await.unwrap().is_err());
        assert!(
            store
                .delete_action("unseal", &accept_all, "bob")
                .await
                .unwrap()
                .unwrap()
        );
        assert!(
            !store
                .delete_action("unseal", &accept_all, "bob")
                .await
                .unwrap()
                .unwrap()
        );
        let (version, verbs) = store.load_actions().await.unwrap();
        assert_eq!(
            (version, verbs.len()),
            (start + 3, names.len()),
            "the refused verb and the refused delete moved nothing"
        );
        assert_eq!(store.audit(0, 10).await.unwrap().len(), 3);
    }
);

on_both_backends!(concurrent_conditional_writers_lose_no_update, |store: Arc<
    dyn NormStore,
>| async move {
    const WRITERS: usize = 8;
    const UPDATES: usize = 50;
    let id = store.create(&noted("0"), "setup").await.unwrap().id;
    let mut tasks = Vec::new();
    for writer in 0..WRITERS {
        let store = store.clone();
        tasks.push(tokio::spawn(async move {
            for _ in 0..UPDATES {
                loop {
                    let current = store.get(id).await.unwrap().unwrap();
                    let count: usize = current.spec.note.as_deref().unwrap().parse().unwrap();
                    let next = noted(&(count + 1).to_string());
                    match store
                        .replace(id, &next, Some(current.revision), &format!("w{writer}"))
                        .await
                    {
                        Ok(Write::Done(_)) => break,
                        Ok(Write::Stale { .. }) => continue,
                        other => panic!("{other:?}"),
                    }
                }
            }
        }));
    }
    for task in tasks {
        task.await.unwrap();
    }
    let last = store.get(id).await.unwrap().unwrap();
    assert_eq!(
        last.spec.note.as_deref(),
        Some((WRITERS * UPDATES).to_string().as_str())
    );
});
