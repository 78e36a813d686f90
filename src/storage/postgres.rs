//! The PostgreSQL backend, for several replicas sharing one norm set: migrations embedded and
//! applied at open (under sqlx's advisory lock, so replicas starting together migrate once);
//! one writer at a time by row locks on the two version rows, waited for at most `lock_timeout`.
//!
//! Must not: write outside a transaction, or read a version and its rows from two snapshots.

use std::str::FromStr;
use std::time::Duration;

use async_trait::async_trait;
use sqlx::postgres::{PgConnectOptions, PgPool, PgPoolOptions};
use sqlx::{Postgres, Transaction};

use super::sql::{ACTIONS_SQL, AuditRow, Backend, Change, NormColumns, NormRow, Set, SqlStore, Tx, action_from_row};
use super::{AuditEntry, StoreError, StoredAction, Versions};
use crate::engine::norms::{Norm, NormSpec};

/// The norm store on PostgreSQL.
pub type PostgresStore = SqlStore<PostgresBackend>;

/// The PostgreSQL schema's migrations, compiled in.
static MIGRATOR: sqlx::migrate::Migrator = sqlx::migrate!("./migrations/postgres");

#[derive(Clone, Debug)]
pub struct PostgresBackend {
    pool: PgPool,
}

impl PostgresStore {
    /// Connects to `postgres://user:password@host:port/database` and applies the migrations.
    pub async fn open(url: &str) -> Result<PostgresStore, StoreError> {
        PostgresStore::migrated(PostgresStore::connect(url).await?).await
    }

    /// As [`PostgresStore::open`], only if the database already holds a store (its norm set):
    /// `None`, with nothing created, when it does not (the offline commands read a store, never
    /// make an empty one to decide under).
    pub async fn open_existing(url: &str) -> Result<Option<PostgresStore>, StoreError> {
        let pool = PostgresStore::connect(url).await?;
        let holds: bool = sqlx::query_scalar("SELECT to_regclass('norm_set') IS NOT NULL")
            .fetch_one(&pool)
            .await?;
        if !holds {
            pool.close().await;
            return Ok(None);
        }
        PostgresStore::migrated(pool).await.map(Some)
    }

    async fn connect(url: &str) -> Result<PgPool, StoreError> {
        // The URL may carry a password: errors name the problem, never the URL.
        let options = PgConnectOptions::from_str(url)
            .map_err(|e| StoreError::new(format!("bad PostgreSQL URL: {e}")))?
            .options([("lock_timeout", "5s"), ("statement_timeout", "30s")]);
        Ok(PgPoolOptions::new()
            .max_connections(8)
            .acquire_timeout(Duration::from_secs(5))
            .connect_with(options)
            .await?)
    }

    async fn migrated(pool: PgPool) -> Result<PostgresStore, StoreError> {
        MIGRATOR
            .run(&pool)
            .await
            .map_err(|e| StoreError::new(format!("migrations: {e}")))?;
        Ok(SqlStore {
            backend: PostgresBackend { pool },
        })
    }

    pub fn pool(&self) -> &PgPool {
        &self.backend.pool
    }
}

