//! What every engine constructor shares when it builds a value from outside input: the error
//! that names the field at fault, the checks of names and numbers, the bounds an operator sets
//! on one request, and the one spelling of each option.
//!
//! Owns: `Invalid` (a JSON Pointer and a message) and the rules that more than one constructor
//! applies. Must not: know a wire format; fields are named as the request's JSON names them.

use std::ops::RangeInclusive;
use std::time::Duration;

use super::term::{TermLimits, is_constant_name};

/// What is wrong with an input, and where: `field` is a JSON Pointer (RFC 6901), relative to
/// what the constructor was given; the caller puts the pointer of that value in front.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{field}: {message}")]
pub struct Invalid {
    pub field: String,
    pub message: String,
}

impl Invalid {
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> Invalid {
        Invalid {
            field: field.into(),
            message: message.into(),
        }
    }

    /// The same fault, with the pointer of the value it was found in put in front.
    pub fn within(mut self, prefix: &str) -> Invalid {
        self.field.insert_str(0, prefix);
        self
    }
}

/// Escapes a key for use as one JSON Pointer segment (RFC 6901).
pub fn pointer_segment(key: &str) -> String {
    key.replace('~', "~0").replace('/', "~1")
}

/// Whether a character changes a screen or a voice rather than showing on it: a control
/// character (NUL, ESC, BEL, ...), a zero-width or invisible one, or one that turns the
/// direction of the text (U+202E).
pub fn is_unseen(c: char) -> bool {
    c.is_control()
        || matches!(c, '\u{200b}'..='\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2060}'..='\u{2069}'
            | '\u{061c}' | '\u{feff}')
}

/// `text` with each character of [`is_unseen`] written as `\u{..}`: for echoing what someone
/// sent in words meant for a person (an error's detail, a report on a terminal), so that it
/// shows what was sent and does nothing to the screen.
pub fn escape_unseen(text: &str) -> std::borrow::Cow<'_, str> {
    if !text.chars().any(is_unseen) {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut shown = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if is_unseen(c) {
            shown.push_str(&format!("\\u{{{:x}}}", u32::from(c)));
        } else {
            shown.push(c);
        }
    }
    std::borrow::Cow::Owned(shown)
}

/// A phrase as words are matched: lower case, one space between words.
pub fn normalise_phrase(text: &str) -> String {
    text.split_whitespace()
        .map(str::to_lowercase)
        .collect::<Vec<_>>()
        .join(" ")
}

pub use super::sym::MAX_NAME_LEN;

/// A name that must read back as a constant of a term: `object3`, `cash_box`, `red`.
pub fn constant(field: &str, text: &str, what: &str) -> Result<(), Invalid> {
    if text.len() > MAX_NAME_LEN {
        return Err(Invalid::new(
            field,
            format!("{what} is longer than {MAX_NAME_LEN} bytes"),
        ));
    }
    // A name with no letter or digit (`_`, `__`) is spoken as nothing: "the  is out of reach".
    if !is_constant_name(text) || !text.chars().any(|c| c.is_ascii_alphanumeric()) {
        return Err(Invalid::new(
            field,
            format!(
                "{what} `{text}` must start with a lower-case letter, digit or `_` and contain only letters, digits, `_`, `-` and `.`"
            ),
        ));
    }
    Ok(())
}

pub fn finite(field: &str, values: &[f64]) -> Result<(), Invalid> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(Invalid::new(field, "must be finite numbers"))
    }
}

pub fn positive(field: &str, value: f64) -> Result<(), Invalid> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Invalid::new(field, "must be a positive number"))
    }
}

/// A number option within its range, or `default` when absent.
pub fn ranged(field: &str, value: Option<u64>, range: RangeInclusive<u64>, default: u64) -> Result<u64, Invalid> {
    match value {
        None => Ok(default),
        Some(v) if range.contains(&v) => Ok(v),
        Some(v) => Err(Invalid::new(
            field,
            format!("{v} is out of range {}..={}", range.start(), range.end()),
        )),
    }
}

