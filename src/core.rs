//! The one internal API every transport calls: norms in and out of the store, and decisions made
//! under the current norm set.
//!
//! Owns: the compiled-norm cache (refreshed only when the stored version moves) and failing
//! closed when the norms cannot be read. Must not: parse wire formats or know which transport asked.

use std::sync::{Arc, RwLock};
use std::time::Instant;

use crate::api::{CheckInput, ClarifyInput};
use crate::engine::Library;
use crate::engine::check::{Check, check};
use crate::engine::clarify::{Decision, clarify};
use crate::engine::norms::{CompiledNorms, Norm, NormInput, Scope};
use crate::error::Error;
use crate::storage::NormStore;

pub struct Core {
    store: Arc<dyn NormStore>,
    library: Arc<Library>,
    /// The last norm set compiled, tagged with the store version it was compiled from.
    compiled: RwLock<Option<Arc<CompiledNorms>>>,
}

impl Core {
    pub fn new(store: Arc<dyn NormStore>) -> Core {
        Core {
            store,
            library: Arc::new(Library::default_library()),
            compiled: RwLock::new(None),
        }
    }

    /// The norm set in force now: one version read per call; a reload and recompile only when
    /// another write (from this process or any other sharing the store) moved the version.
    async fn norms(&self) -> Result<Arc<CompiledNorms>, Error> {
        let unavailable = |e: crate::storage::StoreError| Error::NormsUnavailable(e.0);
        let version = self.store.version().await.map_err(unavailable)?;
        if let Some(current) = self.compiled.read().map_err(|_| poisoned())?.as_ref()
            && current.version == version
        {
            return Ok(current.clone());
        }
        let (version, norms) = self.store.load().await.map_err(unavailable)?;
        let fresh = Arc::new(CompiledNorms::compile(version, norms));
        let mut slot = self.compiled.write().map_err(|_| poisoned())?;
        // Two refreshes may race; keep the newer set.
        if slot.as_ref().is_none_or(|c| c.version <= fresh.version) {
            *slot = Some(fresh.clone());
        }
        Ok(fresh)
    }

    /// Decides what to say about a directive. Fails closed: without readable norms, no decision.
    /// The engine runs on the blocking pool, so a large request does not stall other requests;
    /// its deadline counts from here.
    pub async fn clarify(&self, input: ClarifyInput) -> Result<Decision, Error> {
        let deadline = Instant::now() + input.deadline;
        let norms = self.norms().await?;
        let library = self.library.clone();
        let decision = tokio::task::spawn_blocking(move || {
            let expired = || Instant::now() >= deadline;
            clarify(&input.request, &input.scene, &norms, &library, &expired)
        })
        .await
        .map_err(|e| Error::Internal(format!("the decision task failed: {e}")))??;
        Ok(decision)
    }

    /// Checks steps while acting, under the norms in force now. Fails closed like `clarify`.
    pub async fn check(&self, input: CheckInput) -> Result<Check, Error> {
        let norms = self.norms().await?;
        let library = self.library.clone();
        tokio::task::spawn_blocking(move || {
            let scope = Scope {
                context: &input.context,
                roles: &input.speaker_roles,
            };
            check(&input.steps, &input.scene, &norms, &library, scope, input.style)
        })
        .await
        .map_err(|e| Error::Internal(format!("the check task failed: {e}")))
    }

    /// Validates and stores a norm; nothing is written unless every field is valid.
    pub async fn create_norm(&self, input: NormInput) -> Result<Norm, Error> {
        let spec = input.validate().map_err(|e| Error::invalid(e.field, e.message))?;
        Ok(self.store.create(&spec).await?)
    }

    pub async fn list_norms(&self) -> Result<Vec<Norm>, Error> {
        Ok(self.store.list().await?)
    }

    pub async fn get_norm(&self, id: i64) -> Result<Norm, Error> {
        self.store.get(id).await?.ok_or_else(|| not_found(id))
    }

    pub async fn delete_norm(&self, id: i64) -> Result<(), Error> {
        if self.store.delete(id).await? {
            Ok(())
        } else {
            Err(not_found(id))
        }
    }

    /// Ready when the store answers.
    pub async fn ready(&self) -> Result<(), Error> {
        Ok(self.store.ping().await?)
    }
}

fn not_found(id: i64) -> Error {
    Error::NotFound {
        what: format!("norm {id}"),
    }
}

fn poisoned() -> Error {
    Error::Internal("the norm cache lock is poisoned".to_owned())
}
