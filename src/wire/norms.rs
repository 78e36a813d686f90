//! Norms, norm sets and the audit trail as the API shows them.

use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::engine::input::Spelled;
use crate::engine::norms::{Norm, NormInput, NormSetMode};
use crate::engine::term::Term;

/// A norm as a curator sends it. Unknown members are refused: a misspelt `when` must not
/// silently widen a norm.
#[derive(Clone, Debug, Default, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct NormBody {
    /// Kept by an import (a restored backup keeps its ids); refused on create, and on replace
    /// it must be the id in the path. Ids are otherwise assigned by the service.
    pub id: Option<i64>,
    /// Informational (an exported or fetched norm carries it); preconditions go in `If-Match`.
    pub revision: Option<i64>,
    /// `forbidden_action`, `forbidden_state`; or, softer, `discouraged_action`,
    /// `discouraged_state` (should not) and `preferred_action`, `preferred_state` (should).
    pub kind: Option<String>,
    pub action: Option<String>,
    pub state: Option<String>,
    pub when: Option<Vec<String>>,
    pub context: Option<String>,
    /// 1 (least) to 5 (most); absent: 3.
    #[schema(minimum = 1, maximum = 5)]
    pub severity: Option<i64>,
    pub note: Option<String>,
    /// When given, the norm applies only to speakers with one of these roles.
    pub roles: Option<Vec<String>>,
    /// The norm does not apply to speakers with any of these roles.
    pub exempt_roles: Option<Vec<String>>,
}

impl NormBody {
    /// The norm's members; its `id` and `revision` are the request's to place.
    pub fn into_input(self) -> NormInput {
        NormInput {
            kind: self.kind,
            action: self.action,
            state: self.state,
            when: self.when,
            context: self.context,
            severity: self.severity,
            note: self.note,
            roles: self.roles,
            exempt_roles: self.exempt_roles,
        }
    }
}

/// A stored norm, canonical: terms without spaces or types.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct NormDto {
    pub id: i64,
    /// The norm-set version at which this norm last changed; its ETag is this number quoted.
    /// Send it back in `If-Match` to replace or delete it only if nobody has changed it since.
    pub revision: i64,
    pub kind: String,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub action: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub state: Option<String>,
    pub when: Vec<String>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub context: Option<String>,
    pub severity: u8,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub note: Option<String>,
    #[serde(skip_serializing_if = "Vec::is_empty", default)]
    pub roles: Vec<String>,
    #[serde(skip_serializing_if = "Vec::is_empty", default)]
    pub exempt_roles: Vec<String>,
}

impl From<&Norm> for NormDto {
    fn from(norm: &Norm) -> Self {
        let (action, state) = norm.spec.kind.members(norm.spec.term.text());
        NormDto {
            id: norm.id,
            revision: norm.revision,
            kind: norm.spec.kind.as_str().to_owned(),
            action,
            state,
            when: norm.spec.when.iter().map(Term::text).collect(),
            context: norm.spec.context.clone(),
            severity: norm.spec.severity,
            note: norm.spec.note.clone(),
            roles: norm.spec.roles.clone(),
            exempt_roles: norm.spec.exempt_roles.clone(),
        }
    }
}

/// The whole norm set, as exported for backups and review, with the version it makes up (its
/// ETag is this number quoted).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct NormSetDto {
    pub version: i64,
    pub norms: Vec<NormDto>,
}

/// A whole norm set to import: what an export gives, or a plain list of norms (the offline
/// CLI's norms file), taken as the set's `norms`. Every norm is validated before anything is
/// replaced.
#[derive(Clone, Debug, Serialize)]
pub struct NormSetBody {
    /// Informational; the precondition goes in `If-Match`. None for a list.
    pub version: Option<i64>,
    pub norms: Vec<NormBody>,
    /// Replace (default) or merge; a plain list replaces.
    pub mode: NormSetMode,
    /// Whether the body was a plain list: the pointer of its `i`-th norm is then `/i`, not
    /// `/norms/i`.
    #[serde(skip)]
    pub listed: bool,
}

