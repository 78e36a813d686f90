//! The SQLite backend (the default): WAL mode, `synchronous=FULL`, migrations embedded and
//! applied at open under the database's write lock (so processes starting together on one file
//! migrate it once); one writer at a time through `BEGIN IMMEDIATE`.
//!
//! Must not: write outside a transaction, or keep serving from a database file that has been
//! deleted or replaced under it.

use std::path::Path;
use std::str::FromStr;
use std::sync::Arc;
use std::time::{Duration, Instant};

use async_trait::async_trait;
use sqlx::sqlite::{SqliteConnectOptions, SqliteJournalMode, SqlitePool, SqlitePoolOptions, SqliteSynchronous};
use sqlx::{Sqlite, Transaction};

use super::identity::FileIdentity;
use super::sql::{ACTIONS_SQL, AuditRow, Backend, Change, NormColumns, NormRow, Set, SqlStore, Tx, action_from_row};
use super::{AuditEntry, StoreError, StoredAction, Versions};
use crate::engine::norms::{Norm, NormSpec};

/// The norm store on SQLite.
pub type SqliteStore = SqlStore<SqliteBackend>;

#[derive(Clone, Debug)]
pub struct SqliteBackend {
    pool: SqlitePool,
    /// The database file as opened; `None` in memory. Open connections keep reading a file
    /// deleted or replaced under them, and writes to it would vanish, so every request checks
    /// that the path still names this file and fails closed when it does not.
    file: Option<Arc<FileIdentity>>,
}

/// How long a connection waits for another's write lock before it gives up: a write then
/// answers 503, and a start fails naming the database.
const LOCK_WAIT: Duration = Duration::from_secs(5);

impl SqliteStore {
    /// Opens (creating if missing) the database at `url` (`sqlite://scruple.db`, `sqlite::memory:`)
    /// and applies the embedded migrations.
    pub async fn open(url: &str) -> Result<SqliteStore, StoreError> {
        let options = SqliteConnectOptions::from_str(url)
            .map_err(|e| StoreError::new(format!("bad database URL `{url}`: {e}")))?
            .create_if_missing(true)
            .journal_mode(SqliteJournalMode::Wal)
            .synchronous(SqliteSynchronous::Full)
            .busy_timeout(LOCK_WAIT)
            .foreign_keys(true);
        let path = options.get_filename();
        let pool = connect(&options).await?;
        migrate(&pool, path).await?;
        let in_memory = url.contains(":memory:") || url.contains("mode=memory");
        let file = if in_memory {
            None
        } else {
            let file = FileIdentity::of(path).map_err(|e| StoreError::new(format!("{}: {e}", path.display())))?;
            Some(Arc::new(file))
        };
        Ok(SqlStore {
            backend: SqliteBackend { pool, file },
        })
    }

    pub fn pool(&self) -> &SqlitePool {
        &self.backend.pool
    }
}

/// The pool, its first connection made once no other process is turning a new file to WAL.
/// That change takes a lock SQLite's busy timeout does not wait for: a process that opens the
/// file at that moment is refused at once, so it tries again until [`LOCK_WAIT`] has passed.
async fn connect(options: &SqliteConnectOptions) -> Result<SqlitePool, StoreError> {
    let deadline = Instant::now() + LOCK_WAIT;
    loop {
        let connected = SqlitePoolOptions::new()
            .max_connections(8)
            .acquire_timeout(Duration::from_secs(5))
            .connect_with(options.clone())
            .await;
        match connected {
            Ok(pool) => return Ok(pool),
            Err(e) if is_busy(&e) && Instant::now() < deadline => {
                tokio::time::sleep(Duration::from_millis(10)).await;
            }
            Err(e) if is_busy(&e) => return Err(locked_out(options.get_filename(), "open it", e)),
            Err(e) => return Err(e.into()),
        }
    }
}

/// Applies the embedded migrations holding the database's write lock (`BEGIN IMMEDIATE`), from
/// before the applied ones are read until the last is committed. sqlx's SQLite migrator takes
/// no lock of its own: two processes starting together on a new file both found nothing applied,
/// both applied it, and one failed its start. Under the lock the later one waits for the first
/// (at most [`LOCK_WAIT`], then fails naming the file) and finds every migration applied. Each
/// migration is a savepoint of the one transaction, so a start that fails leaves none of its
/// migrations behind.
async fn migrate(pool: &SqlitePool, path: &Path) -> Result<(), StoreError> {
    let mut locked =
        (pool.begin_with("BEGIN IMMEDIATE").await).map_err(|e| locked_out(path, "apply the migrations", e))?;
    // `run_direct` is `run` on a connection already in hand: `run`'s `Acquire` bound on a
    // borrowed transaction keeps the compiler from proving `Send` the future of every task
    // that opens a store (sqlx keeps `run_direct` public for that).
    MIGRATOR
        .run_direct(None, &mut *locked, false)
        .await
        .map_err(|e| StoreError::new(format!("{}: migrations: {e}", path.display())))?;
    Ok(locked.commit().await?)
}

