//! What both SQL stores do the same way: every write's steps (lock, read, check the revision,
//! bump the version, write, audit, commit) and turning rows into norms.
//!
//! Owns: the write protocol and row parsing. Must not: hold SQL text (each backend has its own
//! dialect) or let a row it cannot parse pass as a norm (a corrupt row is a store error, so
//! clarify fails closed).

use async_trait::async_trait;

use super::{Accept, AuditEntry, NormStore, Operation, StoreError, StoredAction, Subject, Versions, Write};
use crate::engine::action::ActionInput;
use crate::engine::input::Spelled;
use crate::engine::norms::{Norm, NormInput, NormKind, NormSetMode, NormSpec};
use crate::engine::term::Term;

/// Which set's version a write moves.
#[derive(Clone, Copy, Debug)]
pub enum Set {
    Norms,
    Actions,
}

impl Set {
    /// The statements that read and move the set's version: the same in both dialects.
    pub(super) fn sql(self) -> (&'static str, &'static str) {
        match self {
            Set::Norms => (
                "SELECT version FROM norm_set WHERE id = 1",
                "UPDATE norm_set SET version = version + 1 WHERE id = 1 RETURNING version",
            ),
            Set::Actions => (
                "SELECT version FROM action_set WHERE id = 1",
                "UPDATE action_set SET version = version + 1 WHERE id = 1 RETURNING version",
            ),
        }
    }
}

/// Every verb by name: the same in both dialects.
pub(super) const ACTIONS_SQL: &str = "SELECT name, definition FROM actions ORDER BY name";

/// What an audit entry records of one change.
pub struct Change<'a> {
    pub actor: &'a str,
    pub subject: Subject,
    pub operation: Operation,
    pub target: Option<String>,
    pub before: Option<serde_json::Value>,
    pub after: Option<serde_json::Value>,
    pub version: i64,
}

/// A norm row as stored: every column as text or integer.
#[derive(sqlx::FromRow)]
pub(super) struct NormRow {
    id: i64,
    revision: i64,
    kind: String,
    term: String,
    when_json: String,
    context: Option<String>,
    severity: i64,
    note: Option<String>,
    roles_json: String,
    exempt_roles_json: String,
}

fn corrupt(id: i64, what: &str) -> StoreError {
    StoreError::new(format!("norm {id} is unreadable: {what}"))
}

fn json_list(id: i64, column: &str, text: &str) -> Result<Vec<String>, StoreError> {
    serde_json::from_str(text).map_err(|e| corrupt(id, &format!("{column}: {e}")))
}

pub(super) fn to_json(list: &[String]) -> Result<String, StoreError> {
    serde_json::to_string(list).map_err(|e| StoreError::new(e.to_string()))
}

impl NormRow {
    /// A stored row passes the same validation as a norm sent to the API: a row this version
    /// would not accept (written by hand, or under older, looser rules) is a store error naming
    /// the norm and the field, and decisions fail closed until it is mended.
    pub(super) fn into_norm(self) -> Result<Norm, StoreError> {
        let id = self.id;
        let kind = NormKind::parse(&self.kind).ok_or_else(|| corrupt(id, "unknown kind"))?;
        let (action, state) = kind.members(self.term);
        let input = NormInput {
            kind: Some(self.kind),
            action,
            state,
            when: Some(json_list(id, "when_json", &self.when_json)?),
            context: self.context,
            severity: Some(self.severity),
            note: self.note,
            roles: Some(json_list(id, "roles_json", &self.roles_json)?),
            exempt_roles: Some(json_list(id, "exempt_roles_json", &self.exempt_roles_json)?),
        };
        let spec = input.validate().map_err(|e| corrupt(id, &e.to_string()))?;
        Ok(Norm {
            id,
            revision: self.revision,
            spec,
        })
    }
}

/// The columns of a norm as written: canonical terms and JSON lists.
pub(super) struct NormColumns {
    pub kind: &'static str,
    pub term: String,
    pub when_json: String,
    pub severity: i64,
    pub roles_json: String,
    pub exempt_roles_json: String,
}

impl NormColumns {
    pub(super) fn of(spec: &NormSpec) -> Result<NormColumns, StoreError> {
        let when: Vec<String> = spec.when.iter().map(Term::to_string).collect();
        Ok(NormColumns {
            kind: spec.kind.as_str(),
            term: spec.term.to_string(),
            when_json: to_json(&when)?,
            severity: i64::from(spec.severity),
            roles_json: to_json(&spec.roles)?,
            exempt_roles_json: to_json(&spec.exempt_roles)?,
        })
    }
}