pub const DEFAULT_DEADLINE_MS: u64 = 2_000;
/// Default for `--max-objects`.
pub const DEFAULT_MAX_OBJECTS: usize = 10_000;
/// Default for `--max-deadline-ms`: the longest `options.deadline_ms` a request may ask for.
pub const DEFAULT_MAX_DEADLINE_MS: u64 = 60_000;
/// Default for `--max-text-bytes`: the longest human's words a directive or answer may carry.
pub const DEFAULT_MAX_TEXT_BYTES: usize = 1_000;

/// What the operator lets one clarify or check request ask of the service. Going over a limit is
/// an `Invalid` naming the field and the limit; such a request never reaches a simulation.
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
    /// The longest human's words (`directive.text`), bytes.
    pub max_text_bytes: usize,
}

impl Default for RequestLimits {
    fn default() -> Self {
        RequestLimits {
            max_objects: DEFAULT_MAX_OBJECTS,
            terms: TermLimits::DEFAULT,
            default_deadline_ms: DEFAULT_DEADLINE_MS,
            max_deadline_ms: DEFAULT_MAX_DEADLINE_MS,
            max_text_bytes: DEFAULT_MAX_TEXT_BYTES,
        }
    }
}

impl RequestLimits {
    /// The human's words (`directive.text`, `answer.text`) within `--max-text-bytes`; the fault
    /// is named `/text`, relative to what carries them.
    pub fn text(&self, text: &str) -> Result<(), Invalid> {
        if text.len() > self.max_text_bytes {
            return Err(Invalid::new(
                "/text",
                format!(
                    "{} bytes is over the limit of {} (--max-text-bytes)",
                    text.len(),
                    self.max_text_bytes
                ),
            ));
        }
        Ok(())
    }

    /// `options.deadline_ms` of a clarify or a check, within the operator's bound.
    pub fn deadline(&self, value: Option<u64>) -> Result<Duration, Invalid> {
        let ms = ranged(
            "/options/deadline_ms",
            value,
            1..=self.max_deadline_ms,
            self.default_deadline_ms,
        )?;
        Ok(Duration::from_millis(ms))
    }
}

/// An enum whose values are words of the contract (`moral`, `natural`, `forbidden_state`): the
/// one list of its values and the one spelling of each, which serde, gRPC and the store all use.
pub trait Spelled: Sized + Copy + 'static {
    const ALL: &'static [Self];

    fn as_str(self) -> &'static str;

    fn parse(text: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|v| v.as_str() == text)
    }

    /// The words an unknown value is told to choose from: "`moral` or `reflexive`".
    fn expected() -> String {
        let words: Vec<String> = Self::ALL.iter().map(|v| format!("`{}`", v.as_str())).collect();
        match words.as_slice() {
            [] => String::new(),
            [one] => one.clone(),
            [init @ .., last] => format!("{} or {last}", init.join(", ")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Spelled;
    use crate::engine::decision::Style;
    use crate::engine::request::{SinglePermissible, SoftNorms, Strategy};

    /// serde's word for every value is its one spelling, and reads back as that value.
    fn one_spelling<T>()
    where
        T: Spelled + serde::Serialize + serde::de::DeserializeOwned + PartialEq + std::fmt::Debug,
    {
        for value in T::ALL {
            let word = serde_json::to_value(value).unwrap();
            assert_eq!(word, serde_json::Value::from(value.as_str()));
            assert_eq!(serde_json::from_value::<T>(word).unwrap(), *value);
            assert_eq!(T::parse(value.as_str()), Some(*value));
        }
    }

    #[test]
    fn each_option_has_one_spelling_for_serde_grpc_and_the_schema() {
        one_spelling::<Strategy>();
        one_spelling::<SinglePermissible>();
        one_spelling::<Style>();
        one_spelling::<SoftNorms>();
        one_spelling::<crate::engine::norms::NormSetMode>();
        assert_eq!(Strategy::expected(), "`moral` or `reflexive`");
    }
}
