//! One reference's words: a determiner, adjectives and a noun, narrowed by a relative clause or
//! an exclusion, and carrying relations, a superlative or an ordinal (`relations`).
//!
//! Owns: placing every word of a reference. Must not: place a word it does not know as anything
//! but unknown: such a reference matches nothing, and the words not placed are said back.

use super::Phrase;
use super::grammar::PRONOUNS;
use super::lexicon::{Lexicon, Noun};
use super::relations::{related, relation_at};
use super::vocabulary::{DETERMINERS, STRUCTURE};
use crate::engine::describe::after_the_noun;
use crate::engine::resolve::{Reference, Sense};

/// The most words of a reference after its last noun said back as not understood; a longer
/// tail is reported as the whole reference.
const MAX_UNPLACED_TAIL: usize = 12;

/// `base` narrowed inside one reference by a relative clause or an exclusion: what `by` names
/// must (`keep`) or must not be true of the object. Words after the clause that name nothing
/// make it match nothing, as in a narrowing set off by a comma.
fn excluded(base: Phrase, by: Phrase, keep: bool, words: String) -> Phrase {
    let by = match by.words.is_empty() {
        true => Reference::Nothing {
            words: String::new(),
            unplaced: Some(words.clone()),
        },
        false => by.reference,
    };
    Phrase {
        reference: Reference::Narrowed {
            base: Box::new(base.reference),
            by: Box::new(by),
            keep,
            words: words.clone(),
        },
        words,
    }
}

/// A reference, or, where it has no noun, adjectives alone: "red" is what is red.
pub(super) fn reference_or_adjectives(words: &[String], lexicon: &Lexicon) -> Phrase {
    let phrase = reference(words, lexicon);
    if !matches!(phrase.reference, Reference::Nothing { .. }) || words.is_empty() {
        return phrase;
    }
    match adjectives(words, lexicon) {
        Some(adjectives) => Phrase {
            reference: Reference::Spoken {
                kinds: Vec::new(),
                named: Vec::new(),
                adjectives,
                words: phrase.words.clone(),
                indefinite: false,
            },
            words: phrase.words,
        },
        None => phrase,
    }
}

/// One reference's words. Every word must be placed, as determiner, adjective or noun; one
/// that is not makes the reference match nothing, and one the grammar could not place at all
/// is said back ("pls" in "the mug pls").
pub(super) fn reference(span: &[String], lexicon: &Lexicon) -> Phrase {
    let words = span.join(" ");
    // "me" is the speaker: their object when the scene holds them, else the speaker by id.
    if span == ["me"] {
        let reference = Reference::Speaker(lexicon.speaker.to_owned());
        return Phrase { words, reference };
    }
    // "the mug or the cup": any one of them will do.
    if span.len() > 2 && span[1..span.len() - 1].iter().any(|w| w == "or") {
        let options: Vec<Reference> = (span.split(|w| w == "or"))
            .map(|part| match part.is_empty() {
                true => Reference::Nothing {
                    words: String::new(),
                    unplaced: Some("or".to_owned()),
                },
                false => reference(part, lexicon).reference,
            })
            .collect();
        // "the cups or the mugs" would be every cup or every mug: one object of either is not
        // what was said, and the choice between the groups is not read.
        if options.iter().any(|o| o.number().is_some()) {
            return Phrase {
                reference: Reference::Nothing {
                    words: words.clone(),
                    unplaced: Some(words.clone()),
                },
                words,
            };
        }
        return Phrase {
            reference: Reference::Either {
                options,
                words: words.clone(),
            },
            words,
        };
    }
    // "the mug that is not red", "the mug which is red": a relative clause of adjectives;
    // "any cup but (except, other than) the blue one": every match less what follows.
    if let Some(at) = (1..span.len().saturating_sub(2))
        .find(|&i| ["that", "which"].contains(&span[i].as_str()) && ["is", "are"].contains(&span[i + 1].as_str()))
    {
        let negated = span[at + 2] == "not";
        let clause = &span[at + 2 + usize::from(negated)..];
        // "the cup that is on the table" says what "the cup on the table" does; "that is not
        // on the table" leaves out what "the one on the table" selects.
        if relation_at(clause, 0).is_some() {
            let mut said: Vec<String> = match negated {
                true => vec!["one".to_owned()],
                false => span[..at].to_vec(),
            };
            said.extend(clause.iter().cloned());
            let related = reference(&said, lexicon);
            if !negated {
                return Phrase {
                    reference: related.reference,
                    words,
                };
            }
            return excluded(reference(&span[..at], lexicon), related, false, words);
        }
        let by = reference_or_adjectives(clause, lexicon);
        return excluded(reference(&span[..at], lexicon), by, !negated, words);
    }
    if let Some((at, n)) = (1..span.len()).find_map(|i| match span[i].as_str() {
        "but" | "except" => Some((i, 1)),
        "other" if span.get(i + 1).is_some_and(|w| w == "than") => Some((i, 2)),
        _ => None,
    }) {
        let by = reference_or_adjectives(&span[at + n..], lexicon);
        return excluded(reference(&span[..at], lexicon), by, false, words);
    }
    if span.len() == 1 && PRONOUNS.contains(&span[0].as_str())
        || span.len() == 2 && ["this", "that"].contains(&span[0].as_str()) && span[1] == "one"
    {
        return Phrase {
            reference: Reference::Pronoun { words: words.clone() },
            words,
        };
    }
    let body = match span.first() {
        Some(first) if DETERMINERS.contains(&first.as_str()) => &span[1..],
        _ => span,
    };
    let reference = match described(body, lexicon) {
        Some((noun, adjectives)) => Reference::Spoken {
            kinds: noun.kinds,
            named: noun.named,
            adjectives,
            words: words.clone(),
            indefinite: ["a", "an", "any"].contains(&span[0].as_str()),
        },
        None => match related(span, lexicon) {
            Some(phrase) => return phrase,
            None => Reference::Nothing {
                words: words.clone(),
                unplaced: unplaced(body, lexicon),
            },
        },
    };
    Phrase { reference, words }
}

