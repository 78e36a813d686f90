//! SQLite norm store: WAL mode, migrations embedded and applied at open.
//!
//! Must not: write outside a transaction, or let a row it cannot parse pass as a norm (a corrupt
//! row is a store error, so clarify fails closed).

use std::str::FromStr;
use std::time::Duration;

use async_trait::async_trait;
use sqlx::sqlite::{
    SqliteConnectOptions, SqliteJournalMode, SqlitePool, SqlitePoolOptions, SqliteRow, SqliteSynchronous,
};
use sqlx::{Row, Sqlite, Transaction};

use super::{Accept, NormStore, StoreError, StoredAction, Versions};
use crate::engine::action::ActionInput;
use crate::engine::norms::{Norm, NormKind, NormSpec};
use crate::engine::term::Term;

/// The columns a norm is read from, as a literal so that queries stay static strings.
macro_rules! norm_columns {
    () => {
        "id, kind, term, when_json, context, severity, note, roles_json, exempt_roles_json"
    };
}

#[derive(Clone, Debug)]
pub struct SqliteStore {
    pool: SqlitePool,
}

impl SqliteStore {
    /// Opens (creating if missing) the database at `url` (`sqlite://scruple.db`, `sqlite::memory:`)
    /// and applies the embedded migrations.
    pub async fn open(url: &str) -> Result<SqliteStore, StoreError> {
        let options = SqliteConnectOptions::from_str(url)
            .map_err(|e| StoreError(format!("bad database URL `{url}`: {e}")))?
            .create_if_missing(true)
            .journal_mode(SqliteJournalMode::Wal)
            .synchronous(SqliteSynchronous::Full)
            .busy_timeout(Duration::from_secs(5))
            .foreign_keys(true);
        let pool = SqlitePoolOptions::new()
            .max_connections(8)
            .acquire_timeout(Duration::from_secs(5))
            .connect_with(options)
            .await?;
        sqlx::migrate!("./migrations")
            .run(&pool)
            .await
            .map_err(|e| StoreError(format!("migrations: {e}")))?;
        Ok(SqliteStore { pool })
    }

    /// `BEGIN IMMEDIATE`: takes the write lock up front, so concurrent writers queue on the busy
    /// timeout instead of failing to upgrade a read lock.
    async fn write(&self) -> Result<Transaction<'static, Sqlite>, StoreError> {
        Ok(self.pool.begin_with("BEGIN IMMEDIATE").await?)
    }

    pub fn pool(&self) -> &SqlitePool {
        &self.pool
    }
}

/// Which set's version a write moves.
#[derive(Clone, Copy)]
enum Set {
    Norms,
    Actions,
}

/// Moves a set's version inside the write's own transaction, so readers see both or neither.
async fn bump(tx: &mut Transaction<'static, Sqlite>, set: Set) -> Result<(), StoreError> {
    let sql = match set {
        Set::Norms => "UPDATE norm_set SET version = version + 1 WHERE id = 1",
        Set::Actions => "UPDATE action_set SET version = version + 1 WHERE id = 1",
    };
    sqlx::query(sql).execute(&mut **tx).await?;
    Ok(())
}

fn corrupt(id: i64, what: &str) -> StoreError {
    StoreError(format!("norm {id} is unreadable: {what}"))
}

fn json_list(id: i64, row: &SqliteRow, column: &str) -> Result<Vec<String>, StoreError> {
    let text: String = row.try_get(column)?;
    serde_json::from_str(&text).map_err(|e| corrupt(id, &format!("{column}: {e}")))
}

fn to_json(list: &[String]) -> Result<String, StoreError> {
    serde_json::to_string(list).map_err(|e| StoreError(e.to_string()))
}

fn norm_from_row(row: &SqliteRow) -> Result<Norm, StoreError> {
    let id: i64 = row.try_get("id")?;
    let kind: String = row.try_get("kind")?;
    let kind = NormKind::parse(&kind).ok_or_else(|| corrupt(id, "unknown kind"))?;
    let term: String = row.try_get("term")?;
    let term = Term::parse(&term).map_err(|e| corrupt(id, &e.to_string()))?;
    let when_texts = json_list(id, row, "when_json")?;
    let when = when_texts
        .iter()
        .map(|t| Term::parse(t))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| corrupt(id, &e.to_string()))?;
    let severity: i64 = row.try_get("severity")?;
    let severity = u8::try_from(severity)
        .ok()
        .filter(|s| (1..=5).contains(s))
        .ok_or_else(|| corrupt(id, "severity out of range"))?;
    Ok(Norm {
        id,
        spec: NormSpec {
            kind,
            term,
            when,
            context: row.try_get("context")?,
            severity,
            note: row.try_get("note")?,
            roles: json_list(id, row, "roles_json")?,
            exempt_roles: json_list(id, row, "exempt_roles_json")?,
        },
    })
}

#[async_trait]
impl NormStore for SqliteStore {
    async fn versions(&self) -> Result<Versions, StoreError> {
        let (norms, actions): (i64, i64) = sqlx::query_as(
            "SELECT (SELECT version FROM norm_set WHERE id = 1), (SELECT version FROM action_set WHERE id = 1)",
        )
        .fetch_one(&self.pool)
        .await?;
        Ok(Versions { norms, actions })
    }

