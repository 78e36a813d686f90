//! Names as a human speaks them: `cash_box` is "cash box", `pointTo` "point to". What the
//! scene's types, properties and values, and the verbs, are called in words.
//!
//! Owns: the one spoken form of a name, and what an object's names may be. Must not: know which names exist (the lexicon does).

use crate::engine::input::{Invalid, escape_unseen, normalise_phrase};

/// Characters that show nothing, yet change what a listener's screen or speech engine makes of
/// the text around them: control characters, zero-width characters and marks, and the
/// direction controls (U+202E turns what follows around). Never part of a word, never spoken.
pub fn invisible(c: char) -> bool {
    c.is_control()
        || matches!(c, '\u{200b}'..='\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2060}'..='\u{2069}' | '\u{061c}' | '\u{feff}')
}

/// A type, value or verb as spoken: `_` as spaces, camel case split, lower case.
/// `cash_box` → "cash box", `pointTo` → "point to".
pub fn spoken(name: &str) -> String {
    let mut out = String::with_capacity(name.len() + 4);
    spoken_into(name, &mut out);
    out
}

/// `spoken`, written into `out` (cleared first), so that a caller comparing many names needs
/// one buffer.
pub fn spoken_into(name: &str, out: &mut String) {
    out.clear();
    spoken_onto(name, out);
}

/// Whether `name` is spoken as `words`, without copying a name spoken as written; `buffer` is
/// scratch for one that is not.
pub fn spoken_is(name: &str, words: &str, buffer: &mut String) -> bool {
    if as_written(name) {
        return name == words;
    }
    spoken_into(name, buffer);
    buffer == words
}

/// Most names (`vase`, `object3`) are spoken as written: nothing to split, lower or trim.
fn as_written(name: &str) -> bool {
    name.bytes().all(|b| b.is_ascii_lowercase() || b.is_ascii_digit())
}

/// `spoken`, appended to `out`.
pub fn spoken_onto(name: &str, out: &mut String) {
    if as_written(name) {
        out.push_str(name);
        return;
    }
    let start = out.len();
    let mut previous: Option<char> = None;
    for c in name.chars() {
        let at_start = out.len() == start;
        if c == '_' {
            if !out.ends_with(' ') && !at_start {
                out.push(' ');
            }
        } else if c.is_uppercase() {
            if matches!(previous, Some(p) if p.is_lowercase() || p.is_ascii_digit()) && !out[start..].ends_with(' ') {
                out.push(' ');
            }
            out.extend(c.to_lowercase());
        } else {
            out.push(c);
        }
        previous = Some(c);
    }
    let kept = start + out[start..].trim_end().len();
    out.truncate(kept);
}

/// Most names one object may have.
pub const MAX_NAMES: usize = 8;

/// A combining mark: the accent of a decomposed "café" (U+0301), the dot "İstanbul" keeps when
/// lowered (U+0307). Part of the letter before it, as the words a human types keep it.
fn combining_mark(c: char) -> bool {
    matches!(c, '\u{0300}'..='\u{036f}' | '\u{1ab0}'..='\u{1aff}' | '\u{1dc0}'..='\u{1dff}' | '\u{20d0}'..='\u{20ff}' | '\u{fe20}'..='\u{fe2f}')
}

/// An object's names: 1 to 3 words of letters each, lower-cased, each once.
pub(super) fn names_of(given: Vec<String>) -> Result<Vec<String>, Invalid> {
    if given.len() > MAX_NAMES {
        return Err(Invalid::new("/names", format!("at most {MAX_NAMES} names")));
    }
    let mut names: Vec<String> = Vec::with_capacity(given.len());
    for (i, text) in given.iter().enumerate() {
        let name = normalise_phrase(text);
        let words = name.split(' ').count();
        let letters = name.chars().all(|c| c.is_alphabetic() || c == ' ' || combining_mark(c));
        let starts_with_letter = name.chars().next().is_some_and(char::is_alphabetic);
        if name.is_empty() || name.len() > 64 || words > 3 || !letters || !starts_with_letter {
            return Err(Invalid::new(
                format!("/names/{i}"),
                // Echoed so that it shows what was sent and does nothing to the screen.
                format!("`{}` is not a name of 1 to 3 words of letters", escape_unseen(text)),
            ));
        }
        if !names.contains(&name) {
            names.push(name);
        }
    }
    Ok(names)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spoken_forms() {
        for (name, words) in [
            ("cash_box", "cash box"),
            ("pointTo", "point to"),
            ("mug", "mug"),
            ("object3", "object3"),
            ("getURL", "get url"),
            ("dark_red", "dark red"),
        ] {
            assert_eq!(spoken(name), words);
            let mut after = String::from("the ");
            spoken_onto(name, &mut after);
            assert_eq!(after, format!("the {words}"));
        }
        let mut trailing = String::from("a ");
        spoken_onto("_x_", &mut trailing);
        assert_eq!(trailing, "a x");
    }

    #[test]
    fn a_name_is_spoken_as_its_words_only() {
        let mut buffer = String::new();
        for (name, words, is) in [
            ("vase", "vase", true),
            ("vase", "vases", false),
            ("cash_box", "cash box", true),
            ("cash_box", "cash_box", false),
            ("pointTo", "point to", true),
            ("Mug", "mug", true),
            ("Mug", "Mug", false),
        ] {
            assert_eq!(spoken_is(name, words, &mut buffer), is, "{name} as {words:?}");
        }
    }
}
