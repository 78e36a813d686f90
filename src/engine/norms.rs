//! Norms: what they say, how a curator's input becomes one, and the compiled set a request checks.
//!
//! Owns: norm validation (field-relative errors), and through `compiled` the indexes keyed by
//! action name and by fact functor and the two checks (an action about to be done; the facts a
//! step made true). Must not: read the database or know which transport asked.

use super::input::{Invalid, Spelled, escape_unseen};
use super::term::Term;

mod compiled;

pub use compiled::{ActionViolation, CompiledNorms, InForce, SoftMatch, StateViolation};

/// What a norm is about (an action done, or a state entered) and its force.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NormKind {
    ForbiddenAction,
    ForbiddenState,
    /// Should not: breaking it lowers a reading's norm score by its severity.
    DiscouragedAction,
    DiscouragedState,
    /// Should: meeting it raises a reading's norm score by its severity.
    PreferredAction,
    PreferredState,
}

/// What meeting a norm does to a reading. Only `Forbidden` can make one impermissible; the soft
/// forces only rank readings that are permissible and feasible.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Force {
    Forbidden,
    Discouraged,
    Preferred,
}

impl NormKind {
    /// Whether the norm names an action (its `action` member) rather than a state (`state`).
    pub fn on_action(self) -> bool {
        matches!(
            self,
            NormKind::ForbiddenAction | NormKind::DiscouragedAction | NormKind::PreferredAction
        )
    }

    /// The norm's term as its `action` member or as its `state` member, whichever it has.
    pub fn members<T>(self, term: T) -> (Option<T>, Option<T>) {
        if self.on_action() {
            (Some(term), None)
        } else {
            (None, Some(term))
        }
    }

    pub fn force(self) -> Force {
        match self {
            NormKind::ForbiddenAction | NormKind::ForbiddenState => Force::Forbidden,
            NormKind::DiscouragedAction | NormKind::DiscouragedState => Force::Discouraged,
            NormKind::PreferredAction | NormKind::PreferredState => Force::Preferred,
        }
    }

    pub fn is_soft(self) -> bool {
        self.force() != Force::Forbidden
    }

    /// The functor of a reason this kind of norm gives, as speech acts carry it:
    /// `forbiddenAction(destroy)`, `discouragedState(holding(self,mug2))`.
    pub fn reason_functor(self) -> &'static str {
        match self {
            NormKind::ForbiddenAction => "forbiddenAction",
            NormKind::ForbiddenState => "forbiddenState",
            NormKind::DiscouragedAction => "discouragedAction",
            NormKind::DiscouragedState => "discouragedState",
            NormKind::PreferredAction => "preferredAction",
            NormKind::PreferredState => "preferredState",
        }
    }
}

impl Spelled for NormKind {
    const ALL: &'static [NormKind] = &[
        NormKind::ForbiddenAction,
        NormKind::ForbiddenState,
        NormKind::DiscouragedAction,
        NormKind::DiscouragedState,
        NormKind::PreferredAction,
        NormKind::PreferredState,
    ];

    fn as_str(self) -> &'static str {
        match self {
            NormKind::ForbiddenAction => "forbidden_action",
            NormKind::ForbiddenState => "forbidden_state",
            NormKind::DiscouragedAction => "discouraged_action",
            NormKind::DiscouragedState => "discouraged_state",
            NormKind::PreferredAction => "preferred_action",
            NormKind::PreferredState => "preferred_state",
        }
    }
}

/// How an imported norm set meets the stored one: `replace` makes it the whole set; `merge`
/// replaces the norms it names by id, adds those without one, and keeps every other norm (and
/// its revision) as it was.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum NormSetMode {
    #[default]
    Replace,
    Merge,
}

impl Spelled for NormSetMode {
    const ALL: &'static [NormSetMode] = &[NormSetMode::Replace, NormSetMode::Merge];

    fn as_str(self) -> &'static str {
        match self {
            NormSetMode::Replace => "replace",
            NormSetMode::Merge => "merge",
        }
    }
}

