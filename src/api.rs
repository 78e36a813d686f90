//! The wire model shared by every transport: request and response bodies as JSON shapes, and
//! their conversion to and from the engine's types.
//!
//! Owns: boundary parsing (every fault names its field as a JSON Pointer) and the response shape.
//! Must not: decide anything; a valid request becomes engine input, a decision becomes a body.

use std::collections::{BTreeMap, HashSet};

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use crate::core::{CheckInput, ClarifyInput};
use crate::engine::action::verb_name;
use crate::engine::check::Check;
use crate::engine::clarify::{
    Answer, DEFAULT_MAX_READINGS, DEFAULT_MAX_SPOKEN, Directive, Options, Request, SinglePermissible, Strategy,
};
use crate::engine::decision::{Decision, Interpretation, Limits, Style};
use crate::engine::norms::{Norm, NormInput, NormKind, normalise_name, validate_roles};
use crate::engine::resolve::{Candidate, Reference};
use crate::engine::scene::{Agent, Object, Scene, Shape};
use crate::engine::simulate::Reason;
use crate::engine::term::{Sym, Term, TermLimits, is_constant_name};
use crate::error::Error;

/// Escapes a key for use as one JSON Pointer segment (RFC 6901).
pub fn pointer_segment(key: &str) -> String {
    key.replace('~', "~0").replace('/', "~1")
}

/// Parses a JSON body. Text that is not JSON is a 400; JSON of the wrong shape is a 422 whose
/// `field` points at the offending member.
pub fn parse_json<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, Error> {
    let mut deserializer = serde_json::Deserializer::from_slice(bytes);
    let result: Result<T, _> = serde_path_to_error::deserialize(&mut deserializer);
    if result.is_ok() {
        // Trailing text after the value is a syntax error, not a shape error.
        deserializer
            .end()
            .map_err(|e| Error::MalformedBody { detail: e.to_string() })?;
    }
    result.map_err(|err| {
        let inner = err.inner();
        // A shape error can be met before a syntax error further on: text that is not JSON at
        // all is reported as such, whatever its first bytes looked like.
        if let Err(syntax) = serde_json::from_slice::<serde::de::IgnoredAny>(bytes) {
            return Error::MalformedBody {
                detail: syntax.to_string(),
            };
        }
        // The text is JSON, so whatever the deserializer tripped on is the shape of a member:
        // a fixed-length array with more elements ("trailing characters" to serde), a shape with
        // no kind or two, a key given twice. Each is a 422 naming the member.
        let mut field = String::new();
        for segment in err.path().iter() {
            match segment {
                serde_path_to_error::Segment::Seq { index } => field.push_str(&format!("/{index}")),
                serde_path_to_error::Segment::Map { key } => {
                    field.push('/');
                    field.push_str(&pointer_segment(key));
                }
                serde_path_to_error::Segment::Enum { variant } => {
                    field.push('/');
                    field.push_str(&pointer_segment(variant));
                }
                serde_path_to_error::Segment::Unknown => {}
            }
        }
        let message = inner.to_string();
        // serde reports a missing or repeated member at its parent; point at the member itself.
        for prefix in ["missing field `", "duplicate field `"] {
            if let Some(rest) = message.strip_prefix(prefix)
                && let Some(name) = rest.split('`').next()
            {
                field.push('/');
                field.push_str(&pointer_segment(name));
            }
        }
        let detail = match message.rfind(" at line ") {
            Some(cut) => message[..cut].to_owned(),
            None => message,
        };
        let detail = shape_detail(&detail, &field);
        // An empty pointer is the whole document (RFC 6901).
        Error::invalid(field, detail)
    })
}

/// serde's words for a member of the wrong shape, made plain where they would mislead.
fn shape_detail(detail: &str, field: &str) -> String {
    let last = field.rsplit('/').next().unwrap_or_default();
    let what = match last {
        "position" => Some("exactly 3 numbers [x, y, z]"),
        "half_extents" => Some("exactly 3 numbers"),
        "rotation" => Some("exactly 4 numbers [x, y, z, w]"),
        "shape" => Some("one of {\"ball\": ...}, {\"cuboid\": ...}, {\"cylinder\": ...}: exactly one kind"),
        _ => None,
    };
    match what {
        Some(what) if detail.starts_with("trailing characters") || detail.starts_with("invalid length") => {
            format!("must be {what}")
        }
        Some(what) if last == "shape" && !detail.starts_with("unknown variant") => format!("must be {what}"),
        _ if detail.starts_with("trailing characters") => "has more elements or members than it takes".to_owned(),
        _ => detail.to_owned(),
    }
}

// ---------------------------------------------------------------------------------------------
// Verbs: the schema of `engine::action::ActionInput`, which the handlers take and give. The
// engine names no schema crate, so the document's shape is declared here, member for member;
// `tests::the_verb_schema_has_the_members_of_the_verb` holds the two together.

