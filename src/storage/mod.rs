//! The norm store: where norms live between requests and across processes.
//!
//! Owns: the `NormStore` trait the core depends on, and its SQLite implementation.
//! Must not: validate norms (they arrive as valid `NormSpec`s) or compile them.

mod sqlite;

use async_trait::async_trait;

use crate::engine::action::ActionInput;
use crate::engine::norms::{Norm, NormSpec};

pub use sqlite::SqliteStore;

/// A failure of the store itself (I/O, lock, corruption), never of the caller's input.
#[derive(Debug, thiserror::Error)]
#[error("norm store: {0}")]
pub struct StoreError(pub String);

impl From<sqlx::Error> for StoreError {
    fn from(e: sqlx::Error) -> Self {
        StoreError(e.to_string())
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

/// Every write is one transaction that also bumps the version of the set it changes.
#[async_trait]
pub trait NormStore: Send + Sync + 'static {
    /// The current norm-set and action-set versions: one cheap read, made before each decision.
    async fn versions(&self) -> Result<Versions, StoreError>;
    /// Every norm and the version they make up, read in one snapshot.
    async fn load(&self) -> Result<(i64, Vec<Norm>), StoreError>;
    async fn create(&self, spec: &NormSpec) -> Result<Norm, StoreError>;
    /// Every norm, by ascending id.
    async fn list(&self) -> Result<Vec<Norm>, StoreError>;
    async fn get(&self, id: i64) -> Result<Option<Norm>, StoreError>;
    /// Whether a norm with that id existed (and is now gone).
    async fn delete(&self, id: i64) -> Result<bool, StoreError>;
    /// Whether the store is open, migrated and readable.
    async fn ping(&self) -> Result<(), StoreError>;

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
    ) -> Result<Result<bool, crate::error::Error>, StoreError>;
    /// Whether a verb of that name existed (and is now gone).
    async fn delete_action(&self, name: &str) -> Result<bool, StoreError>;
}