/// The kinds as an error lists them: "forbidden_action, forbidden_state, ...".
fn kinds_listed() -> String {
    NormKind::ALL.iter().map(|k| k.as_str()).collect::<Vec<_>>().join(", ")
}

pub const DEFAULT_SEVERITY: u8 = 3;
pub const MAX_WHEN: usize = 16;
pub const MAX_CONTEXT_LEN: usize = 128;
pub const MAX_NOTE_LEN: usize = 4096;
/// Largest norm id a client may send: 2^53 − 1, the largest integer every JSON client reads
/// exactly.
pub const MAX_NORM_ID: i64 = (1 << 53) - 1;

/// A context or role name as norms and requests are matched on: trimmed, lower-case, each run of
/// inner white space one `_`. A norm for "Hospital" must apply to a request in "hospital ": a
/// norm that silently applies nowhere is a safety fault.
pub fn normalise_name(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for (i, word) in text.split_whitespace().enumerate() {
        if i > 0 {
            out.push('_');
        }
        out.extend(word.chars().flat_map(char::to_lowercase));
    }
    out
}

/// Whether a normalised context or role name is made only of what a person can read and type
/// again: ASCII letters, digits, `_` and `-`. One rule for contexts and roles alike: a name
/// holding an invisible, control or direction character ("ward" + U+200B) would be stored and
/// then meet no request anyone could write, a norm that silently applies nowhere.
fn is_plain_name(name: &str) -> bool {
    name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// A context as norms and requests carry it: normalised (see [`normalise_name`]), 1 to
/// [`MAX_CONTEXT_LEN`] bytes of the characters a role name may hold ([`is_plain_name`]); the
/// fault is named `/context`.
pub fn context_name(text: &str) -> Result<String, Invalid> {
    let context = normalise_name(text);
    if context.is_empty() || context.len() > MAX_CONTEXT_LEN {
        return Err(Invalid::new(
            "/context",
            format!("must be 1 to {MAX_CONTEXT_LEN} bytes long"),
        ));
    }
    if !is_plain_name(&context) {
        return Err(Invalid::new(
            "/context",
            format!(
                "`{}` is not a context name (letters, digits, `_`, `-`)",
                escape_unseen(text)
            ),
        ));
    }
    Ok(context)
}

/// A valid norm, not yet stored. `term` is the action (a bare name names every action of that
/// name, any arity) or the state fact the norm is about.
#[derive(Clone, Debug, PartialEq)]
pub struct NormSpec {
    pub kind: NormKind,
    pub term: Term,
    /// Facts that must hold, under the same bindings, in the world at that moment.
    pub when: Vec<Term>,
    /// `None`: in force in every context.
    pub context: Option<String>,
    /// 1 (mild) ..= 5 (grave).
    pub severity: u8,
    pub note: Option<String>,
    /// When not empty, the norm applies only to speakers with at least one of these roles.
    pub roles: Vec<String>,
    /// The norm does not apply to speakers with any of these roles.
    pub exempt_roles: Vec<String>,
}

impl NormSpec {
    /// Whether the norm holds only under conditions (facts, roles, a context): a reason it
    /// gives is never spoken as if it forbade the action or state outright.
    pub fn conditional(&self) -> bool {
        !self.when.is_empty() || !self.roles.is_empty() || !self.exempt_roles.is_empty() || self.context.is_some()
    }
}

/// Who asks and where: the context and the speaker's roles select the norms in force, and
/// `soft` whether the soft norms are among them (off for `soft_norms: ignore`).
#[derive(Clone, Copy, Debug)]
pub struct Scope<'a> {
    pub context: &'a str,
    pub roles: &'a [String],
    pub soft: bool,
}

/// A stored norm.
#[derive(Clone, Debug, PartialEq)]
pub struct Norm {
    pub id: i64,
    /// The norm-set version at which this norm last changed: its ETag, unique over the store's
    /// history (0 for a norm that was never stored).
    pub revision: i64,
    pub spec: NormSpec,
}