/// A verb as a curator writes it, as the API carries it and as the store keeps it: terms as
/// text.
#[derive(Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(as = Action)]
pub struct ActionSchema {
    /// The verb's name; when sent, it must equal the name it is stored as (the request's path).
    #[serde(default)]
    pub name: Option<String>,
    /// Variables such as `X`, bound to the arguments in order.
    #[serde(default)]
    pub parameters: Vec<String>,
    /// The word joining the arguments when spoken: `on` for "put the cup on the plate".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joiner: Option<String>,
    /// The arguments must name different objects (`put` does): a reading that names one object
    /// twice is infeasible (`same_object`) and never offered. Default false.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub distinct: bool,
    /// One or more ways of carrying the verb out; a reading is acceptable when any is.
    #[serde(default)]
    pub methods: Vec<MethodSchema>,
}

/// One way of carrying a verb out. Terms are written over the verb's parameters.
#[derive(Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(as = Method)]
pub struct MethodSchema {
    /// Action terms, and the word `itself` for the verb's own execution; default `["itself"]`,
    /// and `itself` is appended when not listed.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub steps: Vec<String>,
    /// Parameters whose object must be within reach, with a clear path, for `itself`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub reach: Vec<String>,
    /// Parameters whose object the gripper closes around (aperture and payload).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub grasp: Vec<String>,
    /// `[item, support]`: the support must have room for the item.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub place: Option<Vec<String>>,
    /// Facts that must hold when `itself` runs: `closed(X)`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub preconditions: Vec<String>,
    /// Facts `itself` makes true (besides `did(self,action)`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub adds: Vec<String>,
    /// Facts `itself` makes false.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub removes: Vec<String>,
}

// ---------------------------------------------------------------------------------------------
// Norms

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
    /// For a create: the service assigns the id.
    pub fn for_create(self) -> Result<NormInput, Error> {
        if self.id.is_some() {
            return Err(Error::invalid(
                "/id",
                "ids are assigned by the service; replace a norm with PUT /v1/norms/{id}",
            ));
        }
        Ok(self.into_input())
    }

    /// For a replace of norm `id`: an id in the body must be that one.
    pub fn for_replace(self, id: i64) -> Result<NormInput, Error> {
        if let Some(given) = self.id
            && given != id
        {
            return Err(Error::invalid(
                "/id",
                format!("the body names norm {given} but the request replaces norm {id}"),
            ));
        }
        Ok(self.into_input())
    }

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
        let term = Some(norm.spec.term.to_string());
        let (action, state) = match norm.spec.kind {
            NormKind::ForbiddenAction => (term, None),
            NormKind::ForbiddenState => (None, term),
        };
        NormDto {
            id: norm.id,
            revision: norm.revision,
            kind: norm.spec.kind.as_str().to_owned(),
            action,
            state,
            when: norm.spec.when.iter().map(Term::to_string).collect(),
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

/// A whole norm set to import: exactly what an export gives (its `version` is informational;
/// the precondition goes in `If-Match`). Every norm is validated before anything is replaced.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct NormSetBody {
    pub version: Option<i64>,
    pub norms: Vec<NormBody>,
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

/// Default and largest page of the audit trail.
pub const DEFAULT_AUDIT_PAGE: i64 = 100;
pub const MAX_AUDIT_PAGE: i64 = 1_000;

// ---------------------------------------------------------------------------------------------
// Clarify: request

/// Unknown members are refused here and in the directive and options (a misspelt `options`
/// would silently change an experiment's condition); scenes and objects accept extra members,
/// since perception pipelines attach their own.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ClarifyBody {
    #[serde(default)]
    pub speaker: Option<String>,
    pub directive: DirectiveBody,
    pub scene: SceneBody,
    #[serde(default)]
    pub context: Option<String>,
    #[serde(default)]
    pub options: Option<OptionsBody>,
    /// The speaker's roles (`owner`): with `context`, they select the norms in force.
    #[serde(default)]
    pub speaker_roles: Option<Vec<String>>,
    /// The human's answer to the question this request's directive led to.
    #[serde(default)]
    pub answer: Option<AnswerBody>,
}

/// A follow-up: exactly one of `choice` (the position, from 0, among the readings the question
/// named: the `offered` of the answer to the original request), `id`, or `reference`.
#[derive(Clone, Debug, Default, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct AnswerBody {
    #[serde(default)]
    pub choice: Option<u64>,
    #[serde(default)]
    pub id: Option<String>,
    #[serde(default)]
    pub reference: Option<ReferenceBody>,
}

/// Either `action` + `arguments` or `form` + `bindings`; `text` is the human's words, echoed.
#[derive(Clone, Debug, Default, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct DirectiveBody {
    #[serde(default)]
    pub action: Option<String>,
    #[serde(default)]
    pub arguments: Option<Vec<ReferenceBody>>,
    #[serde(default)]
    pub form: Option<String>,
    #[serde(default)]
    pub bindings: Option<BTreeMap<String, Vec<BindingBody>>>,
    #[serde(default)]
    pub text: Option<String>,
}

#[derive(Clone, Debug, Default, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ReferenceBody {
    #[serde(default)]
    pub id: Option<String>,
    #[serde(rename = "type", default)]
    pub kind: Option<String>,
    #[serde(default)]
    pub attributes: Option<BTreeMap<String, Scalar>>,
    #[serde(default)]
    pub properties: Option<Vec<String>>,
}

