//! The norm store: where norms live between requests, across processes and across replicas.
//!
//! Owns: the `NormStore` trait the core depends on, its SQLite (default) and PostgreSQL
//! implementations, and choosing one from a database URL.
//! Must not: validate norms (they arrive as valid `NormSpec`s) or compile them.

/// The columns a norm row is read from, as a literal so that queries stay static strings
/// (defined before the backends so that each can use it).
macro_rules! norm_columns {
    () => {
        "id, revision, kind, term, when_json, context, severity, note, roles_json, exempt_roles_json"
    };
}

mod identity;
mod postgres;
mod sql;
mod sqlite;

use async_trait::async_trait;

use crate::engine::action::ActionInput;
use crate::engine::norms::{Norm, NormSetMode, NormSpec};

pub use postgres::PostgresStore;
pub use sql::SqlStore;
pub use sqlite::SqliteStore;

/// Opens the store a database URL names: `postgres://` or `postgresql://` for PostgreSQL,
/// anything else for SQLite. Migrations are applied before it returns.
pub async fn open(url: &str) -> Result<std::sync::Arc<dyn NormStore>, StoreError> {
    if is_postgres(url) {
        Ok(std::sync::Arc::new(PostgresStore::open(url).await?))
    } else {
        Ok(std::sync::Arc::new(SqliteStore::open(url).await?))
    }
}

/// Whether a database URL names PostgreSQL (`postgres://`, `postgresql://`) rather than SQLite.
pub fn is_postgres(url: &str) -> bool {
    url.starts_with("postgres://") || url.starts_with("postgresql://")
}

/// A failure of the store itself (I/O, lock, corruption), never of the caller's input.
#[derive(Debug, thiserror::Error)]
#[error("norm store: {detail}")]
pub struct StoreError {
    pub detail: String,
    /// No connection could be had in time: the store is healthy but this process is at its
    /// limit, which is overload (retry shortly), not unreadable norms.
    pub busy: bool,
}

impl StoreError {
    pub fn new(detail: impl Into<String>) -> StoreError {
        StoreError {
            detail: detail.into(),
            busy: false,
        }
    }
}

impl StoreError {
    /// The failure as the service answers it: overload when only a connection was wanting (the
    /// store is healthy), else `unavailable` with the detail.
    pub fn answer(self, unavailable: fn(String) -> crate::error::Error) -> crate::error::Error {
        if self.busy {
            crate::error::Error::Overloaded { retry_after_s: 1 }
        } else {
            unavailable(self.detail)
        }
    }
}

impl From<StoreError> for crate::error::Error {
    /// A store that cannot answer a curator.
    fn from(e: StoreError) -> Self {
        e.answer(crate::error::Error::StoreUnavailable)
    }
}

impl From<sqlx::Error> for StoreError {
    fn from(e: sqlx::Error) -> Self {
        StoreError {
            busy: matches!(e, sqlx::Error::PoolTimedOut),
            detail: e.to_string(),
        }
    }
}

/// The versions of what decisions depend on, read together in one cheap query.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Versions {
    pub norms: i64,
    pub actions: i64,
}

/// A verb as stored: its name and its written definition.
pub type StoredAction = (String, ActionInput);

/// Judges a whole library before a write commits (an alias, so that `async_trait` leaves the
/// closure's higher-ranked lifetime alone).
pub type Accept = dyn Fn(&[StoredAction]) -> Result<(), crate::error::Error> + Send + Sync;

/// How a conditional write on one norm ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Write<T> {
    Done(T),
    /// No norm has that id.
    Missing,
    /// The norm's revision is not the one the caller expected; nothing was written.
    Stale {
        current: i64,
    },
}

/// What changed: the subject of an audit entry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Subject {
    Norm,
    Action,
    NormSet,
}

impl Subject {
    pub fn as_str(self) -> &'static str {
        match self {
            Subject::Norm => "norm",
            Subject::Action => "action",
            Subject::NormSet => "norm_set",
        }
    }
}

/// How it changed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Operation {
    Create,
    Replace,
    Delete,
    Import,
}

impl Operation {
    pub fn as_str(self) -> &'static str {
        match self {
            Operation::Create => "create",
            Operation::Replace => "replace",
            Operation::Delete => "delete",
            Operation::Import => "import",
        }
    }
}

