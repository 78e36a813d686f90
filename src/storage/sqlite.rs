//! SQLite norm store: WAL mode, migrations embedded and applied at open.
//!
//! Must not: write outside a transaction, or let a row it cannot parse pass as a norm (a corrupt
//! row is a store error, so clarify fails closed).

use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::time::Duration;

use async_trait::async_trait;
use sqlx::sqlite::{
    SqliteConnectOptions, SqliteJournalMode, SqlitePool, SqlitePoolOptions, SqliteRow, SqliteSynchronous,
};
use sqlx::{Row, Sqlite, Transaction};

use super::{Accept, AuditEntry, NormStore, Operation, StoreError, StoredAction, Subject, Versions, Write};
use crate::api::NormDto;
use crate::engine::action::ActionInput;
use crate::engine::norms::{Norm, NormKind, NormSpec};
use crate::engine::term::Term;

/// The columns a norm is read from, as a literal so that queries stay static strings.
macro_rules! norm_columns {
    () => {
        "id, revision, kind, term, when_json, context, severity, note, roles_json, exempt_roles_json"
    };
}

#[derive(Clone, Debug)]
pub struct SqliteStore {
    pool: SqlitePool,
    /// The database file as opened and its (device, inode); `None` in memory. Open connections
    /// keep reading a file deleted or replaced under them, and writes to it would vanish, so
    /// every request checks that the path still names this file (one `stat`) and fails closed
    /// when it does not.
    file: Option<(PathBuf, (u64, u64))>,
}

fn identity(path: &Path) -> std::io::Result<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    let metadata = std::fs::metadata(path)?;
    Ok((metadata.dev(), metadata.ino()))
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
            .connect_with(options.clone())
            .await?;
        sqlx::migrate!("./migrations")
            .run(&pool)
            .await
            .map_err(|e| StoreError(format!("migrations: {e}")))?;
        let path = options.get_filename();
        let in_memory = url.contains(":memory:") || url.contains("mode=memory");
        let file = if in_memory {
            None
        } else {
            let id = identity(path).map_err(|e| StoreError(format!("{}: {e}", path.display())))?;
            Some((path.to_owned(), id))
        };
        Ok(SqliteStore { pool, file })
    }

    /// Whether the path still names the file opened (see `file`).
    fn still_there(&self) -> Result<(), StoreError> {
        let Some((path, opened)) = &self.file else {
            return Ok(());
        };
        match identity(path) {
            Ok(now) if now == *opened => Ok(()),
            Ok(_) => Err(StoreError(format!("{} was replaced by another file", path.display()))),
            Err(e) => Err(StoreError(format!("{} is gone: {e}", path.display()))),
        }
    }

    /// `BEGIN IMMEDIATE`: takes the write lock up front, so concurrent writers queue on the busy
    /// timeout instead of failing to upgrade a read lock.
    async fn write(&self) -> Result<Transaction<'static, Sqlite>, StoreError> {
        self.still_there()?;
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

/// Moves a set's version inside the write's own transaction, so readers see both or neither;
/// returns the new version.
async fn bump(tx: &mut Transaction<'static, Sqlite>, set: Set) -> Result<i64, StoreError> {
    let sql = match set {
        Set::Norms => "UPDATE norm_set SET version = version + 1 WHERE id = 1 RETURNING version",
        Set::Actions => "UPDATE action_set SET version = version + 1 WHERE id = 1 RETURNING version",
    };
    Ok(sqlx::query_scalar(sql).fetch_one(&mut **tx).await?)
}

/// What an audit entry records of one change; written by `audit` in the change's transaction.
struct Change<'a> {
    actor: &'a str,
    subject: Subject,
    operation: Operation,
    target: Option<String>,
    before: Option<serde_json::Value>,
    after: Option<serde_json::Value>,
    version: i64,
}

async fn record(tx: &mut Transaction<'static, Sqlite>, change: Change<'_>) -> Result<(), StoreError> {
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
    .execute(&mut **tx)
    .await?;
    Ok(())
}

/// A norm as the audit trail and exports show it: the REST representation.
fn norm_json(norm: &Norm) -> serde_json::Value {
    serde_json::to_value(NormDto::from(norm)).unwrap_or(serde_json::Value::Null)
}

fn norms_json(norms: &[Norm]) -> serde_json::Value {
    serde_json::Value::Array(norms.iter().map(norm_json).collect())
}

/// Writes a norm's content into row `id` (inserting or replacing) at `revision`.
async fn upsert_norm(
    tx: &mut Transaction<'static, Sqlite>,
    id: Option<i64>,
    spec: &NormSpec,
    revision: i64,
) -> Result<i64, StoreError> {
    let when: Vec<String> = spec.when.iter().map(Term::to_string).collect();
    let id: i64 = sqlx::query_scalar(
        "INSERT INTO norms (id, revision, kind, term, when_json, context, severity, note, roles_json, exempt_roles_json) \
         VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?) \
         ON CONFLICT (id) DO UPDATE SET revision = excluded.revision, kind = excluded.kind, term = excluded.term, \
         when_json = excluded.when_json, context = excluded.context, severity = excluded.severity, \
         note = excluded.note, roles_json = excluded.roles_json, exempt_roles_json = excluded.exempt_roles_json \
         RETURNING id",
    )
    .bind(id)
    .bind(revision)
    .bind(spec.kind.as_str())
    .bind(spec.term.to_string())
    .bind(to_json(&when)?)
    .bind(spec.context.as_deref())
    .bind(i64::from(spec.severity))
    .bind(spec.note.as_deref())
    .bind(to_json(&spec.roles)?)
    .bind(to_json(&spec.exempt_roles)?)
    .fetch_one(&mut **tx)
    .await?;
    Ok(id)
}