/// A candidate from an upstream resolver: an object id, or an id with a score.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(untagged, expecting = "an object id, or {\"id\": ID, \"score\": NUMBER}")]
pub enum BindingBody {
    Id(String),
    Scored { id: String, score: f64 },
}

/// An attribute value: a string, or a number or boolean taken as its JSON text.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(untagged, expecting = "a string, number or boolean")]
pub enum Scalar {
    Text(String),
    Number(f64),
    Bool(bool),
}

impl Scalar {
    fn text(&self) -> String {
        match self {
            Scalar::Text(s) => s.clone(),
            Scalar::Number(n) => n.to_string(),
            Scalar::Bool(b) => b.to_string(),
        }
    }
}

#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
pub struct SceneBody {
    pub agent: AgentBody,
    #[serde(default)]
    pub objects: Vec<ObjectBody>,
    #[serde(default)]
    pub facts: Vec<String>,
}

#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
pub struct AgentBody {
    #[serde(default)]
    pub id: Option<String>,
    /// Metres, world frame (z up).
    #[schema(min_items = 3, max_items = 3)]
    pub position: [f64; 3],
    /// Metres.
    pub reach: f64,
    /// Widest object, metres, the gripper can close around; absent: grasp is not checked.
    #[serde(default)]
    pub gripper_aperture: Option<f64>,
    /// Heaviest object, kilograms, the arm can lift; absent: payload is not checked.
    #[serde(default)]
    pub payload: Option<f64>,
    /// Radius, metres, of the ball the gripper sweeps on its way to an object; absent: clearance
    /// is not checked.
    #[serde(default)]
    pub gripper_size: Option<f64>,
}

#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
pub struct ObjectBody {
    pub id: String,
    #[serde(rename = "type")]
    pub kind: String,
    #[serde(default)]
    pub properties: Vec<String>,
    #[serde(default)]
    pub attributes: BTreeMap<String, Scalar>,
    /// Centre of the shape, metres, world frame.
    #[schema(min_items = 3, max_items = 3)]
    pub position: [f64; 3],
    #[serde(default)]
    pub shape: Option<ShapeBody>,
    /// Unit quaternion `[x, y, z, w]`.
    #[serde(default)]
    #[schema(min_items = 4, max_items = 4)]
    pub rotation: Option<[f64; 4]>,
    /// Kilograms; absent: payload is not checked for this object.
    #[serde(default)]
    pub mass: Option<f64>,
}

#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ShapeBody {
    Ball {
        radius: f64,
    },
    Cuboid {
        #[schema(min_items = 3, max_items = 3)]
        half_extents: [f64; 3],
    },
    Cylinder {
        radius: f64,
        half_height: f64,
    },
}

#[derive(Clone, Debug, Default, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct OptionsBody {
    #[serde(default)]
    pub strategy: Option<StrategyBody>,
    #[serde(default)]
    pub single_permissible: Option<SinglePermissibleBody>,
    /// `diarc` (default, the paper's words) or `natural`.
    #[serde(default)]
    pub style: Option<StyleBody>,
    /// Most readings a question names (2..=50, default 5).
    #[serde(default)]
    #[schema(minimum = 2, maximum = 50)]
    pub max_spoken: Option<u64>,
    /// Most readings simulated (1..=100000, default 10000).
    #[serde(default)]
    #[schema(minimum = 1, maximum = 100000)]
    pub max_readings: Option<u64>,
    /// Milliseconds the decision may take (1..=60000, default 2000); past it, what is not yet
    /// simulated is not offered and the answer says the deadline was hit.
    #[serde(default)]
    #[schema(minimum = 1, maximum = 60000)]
    pub deadline_ms: Option<u64>,
    /// Confirm instead of assuming when the share of unacceptable readings is above this
    /// (0 ≤ ratio < 1). Absent: Algorithm 1's assumption.
    #[serde(default)]
    #[schema(minimum = 0, exclusive_maximum = 1)]
    pub confirm_above_ratio: Option<f64>,
}

#[derive(Clone, Copy, Debug, Deserialize, Serialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum StyleBody {
    Diarc,
    Natural,
}

#[derive(Clone, Copy, Debug, Deserialize, Serialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum StrategyBody {
    Moral,
    Reflexive,
}

#[derive(Clone, Copy, Debug, Deserialize, Serialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum SinglePermissibleBody {
    Assume,
    Confirm,
}

pub const DEFAULT_DEADLINE_MS: u64 = 2_000;
/// Default for `--max-objects`.
pub const DEFAULT_MAX_OBJECTS: usize = 10_000;
/// Default for `--max-deadline-ms`: the longest `options.deadline_ms` a request may ask for.
pub const DEFAULT_MAX_DEADLINE_MS: u64 = 60_000;

/// What the operator lets one clarify or check request ask of the service. Going over a limit is
/// a 422 naming the field and the limit; it never reaches the engine.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RequestLimits {
    /// Most objects in one scene.
    pub max_objects: usize,
    /// Nesting depth and length of each term in a request (logical forms, facts, steps).
    pub terms: TermLimits,
    /// The decision deadline when a request names none, milliseconds.
    pub default_deadline_ms: u64,
    /// The longest deadline a request may ask for, milliseconds.
    pub max_deadline_ms: u64,
}