pub struct PostgresTx(Transaction<'static, Postgres>);

#[async_trait]
impl Tx for PostgresTx {
    async fn version(&mut self, set: Set) -> Result<i64, StoreError> {
        Ok(sqlx::query_scalar(set.sql().0).fetch_one(&mut *self.0).await?)
    }

    async fn bump(&mut self, set: Set) -> Result<i64, StoreError> {
        Ok(sqlx::query_scalar(set.sql().1).fetch_one(&mut *self.0).await?)
    }

    async fn norm(&mut self, id: i64) -> Result<Option<Norm>, StoreError> {
        let sql = concat!("SELECT ", norm_columns!(), " FROM norms WHERE id = $1");
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
        // Without an id the identity column numbers it; with one, that row is written.
        let sql = match id {
            None => {
                "INSERT INTO norms (revision, kind, term, when_json, context, severity, note, roles_json, exempt_roles_json) \
                 VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9) RETURNING id"
            }
            Some(_) => {
                "INSERT INTO norms (revision, kind, term, when_json, context, severity, note, roles_json, exempt_roles_json, id) \
                 VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10) \
                 ON CONFLICT (id) DO UPDATE SET revision = excluded.revision, kind = excluded.kind, term = excluded.term, \
                 when_json = excluded.when_json, context = excluded.context, severity = excluded.severity, \
                 note = excluded.note, roles_json = excluded.roles_json, exempt_roles_json = excluded.exempt_roles_json \
                 RETURNING id"
            }
        };
        let mut query = sqlx::query_scalar(sql)
            .bind(revision)
            .bind(c.kind)
            .bind(c.term)
            .bind(c.when_json)
            .bind(spec.context.as_deref())
            .bind(c.severity)
            .bind(spec.note.as_deref())
            .bind(c.roles_json)
            .bind(c.exempt_roles_json);
        if let Some(id) = id {
            query = query.bind(id);
        }
        Ok(query.fetch_one(&mut *self.0).await?)
    }

    async fn delete_norms(&mut self, id: Option<i64>) -> Result<(), StoreError> {
        match id {
            Some(id) => {
                sqlx::query("DELETE FROM norms WHERE id = $1")
                    .bind(id)
                    .execute(&mut *self.0)
                    .await?
            }
            None => sqlx::query("DELETE FROM norms").execute(&mut *self.0).await?,
        };
        Ok(())
    }

    async fn after_explicit_ids(&mut self) -> Result<(), StoreError> {
        // The sequence only moves forward: past its own next value and past every id stored.
        sqlx::query(
            "SELECT setval(pg_get_serial_sequence('norms', 'id'), \
             GREATEST(nextval(pg_get_serial_sequence('norms', 'id')), COALESCE((SELECT max(id) FROM norms), 0) + 1), \
             false)",
        )
        .execute(&mut *self.0)
        .await?;
        Ok(())
    }

    async fn actions(&mut self) -> Result<Vec<StoredAction>, StoreError> {
        let rows: Vec<(String, String)> = sqlx::query_as(ACTIONS_SQL).fetch_all(&mut *self.0).await?;
        rows.into_iter().map(action_from_row).collect()
    }

    async fn upsert_action(&mut self, name: &str, definition: &str) -> Result<(), StoreError> {
        sqlx::query(
            "INSERT INTO actions (name, definition) VALUES ($1, $2) \
             ON CONFLICT (name) DO UPDATE SET definition = excluded.definition, updated_at = now()",
        )
        .bind(name)
        .bind(definition)
        .execute(&mut *self.0)
        .await?;
        Ok(())
    }

    async fn delete_action(&mut self, name: &str) -> Result<(), StoreError> {
        sqlx::query("DELETE FROM actions WHERE name = $1")
            .bind(name)
            .execute(&mut *self.0)
            .await?;
        Ok(())
    }

    async fn record(&mut self, change: Change<'_>) -> Result<(), StoreError> {
        let text = |v: Option<serde_json::Value>| v.map(|v| v.to_string());
        sqlx::query(
            "INSERT INTO audit (actor, subject, operation, target, before_json, after_json, version) \
             VALUES ($1, $2, $3, $4, $5, $6, $7)",
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
            sqlx::query_scalar("INSERT INTO leases (lease_ms, holder) VALUES ($1, $2) RETURNING id")
                .bind(lease_ms)
                .bind(holder)
                .fetch_one(&mut *self.0)
                .await?,
        )
    }

    async fn release_lease(&mut self, id: i64) -> Result<(), StoreError> {
        sqlx::query("DELETE FROM leases WHERE id = $1")
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

#[async_trait]
impl Backend for PostgresBackend {
    fn migrator(&self) -> &'static sqlx::migrate::Migrator {
        &MIGRATOR
    }

    type Tx = PostgresTx;

    fn still_there(&self) -> Result<(), StoreError> {
        // A server that is down or gone fails the query itself.
        Ok(())
    }

    /// One snapshot for the whole read, so a version and its rows agree.
    async fn read(&self) -> Result<PostgresTx, StoreError> {
        Ok(PostgresTx(
            self.pool
                .begin_with("BEGIN ISOLATION LEVEL REPEATABLE READ READ ONLY")
                .await?,
        ))
    }

    /// Locks both version rows first: the store's single write lock, as `BEGIN IMMEDIATE` is
    /// on SQLite. Reads after it (READ COMMITTED) see every write committed before it.
    async fn write(&self) -> Result<PostgresTx, StoreError> {
        let mut tx = self.pool.begin().await?;
        sqlx::query("SELECT n.version, a.version FROM norm_set n, action_set a FOR UPDATE")
            .execute(&mut *tx)
            .await?;
        Ok(PostgresTx(tx))
    }

    async fn versions(&self) -> Result<Versions, StoreError> {
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
            "SELECT id, to_char(at AT TIME ZONE 'UTC', 'YYYY-MM-DD\"T\"HH24:MI:SS.MS\"Z\"') AS at, actor, subject, \
             operation, target, before_json, after_json, version FROM audit WHERE id > $1 ORDER BY id LIMIT $2",
        )
        .bind(after)
        .bind(limit)
        .fetch_all(&self.pool)
        .await?;
        rows.into_iter().map(AuditRow::into_entry).collect()
    }
}