/// One change to norms or verbs, as the audit trail keeps it.
#[derive(Clone, Debug, PartialEq)]
pub struct AuditEntry {
    /// Ascending in commit order; a reader pages with `after`.
    pub id: i64,
    /// RFC 3339, UTC, milliseconds.
    pub at: String,
    /// The label of the token that made the change (`anonymous` when no token is configured).
    pub actor: String,
    pub subject: String,
    pub operation: String,
    /// The norm id or verb name; none for a whole-set import.
    pub target: Option<String>,
    /// Canonical JSON before and after; `None` where there was nothing (a create's before).
    pub before: Option<serde_json::Value>,
    pub after: Option<serde_json::Value>,
    /// The version of the changed set once the change committed.
    pub version: i64,
}

/// Every write is one transaction that bumps the version of the set it changes and appends its
/// audit entry: a write is all three or nothing.
#[async_trait]
pub trait NormStore: Send + Sync + 'static {
    /// Whether the store is still the one opened (for SQLite, that the path still names the
    /// file opened): a `poll` or a `stat`, no query, so it can be asked on every request.
    fn still_there(&self) -> Result<(), StoreError>;
    /// The current norm-set and action-set versions: one cheap read, made whenever a lease on
    /// them has run out.
    async fn versions(&self) -> Result<Versions, StoreError>;
    /// Every norm and the version they make up, read in one snapshot, by ascending id.
    async fn load(&self) -> Result<(i64, Vec<Norm>), StoreError>;
    async fn create(&self, spec: &NormSpec, actor: &str) -> Result<Norm, StoreError>;
    async fn get(&self, id: i64) -> Result<Option<Norm>, StoreError>;
    /// Replaces a norm's content, keeping its id, when its revision is `expected` (or always,
    /// with `None`).
    async fn replace(
        &self,
        id: i64,
        spec: &NormSpec,
        expected: Option<i64>,
        actor: &str,
    ) -> Result<Write<Norm>, StoreError>;
    /// Removes a norm when its revision is `expected` (or always, with `None`).
    async fn delete(&self, id: i64, expected: Option<i64>, actor: &str) -> Result<Write<()>, StoreError>;
    /// Imports `norms` (ids kept) in one transaction, when the set's version is `expected` (or
    /// always, with `None`): as the whole set (`Replace`), or over it (`Merge`: the norms named
    /// by id are replaced, the others kept with their revisions); returns the new set as `load`
    /// would.
    async fn import(
        &self,
        norms: &[(Option<i64>, NormSpec)],
        mode: NormSetMode,
        expected: Option<i64>,
        actor: &str,
    ) -> Result<Write<(i64, Vec<Norm>)>, StoreError>;
    /// Up to `limit` audit entries with ids above `after`, ascending.
    async fn audit(&self, after: i64, limit: i64) -> Result<Vec<AuditEntry>, StoreError>;
    /// Whether the store is open, migrated and readable.
    async fn ping(&self) -> Result<(), StoreError>;
    /// The newest migration this build applies to its kind of store (and found applied at start).
    fn schema_version(&self) -> i64;

    /// Records that a process serving this store trusts the stored versions it reads for
    /// `lease` (its `--versions-lease-ms`); `holder` names the process for an operator. Made
    /// before the process first reads the versions; returns the record's id.
    async fn hold_lease(&self, lease: std::time::Duration, holder: &str) -> Result<i64, StoreError>;
    /// Removes a record of [`NormStore::hold_lease`] once its process answers no more requests.
    async fn release_lease(&self, id: i64) -> Result<(), StoreError>;
    /// The longest lease any process serving this store records (zero when none does): how
    /// long after a commit some process may still answer under the versions before it.
    async fn longest_lease(&self) -> Result<std::time::Duration, StoreError>;

    /// Every verb and the action-set version they make up, read in one snapshot, by name.
    async fn load_actions(&self) -> Result<(i64, Vec<StoredAction>), StoreError>;
    /// Adds or replaces a verb in one transaction. `accept` sees the whole library as it would
    /// be and may refuse it (a cycle through the steps); then nothing is written. Returns
    /// whether the verb is new.
    async fn put_action(
        &self,
        name: &str,
        definition: &ActionInput,
        accept: &Accept,
        actor: &str,
    ) -> Result<Result<bool, crate::error::Error>, StoreError>;
    /// Removes a verb in one transaction; whether a verb of that name existed (and is now
    /// gone). `accept` sees the library as it would be without it and may refuse (another verb
    /// calls it); then nothing is written.
    async fn delete_action(
        &self,
        name: &str,
        accept: &Accept,
        actor: &str,
    ) -> Result<Result<bool, crate::error::Error>, StoreError>;
}