    async fn load(&self) -> Result<(i64, Vec<Norm>), StoreError> {
        // One read transaction: the version and the rows come from the same snapshot.
        let mut tx = self.pool.begin().await?;
        let version: i64 = sqlx::query_scalar("SELECT version FROM norm_set WHERE id = 1")
            .fetch_one(&mut *tx)
            .await?;
        let rows = sqlx::query(concat!("SELECT ", norm_columns!(), " FROM norms ORDER BY id"))
            .fetch_all(&mut *tx)
            .await?;
        tx.commit().await?;
        let norms = rows.iter().map(norm_from_row).collect::<Result<_, _>>()?;
        Ok((version, norms))
    }

    async fn create(&self, spec: &NormSpec) -> Result<Norm, StoreError> {
        let when: Vec<String> = spec.when.iter().map(Term::to_string).collect();
        let when_json = to_json(&when)?;
        let mut tx = self.write().await?;
        let id: i64 = sqlx::query_scalar(
            "INSERT INTO norms (kind, term, when_json, context, severity, note, roles_json, exempt_roles_json) \
             VALUES (?, ?, ?, ?, ?, ?, ?, ?) RETURNING id",
        )
        .bind(spec.kind.as_str())
        .bind(spec.term.to_string())
        .bind(when_json)
        .bind(spec.context.as_deref())
        .bind(i64::from(spec.severity))
        .bind(spec.note.as_deref())
        .bind(to_json(&spec.roles)?)
        .bind(to_json(&spec.exempt_roles)?)
        .fetch_one(&mut *tx)
        .await?;
        bump(&mut tx, Set::Norms).await?;
        tx.commit().await?;
        Ok(Norm { id, spec: spec.clone() })
    }

    async fn list(&self) -> Result<Vec<Norm>, StoreError> {
        Ok(self.load().await?.1)
    }

    async fn get(&self, id: i64) -> Result<Option<Norm>, StoreError> {
        let row = sqlx::query(concat!("SELECT ", norm_columns!(), " FROM norms WHERE id = ?"))
            .bind(id)
            .fetch_optional(&self.pool)
            .await?;
        row.as_ref().map(norm_from_row).transpose()
    }

    async fn delete(&self, id: i64) -> Result<bool, StoreError> {
        let mut tx = self.write().await?;
        let deleted = sqlx::query("DELETE FROM norms WHERE id = ?")
            .bind(id)
            .execute(&mut *tx)
            .await?
            .rows_affected()
            > 0;
        if deleted {
            bump(&mut tx, Set::Norms).await?;
        }
        tx.commit().await?;
        Ok(deleted)
    }

    async fn ping(&self) -> Result<(), StoreError> {
        self.versions().await.map(|_| ())
    }

    async fn load_actions(&self) -> Result<(i64, Vec<StoredAction>), StoreError> {
        let mut tx = self.pool.begin().await?;
        let version: i64 = sqlx::query_scalar("SELECT version FROM action_set WHERE id = 1")
            .fetch_one(&mut *tx)
            .await?;
        let rows = read_actions(&mut tx).await?;
        tx.commit().await?;
        Ok((version, rows))
    }

    async fn put_action(
        &self,
        name: &str,
        definition: &ActionInput,
        accept: &Accept,
    ) -> Result<Result<bool, crate::error::Error>, StoreError> {
        let text = serde_json::to_string(definition).map_err(|e| StoreError(e.to_string()))?;
        // The write lock is taken first, so the library `accept` judges is the one written to.
        let mut tx = self.write().await?;
        let mut all = read_actions(&mut tx).await?;
        let created = match all.iter_mut().find(|(n, _)| n == name) {
            Some(existing) => {
                existing.1 = definition.clone();
                false
            }
            None => {
                all.push((name.to_owned(), definition.clone()));
                true
            }
        };
        if let Err(refused) = accept(&all) {
            tx.rollback().await?;
            return Ok(Err(refused));
        }
        sqlx::query(
            "INSERT INTO actions (name, definition) VALUES (?, ?) \
             ON CONFLICT (name) DO UPDATE SET definition = excluded.definition, \
             updated_at = strftime('%Y-%m-%dT%H:%M:%fZ', 'now')",
        )
        .bind(name)
        .bind(text)
        .execute(&mut *tx)
        .await?;
        bump(&mut tx, Set::Actions).await?;
        tx.commit().await?;
        Ok(Ok(created))
    }

    async fn delete_action(&self, name: &str) -> Result<bool, StoreError> {
        let mut tx = self.write().await?;
        let deleted = sqlx::query("DELETE FROM actions WHERE name = ?")
            .bind(name)
            .execute(&mut *tx)
            .await?
            .rows_affected()
            > 0;
        if deleted {
            bump(&mut tx, Set::Actions).await?;
        }
        tx.commit().await?;
        Ok(deleted)
    }
}

/// Every stored verb by name; a row that is not a verb's JSON is a store error (fail closed).
async fn read_actions(tx: &mut Transaction<'static, Sqlite>) -> Result<Vec<StoredAction>, StoreError> {
    let rows: Vec<(String, String)> = sqlx::query_as("SELECT name, definition FROM actions ORDER BY name")
        .fetch_all(&mut **tx)
        .await?;
    rows.into_iter()
        .map(|(name, text)| {
            let definition =
                serde_json::from_str(&text).map_err(|e| StoreError(format!("action `{name}` is unreadable: {e}")))?;
            Ok((name, definition))
        })
        .collect()
}