// The object form `NormSetBody` reads; its schema keeps the name the document always gave it.
/// A whole norm set to import, as an export gives it. Every norm is validated before anything
/// is replaced.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(as = NormSetBody)]
pub struct NormSetObject {
    /// Informational (an export carries it); the precondition goes in `If-Match`.
    pub version: Option<i64>,
    pub norms: Vec<NormBody>,
    /// `replace` (the default): these norms become the whole set. `merge`: each norm with an id
    /// replaces the stored norm of that id (or is added with it), each without one is added with
    /// a fresh id, and every stored norm not named is kept as it was (its revision too); merging
    /// no norms changes nothing.
    pub mode: Option<NormSetMode>,
}

// The schema of what `NormSetBody` reads, for the API's document only.
/// What `PUT /v1/norm-set` takes: a norm set as an export gives it, or a plain list of norms
/// (the offline CLI's norms file), taken as the set's `norms`.
#[derive(Serialize, ToSchema)]
#[serde(untagged)]
#[schema(as = NormSetImport)]
pub enum NormSetImportSchema {
    Set(NormSetObject),
    List(Vec<NormBody>),
}

impl<'de> Deserialize<'de> for NormSetBody {
    /// An object is read as a norm set (unknown members refused), a list as its norms; any
    /// other JSON says which two shapes are wanted. Both are read through the deserializer
    /// given, so a fault inside still names its member.
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Shape;
        impl<'de> serde::de::Visitor<'de> for Shape {
            type Value = NormSetBody;

            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a norm set {\"version\": N, \"norms\": [...]} or a list of norms")
            }

            fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<NormSetBody, A::Error> {
                let set = NormSetObject::deserialize(serde::de::value::MapAccessDeserializer::new(map))?;
                Ok(NormSetBody {
                    version: set.version,
                    norms: set.norms,
                    mode: set.mode.unwrap_or_default(),
                    listed: false,
                })
            }

            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, seq: A) -> Result<NormSetBody, A::Error> {
                let norms = Vec::<NormBody>::deserialize(serde::de::value::SeqAccessDeserializer::new(seq))?;
                Ok(NormSetBody {
                    version: None,
                    norms,
                    mode: NormSetMode::Replace,
                    listed: true,
                })
            }
        }
        deserializer.deserialize_any(Shape)
    }
}

/// One change to norms or verbs.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct AuditEntryDto {
    /// Ascending in commit order; page with `?after=`.
    pub id: i64,
    /// When it committed: RFC 3339, UTC.
    pub at: String,
    /// The label of the token that made it (`admin` for `--admin-token`, `anonymous` when no
    /// token is configured).
    pub actor: String,
    /// `norm`, `action` or `norm_set`.
    pub subject: String,
    /// `create`, `replace`, `delete` or `import`.
    pub operation: String,
    /// The norm id or verb name; absent for a whole-set import.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub target: Option<String>,
    /// The norm or verb before (absent for a create), as the API shows it; for an import, the
    /// whole set as a list.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub before: Option<serde_json::Value>,
    /// After (absent for a delete).
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub after: Option<serde_json::Value>,
    /// The version of the norm set (or action library) once the change committed.
    pub version: i64,
}

impl From<crate::storage::AuditEntry> for AuditEntryDto {
    fn from(e: crate::storage::AuditEntry) -> Self {
        AuditEntryDto {
            id: e.id,
            at: e.at,
            actor: e.actor,
            subject: e.subject,
            operation: e.operation,
            target: e.target,
            before: e.before,
            after: e.after,
            version: e.version,
        }
    }
}

/// A page of the audit trail.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct AuditPageDto {
    pub entries: Vec<AuditEntryDto>,
    /// Pass as `after` for the next page (the last id here, or the `after` asked for).
    pub next_after: i64,
}