/// An audit row as stored; `at` already formatted as RFC 3339 by the query.
#[derive(sqlx::FromRow)]
pub(super) struct AuditRow {
    id: i64,
    at: String,
    actor: String,
    subject: String,
    operation: String,
    target: Option<String>,
    before_json: Option<String>,
    after_json: Option<String>,
    version: i64,
}

impl AuditRow {
    pub(super) fn into_entry(self) -> Result<AuditEntry, StoreError> {
        let id = self.id;
        let json = |column: &str, text: Option<String>| -> Result<Option<serde_json::Value>, StoreError> {
            text.map(|t| serde_json::from_str(&t))
                .transpose()
                .map_err(|e| StoreError::new(format!("audit entry {id} is unreadable: {column}: {e}")))
        };
        Ok(AuditEntry {
            id,
            at: self.at,
            actor: self.actor,
            subject: self.subject,
            operation: self.operation,
            target: self.target,
            before: json("before_json", self.before_json)?,
            after: json("after_json", self.after_json)?,
            version: self.version,
        })
    }
}

/// A verb row; a definition that is not a verb's JSON is a store error (fail closed).
pub(super) fn action_from_row((name, text): (String, String)) -> Result<StoredAction, StoreError> {
    let definition =
        serde_json::from_str(&text).map_err(|e| StoreError::new(format!("action `{name}` is unreadable: {e}")))?;
    Ok((name, definition))
}

/// A norm as the audit trail and exports show it: the REST representation.
/// A norm as the audit trail records it: the store's own shape, not a response's, so that
/// renaming a field of the API changes nothing stored. It is the shape entries have had since
/// the trail began (canonical terms; optional members left out when absent), and must stay so:
/// old entries are read back as they were written.
#[derive(serde::Serialize)]
struct AuditedNorm<'a> {
    id: i64,
    revision: i64,
    kind: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    action: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    state: Option<String>,
    when: Vec<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    context: Option<&'a str>,
    severity: u8,
    #[serde(skip_serializing_if = "Option::is_none")]
    note: Option<&'a str>,
    #[serde(skip_serializing_if = "<[String]>::is_empty")]
    roles: &'a [String],
    #[serde(skip_serializing_if = "<[String]>::is_empty")]
    exempt_roles: &'a [String],
}

fn norm_json(norm: &Norm) -> serde_json::Value {
    let spec = &norm.spec;
    let (action, state) = spec.kind.members(spec.term.to_string());
    let record = AuditedNorm {
        id: norm.id,
        revision: norm.revision,
        kind: spec.kind.as_str(),
        action,
        state,
        when: spec.when.iter().map(Term::to_string).collect(),
        context: spec.context.as_deref(),
        severity: spec.severity,
        note: spec.note.as_deref(),
        roles: &spec.roles,
        exempt_roles: &spec.exempt_roles,
    };
    serde_json::to_value(record).unwrap_or(serde_json::Value::Null)
}

fn norms_json(norms: &[Norm]) -> serde_json::Value {
    serde_json::Value::Array(norms.iter().map(norm_json).collect())
}

fn action_json(definition: &ActionInput) -> serde_json::Value {
    serde_json::to_value(definition).unwrap_or(serde_json::Value::Null)
}

