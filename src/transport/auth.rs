//! Who may read and change norms and verbs: bearer tokens, each with a label and a grant.
//!
//! Owns: token configuration, constant-time matching and the 401/403 rules both transports apply.
//! Must not: log or echo a secret (only labels leave this module), or decide anything else.

use std::fmt;
use std::sync::Arc;

use sha2::{Digest, Sha256};
use subtle::ConstantTimeEq;

use crate::error::Error;

/// What a request does to the curated state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// Lists or reads norms, verbs, the norm set or the audit trail.
    Read,
    /// Creates, replaces, deletes or imports.
    Write,
}

/// The label recorded in the audit trail when no token is configured.
pub const ANONYMOUS: &str = "anonymous";

/// The label of the `--admin-token`.
pub const ADMIN: &str = "admin";

struct Token {
    label: Arc<str>,
    /// SHA-256 of the secret: every comparison is over 32 bytes, so neither the secret's
    /// content nor its length shows in the time a comparison takes.
    digest: [u8; 32],
    may_write: bool,
}

/// The configured tokens. None at all: everything is open and writes are recorded as
/// `anonymous`. Write tokens (the admin token and curator tokens) guard every write; reader
/// tokens, once any is configured, guard reads of the curated state too (clarify and check are
/// never guarded: a robot must not lose its conscience to a missing header).
#[derive(Default)]
pub struct Tokens {
    tokens: Vec<Token>,
    reads_guarded: bool,
}

impl fmt::Debug for Tokens {
    /// Labels only: a secret never reaches a log line through `{:?}`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let labels: Vec<(&str, bool)> = self.tokens.iter().map(|t| (&*t.label, t.may_write)).collect();
        f.debug_struct("Tokens")
            .field("labels_may_write", &labels)
            .field("reads_guarded", &self.reads_guarded)
            .finish()
    }
}

/// A token as configured: `LABEL=SECRET`.
#[derive(Clone, PartialEq, Eq)]
pub struct LabelledSecret {
    pub label: String,
    pub secret: String,
}

impl fmt::Debug for LabelledSecret {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}=<redacted>", self.label)
    }
}

impl std::str::FromStr for LabelledSecret {
    type Err = String;

    /// `LABEL=SECRET`; the label names the token in the audit trail.
    fn from_str(text: &str) -> Result<Self, String> {
        let (label, secret) = text.split_once('=').ok_or_else(|| "expected LABEL=SECRET".to_owned())?;
        Ok(LabelledSecret {
            label: label.to_owned(),
            secret: secret.to_owned(),
        })
    }
}

fn digest(bytes: &[u8]) -> [u8; 32] {
    Sha256::digest(bytes).into()
}

/// The fewest bytes a secret may have: a guess at a shorter one is too likely to succeed.
pub const MIN_SECRET_BYTES: usize = 16;

/// Where a token was configured, as an operator would look for it.
#[derive(Clone, Copy)]
enum Given {
    Admin,
    Curator,
    Reader,
}

impl Given {
    /// The flag and the variable, to name in a startup error; and the label, for the others.
    fn named(self, label: &str) -> String {
        match self {
            Given::Admin => "--admin-token (SCRUPLE_ADMIN_TOKEN)".to_owned(),
            Given::Curator => format!("the secret of --curator-token `{label}` (SCRUPLE_CURATOR_TOKENS)"),
            Given::Reader => format!("the secret of --reader-token `{label}` (SCRUPLE_READER_TOKENS)"),
        }
    }
}

impl Tokens {
    /// Checks labels (letters, digits, `_`, `-`, `.`; unique; not `anonymous`) and secrets
    /// (unique, at least [`MIN_SECRET_BYTES`], not blank), so that a typo cannot open a door.
    /// The admin token is held to the same rule: set but empty (a variable filled from an
    /// unset one) it used to mean no token, every write open without a word. Errors name the
    /// flag and the variable, never the secret.
    pub fn new(admin: Option<&str>, curators: &[LabelledSecret], readers: &[LabelledSecret]) -> Result<Tokens, String> {
        let admin = admin.map(|secret| LabelledSecret {
            label: ADMIN.to_owned(),
            secret: secret.to_owned(),
        });
        let writers = (admin.iter().map(|t| (t, Given::Admin))).chain(curators.iter().map(|t| (t, Given::Curator)));
        let mut tokens: Vec<Token> = Vec::new();
        let mut seen_secrets: Vec<[u8; 32]> = Vec::new();
        for (token, given) in writers.chain(readers.iter().map(|t| (t, Given::Reader))) {
            let may_write = !matches!(given, Given::Reader);
            let label = &token.label;
            let label_ok = !label.is_empty()
                && label.len() <= 64
                && label != ANONYMOUS
                && label
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'));
            if !label_ok {
                return Err(format!(
                    "token label `{label}` must be 1..64 letters, digits, `_`, `-` or `.`, and not `{ANONYMOUS}`"
                ));
            }
            if tokens.iter().any(|t| &*t.label == label) {
                return Err(format!("token label `{label}` is used twice"));
            }
            if token.secret.trim().is_empty() {
                return Err(format!(
                    "{} is empty: give a secret of at least {MIN_SECRET_BYTES} bytes, or leave it unset",
                    given.named(label)
                ));
            }
            if token.secret.len() < MIN_SECRET_BYTES {
                return Err(format!(
                    "{} is shorter than {MIN_SECRET_BYTES} bytes",
                    given.named(label)
                ));
            }
            let digest = digest(token.secret.as_bytes());
            if seen_secrets.contains(&digest) {
                return Err(format!("token `{label}` has the same secret as another token"));
            }
            seen_secrets.push(digest);
            tokens.push(Token {
                label: Arc::from(label.as_str()),
                digest,
                may_write,
            });
        }
        let reads_guarded = tokens.iter().any(|t| !t.may_write);
        Ok(Tokens { tokens, reads_guarded })
    }

