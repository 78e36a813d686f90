//! The number a reference says: "the cups", "all (of) the cups", "every cup", "each cup", "both
//! (of the) cups", "the two cups", "two (of the) cups", and nouns in the plural.
//!
//! Owns: the closed list of quantifier words and the agreement of a quantifier with its noun.
//! Must not: read a number it does not know ("some cups", "a few cups") as any other: such a
//! reference matches nothing, and the word is said back.

use super::lexicon::{Lexicon, Noun};
use super::reference::described;
use crate::engine::resolve::{Number, Sense, count_of, singulars};

/// Determiners a quantifier may take after it ("all the", "both of my").
const AFTER: &[&str] = &["the", "my", "your", "these", "those"];

/// A quantifier at the start of a reference: its number, how many words it takes (with "of"
/// and a determiner after it), and whether its noun is plural.
pub(super) fn quantifier(said: &[String]) -> Option<(Number, usize, bool)> {
    let word = |i: usize| said.get(i).map(String::as_str);
    // "of the", "the", or nothing, from `at`: how many words.
    let determined = |at: usize| {
        let of = usize::from(word(at) == Some("of"));
        let the = usize::from(word(at + of).is_some_and(|w| AFTER.contains(&w)));
        // "of" must lead to a determiner: "two of cups" is not said.
        if of == 1 && the == 0 { None } else { Some(of + the) }
    };
    let first = word(0)?;
    let found = match first {
        "all" => {
            let after = determined(1)?;
            match word(1 + after).and_then(count_of) {
                // "all three cups"
                Some(k) if k > 1 => (Number::Exactly(k), 2 + after, true),
                _ => (Number::Every, 1 + after, true),
            }
        }
        "every" => (Number::Every, 1, false),
        "each" => match determined(1)? {
            0 => (Number::Every, 1, false),
            after => (Number::Every, 1 + after, true),
        },
        "both" => (Number::Exactly(2), 1 + determined(1)?, true),
        "the" | "these" | "those" | "my" | "your" => match word(1).and_then(count_of) {
            Some(k) if k > 1 => (Number::Exactly(k), 2, true),
            _ => return None,
        },
        _ => match count_of(first) {
            // "one cup", "one of the cups"; "one" alone is a noun ("the red one").
            Some(1) if said.len() > 1 => match determined(1)? {
                0 => (Number::Any(1), 1, false),
                after => (Number::Any(1), 1 + after, true),
            },
            Some(k) if k > 1 => (Number::Any(k), 1 + determined(1)?, true),
            _ => return None,
        },
    };
    Some(found)
}

/// `body` (a reference without its determiner) as adjectives before a head noun in the plural
/// ("red cups", "ones"), if every word is placed.
pub(super) fn described_plural(body: &[String], lexicon: &Lexicon) -> Option<(Noun, Vec<Vec<Sense>>)> {
    let last = body.last()?;
    let forms = match last.as_str() {
        "ones" => vec!["one".to_owned()],
        _ => singulars(last),
    };
    let mut singular = body.to_vec();
    forms.into_iter().find_map(|form| {
        *singular.last_mut().expect("a word at least") = form;
        described(&singular, lexicon)
    })
}