impl Default for RequestLimits {
    fn default() -> Self {
        RequestLimits {
            max_objects: DEFAULT_MAX_OBJECTS,
            terms: TermLimits::DEFAULT,
            default_deadline_ms: DEFAULT_DEADLINE_MS,
            max_deadline_ms: DEFAULT_MAX_DEADLINE_MS,
        }
    }
}

/// A term from a request, parsed within the operator's limits.
fn request_term(field: &str, text: &str, limits: &RequestLimits) -> Result<Term, Error> {
    Term::parse_within(text, limits.terms).map_err(|e| Error::invalid(field, format!("not a term: {e}")))
}

/// A number option within its range, or an error naming it.
fn ranged(field: &str, value: Option<u64>, range: std::ops::RangeInclusive<u64>, default: u64) -> Result<u64, Error> {
    match value {
        None => Ok(default),
        Some(v) if range.contains(&v) => Ok(v),
        Some(v) => Err(Error::invalid(
            field,
            format!("{v} is out of range {}..={}", range.start(), range.end()),
        )),
    }
}

/// `options.deadline_ms` of a clarify or a check, within the operator's bound.
fn deadline_of(value: Option<u64>, limits: &RequestLimits) -> Result<std::time::Duration, Error> {
    let ms = ranged(
        "/options/deadline_ms",
        value,
        1..=limits.max_deadline_ms,
        limits.default_deadline_ms,
    )?;
    Ok(std::time::Duration::from_millis(ms))
}

fn style_of(style: Option<StyleBody>) -> Style {
    match style {
        None | Some(StyleBody::Diarc) => Style::Diarc,
        Some(StyleBody::Natural) => Style::Natural,
    }
}

fn roles_of(roles: Option<Vec<String>>) -> Result<Vec<String>, Error> {
    validate_roles("/speaker_roles", roles).map_err(|e| Error::invalid(e.field, e.message))
}

impl AnswerBody {
    fn into_answer(self, scene: &Scene) -> Result<Answer, Error> {
        match (self.choice, self.id, self.reference) {
            (Some(choice), None, None) => Ok(Answer::Choice(usize::try_from(choice).unwrap_or(usize::MAX))),
            (None, Some(id), None) => {
                if scene.object(&id).is_none() {
                    return Err(Error::invalid("/answer/id", format!("no object `{id}` in the scene")));
                }
                Ok(Answer::Id(id))
            }
            (None, None, Some(reference)) => match reference.into_reference("/answer/reference", scene)? {
                Reference::Id(id) => Ok(Answer::Id(id)),
                described => Ok(Answer::Reference(described)),
            },
            _ => Err(Error::invalid(
                "/answer",
                "give exactly one of `choice`, `id`, `reference`",
            )),
        }
    }
}

const MAX_NAME_LEN: usize = 128;

/// A name that must read back as a constant of a term: `object3`, `cash_box`, `red`.
fn constant(field: &str, text: &str, what: &str) -> Result<(), Error> {
    if text.len() > MAX_NAME_LEN {
        return Err(Error::invalid(
            field,
            format!("{what} is longer than {MAX_NAME_LEN} bytes"),
        ));
    }
    // A name with no letter or digit (`_`, `__`) is spoken as nothing: "the  is out of reach".
    if !is_constant_name(text) || !text.chars().any(|c| c.is_ascii_alphanumeric()) {
        return Err(Error::invalid(
            field,
            format!(
                "{what} `{text}` must start with a lower-case letter, digit or `_` and contain only letters, digits, `_`, `-` and `.`"
            ),
        ));
    }
    Ok(())
}

fn finite(field: &str, values: &[f64]) -> Result<(), Error> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(Error::invalid(field, "must be finite numbers"))
    }
}

fn positive(field: &str, value: f64) -> Result<(), Error> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(field, "must be a positive number"))
    }
}

fn context_of(context: Option<String>) -> Result<String, Error> {
    // Normalised as a norm's context is, so that the two meet.
    let context = context.map_or_else(|| "default".to_owned(), |c| normalise_name(&c));
    if context.is_empty() || context.len() > MAX_NAME_LEN {
        return Err(Error::invalid(
            "/context",
            format!("must be 1 to {MAX_NAME_LEN} bytes long"),
        ));
    }
    Ok(context)
}