/// The SQLite schema's migrations, compiled in.
static MIGRATOR: sqlx::migrate::Migrator = sqlx::migrate!("./migrations/sqlite");

/// SQLite's `SQLITE_BUSY` and its extended codes: another connection holds the lock wanted.
fn is_busy(e: &sqlx::Error) -> bool {
    const SQLITE_BUSY: i32 = 5;
    let code = |e: &dyn sqlx::error::DatabaseError| e.code().and_then(|code| code.parse::<i32>().ok());
    matches!(e, sqlx::Error::Database(e) if code(&**e).is_some_and(|code| code & 0xff == SQLITE_BUSY))
}

/// A start refused because another process held the database's lock for too long: named by its
/// file, so that the operator knows which database to look at.
fn locked_out(path: &Path, to: &str, e: sqlx::Error) -> StoreError {
    if is_busy(&e) {
        StoreError::new(format!(
            "{}: another process kept the database locked for more than {} s; could not {to}: {e}",
            path.display(),
            LOCK_WAIT.as_secs()
        ))
    } else {
        StoreError::new(format!("{}: could not {to}: {e}", path.display()))
    }
}

pub struct SqliteTx(Transaction<'static, Sqlite>);

#[async_trait]
impl Tx for SqliteTx {
    async fn version(&mut self, set: Set) -> Result<i64, StoreError> {
        Ok(sqlx::query_scalar(set.sql().0).fetch_one(&mut *self.0).await?)
    }

    async fn bump(&mut self, set: Set) -> Result<i64, StoreError> {
        Ok(sqlx::query_scalar(set.sql().1).fetch_one(&mut *self.0).await?)
    }

    async fn norm(&mut self, id: i64) -> Result<Option<Norm>, StoreError> {
        let sql = concat!("SELECT ", norm_columns!(), " FROM norms WHERE id = ?");
        let row: Option<NormRow> = sqlx::query_as(sql).bind(id).fetch_optional(&mut *self.0).await?;
        row.map(NormRow::into_norm).transpose()
    }

    async fn norms(&mut self) -> Result<Vec<Norm>, StoreError> {
        let sql = concat!("SELECT ", norm_columns!(), " FROM norms ORDER BY id");
        let rows: Vec<NormRow> = sqlx::query_as(sql).fetch_all(&mut *self.0).await?;
        rows.into_iter().map(NormRow::into_norm).collect()
    }

    async fn upsert_norm(&mut self, id: Option<i64>, spec: &NormSpec, revision: i64) -> Result<i64, StoreError> {
        let c = NormColumns::of(spec)?;
        Ok(sqlx::query_scalar(
            "INSERT INTO norms (id, revision, kind, term, when_json, context, severity, note, roles_json, exempt_roles_json) \
             VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?) \
             ON CONFLICT (id) DO UPDATE SET revision = excluded.revision, kind = excluded.kind, term = excluded.term, \
             when_json = excluded.when_json, context = excluded.context, severity = excluded.severity, \
             note = excluded.note, roles_json = excluded.roles_json, exempt_roles_json = excluded.exempt_roles_json \
             RETURNING id",
        )
        .bind(id)
        .bind(revision)
        .bind(c.kind)
        .bind(c.term)
        .bind(c.when_json)
        .bind(spec.context.as_deref())
        .bind(c.severity)
        .bind(spec.note.as_deref())
        .bind(c.roles_json)
        .bind(c.exempt_roles_json)
        .fetch_one(&mut *self.0)
        .await?)
    }

    async fn delete_norms(&mut self, id: Option<i64>) -> Result<(), StoreError> {
        match id {
            Some(id) => {
                sqlx::query("DELETE FROM norms WHERE id = ?")
                    .bind(id)
                    .execute(&mut *self.0)
                    .await?
            }
            None => sqlx::query("DELETE FROM norms").execute(&mut *self.0).await?,
        };
        Ok(())
    }

    async fn after_explicit_ids(&mut self) -> Result<(), StoreError> {
        // AUTOINCREMENT already numbers after the largest id ever stored.
        Ok(())
    }

    async fn actions(&mut self) -> Result<Vec<StoredAction>, StoreError> {
        let rows: Vec<(String, String)> = sqlx::query_as(ACTIONS_SQL).fetch_all(&mut *self.0).await?;
        rows.into_iter().map(action_from_row).collect()
    }

    async fn upsert_action(&mut self, name: &str, definition: &str) -> Result<(), StoreError> {
        sqlx::query(
            "INSERT INTO actions (name, definition) VALUES (?, ?) \
             ON CONFLICT (name) DO UPDATE SET definition = excluded.definition, \
             updated_at = strftime('%Y-%m-%dT%H:%M:%fZ', 'now')",
        )
        .bind(name)
        .bind(definition)
        .execute(&mut *self.0)
        .await?;
        Ok(())
    }

    async fn delete_action(&mut self, name: &str) -> Result<(), StoreError> {
        sqlx::query("DELETE FROM actions WHERE name = ?")
            .bind(name)
            .execute(&mut *self.0)
            .await?;
        Ok(())
    }

    async fn record(&mut self, change: Change<'_>) -> Result<(), StoreError> {
        let text = |v: Option<serde_json::Value>| v.map(|v| v.to_string());
        sqlx::query(
            "INSERT INTO audit (actor, subject, operation, target, before_json, after_json, version) \
             VALUES (?, ?, ?, ?, ?, ?, ?)",
        )
        .bind(change.actor)
        .bind(change.subject.as_str())
        .bind(change.operation.as_str())
        .bind(change.target)
        .bind(text(change.before))
        .bind(text(change.after))
        .bind(change.version)
        .execute(&mut *self.0)
        .await?;
        Ok(())
    }

    async fn hold_lease(&mut self, lease_ms: i64, holder: &str) -> Result<i64, StoreError> {
        Ok(
            sqlx::query_scalar("INSERT INTO leases (lease_ms, holder) VALUES (?, ?) RETURNING id")
                .bind(lease_ms)
                .bind(holder)
                .fetch_one(&mut *self.0)
                .await?,
        )
    }

    async fn release_lease(&mut self, id: i64) -> Result<(), StoreError> {
        sqlx::query("DELETE FROM leases WHERE id = ?")
            .bind(id)
            .execute(&mut *self.0)
            .await?;
        Ok(())
    }

    async fn commit(self) -> Result<(), StoreError> {
        Ok(self.0.commit().await?)
    }

    async fn rollback(self) -> Result<(), StoreError> {
        Ok(self.0.rollback().await?)
    }
}

impl SqliteBackend {
    /// The file checked with a `stat` of its path, as writes and each lease's read are: they
    /// also see a change no event reports (a file system mounted over a directory of the path).
    fn stat(&self) -> Result<(), StoreError> {
        match &self.file {
            Some(file) => file.stat(),
            None => Ok(()),
        }
    }
}

#[async_trait]
impl Backend for SqliteBackend {
    fn migrator(&self) -> &'static sqlx::migrate::Migrator {
        &MIGRATOR
    }

    type Tx = SqliteTx;

    fn still_there(&self) -> Result<(), StoreError> {
        match &self.file {
            Some(file) => file.check(),
            None => Ok(()),
        }
    }

    async fn read(&self) -> Result<SqliteTx, StoreError> {
        Ok(SqliteTx(self.pool.begin().await?))
    }

    /// `BEGIN IMMEDIATE`: takes the write lock up front, so concurrent writers queue on the busy
    /// timeout instead of failing to upgrade a read lock.
    async fn write(&self) -> Result<SqliteTx, StoreError> {
        self.stat()?;
        Ok(SqliteTx(self.pool.begin_with("BEGIN IMMEDIATE").await?))
    }

    async fn versions(&self) -> Result<Versions, StoreError> {
        self.stat()?;
        let (norms, actions): (i64, i64) = sqlx::query_as(
            "SELECT (SELECT version FROM norm_set WHERE id = 1), (SELECT version FROM action_set WHERE id = 1)",
        )
        .fetch_one(&self.pool)
        .await?;
        Ok(Versions { norms, actions })
    }

    async fn longest_lease_ms(&self) -> Result<i64, StoreError> {
        Ok(sqlx::query_scalar("SELECT COALESCE(MAX(lease_ms), 0) FROM leases")
            .fetch_one(&self.pool)
            .await?)
    }

    async fn audit(&self, after: i64, limit: i64) -> Result<Vec<AuditEntry>, StoreError> {
        let rows: Vec<AuditRow> = sqlx::query_as(
            "SELECT id, at, actor, subject, operation, target, before_json, after_json, version \
             FROM audit WHERE id > ? ORDER BY id LIMIT ?",
        )
        .bind(after)
        .bind(limit)
        .fetch_all(&self.pool)
        .await?;
        rows.into_iter().map(AuditRow::into_entry).collect()
    }
}