/// One backend's transaction: reads see one snapshot; a write transaction holds the store's
/// single write lock from its start, so what it reads is what it writes over.
#[async_trait]
pub trait Tx: Send + Sized {
    async fn version(&mut self, set: Set) -> Result<i64, StoreError>;
    /// Moves a set's version and returns the new one.
    async fn bump(&mut self, set: Set) -> Result<i64, StoreError>;
    async fn norm(&mut self, id: i64) -> Result<Option<Norm>, StoreError>;
    /// Every norm by ascending id.
    async fn norms(&mut self) -> Result<Vec<Norm>, StoreError>;
    /// Inserts (a fresh id when `id` is `None`) or overwrites row `id`; returns the id.
    async fn upsert_norm(&mut self, id: Option<i64>, spec: &NormSpec, revision: i64) -> Result<i64, StoreError>;
    /// Removes norm `id`, or every norm with `None`.
    async fn delete_norms(&mut self, id: Option<i64>) -> Result<(), StoreError>;
    /// After ids were given explicitly: fresh ids must still come after every id ever used.
    async fn after_explicit_ids(&mut self) -> Result<(), StoreError>;
    /// Every verb by name.
    async fn actions(&mut self) -> Result<Vec<StoredAction>, StoreError>;
    async fn upsert_action(&mut self, name: &str, definition: &str) -> Result<(), StoreError>;
    async fn delete_action(&mut self, name: &str) -> Result<(), StoreError>;
    async fn record(&mut self, change: Change<'_>) -> Result<(), StoreError>;
    /// Adds a serving process's lease record; returns its id.
    async fn hold_lease(&mut self, lease_ms: i64, holder: &str) -> Result<i64, StoreError>;
    async fn release_lease(&mut self, id: i64) -> Result<(), StoreError>;
    async fn commit(self) -> Result<(), StoreError>;
    async fn rollback(self) -> Result<(), StoreError>;
}

/// A SQL database the store runs on.
#[async_trait]
pub trait Backend: Send + Sync + 'static {
    type Tx: Tx;
    /// Checks that the store is still the one opened (see the SQLite file check).
    fn still_there(&self) -> Result<(), StoreError>;
    /// A read-only snapshot.
    async fn read(&self) -> Result<Self::Tx, StoreError>;
    /// A transaction holding the store's write lock.
    async fn write(&self) -> Result<Self::Tx, StoreError>;
    /// Both set versions in one cheap statement.
    async fn versions(&self) -> Result<Versions, StoreError>;
    async fn audit(&self, after: i64, limit: i64) -> Result<Vec<AuditEntry>, StoreError>;
    /// The longest lease recorded, in milliseconds (0 when none is).
    async fn longest_lease_ms(&self) -> Result<i64, StoreError>;
    /// The migrations this build applies to the backend, oldest first.
    fn migrator(&self) -> &'static sqlx::migrate::Migrator;
}

/// A norm store on a SQL backend.
#[derive(Clone, Debug)]
pub struct SqlStore<B> {
    pub(super) backend: B,
}

/// Aborts a write whose precondition failed: nothing was written.
async fn abandon<T: Tx, R>(tx: T, outcome: Write<R>) -> Result<Write<R>, StoreError> {
    tx.rollback().await?;
    Ok(outcome)
}

impl<B: Backend> SqlStore<B> {
    /// Takes the write lock and reads norm `id` under it: the norm, or why the conditional
    /// write cannot go ahead (then the transaction is already rolled back).
    async fn locked<R>(&self, id: i64, expected: Option<i64>) -> Result<Result<(B::Tx, Norm), Write<R>>, StoreError> {
        let mut tx = self.backend.write().await?;
        let Some(before) = tx.norm(id).await? else {
            return abandon(tx, Write::Missing).await.map(Err);
        };
        if expected.is_some_and(|e| e != before.revision) {
            let current = before.revision;
            return abandon(tx, Write::Stale { current }).await.map(Err);
        }
        Ok(Ok((tx, before)))
    }
}

#[async_trait]
impl<B: Backend> NormStore for SqlStore<B> {
    fn still_there(&self) -> Result<(), StoreError> {
        self.backend.still_there()
    }

    async fn versions(&self) -> Result<Versions, StoreError> {
        self.backend.still_there()?;
        self.backend.versions().await
    }

    async fn load(&self) -> Result<(i64, Vec<Norm>), StoreError> {
        self.backend.still_there()?;
        let mut tx = self.backend.read().await?;
        let version = tx.version(Set::Norms).await?;
        let norms = tx.norms().await?;
        tx.commit().await?;
        Ok((version, norms))
    }

    async fn create(&self, spec: &NormSpec, actor: &str) -> Result<Norm, StoreError> {
        let mut tx = self.backend.write().await?;
        let version = tx.bump(Set::Norms).await?;
        let id = tx.upsert_norm(None, spec, version).await?;
        let norm = Norm {
            id,
            revision: version,
            spec: spec.clone(),
        };
        tx.record(Change {
            actor,
            subject: Subject::Norm,
            operation: Operation::Create,
            target: Some(id.to_string()),
            before: None,
            after: Some(norm_json(&norm)),
            version,
        })
        .await?;
        tx.commit().await?;
        Ok(norm)
    }

