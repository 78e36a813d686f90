//! What a directive is for ("… to smash the vase", "… so I can cut the bread"), and
//! requests said as needs ("I need the mug", "Can I have the mug?").
//!
//! Owns: where a purpose starts, and reading it as an act the robot knows with the objects it
//! names. Must not: take a purpose for a step of the robot's, or leave out a purpose whose verb
//! is known and that names objects (it is read, or the words are not understood).

use super::Phrase;
use super::grammar::{
    DETERMINERS, FUNCTION_WORDS, PRONOUNS, is, reference, split_particle, strip_trailing_manner, verb_at,
};
use super::lexicon::Lexicon;
use crate::engine::decision::Act;

/// A purpose read: the act it names and its references.
pub(super) struct PurposeClause {
    /// As said: "to smash the vase".
    pub(super) words: String,
    pub(super) verb: String,
    pub(super) phrases: Vec<Phrase>,
}

/// What a purpose's words are.
pub(super) enum Purposed {
    /// A verb the robot knows, with the objects it names: checked against the norms.
    Read(PurposeClause),
    /// An unknown verb, or no object ("for reheating"): shown in the parse, changing nothing.
    Shown,
    /// A known verb whose objects cannot be placed: the words are not understood.
    Unplaced,
}

/// Reads `words` (a purpose, from its opening word) whose verb is at `verb_word`.
pub(super) fn read_purpose(words: &[String], verb_word: usize, lexicon: &Lexicon) -> Purposed {
    let Some((phrase, taken)) = verb_at(words, verb_word, lexicon) else {
        // "to teh left of the box", "to zorp the right of it" are a relation misspelt, not a
        // purpose: an unknown word before "(the) left of" (right, front, back, top, side) is
        // not understood, never left out.
        let after = &words[(verb_word + 1).min(words.len())..];
        let side_of = |i: usize| {
            after
                .get(i)
                .is_some_and(|w| ["left", "right", "front", "back", "top", "side"].contains(&w.as_str()))
                && after.get(i + 1).is_some_and(|w| w == "of")
        };
        if side_of(0) || after.first().is_some_and(|w| w == "the") && side_of(1) {
            return Purposed::Unplaced;
        }
        return Purposed::Shown;
    };
    let mut rest = split_particle(&words[verb_word + taken..], phrase);
    strip_trailing_manner(&mut rest, &mut Vec::new());
    if rest.len() > 1 && (rest[0] == "me" || rest[0] == "us") {
        rest.remove(0);
    }
    if phrase.arity == 0 || rest.is_empty() {
        return Purposed::Shown;
    }
    let phrases = match phrase.arity {
        1 => vec![reference(&rest, lexicon)],
        2 => match (1..rest.len()).find(|&i| phrase.joiners.contains(&rest[i])) {
            Some(i) if i + 1 < rest.len() => vec![reference(&rest[..i], lexicon), reference(&rest[i + 1..], lexicon)],
            _ => return Purposed::Unplaced,
        },
        _ => return Purposed::Unplaced,
    };
    Purposed::Read(PurposeClause {
        words: words.join(" "),
        verb: phrase.verb.clone(),
        phrases,
    })
}

/// A request said as a need, at the start of `words`: how many words the frame takes and the
/// act it is. Never before "you" ("I want you to …" is another frame) or "to" ("I want to
/// get the mug" is what the speaker will do), and never with nothing after it.
pub(super) fn need_at(words: &[String]) -> Option<(usize, Act)> {
    const NEEDS: &[(&[&str], Act)] = &[
        (&["i", "need"], Act::Want),
        (&["i", "want"], Act::Want),
        (&["i'd", "like"], Act::Want),
        (&["i", "would", "like"], Act::Want),
        (&["can", "i", "have"], Act::IndirectRequest),
        (&["could", "i", "have"], Act::IndirectRequest),
        (&["may", "i", "have"], Act::IndirectRequest),
        (&["can", "i", "get"], Act::IndirectRequest),
        (&["could", "i", "get"], Act::IndirectRequest),
    ];
    let (frame, act) = NEEDS.iter().find(|(frame, _)| is(words, 0, frame))?;
    let next = words.get(frame.len())?;
    (next != "you" && next != "to").then_some((frame.len(), *act))
}

/// Where a purpose starts in `rest` (after a reference's first word), and the position of its
/// verb within it. `known_verb(i)`: whether a verb the robot knows is said at `rest[i]`; after
/// a "to" that joins the verb's arguments ("give the knife to the child to smash the cup")
/// only such a verb, or a negation, starts a purpose: anything else is the second argument.
pub(super) fn purpose_at(
    rest: &[String],
    joiners: &[String],
    known_verb: &dyn Fn(usize) -> bool,
) -> Option<(usize, usize)> {
    const SUBJECTS: &[&str] = &["i", "we", "you", "he", "she", "they"];
    const MODALS: &[&str] = &["can", "could", "may", "might", "will", "would"];
    /// Words after "to" that make it a place or a relation, not a purpose.
    const NOT_A_VERB: &[&str] = &[
        "right", "left", "front", "back", "top", "bottom", "side", "me", "us", "him", "her",
    ];
    (1..rest.len()).find_map(|i| {
        let next = rest.get(i + 1).map(String::as_str);
        if is(rest, i, &["in", "order", "to"]) {
            return Some((i, 3));
        }
        if rest[i] == "to" && joiners.iter().any(|j| j == "to") {
            let w = next?;
            return (["not", "never"].contains(&w) || known_verb(i + 1)).then_some((i, 1));
        }
        if rest[i] == "to" {
            let w = next?;
            // "to not reheat it" is a purpose too, negated.
            let verb_like = ["not", "never"].contains(&w)
                || !DETERMINERS.contains(&w)
                    && !PRONOUNS.contains(&w)
                    && !FUNCTION_WORDS.contains(&w)
                    && !NOT_A_VERB.contains(&w)
                    && !w.bytes().all(|b| b.is_ascii_digit());
            return verb_like.then_some((i, 1));
        }
        if rest[i] == "so" {
            let skip = usize::from(next == Some("that"));
            let subject = rest.get(i + 1 + skip).map(String::as_str);
            let modal = rest.get(i + 2 + skip).map(String::as_str);
            if subject.is_some_and(|s| SUBJECTS.contains(&s)) && modal.is_some_and(|m| MODALS.contains(&m)) {
                return Some((i, 3 + skip));
            }
        }
        if rest[i] == "for"
            && next.is_some_and(|w| w.len() > 4 && w.ends_with("ing"))
            && !joiners.iter().any(|j| j == "for")
        {
            return Some((i, 1));
        }
        None
    })
}