impl Norm {
    /// In force for this request: its context (if any) is the request's, it names one of the
    /// speaker's roles (if it names any), and it exempts none of them.
    fn applies_in(&self, scope: Scope<'_>) -> bool {
        let spec = &self.spec;
        (scope.soft || !spec.kind.is_soft())
            && spec.context.as_deref().is_none_or(|c| c == scope.context)
            && (spec.roles.is_empty() || spec.roles.iter().any(|r| scope.roles.contains(r)))
            && !spec.exempt_roles.iter().any(|r| scope.roles.contains(r))
    }
}

/// A norm as a curator wrote it, before validation. Every field optional so that a missing one
/// gets its own error naming it.
#[derive(Clone, Debug, Default)]
pub struct NormInput {
    pub kind: Option<String>,
    pub action: Option<String>,
    pub state: Option<String>,
    pub when: Option<Vec<String>>,
    pub context: Option<String>,
    pub severity: Option<i64>,
    pub note: Option<String>,
    pub roles: Option<Vec<String>>,
    pub exempt_roles: Option<Vec<String>>,
}

/// A literal must name a fact or an action: a bare variable would match anything.
fn parse_literal(field: &str, text: &str, what: &str) -> Result<Term, Invalid> {
    let term = Term::parse(text).map_err(|e| Invalid::new(field, format!("not a term: {e}")))?;
    if term.is_var() {
        return Err(Invalid::new(
            field,
            format!("{what} must start with a name, not a variable"),
        ));
    }
    Ok(term)
}

impl NormInput {
    /// Validates every field; the first fault found is reported, nothing is half-accepted.
    pub fn validate(self) -> Result<NormSpec, Invalid> {
        let kind_text = self
            .kind
            .ok_or_else(|| Invalid::new("/kind", format!("missing; one of {}", kinds_listed())))?;
        let kind = NormKind::parse(&kind_text).ok_or_else(|| {
            Invalid::new(
                "/kind",
                format!("unknown kind `{kind_text}`; one of {}", kinds_listed()),
            )
        })?;
        let name = kind.as_str();
        let term = if kind.on_action() {
            if self.state.is_some() {
                return Err(Invalid::new(
                    "/state",
                    format!("a {name} norm has `action`, not `state`"),
                ));
            }
            let text = self
                .action
                .ok_or_else(|| Invalid::new("/action", "missing; e.g. \"destroy\" or \"get(X)\""))?;
            let action = parse_literal("/action", &text, "an action")?;
            // A norm on a verb no library can hold applies nowhere, and its words would be
            // empty ("_ is forbidden action").
            if let Some(name) = action.name() {
                super::action::verb_name(name).map_err(|m| Invalid::new("/action", m))?;
            }
            action
        } else {
            if self.action.is_some() {
                return Err(Invalid::new(
                    "/action",
                    format!("a {name} norm has `state`, not `action`"),
                ));
            }
            let text = self
                .state
                .ok_or_else(|| Invalid::new("/state", "missing; e.g. \"holding(self,X)\""))?;
            parse_literal("/state", &text, "a state")?
        };
        let when_texts = self.when.unwrap_or_default();
        if when_texts.len() > MAX_WHEN {
            return Err(Invalid::new("/when", format!("at most {MAX_WHEN} conditions")));
        }
        let when = when_texts
            .iter()
            .enumerate()
            .map(|(i, text)| parse_literal(&format!("/when/{i}"), text, "a condition"))
            .collect::<Result<Vec<_>, _>>()?;
        let context = self.context.as_deref().map(context_name).transpose()?;
        let severity = match self.severity {
            None => DEFAULT_SEVERITY,
            Some(s @ 1..=5) => s as u8,
            Some(s) => return Err(Invalid::new("/severity", format!("{s} is out of range 1..5"))),
        };
        if let Some(note) = &self.note
            && note.len() > MAX_NOTE_LEN
        {
            return Err(Invalid::new("/note", format!("at most {MAX_NOTE_LEN} bytes")));
        }
        let roles = validate_roles("/roles", self.roles)?;
        let exempt_roles = validate_roles("/exempt_roles", self.exempt_roles)?;
        if let Some(both) = roles.iter().find(|r| exempt_roles.contains(r)) {
            return Err(Invalid::new(
                "/exempt_roles",
                format!("`{both}` is both a role the norm applies to and one it exempts"),
            ));
        }
        Ok(NormSpec {
            kind,
            term,
            when,
            context,
            severity,
            note: self.note,
            roles,
            exempt_roles,
        })
    }
}

