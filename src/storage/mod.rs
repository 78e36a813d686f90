//! The norm store: where norms live between requests and across processes.
//!
//! Owns: the `NormStore` trait the core depends on, and its SQLite implementation.
//! Must not: validate norms (they arrive as valid `NormSpec`s) or compile them.

mod sqlite;

use async_trait::async_trait;

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

/// Every write is one transaction that also bumps the norm-set version.
#[async_trait]
pub trait NormStore: Send + Sync + 'static {
    /// The current norm-set version: one cheap read, made before each decision.
    async fn version(&self) -> Result<i64, StoreError>;
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
}
