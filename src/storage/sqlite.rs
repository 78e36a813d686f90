//! The SQLite backend (the default): WAL mode, `synchronous=FULL`, migrations embedded and
//! applied at open; one writer at a time through `BEGIN IMMEDIATE`.
//!
//! Must not: write outside a transaction, or keep serving from a database file that has been
//! deleted or replaced under it.

use std::str::FromStr;
use std::sync::Arc;
use std::time::Duration;

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

impl SqliteStore {
    /// Opens (creating if missing) the database at `url` (`sqlite://scruple.db`, `sqlite::memory:`)
    /// and applies the embedded migrations.
    pub async fn open(url: &str) -> Result<SqliteStore, StoreError> {
        let options = SqliteConnectOptions::from_str(url)
            .map_err(|e| StoreError::new(format!("bad database URL `{url}`: {e}")))?
            .create_if_missing(true)
            .journal_mode(SqliteJournalMode::Wal)
            .synchronous(SqliteSynchronous::Full)
            .busy_timeout(Duration::from_secs(5))
            .foreign_keys(true);
        let pool = SqlitePoolOptions::new()
            .max_connections(8)
            .acquire_timeout(Duration::from_secs(5))
            .connect_with(options.clone())
            .await?;
        sqlx::migrate!("./migrations/sqlite")
            .run(&pool)
            .await
            .map_err(|e| StoreError::new(format!("migrations: {e}")))?;
        let path = options.get_filename();
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