async fn norm_in(tx: &mut Transaction<'static, Sqlite>, id: i64) -> Result<Option<Norm>, StoreError> {
    let row = sqlx::query(concat!("SELECT ", norm_columns!(), " FROM norms WHERE id = ?"))
        .bind(id)
        .fetch_optional(&mut **tx)
        .await?;
    row.as_ref().map(norm_from_row).transpose()
}

async fn all_norms(tx: &mut Transaction<'static, Sqlite>) -> Result<Vec<Norm>, StoreError> {
    let rows = sqlx::query(concat!("SELECT ", norm_columns!(), " FROM norms ORDER BY id"))
        .fetch_all(&mut **tx)
        .await?;
    rows.iter().map(norm_from_row).collect()
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
        revision: row.try_get("revision")?,
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
        self.still_there()?;
        let (norms, actions): (i64, i64) = sqlx::query_as(
            "SELECT (SELECT version FROM norm_set WHERE id = 1), (SELECT version FROM action_set WHERE id = 1)",
        )
        .fetch_one(&self.pool)
        .await?;
        Ok(Versions { norms, actions })
    }

    async fn load(&self) -> Result<(i64, Vec<Norm>), StoreError> {
        self.still_there()?;
        // One read transaction: the version and the rows come from the same snapshot.
        let mut tx = self.pool.begin().await?;
        let version: i64 = sqlx::query_scalar("SELECT version FROM norm_set WHERE id = 1")
            .fetch_one(&mut *tx)
            .await?;
        let norms = all_norms(&mut tx).await?;
        tx.commit().await?;
        Ok((version, norms))
    }

    async fn create(&self, spec: &NormSpec, actor: &str) -> Result<Norm, StoreError> {
        let mut tx = self.write().await?;
        let version = bump(&mut tx, Set::Norms).await?;
        let id = upsert_norm(&mut tx, None, spec, version).await?;
        let norm = Norm {
            id,
            revision: version,
            spec: spec.clone(),
        };
        let change = Change {
            actor,
            subject: Subject::Norm,
            operation: Operation::Create,
            target: Some(id.to_string()),
            before: None,
            after: Some(norm_json(&norm)),
            version,
        };
        record(&mut tx, change).await?;
        tx.commit().await?;
        Ok(norm)
    }

    async fn get(&self, id: i64) -> Result<Option<Norm>, StoreError> {
        let row = sqlx::query(concat!("SELECT ", norm_columns!(), " FROM norms WHERE id = ?"))
            .bind(id)
            .fetch_optional(&self.pool)
            .await?;
        row.as_ref().map(norm_from_row).transpose()
    }

    async fn replace(
        &self,
        id: i64,
        spec: &NormSpec,
        expected: Option<i64>,
        actor: &str,
    ) -> Result<Write<Norm>, StoreError> {
        // The write lock comes first, so the revision compared is the one replaced.
        let mut tx = self.write().await?;
        let Some(before) = norm_in(&mut tx, id).await? else {
            return Ok(Write::Missing);
        };
        if expected.is_some_and(|e| e != before.revision) {
            return Ok(Write::Stale {
                current: before.revision,
            });
        }
        let version = bump(&mut tx, Set::Norms).await?;
        upsert_norm(&mut tx, Some(id), spec, version).await?;
        let norm = Norm {
            id,
            revision: version,
            spec: spec.clone(),
        };
        let change = Change {
            actor,
            subject: Subject::Norm,
            operation: Operation::Replace,
            target: Some(id.to_string()),
            before: Some(norm_json(&before)),
            after: Some(norm_json(&norm)),
            version,
        };
        record(&mut tx, change).await?;
        tx.commit().await?;
        Ok(Write::Done(norm))
    }

    async fn delete(&self, id: i64, expected: Option<i64>, actor: &str) -> Result<Write<()>, StoreError> {
        let mut tx = self.write().await?;
        let Some(before) = norm_in(&mut tx, id).await? else {
            return Ok(Write::Missing);
        };
        if expected.is_some_and(|e| e != before.revision) {
            return Ok(Write::Stale {
                current: before.revision,
            });
        }
        sqlx::query("DELETE FROM norms WHERE id = ?")
            .bind(id)
            .execute(&mut *tx)
            .await?;
        let version = bump(&mut tx, Set::Norms).await?;
        let change = Change {
            actor,
            subject: Subject::Norm,
            operation: Operation::Delete,
            target: Some(id.to_string()),
            before: Some(norm_json(&before)),
            after: None,
            version,
        };
        record(&mut tx, change).await?;
        tx.commit().await?;
        Ok(Write::Done(()))
    }

    async fn import(
        &self,
        norms: &[(Option<i64>, NormSpec)],
        expected: Option<i64>,
        actor: &str,
    ) -> Result<Write<(i64, Vec<Norm>)>, StoreError> {
        let mut tx = self.write().await?;
        let current: i64 = sqlx::query_scalar("SELECT version FROM norm_set WHERE id = 1")
            .fetch_one(&mut *tx)
            .await?;
        if expected.is_some_and(|e| e != current) {
            return Ok(Write::Stale { current });
        }
        let before = all_norms(&mut tx).await?;
        sqlx::query("DELETE FROM norms").execute(&mut *tx).await?;
        let version = bump(&mut tx, Set::Norms).await?;
        // Given ids first: a fresh id is then above every one of them, and never collides.
        let (given, fresh): (Vec<_>, Vec<_>) = norms.iter().partition(|(id, _)| id.is_some());
        for (id, spec) in given.into_iter().chain(fresh) {
            upsert_norm(&mut tx, *id, spec, version).await?;
        }
        let after = all_norms(&mut tx).await?;
        let change = Change {
            actor,
            subject: Subject::NormSet,
            operation: Operation::Import,
            target: None,
            before: Some(norms_json(&before)),
            after: Some(norms_json(&after)),
            version,
        };
        record(&mut tx, change).await?;
        tx.commit().await?;
        Ok(Write::Done((version, after)))
    }

    async fn audit(&self, after: i64, limit: i64) -> Result<Vec<AuditEntry>, StoreError> {
        let rows = sqlx::query(
            "SELECT id, at, actor, subject, operation, target, before_json, after_json, version \
             FROM audit WHERE id > ? ORDER BY id LIMIT ?",
        )
        .bind(after)
        .bind(limit)
        .fetch_all(&self.pool)
        .await?;
        rows.iter().map(audit_from_row).collect()
    }

    async fn ping(&self) -> Result<(), StoreError> {
        self.versions().await.map(|_| ())
    }

    async fn load_actions(&self) -> Result<(i64, Vec<StoredAction>), StoreError> {
        self.still_there()?;
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
        actor: &str,
    ) -> Result<Result<bool, crate::error::Error>, StoreError> {
        let text = serde_json::to_string(definition).map_err(|e| StoreError(e.to_string()))?;
        // The write lock is taken first, so the library `accept` judges is the one written to.
        let mut tx = self.write().await?;
        let mut all = read_actions(&mut tx).await?;
        let before = match all.iter_mut().find(|(n, _)| n == name) {
            Some(existing) => Some(std::mem::replace(&mut existing.1, definition.clone())),
            None => {
                all.push((name.to_owned(), definition.clone()));
                None
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
        let version = bump(&mut tx, Set::Actions).await?;
        let created = before.is_none();
        let change = Change {
            actor,
            subject: Subject::Action,
            operation: if created { Operation::Create } else { Operation::Replace },
            target: Some(name.to_owned()),
            before: before.as_ref().map(action_json),
            after: Some(action_json(definition)),
            version,
        };
        record(&mut tx, change).await?;
        tx.commit().await?;
        Ok(Ok(created))
    }

    async fn delete_action(&self, name: &str, actor: &str) -> Result<bool, StoreError> {
        let mut tx = self.write().await?;
        let all = read_actions(&mut tx).await?;
        let Some((_, before)) = all.iter().find(|(n, _)| n == name) else {
            return Ok(false);
        };
        sqlx::query("DELETE FROM actions WHERE name = ?")
            .bind(name)
            .execute(&mut *tx)
            .await?;
        let version = bump(&mut tx, Set::Actions).await?;
        let change = Change {
            actor,
            subject: Subject::Action,
            operation: Operation::Delete,
            target: Some(name.to_owned()),
            before: Some(action_json(before)),
            after: None,
            version,
        };
        record(&mut tx, change).await?;
        tx.commit().await?;
        Ok(true)
    }
}

fn action_json(definition: &ActionInput) -> serde_json::Value {
    serde_json::to_value(definition).unwrap_or(serde_json::Value::Null)
}

fn audit_from_row(row: &SqliteRow) -> Result<AuditEntry, StoreError> {
    let id: i64 = row.try_get("id")?;
    let json = |column: &str| -> Result<Option<serde_json::Value>, StoreError> {
        let text: Option<String> = row.try_get(column)?;
        text.map(|t| serde_json::from_str(&t))
            .transpose()
            .map_err(|e| StoreError(format!("audit entry {id} is unreadable: {column}: {e}")))
    };
    Ok(AuditEntry {
        id,
        at: row.try_get("at")?,
        actor: row.try_get("actor")?,
        subject: row.try_get("subject")?,
        operation: row.try_get("operation")?,
        target: row.try_get("target")?,
        before: json("before_json")?,
        after: json("after_json")?,
        version: row.try_get("version")?,
    })
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