impl SceneBody {
    fn into_scene(self, limits: &RequestLimits) -> Result<Scene, Error> {
        if self.objects.len() > limits.max_objects {
            return Err(Error::invalid(
                "/scene/objects",
                format!(
                    "{} objects is over the limit of {} per scene (--max-objects)",
                    self.objects.len(),
                    limits.max_objects
                ),
            ));
        }
        let agent_id = self.agent.id.unwrap_or_else(|| "self".to_owned());
        constant("/scene/agent/id", &agent_id, "the agent id")?;
        finite("/scene/agent/position", &self.agent.position)?;
        if !(self.agent.reach.is_finite() && self.agent.reach >= 0.0) {
            return Err(Error::invalid(
                "/scene/agent/reach",
                "must be a non-negative number of metres",
            ));
        }
        for (field, value) in [
            ("/scene/agent/gripper_aperture", self.agent.gripper_aperture),
            ("/scene/agent/payload", self.agent.payload),
            ("/scene/agent/gripper_size", self.agent.gripper_size),
        ] {
            if let Some(v) = value {
                positive(field, v)?;
            }
        }
        let mut seen = HashSet::new();
        let mut objects = Vec::with_capacity(self.objects.len());
        for (i, o) in self.objects.into_iter().enumerate() {
            let at = format!("/scene/objects/{i}");
            constant(&format!("{at}/id"), &o.id, "an object id")?;
            if !seen.insert(o.id.clone()) {
                return Err(Error::invalid(
                    format!("{at}/id"),
                    format!("duplicate object id `{}`", o.id),
                ));
            }
            constant(&format!("{at}/type"), &o.kind, "a type")?;
            for (j, p) in o.properties.iter().enumerate() {
                constant(&format!("{at}/properties/{j}"), p, "a property")?;
            }
            let mut attributes = BTreeMap::new();
            for (key, value) in &o.attributes {
                let field = format!("{at}/attributes/{}", pointer_segment(key));
                constant(&field, key, "an attribute name")?;
                let value = value.text();
                constant(&field, &value, "an attribute value")?;
                attributes.insert(key.clone(), value);
            }
            finite(&format!("{at}/position"), &o.position)?;
            let shape = match o.shape {
                None => None,
                Some(ShapeBody::Ball { radius }) => {
                    positive(&format!("{at}/shape/ball/radius"), radius)?;
                    Some(Shape::Ball { radius })
                }
                Some(ShapeBody::Cuboid { half_extents }) => {
                    for (k, h) in half_extents.iter().enumerate() {
                        positive(&format!("{at}/shape/cuboid/half_extents/{k}"), *h)?;
                    }
                    Some(Shape::Cuboid { half_extents })
                }
                Some(ShapeBody::Cylinder { radius, half_height }) => {
                    positive(&format!("{at}/shape/cylinder/radius"), radius)?;
                    positive(&format!("{at}/shape/cylinder/half_height"), half_height)?;
                    Some(Shape::Cylinder { radius, half_height })
                }
            };
            let rotation = match o.rotation {
                None => None,
                Some(q) => {
                    let field = format!("{at}/rotation");
                    finite(&field, &q)?;
                    let norm = q.iter().map(|c| c * c).sum::<f64>().sqrt();
                    if (norm - 1.0).abs() > 1e-3 {
                        return Err(Error::invalid(
                            field,
                            format!("must be a unit quaternion [x,y,z,w]; its norm is {norm}"),
                        ));
                    }
                    Some(q.map(|c| c / norm))
                }
            };
            if let Some(mass) = o.mass
                && !(mass.is_finite() && mass >= 0.0)
            {
                return Err(Error::invalid(
                    format!("{at}/mass"),
                    "must be a non-negative number of kilograms",
                ));
            }
            objects.push(Object {
                mass: o.mass,
                id: o.id,
                kind: o.kind,
                properties: o.properties,
                attributes,
                position: o.position,
                shape,
                rotation,
            });
        }
        let mut facts = Vec::with_capacity(self.facts.len());
        for (k, text) in self.facts.iter().enumerate() {
            let field = format!("/scene/facts/{k}");
            let fact = request_term(&field, text, limits)?;
            if !fact.is_ground() || fact.is_var() {
                return Err(Error::invalid(field, "a scene fact must be ground (no variables)"));
            }
            facts.push(fact);
        }
        Ok(Scene::new(
            Agent {
                id: agent_id,
                position: self.agent.position,
                reach: self.agent.reach,
                gripper_aperture: self.agent.gripper_aperture,
                payload: self.agent.payload,
                gripper_size: self.agent.gripper_size,
            },
            objects,
            facts,
        ))
    }
}

impl ReferenceBody {
    fn into_reference(self, at: &str, scene: &Scene) -> Result<Reference, Error> {
        if let Some(id) = self.id {
            if self.kind.is_some() || self.attributes.is_some() || self.properties.is_some() {
                return Err(Error::invalid(
                    at,
                    "a reference gives either `id` or `type` (with attributes and properties), not both",
                ));
            }
            if scene.object(&id).is_none() {
                return Err(Error::invalid(
                    format!("{at}/id"),
                    format!("no object `{id}` in the scene"),
                ));
            }
            return Ok(Reference::Id(id));
        }
        if self.kind.is_none() && self.attributes.is_none() && self.properties.is_none() {
            return Err(Error::invalid(
                at,
                "a reference needs `id`, or `type` with optional attributes and properties",
            ));
        }
        if let Some(kind) = &self.kind {
            constant(&format!("{at}/type"), kind, "a type")?;
        }
        let attributes = self
            .attributes
            .unwrap_or_default()
            .into_iter()
            .map(|(k, v)| (k, v.text()))
            .collect();
        Ok(Reference::Described {
            kind: self.kind,
            attributes,
            properties: self.properties.unwrap_or_default(),
        })
    }
}