pub const MAX_ROLES: usize = 16;

/// Role names are short words: letters, digits, `_`, `-` (the rule contexts follow,
/// [`is_plain_name`]); at most [`MAX_ROLES`] of them. Used for a norm's roles and for a
/// request's speaker roles alike.
pub fn validate_roles(field: &str, roles: Option<Vec<String>>) -> Result<Vec<String>, Invalid> {
    let given = roles.unwrap_or_default();
    if given.len() > MAX_ROLES {
        return Err(Invalid::new(field, format!("at most {MAX_ROLES} roles")));
    }
    // Normalised as contexts are; a role named twice (perhaps in two spellings) counts once.
    let mut roles: Vec<String> = Vec::with_capacity(given.len());
    for (i, text) in given.iter().enumerate() {
        let role = normalise_name(text);
        let valid = !role.is_empty() && role.len() <= MAX_CONTEXT_LEN && is_plain_name(&role);
        if !valid {
            return Err(Invalid::new(
                format!("{field}/{i}"),
                format!(
                    "`{}` is not a role name (letters, digits, `_`, `-`)",
                    escape_unseen(text)
                ),
            ));
        }
        if !roles.contains(&role) {
            roles.push(role);
        }
    }
    Ok(roles)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn input(kind: &str) -> NormInput {
        NormInput {
            kind: Some(kind.into()),
            ..NormInput::default()
        }
    }

    #[test]
    fn validation_names_the_field_at_fault() {
        let cases: Vec<(NormInput, &str)> = vec![
            (NormInput::default(), "/kind"),
            (input("forbidden_thing"), "/kind"),
            (input("forbidden_action"), "/action"),
            (input("forbidden_state"), "/state"),
            (
                NormInput {
                    action: Some("get(".into()),
                    ..input("forbidden_action")
                },
                "/action",
            ),
            (
                NormInput {
                    action: Some("X".into()),
                    ..input("forbidden_action")
                },
                "/action",
            ),
            (
                NormInput {
                    state: Some("p(a)".into()),
                    ..input("forbidden_action")
                },
                "/state",
            ),
            (
                NormInput {
                    state: Some("p(X)".into()),
                    when: Some(vec!["q(X)".into(), "r(".into()]),
                    ..input("forbidden_state")
                },
                "/when/1",
            ),
            (
                NormInput {
                    action: Some("get".into()),
                    severity: Some(0),
                    ..input("forbidden_action")
                },
                "/severity",
            ),
            (
                NormInput {
                    action: Some("get".into()),
                    severity: Some(6),
                    ..input("forbidden_action")
                },
                "/severity",
            ),
            (
                NormInput {
                    action: Some("get".into()),
                    context: Some(String::new()),
                    ..input("forbidden_action")
                },
                "/context",
            ),
        ];
        for (norm, field) in cases {
            let err = norm.clone().validate().unwrap_err();
            assert_eq!(err.field, field, "{norm:?}: {err}");
        }
    }

    #[test]
    fn valid_norms_get_defaults_and_canonical_terms() {
        let spec = NormInput {
            action: Some("get( X )".into()),
            ..input("forbidden_action")
        }
        .validate()
        .unwrap();
        assert_eq!(spec.term.to_string(), "get(X)");
        assert_eq!(spec.severity, DEFAULT_SEVERITY);
        assert!(spec.when.is_empty() && spec.context.is_none());
    }
}