    async fn get(&self, id: i64) -> Result<Option<Norm>, StoreError> {
        self.backend.still_there()?;
        let mut tx = self.backend.read().await?;
        let norm = tx.norm(id).await?;
        tx.commit().await?;
        Ok(norm)
    }

    async fn replace(
        &self,
        id: i64,
        spec: &NormSpec,
        expected: Option<i64>,
        actor: &str,
    ) -> Result<Write<Norm>, StoreError> {
        let (mut tx, before) = match self.locked(id, expected).await? {
            Ok(locked) => locked,
            Err(refused) => return Ok(refused),
        };
        let version = tx.bump(Set::Norms).await?;
        tx.upsert_norm(Some(id), spec, version).await?;
        let norm = Norm {
            id,
            revision: version,
            spec: spec.clone(),
        };
        tx.record(Change {
            actor,
            subject: Subject::Norm,
            operation: Operation::Replace,
            target: Some(id.to_string()),
            before: Some(norm_json(&before)),
            after: Some(norm_json(&norm)),
            version,
        })
        .await?;
        tx.commit().await?;
        Ok(Write::Done(norm))
    }

    async fn delete(&self, id: i64, expected: Option<i64>, actor: &str) -> Result<Write<()>, StoreError> {
        let (mut tx, before) = match self.locked(id, expected).await? {
            Ok(locked) => locked,
            Err(refused) => return Ok(refused),
        };
        tx.delete_norms(Some(id)).await?;
        let version = tx.bump(Set::Norms).await?;
        tx.record(Change {
            actor,
            subject: Subject::Norm,
            operation: Operation::Delete,
            target: Some(id.to_string()),
            before: Some(norm_json(&before)),
            after: None,
            version,
        })
        .await?;
        tx.commit().await?;
        Ok(Write::Done(()))
    }

    async fn import(
        &self,
        norms: &[(Option<i64>, NormSpec)],
        mode: NormSetMode,
        expected: Option<i64>,
        actor: &str,
    ) -> Result<Write<(i64, Vec<Norm>)>, StoreError> {
        let mut tx = self.backend.write().await?;
        let current = tx.version(Set::Norms).await?;
        if expected.is_some_and(|e| e != current) {
            return abandon(tx, Write::Stale { current }).await;
        }
        let before = tx.norms().await?;
        match mode {
            NormSetMode::Replace => tx.delete_norms(None).await?,
            // Nothing to merge changes nothing: no new version, no audit entry.
            NormSetMode::Merge if norms.is_empty() => return abandon(tx, Write::Done((current, before))).await,
            // Each norm named by id is replaced by the upsert below; the rest stay as stored.
            NormSetMode::Merge => {}
        }
        let version = tx.bump(Set::Norms).await?;
        // Given ids first: a fresh id is then above every one of them, and never collides.
        let (given, fresh): (Vec<_>, Vec<_>) = norms.iter().partition(|(id, _)| id.is_some());
        for (id, spec) in &given {
            tx.upsert_norm(*id, spec, version).await?;
        }
        tx.after_explicit_ids().await?;
        for (_, spec) in &fresh {
            tx.upsert_norm(None, spec, version).await?;
        }
        let after = tx.norms().await?;
        tx.record(Change {
            actor,
            subject: Subject::NormSet,
            operation: Operation::Import,
            target: None,
            before: Some(norms_json(&before)),
            after: Some(norms_json(&after)),
            version,
        })
        .await?;
        tx.commit().await?;
        Ok(Write::Done((version, after)))
    }

    async fn audit(&self, after: i64, limit: i64) -> Result<Vec<AuditEntry>, StoreError> {
        self.backend.still_there()?;
        self.backend.audit(after, limit).await
    }

    async fn ping(&self) -> Result<(), StoreError> {
        self.versions().await.map(|_| ())
    }

    fn schema_version(&self) -> i64 {
        self.backend.migrator().iter().map(|m| m.version).max().unwrap_or(0)
    }

    async fn hold_lease(&self, lease: std::time::Duration, holder: &str) -> Result<i64, StoreError> {
        let lease_ms =
            i64::try_from(lease.as_millis()).map_err(|_| StoreError::new("the lease is too long to record"))?;
        let mut tx = self.backend.write().await?;
        let id = tx.hold_lease(lease_ms, holder).await?;
        tx.commit().await?;
        Ok(id)
    }