/// Splits a logical form into its speaker (when wrapped as `want(S,...)`) and the action of
/// `did(self,ACTION)`; a bare action is taken as the action itself.
fn unwrap_form(form: &Term, agent: &str) -> Result<(Option<Sym>, Term), String> {
    let (speaker, inner) = match (form.name().map(|n| &**n), form.args()) {
        (Some("want"), [speaker, inner]) => match speaker {
            Term::Const(s) => (Some(s.clone()), inner.clone()),
            _ => return Err("the speaker in want(S,...) must be a constant".to_owned()),
        },
        _ => (None, form.clone()),
    };
    let action = match (inner.name().map(|n| &**n), inner.args()) {
        (Some("did"), [actor, action]) => {
            match actor {
                Term::Const(a) if &**a == "self" || &**a == agent => {}
                _ => {
                    let names = if agent == "self" {
                        "`self`".to_owned()
                    } else {
                        format!("`self` or `{agent}`")
                    };
                    return Err(format!("did(A,...) must name the agent: {names}"));
                }
            }
            action.clone()
        }
        _ => inner,
    };
    if action.is_var() {
        return Err("the action must name a verb, not be a variable".to_owned());
    }
    Ok((speaker, action))
}

impl DirectiveBody {
    fn into_directive(self, scene: &Scene, limits: &RequestLimits) -> Result<(Directive, Option<Sym>), Error> {
        match (self.action, self.form) {
            (Some(_), Some(_)) => Err(Error::invalid("/directive", "give either `action` or `form`, not both")),
            (None, None) => Err(Error::invalid(
                "/directive",
                "needs `action` (with `arguments`) or `form` (with `bindings`)",
            )),
            (Some(verb), None) => {
                verb_name(&verb).map_err(|m| Error::invalid("/directive/action", m))?;
                if self.bindings.is_some() {
                    return Err(Error::invalid(
                        "/directive/bindings",
                        "`bindings` go with `form`, not with `action`",
                    ));
                }
                let arguments = self
                    .arguments
                    .unwrap_or_default()
                    .into_iter()
                    .enumerate()
                    .map(|(i, r)| r.into_reference(&format!("/directive/arguments/{i}"), scene))
                    .collect::<Result<_, _>>()?;
                Ok((Directive::Action { verb, arguments }, None))
            }
            (None, Some(text)) => {
                if self.arguments.is_some() {
                    return Err(Error::invalid(
                        "/directive/arguments",
                        "`arguments` go with `action`, not with `form`",
                    ));
                }
                let form = request_term("/directive/form", &text, limits)?;
                let (speaker, action) =
                    unwrap_form(&form, &scene.agent.id).map_err(|m| Error::invalid("/directive/form", m))?;
                if let Some(name) = action.name() {
                    verb_name(name).map_err(|m| Error::invalid("/directive/form", m))?;
                }
                let variables = action.variables();
                let given = self.bindings.unwrap_or_default();
                for name in given.keys() {
                    if !variables.iter().any(|v| &**v == name) {
                        return Err(Error::invalid(
                            format!("/directive/bindings/{}", pointer_segment(name)),
                            format!("`{name}` is not a variable of the form"),
                        ));
                    }
                }
                let mut bindings = Vec::with_capacity(variables.len());
                for variable in variables {
                    let at = format!("/directive/bindings/{}", pointer_segment(&variable));
                    let Some(list) = given.get(&*variable) else {
                        return Err(Error::invalid(
                            at,
                            format!("no candidates given for the variable `{variable}`"),
                        ));
                    };
                    let mut candidates: Vec<Candidate> = Vec::with_capacity(list.len());
                    for (j, binding) in list.iter().enumerate() {
                        let (id, score, id_at) = match binding {
                            BindingBody::Id(id) => (id, 1.0, format!("{at}/{j}")),
                            BindingBody::Scored { id, score } => {
                                if !(score.is_finite() && *score >= 0.0) {
                                    return Err(Error::invalid(
                                        format!("{at}/{j}/score"),
                                        "must be a finite number ≥ 0",
                                    ));
                                }
                                (id, *score, format!("{at}/{j}/id"))
                            }
                        };
                        if scene.object(id).is_none() {
                            return Err(Error::invalid(id_at, format!("no object `{id}` in the scene")));
                        }
                        if candidates.iter().any(|c| &c.id == id) {
                            return Err(Error::invalid(id_at, format!("`{id}` is listed twice")));
                        }
                        candidates.push(Candidate { id: id.clone(), score });
                    }
                    bindings.push((variable, candidates));
                }
                Ok((Directive::Form { action, bindings }, speaker))
            }
        }
    }
}

impl TryFrom<ClarifyBody> for ClarifyInput {
    type Error = Error;

    /// Under the default limits.
    fn try_from(body: ClarifyBody) -> Result<Self, Error> {
        ClarifyInput::from_body(body, &RequestLimits::default())
    }
}