/// `body` (a reference without its determiner) as adjectives and a head noun (or "one"), if
/// every word is placed; "the one" alone names nothing.
pub(super) fn described(body: &[String], lexicon: &Lexicon) -> Option<(Noun, Vec<Vec<Sense>>)> {
    if let Some(found) = described_before(body, lexicon) {
        return Some(found);
    }
    // "the book on floor": a property that is a phrase, after the noun, as the robot speaks it.
    let shortest = body.len().saturating_sub(MAX_UNPLACED_TAIL).max(1);
    (shortest..body.len()).rev().find_map(|end| {
        if !after_the_noun(&body[end..].join(" ")) {
            return None;
        }
        let (noun, mut before) = described_before(&body[..end], lexicon)?;
        before.extend(adjectives(&body[end..], lexicon)?);
        Some((noun, before))
    })
}

/// `body` as adjectives before a head noun (or "one").
fn described_before(body: &[String], lexicon: &Lexicon) -> Option<(Noun, Vec<Vec<Sense>>)> {
    let (noun, head) = match body.last()?.as_str() {
        "one" => (Noun::default(), 1),
        _ => lexicon.head_noun(body)?,
    };
    let adjectives = adjectives(&body[..body.len() - head], lexicon)?;
    if noun == Noun::default() && adjectives.is_empty() {
        return None;
    }
    Some((noun, adjectives))
}

/// Every word of `words` placed as an adjective (the longest known phrase first), or `None`.
fn adjectives(words: &[String], lexicon: &Lexicon) -> Option<Vec<Vec<Sense>>> {
    let mut adjectives = Vec::new();
    let mut i = 0;
    while i < words.len() {
        if lexicon.expired() {
            return None;
        }
        let (senses, n) = lexicon.adjective_at(&words[i..])?;
        adjectives.push(senses);
        i += n;
    }
    Some(adjectives)
}

/// The words of a reference that failed which the grammar could not place at all: those after
/// a complete reference ("pls" in "the mug pls", "to the right of the fork"), else a word it
/// knows as a shape it does not read yet ("second", "mugs"). `None` when every word was
/// understood as what it could be and the scene has nothing so described ("the wet mug").
pub(super) fn unplaced(body: &[String], lexicon: &Lexicon) -> Option<String> {
    let shortest = body.len().saturating_sub(MAX_UNPLACED_TAIL).max(1);
    for end in (shortest..body.len()).rev() {
        if lexicon.expired() {
            return None;
        }
        if described(&body[..end], lexicon).is_some() {
            return Some(body[end..].join(" "));
        }
    }
    // "it back": a pronoun with words after it that place nothing.
    if body.len() > 1 && PRONOUNS.contains(&body[0].as_str()) {
        return Some(body[1..].join(" "));
    }
    let plural_of_known = |w: &String| {
        (w.strip_suffix("es").into_iter().chain(w.strip_suffix('s')))
            .any(|stem| !stem.is_empty() && lexicon.head_noun(&[stem.to_owned()]).is_some())
    };
    body.iter()
        .find(|w| STRUCTURE.contains(&w.as_str()) || plural_of_known(w))
        .cloned()
}