    /// Whether any token guards writes.
    pub fn writes_guarded(&self) -> bool {
        !self.tokens.is_empty()
    }

    /// The label of the caller allowed `access` with this `authorization` value (HTTP header or
    /// gRPC metadata). Unguarded: `anonymous`. No bearer credential: 401. A credential that is no
    /// configured token, or a reader's on a write: 403.
    pub fn authorize(&self, authorization: Option<&str>, access: Access) -> Result<Arc<str>, Error> {
        let guarded = match access {
            Access::Read => self.reads_guarded,
            Access::Write => self.writes_guarded(),
        };
        if !guarded {
            return Ok(Arc::from(ANONYMOUS));
        }
        let sent = authorization.and_then(bearer).ok_or(Error::Unauthenticated)?;
        let sent = digest(sent.as_bytes());
        // Every token is compared, whichever matches, so the time taken does not say which.
        let mut found: Option<&Token> = None;
        for token in &self.tokens {
            if bool::from(token.digest.ct_eq(&sent)) {
                found = Some(token);
            }
        }
        let token = found.ok_or(Error::Forbidden("the token sent is not one this service knows"))?;
        if access == Access::Write && !token.may_write {
            return Err(Error::Forbidden(
                "this token may read norms and verbs but not change them",
            ));
        }
        Ok(token.label.clone())
    }
}

/// The token of an `Authorization` value with the Bearer scheme, which RFC 9110 §11.1 makes
/// case-insensitive (`bearer`, `BEARER`); the token itself is compared exactly.
fn bearer(authorization: &str) -> Option<&str> {
    let (scheme, token) = authorization.trim().split_once(' ')?;
    let token = token.trim_start();
    (scheme.eq_ignore_ascii_case("bearer") && !token.is_empty()).then_some(token)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labelled(label: &str, secret: &str) -> LabelledSecret {
        LabelledSecret {
            label: label.to_owned(),
            secret: secret.to_owned(),
        }
    }

    #[test]
    fn writers_readers_and_strangers_get_what_they_may() {
        let tokens = Tokens::new(
            Some("admin-secret-0123456789"),
            &[labelled("alice", "alice-secret-0123456789")],
            &[labelled("dashboard", "reader-secret-0123456789")],
        )
        .unwrap();
        let bearer = |s: &str| format!("Bearer {s}");
        let write = |auth: Option<&str>| tokens.authorize(auth, Access::Write).map(|l| l.to_string());
        let read = |auth: Option<&str>| tokens.authorize(auth, Access::Read).map(|l| l.to_string());
        assert_eq!(write(Some(&bearer("admin-secret-0123456789"))).unwrap(), "admin");
        assert_eq!(write(Some(&bearer("alice-secret-0123456789"))).unwrap(), "alice");
        assert!(matches!(write(None), Err(Error::Unauthenticated)));
        assert!(matches!(write(Some("Basic abc")), Err(Error::Unauthenticated)));
        assert!(matches!(
            write(Some(&bearer("reader-secret-0123456789"))),
            Err(Error::Forbidden(_))
        ));
        assert!(matches!(
            write(Some(&bearer("nobody-0123456789abc"))),
            Err(Error::Forbidden(_))
        ));
        assert_eq!(read(Some(&bearer("reader-secret-0123456789"))).unwrap(), "dashboard");
        assert_eq!(read(Some(&bearer("alice-secret-0123456789"))).unwrap(), "alice");
        assert!(matches!(read(None), Err(Error::Unauthenticated)));
    }

    #[test]
    fn without_tokens_everything_is_open_and_anonymous() {
        let tokens = Tokens::new(None, &[], &[]).unwrap();
        assert_eq!(&*tokens.authorize(None, Access::Write).unwrap(), ANONYMOUS);
        let writers_only = Tokens::new(Some("admin-secret-0123456789"), &[], &[]).unwrap();
        assert_eq!(&*writers_only.authorize(None, Access::Read).unwrap(), ANONYMOUS);
    }

    #[test]
    fn bad_configurations_are_refused_before_the_port_opens() {
        let short = Tokens::new(None, &[labelled("bob", "short")], &[]).unwrap_err();
        assert!(short.contains("shorter than 16"), "{short}");
        let twice = Tokens::new(
            None,
            &[labelled("bob", "bob-secret-0123456789")],
            &[labelled("bob", "other-secret-0123456789")],
        )
        .unwrap_err();
        assert!(twice.contains("used twice"), "{twice}");
        let same = Tokens::new(
            Some("shared-secret-0123456789"),
            &[],
            &[labelled("r", "shared-secret-0123456789")],
        )
        .unwrap_err();
        assert!(same.contains("same secret"), "{same}");
        assert!(Tokens::new(None, &[labelled("a b", "bob-secret-0123456789")], &[]).is_err());
        for admin in ["", " \t ", "short-SECRET"] {
            let refused = Tokens::new(Some(admin), &[], &[]).unwrap_err();
            assert!(
                refused.starts_with("--admin-token (SCRUPLE_ADMIN_TOKEN) is "),
                "{refused}"
            );
            assert!(!refused.contains("SECRET"), "the secret is not echoed: {refused}");
        }
        assert!(format!("{:?}", labelled("bob", "bob-secret-0123456789")).contains("redacted"));
    }
}