impl ClarifyInput {
    /// Validates a request within `limits`; the first fault is reported with its field.
    pub fn from_body(body: ClarifyBody, limits: &RequestLimits) -> Result<Self, Error> {
        let speaker = body.speaker.unwrap_or_else(|| "human".to_owned());
        constant("/speaker", &speaker, "the speaker")?;
        let context = context_of(body.context)?;
        let scene = body.scene.into_scene(limits)?;
        let text = body.directive.text.clone();
        let (directive, form_speaker) = body.directive.into_directive(&scene, limits)?;
        let speaker_roles = roles_of(body.speaker_roles)?;
        let answer = body.answer.map(|a| a.into_answer(&scene)).transpose()?;
        let options = body.options.unwrap_or_default();
        if let Some(ratio) = options.confirm_above_ratio
            && !(ratio.is_finite() && (0.0..1.0).contains(&ratio))
        {
            return Err(Error::invalid(
                "/options/confirm_above_ratio",
                "must be a ratio with 0 ≤ ratio < 1",
            ));
        }
        let deadline = deadline_of(options.deadline_ms, limits)?;
        let engine_options = Options {
            strategy: match options.strategy {
                None | Some(StrategyBody::Moral) => Strategy::Moral,
                Some(StrategyBody::Reflexive) => Strategy::Reflexive,
            },
            single_permissible: match options.single_permissible {
                None | Some(SinglePermissibleBody::Assume) => SinglePermissible::Assume,
                Some(SinglePermissibleBody::Confirm) => SinglePermissible::Confirm,
            },
            style: style_of(options.style),
            max_spoken: ranged(
                "/options/max_spoken",
                options.max_spoken,
                2..=50,
                DEFAULT_MAX_SPOKEN as u64,
            )? as usize,
            max_readings: ranged(
                "/options/max_readings",
                options.max_readings,
                1..=100_000,
                DEFAULT_MAX_READINGS as u64,
            )? as usize,
            confirm_above_ratio: options.confirm_above_ratio,
        };
        Ok(ClarifyInput {
            request: Request {
                speaker: form_speaker.unwrap_or_else(|| Sym::from(speaker)),
                speaker_roles,
                directive,
                context,
                options: engine_options,
                answer,
            },
            scene,
            text,
            deadline,
        })
    }
}

// ---------------------------------------------------------------------------------------------
// Clarify: response

#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct ReasonDto {
    pub kind: String,
    pub detail: String,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub norm_id: Option<i64>,
    /// The norm's severity, 1..5, for a `forbidden_*` reason.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub severity: Option<u8>,
    /// The reason in words, in the request's style ("it requires a forbidden state").
    pub words: String,
}

/// Reasons with their words, as both decisions and checks report them.
fn reason_dtos(reasons: &[Reason], words: &[String]) -> Vec<ReasonDto> {
    reasons
        .iter()
        .zip(words)
        .map(|(reason, words)| ReasonDto {
            kind: reason.kind().to_owned(),
            detail: reason.detail(),
            norm_id: reason.norm_id,
            severity: reason.severity,
            words: words.clone(),
        })
        .collect()
}

#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct InterpretationDto {
    pub action: String,
    pub description: String,
    pub permissible: bool,
    pub feasible: bool,
    pub reasons: Vec<ReasonDto>,
    /// The primitive steps simulated, in order, as canonical terms.
    pub plan: Vec<String>,
    pub score: f64,
}

impl From<&Interpretation> for InterpretationDto {
    fn from(i: &Interpretation) -> Self {
        InterpretationDto {
            action: i.action.to_string(),
            description: i.description.clone(),
            permissible: i.permissible(),
            feasible: i.feasible(),
            reasons: reason_dtos(&i.outcome.reasons, &i.reason_words),
            plan: i.outcome.plan.iter().map(Term::to_string).collect(),
            score: i.score,
        }
    }
}

#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct DecisionDto {
    pub decision: String,
    pub utterance: String,
    pub speech_act: String,
    pub goal: Option<String>,
    pub interpretations: Vec<InterpretationDto>,
    /// The readings the utterance proposes, in order: those a question names (a follow-up's
    /// `choice` counts from 0 among them), or the one assumed, confirmed or obeyed.
    pub offered: Vec<String>,
    /// Present when a cap or the deadline kept readings from being simulated.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub limits: Option<LimitsDto>,
    /// The version of the norm set this decision was made under.
    pub norm_version: i64,
    /// The version of the action library it was simulated with.
    pub library_version: i64,
    /// The human's words, as sent in `directive.text`.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub text: Option<String>,
}

/// Which limit was hit, and how much of the directive was simulated.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct LimitsDto {
    /// `too_many_readings` (more than `options.max_readings`: none simulated) or `deadline`.
    pub reason: String,
    /// How many readings the directive has (saturating at the largest 64-bit number).
    pub readings: u64,
    pub simulated: u64,
}

impl From<&Limits> for LimitsDto {
    fn from(l: &Limits) -> Self {
        LimitsDto {
            reason: l.kind.as_str().to_owned(),
            readings: u64::try_from(l.readings).unwrap_or(u64::MAX),
            simulated: l.simulated as u64,
        }
    }
}