    async fn release_lease(&self, id: i64) -> Result<(), StoreError> {
        let mut tx = self.backend.write().await?;
        tx.release_lease(id).await?;
        tx.commit().await
    }

    async fn longest_lease(&self) -> Result<std::time::Duration, StoreError> {
        self.backend.still_there()?;
        let ms = self.backend.longest_lease_ms().await?;
        Ok(std::time::Duration::from_millis(u64::try_from(ms).unwrap_or(0)))
    }

    async fn load_actions(&self) -> Result<(i64, Vec<StoredAction>), StoreError> {
        self.backend.still_there()?;
        let mut tx = self.backend.read().await?;
        let version = tx.version(Set::Actions).await?;
        let actions = tx.actions().await?;
        tx.commit().await?;
        Ok((version, actions))
    }

    async fn put_action(
        &self,
        name: &str,
        definition: &ActionInput,
        accept: &Accept,
        actor: &str,
    ) -> Result<Result<bool, crate::error::Error>, StoreError> {
        let text = serde_json::to_string(definition).map_err(|e| StoreError::new(e.to_string()))?;
        // The write lock is held from the start, so the library `accept` judges is the one
        // written to.
        let mut tx = self.backend.write().await?;
        let mut all = tx.actions().await?;
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
        tx.upsert_action(name, &text).await?;
        let version = tx.bump(Set::Actions).await?;
        let created = before.is_none();
        tx.record(Change {
            actor,
            subject: Subject::Action,
            operation: if created { Operation::Create } else { Operation::Replace },
            target: Some(name.to_owned()),
            before: before.as_ref().map(action_json),
            after: Some(action_json(definition)),
            version,
        })
        .await?;
        tx.commit().await?;
        Ok(Ok(created))
    }

    async fn delete_action(
        &self,
        name: &str,
        accept: &Accept,
        actor: &str,
    ) -> Result<Result<bool, crate::error::Error>, StoreError> {
        // Under the write lock from the start: no verb can come to call this one between the
        // judgement and the delete.
        let mut tx = self.backend.write().await?;
        let mut rest = tx.actions().await?;
        let Some(at) = rest.iter().position(|(n, _)| n == name) else {
            tx.rollback().await?;
            return Ok(Ok(false));
        };
        let (_, before) = rest.remove(at);
        if let Err(refused) = accept(&rest) {
            tx.rollback().await?;
            return Ok(Err(refused));
        }
        tx.delete_action(name).await?;
        let version = tx.bump(Set::Actions).await?;
        tx.record(Change {
            actor,
            subject: Subject::Action,
            operation: Operation::Delete,
            target: Some(name.to_owned()),
            before: Some(action_json(&before)),
            after: None,
            version,
        })
        .await?;
        tx.commit().await?;
        Ok(Ok(true))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::norms::NormInput;

    /// Stored audit entries keep one shape whatever the API's norm looks like: these are the
    /// members an entry has always had.
    #[test]
    fn an_audited_norm_keeps_the_trails_shape() {
        let spec = NormInput {
            kind: Some("forbidden_state".into()),
            state: Some("holding(self, X:object)".into()),
            when: Some(vec!["fragile(X)".into()]),
            context: Some("lab".into()),
            severity: Some(4),
            note: Some("n".into()),
            roles: Some(vec!["child".into()]),
            exempt_roles: Some(vec!["owner".into()]),
            ..NormInput::default()
        }
        .validate()
        .unwrap();
        let full = norm_json(&Norm {
            id: 7,
            revision: 9,
            spec,
        });
        assert_eq!(
            full,
            serde_json::json!({"id": 7, "revision": 9, "kind": "forbidden_state", "state": "holding(self,X)",
                "when": ["fragile(X)"], "context": "lab", "severity": 4, "note": "n",
                "roles": ["child"], "exempt_roles": ["owner"]})
        );
        let spec = NormInput {
            kind: Some("forbidden_action".into()),
            action: Some("destroy".into()),
            ..NormInput::default()
        }
        .validate()
        .unwrap();
        let bare = norm_json(&Norm {
            id: 1,
            revision: 1,
            spec,
        });
        assert_eq!(
            bare,
            serde_json::json!({"id": 1, "revision": 1, "kind": "forbidden_action", "action": "destroy", "when": [], "severity": 3})
        );
    }
}