impl DecisionDto {
    pub fn new(decision: &Decision, text: Option<String>) -> Self {
        DecisionDto {
            decision: decision.kind.as_str().to_owned(),
            utterance: decision.utterance.clone(),
            speech_act: decision.speech_act.to_string(),
            goal: decision.goal.as_ref().map(Term::to_string),
            interpretations: decision.interpretations.iter().map(InterpretationDto::from).collect(),
            offered: decision.offered.iter().map(Term::to_string).collect(),
            limits: decision.limits.as_ref().map(LimitsDto::from),
            norm_version: decision.norm_version,
            library_version: decision.library_version,
            text,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Check: the next step, or the rest of a plan, while acting

/// Steps to check in order from the current scene, e.g. `["get(object4)", "put(object4,tray1)"]`.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct CheckBody {
    pub scene: SceneBody,
    /// Ground action terms, 1 to 1000, done in this order.
    pub steps: Vec<String>,
    #[serde(default)]
    pub context: Option<String>,
    #[serde(default)]
    pub speaker_roles: Option<Vec<String>>,
    #[serde(default)]
    pub options: Option<CheckOptionsBody>,
}

#[derive(Clone, Debug, Default, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct CheckOptionsBody {
    /// `diarc` (default) or `natural`.
    #[serde(default)]
    pub style: Option<StyleBody>,
    /// Milliseconds the check may take, from the request's arrival (1..=60000, default 2000);
    /// past it, the steps not checked to the end are not permitted and `limits` says so.
    #[serde(default)]
    #[schema(minimum = 1, maximum = 60000)]
    pub deadline_ms: Option<u64>,
}

pub const MAX_STEPS: usize = 1000;

impl CheckInput {
    /// Validates a check request within `limits`.
    pub fn from_body(body: CheckBody, limits: &RequestLimits) -> Result<Self, Error> {
        let context = context_of(body.context)?;
        let speaker_roles = roles_of(body.speaker_roles)?;
        let scene = body.scene.into_scene(limits)?;
        if body.steps.is_empty() || body.steps.len() > MAX_STEPS {
            return Err(Error::invalid("/steps", format!("give 1 to {MAX_STEPS} steps")));
        }
        let steps = body
            .steps
            .iter()
            .enumerate()
            .map(|(i, text)| {
                let field = format!("/steps/{i}");
                let step = request_term(&field, text, limits)?;
                if step.is_var() || !step.is_ground() {
                    return Err(Error::invalid(field, "a step is a ground action, such as get(object4)"));
                }
                if let Some(name) = step.name() {
                    verb_name(name).map_err(|m| Error::invalid(&field, m))?;
                }
                Ok(step)
            })
            .collect::<Result<_, _>>()?;
        let options = body.options.unwrap_or_default();
        let style = style_of(options.style);
        let deadline = deadline_of(options.deadline_ms, limits)?;
        Ok(CheckInput {
            scene,
            steps,
            context,
            speaker_roles,
            style,
            deadline,
        })
    }
}

#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct StepCheckDto {
    pub step: String,
    pub permissible: bool,
    pub feasible: bool,
    pub reasons: Vec<ReasonDto>,
    /// The primitive steps simulated for it, in order.
    pub plan: Vec<String>,
}

#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct CheckDto {
    /// Every step is permissible and feasible under the norms in force now.
    pub permitted: bool,
    pub steps: Vec<StepCheckDto>,
    /// "Okay.", or why not the first step that may not be done.
    pub utterance: String,
    pub norm_version: i64,
    /// Present when the deadline kept steps from being checked to the end.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub limits: Option<LimitsDto>,
}

impl From<&Check> for CheckDto {
    fn from(check: &Check) -> Self {
        CheckDto {
            permitted: check.permitted(),
            steps: check
                .steps
                .iter()
                .map(|s| StepCheckDto {
                    step: s.step.to_string(),
                    permissible: s.outcome.permissible(),
                    feasible: s.outcome.feasible(),
                    reasons: reason_dtos(&s.outcome.reasons, &s.reason_words),
                    plan: s.outcome.plan.iter().map(Term::to_string).collect(),
                })
                .collect(),
            utterance: check.utterance.clone(),
            norm_version: check.norm_version,
            limits: check.limits.as_ref().map(LimitsDto::from),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::action::{ActionInput, MethodInput};

    fn members(value: serde_json::Value) -> Vec<String> {
        value.as_object().unwrap().keys().cloned().collect()
    }

    fn schema_members<T: utoipa::PartialSchema>() -> Vec<String> {
        let schema = serde_json::to_value(T::schema()).unwrap();
        members(schema["properties"].clone())
    }

    /// The document's verb is the verb the handlers take: every member of a verb with every
    /// member set is in the schema, and nothing else is.
    #[test]
    fn the_verb_schema_has_the_members_of_the_verb() {
        let method = MethodInput {
            steps: vec!["itself".into()],
            reach: vec!["X".into()],
            grasp: vec!["X".into()],
            place: Some(vec!["X".into(), "Y".into()]),
            preconditions: vec!["closed(X)".into()],
            adds: vec!["open(X)".into()],
            removes: vec!["closed(X)".into()],
        };
        let verb = ActionInput {
            name: Some("open".into()),
            parameters: vec!["X".into(), "Y".into()],
            joiner: Some("on".into()),
            distinct: true,
            methods: vec![method.clone()],
        };
        let mut written = members(serde_json::to_value(&verb).unwrap());
        let mut declared = schema_members::<ActionSchema>();
        written.sort();
        declared.sort();
        assert_eq!(written, declared);
        let mut written = members(serde_json::to_value(&method).unwrap());
        let mut declared = schema_members::<MethodSchema>();
        written.sort();
        declared.sort();
        assert_eq!(written, declared);
    }
}
