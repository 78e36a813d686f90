//! The grammar of a directive in words, hand-written and deterministic: each step looks at the
//! words in front of it and either takes them or stops; nothing is tried twice.
//!
//! ```text
//! sentence  := vocative? politeness* frame? verb-phrase adjunct* politeness* vocative?
//! frame     := "can"|"could"|"will"|"would" "you" | "would you mind" | "i want/need/'d like you to"
//!              | "go" "and"?
//! verb-phrase := verb "me"? reference (joiner reference)? particle?
//! reference := pronoun | determiner? adjective* noun | determiner? adjective* "one"
//! ```
//!
//! Owns: the sentence's shape. Must not: place a word it does not know inside a reference as
//! anything but unknown.

use super::lexicon::{Lexicon, Noun, inflects};
use super::{Parse, Phrase, Understanding};
use crate::engine::action::VerbPhrase;
use crate::engine::action::verb_name;
use crate::engine::decision::{Act, Unclear};
use crate::engine::request::{Answer, Directive};
use crate::engine::resolve::Reference;
use crate::engine::scene::Scene;

const DETERMINERS: &[&str] = &["the", "a", "an", "this", "that", "my", "your"];
const PRONOUNS: &[&str] = &["it", "this", "that"];
/// Words that open a question asking for information rather than action.
const QUESTION_WORDS: &[&str] = &[
    "what", "which", "who", "whom", "whose", "where", "when", "why", "how", "is", "are", "was", "were", "does", "did",
    "do", "has", "have", "am", "should", "shall", "may", "might", "must",
];
/// Words that are never a verb, so never the unknown verb an imperative names: "on the mug"
/// is not a request to "on" it.
const FUNCTION_WORDS: &[&str] = &[
    "the", "a", "an", "my", "your", "on", "onto", "in", "into", "inside", "upon", "at", "to", "with", "from", "of",
    "by", "under", "over", "off", "up", "down", "for", "me", "us", "you", "i", "we", "and", "or", "not", "yes", "no",
];
/// Words that open a trailing adjunct, which selects no object and may be left out.
const ADJUNCTS: &[&str] = &[
    "for",
    "to",
    "quickly",
    "now",
    "carefully",
    "gently",
    "slowly",
    "immediately",
    "again",
    "soon",
    "asap",
];

/// One word of the text, lower case, and whether a comma followed it.
#[derive(Clone, Debug)]
struct Token {
    word: String,
    comma: bool,
}

/// Words, lower case; commas remembered (a vocative is set off by one); the punctuation of a
/// sentence and invisible characters dropped, apostrophes kept ("don't", "i'd"). Any other
/// character (a sign, a symbol, an emoji) is part of its word and never dropped: "the ★ vase"
/// has a word nobody knows, which must narrow the reference to nothing, not to every vase.
fn tokens(text: &str) -> Vec<Token> {
    let mut out: Vec<Token> = Vec::new();
    for piece in text.split_whitespace() {
        let mut word = String::new();
        for c in piece.chars() {
            match c {
                // Most words are ASCII: lowered without `to_lowercase`'s iterator.
                c if c.is_ascii_alphanumeric() => word.push(c.to_ascii_lowercase()),
                ',' => {
                    if !word.is_empty() {
                        out.push(Token {
                            word: std::mem::take(&mut word),
                            comma: false,
                        });
                    }
                    if let Some(last) = out.last_mut() {
                        last.comma = true;
                    }
                }
                '\'' | '’' => word.push('\''),
                c if is_punctuation(c) || is_invisible(c) => {}
                c => word.extend(c.to_lowercase()),
            }
        }
        if !word.is_empty() {
            out.push(Token { word, comma: false });
        }
    }
    out
}

/// Marks that end or set off a sentence or a quotation, which carry no word: ASCII's and the
/// common ones of other scripts.
const PUNCTUATION: &str = ".!?;:\"`()[]{}‘“”„«»‹›…¡¿–—。、，！？：；（）「」『』";

fn is_punctuation(c: char) -> bool {
    PUNCTUATION.contains(c)
}

/// Characters that show nothing: control characters, and the zero-width space and byte-order
/// mark that copying text can leave inside a word.
fn is_invisible(c: char) -> bool {
    c.is_control() || matches!(c, '\u{200b}' | '\u{feff}')
}

fn is(words: &[String], at: usize, expected: &[&str]) -> bool {
    expected.len() <= words.len().saturating_sub(at) && expected.iter().zip(&words[at..]).all(|(e, w)| e == w)
}

/// The sentence's shape, stage by stage; `words` shrinks from both ends as each stage takes
/// what is its own.
pub fn read(text: &str, lexicon: &Lexicon) -> Understanding {
    let mut tokens = tokens(text);
    let all = |tokens: &[Token]| tokens.iter().map(|t| t.word.as_str()).collect::<Vec<_>>().join(" ");
    let unclear = |why, words: String| Understanding::NotUnderstood { why, words };
    // Politeness at the very end ("..., please"), before a vocative there is looked for.
    while tokens.last().is_some_and(|t| t.word == "please") {
        tokens.pop();
    }
    let mut addressee = None;
    // A vocative: one or two words set off by a comma, at the start or at the end.
    if let Some(i) = tokens.iter().position(|t| t.comma)
        && i < 2
    {
        addressee = Some(all(&tokens[..=i]));
        tokens.drain(..=i);
    }
    if addressee.is_none()
        && tokens.len() >= 3
        && let Some(i) = tokens[..tokens.len() - 1].iter().rposition(|t| t.comma)
        && tokens.len() - (i + 1) <= 2
    {
        addressee = Some(all(&tokens[i + 1..]));
        tokens.truncate(i + 1);
    }
    let mut words: Vec<String> = tokens.into_iter().map(|t| t.word).collect();
    if words.is_empty() {
        return unclear(Unclear::Empty, String::new());
    }
    let mut act = Act::Command;
    // Frames and politeness at the start, in any order they come: "please can you go and ...".
    loop {
        if is(&words, 0, &["please"]) || is(&words, 0, &["just"]) {
            words.remove(0);
        } else if is(&words, 0, &["would", "you", "mind"]) {
            words.drain(..3);
            act = Act::IndirectRequest;
        } else if ["can", "could", "will", "would"]
            .iter()
            .any(|m| is(&words, 0, &[m, "you"]))
        {
            words.drain(..2);
            act = Act::IndirectRequest;
        } else if let Some(n) = [
            &["i", "want", "you", "to"][..],
            &["i", "need", "you", "to"],
            &["i'd", "like", "you", "to"],
            &["i", "would", "like", "you", "to"],
        ]
        .iter()
        .find(|frame| is(&words, 0, frame))
        .map(|frame| frame.len())
        {
            words.drain(..n);
            act = Act::Want;
        } else if is(&words, 0, &["go", "and"]) {
            words.drain(..2);
        } else if is(&words, 0, &["go"]) && words.len() > 1 && verb_at(&words, 1, lexicon).is_some() {
            words.remove(0);
        } else {
            break;
        }
    }
    // Politeness at the end: "... for me", "... please".
    loop {
        let n = words.len();
        if n > 2 && (is(&words, n - 2, &["for", "me"]) || is(&words, n - 2, &["for", "us"])) {
            words.truncate(n - 2);
        } else if n > 1 && words[n - 1] == "please" {
            words.truncate(n - 1);
        } else {
            break;
        }
    }
    if words.is_empty() {
        return unclear(Unclear::Empty, String::new());
    }
    if is(&words, 0, &["don't"])
        || is(&words, 0, &["dont"])
        || is(&words, 0, &["do", "not"])
        || is(&words, 0, &["never"])
    {
        return unclear(Unclear::Negated, words.join(" "));
    }
    if QUESTION_WORDS.contains(&words[0].as_str()) || ["can", "could", "will", "would"].contains(&words[0].as_str()) {
        return unclear(Unclear::Question, words.join(" "));
    }
    if words.iter().any(|w| w == "and" || w == "then") {
        return unclear(Unclear::Several, words.join(" "));
    }
    let (verb, arity, joiners, mut rest) = match verb_at(&words, 0, lexicon) {
        Some((phrase, taken)) => {
            let rest = split_particle(&words[taken..], phrase);
            (phrase.verb.clone(), phrase.arity, phrase.joiners.clone(), rest)
        }
        None => {
            // An imperative of a verb no verb's word names: the unknown verb it names, as the
            // structured directive gives it. Anything else is not a directive's shape.
            let opens_reference = words
                .get(1)
                .is_some_and(|w| DETERMINERS.contains(&w.as_str()) || PRONOUNS.contains(&w.as_str()));
            let function_word = FUNCTION_WORDS.contains(&words[0].as_str()) || PRONOUNS.contains(&words[0].as_str());
            if !(opens_reference && !function_word && verb_name(&words[0]).is_ok()) {
                return unclear(Unclear::Unplaced, words.join(" "));
            }
            (words[0].clone(), 1, Vec::new(), words[1..].to_vec())
        }
    };
    // A beneficiary: "get me the mug", "hand me the mug".
    if rest.len() > 1 && (rest[0] == "me" || rest[0] == "us") {
        rest.remove(0);
    }
    let mut ignored = Vec::new();
    // Trailing adjuncts: from the first adjunct word after a reference's words to the end.
    let opens_adjunct =
        |w: &String| ADJUNCTS.contains(&w.as_str()) && !joiners.contains(w) && !lexicon_word(lexicon, w);
    // A reference needs a word of its own first; a verb of no arguments has none to need.
    let from = usize::from(arity > 0);
    if let Some(i) = (from..rest.len()).find(|&i| opens_adjunct(&rest[i])) {
        ignored.push(rest[i..].join(" "));
        rest.truncate(i);
    }
    let spans: Vec<&[String]> = if arity == 0 {
        // A verb of no arguments ("Wave."): nothing may follow it but what was left out.
        if !rest.is_empty() {
            return unclear(Unclear::Unplaced, words.join(" "));
        }
        Vec::new()
    } else if rest.is_empty() {
        return unclear(Unclear::Unplaced, words.join(" "));
    } else if arity == 2 {
        match (1..rest.len()).find(|&i| joiners.contains(&rest[i])) {
            Some(i) if i + 1 < rest.len() => vec![&rest[..i], &rest[i + 1..]],
            // Two arguments and no joiner between them: the words do not say which is which.
            _ => return unclear(Unclear::Unplaced, words.join(" ")),
        }
    } else {
        vec![&rest[..]]
    };
    let references: Vec<Phrase> = spans.iter().map(|span| reference(span, lexicon)).collect();
    let arguments = references.iter().map(|p| p.reference.clone()).collect();
    Understanding::Directive {
        directive: Directive::Action {
            verb: verb.clone(),
            arguments,
        },
        parse: Parse {
            act,
            addressee,
            verb,
            references,
            ignored,
        },
    }
}

/// Whether the lexicon knows `word` as a noun or an adjective on its own.
fn lexicon_word(lexicon: &Lexicon, word: &str) -> bool {
    let one = [word.to_owned()];
    lexicon.noun(&one).is_some() || lexicon.adjective(&one).is_some()
}

/// The verb phrase at `at`, and how many words it takes there: the first word inflected, the
/// rest (particles) either next to it or, split, after the reference ("pick the sponge up").
fn verb_at<'l>(words: &[String], at: usize, lexicon: &'l Lexicon) -> Option<(&'l VerbPhrase, usize)> {
    let first = words.get(at)?;
    let mut split = None;
    for phrase in lexicon.verbs {
        if !inflects(first, &phrase.words[0]) {
            continue;
        }
        let particles = &phrase.words[1..];
        if words.len() >= at + 1 + particles.len() && words[at + 1..at + 1 + particles.len()] == *particles {
            return Some((phrase, 1 + particles.len()));
        }
        if !particles.is_empty() && split.is_none() && words[at + 1..].windows(particles.len()).any(|w| w == particles)
        {
            split = Some((phrase, 1));
        }
    }
    split
}

/// The words after a verb whose particles come after its object: the particles taken out.
fn split_particle(rest: &[String], phrase: &VerbPhrase) -> Vec<String> {
    let particles = &phrase.words[1..];
    let mut rest = rest.to_vec();
    if particles.is_empty() || rest.len() < particles.len() || rest[..particles.len()] == *particles {
        return rest;
    }
    if let Some(i) = rest.windows(particles.len()).position(|w| w == particles) {
        rest.drain(i..i + particles.len());
    }
    rest
}

/// One reference's words. Every word must be placed, as determiner, adjective or noun; one
/// that is not makes the reference match nothing.
fn reference(span: &[String], lexicon: &Lexicon) -> Phrase {
    let words = span.join(" ");
    let nothing = |words: String| Phrase {
        reference: Reference::Nothing { words: words.clone() },
        words,
    };
    if span.len() == 1 && PRONOUNS.contains(&span[0].as_str())
        || span.len() == 2 && ["this", "that"].contains(&span[0].as_str()) && span[1] == "one"
    {
        return Phrase {
            reference: Reference::Pronoun { words: words.clone() },
            words,
        };
    }
    let body = if DETERMINERS.contains(&span[0].as_str()) {
        &span[1..]
    } else {
        span
    };
    if body.is_empty() {
        return nothing(words);
    }
    // The head noun: the longest known noun ending the reference, or "one".
    let (noun, head) = if body[body.len() - 1] == "one" {
        (Noun::default(), 1)
    } else {
        let longest = lexicon.longest_within(body.len());
        match (1..=longest)
            .rev()
            .find_map(|n| lexicon.noun(&body[body.len() - n..]).map(|k| (k, n)))
        {
            Some(found) => found,
            None => return nothing(words),
        }
    };
    let mut adjectives = Vec::new();
    let mut i = 0;
    let before = body.len() - head;
    while i < before {
        let longest = lexicon.longest_within(before - i);
        match (1..=longest)
            .rev()
            .find_map(|n| lexicon.adjective(&body[i..i + n]).map(|s| (s, n)))
        {
            Some((senses, n)) => {
                adjectives.push(senses);
                i += n;
            }
            None => return nothing(words),
        }
    }
    if noun == Noun::default() && adjectives.is_empty() {
        // "the one": nothing narrows it, and the words name no object.
        return nothing(words);
    }
    Phrase {
        reference: Reference::Spoken {
            kinds: noun.kinds,
            named: noun.named,
            adjectives,
            words: words.clone(),
            indefinite: ["a", "an"].contains(&span[0].as_str()),
        },
        words,
    }
}

const YES: &[&[&str]] = &[
    &["yes"],
    &["yeah"],
    &["yep"],
    &["sure"],
    &["ok"],
    &["okay"],
    &["do", "it"],
    &["go", "ahead"],
];
const NO: &[&[&str]] = &[
    &["no"],
    &["nope"],
    &["don't"],
    &["dont"],
    &["no", "thanks"],
    &["no", "thank", "you"],
];
const ORDINALS: &[(&str, &str)] = &[
    ("first", "1st"),
    ("second", "2nd"),
    ("third", "3rd"),
    ("fourth", "4th"),
    ("fifth", "5th"),
    ("sixth", "6th"),
    ("seventh", "7th"),
    ("eighth", "8th"),
    ("ninth", "9th"),
    ("tenth", "10th"),
];

/// A follow-up answer's words; see `words::understand_answer`.
pub fn read_answer(text: &str, scene: &Scene, lexicon: &Lexicon) -> Answer {
    let mut words: Vec<String> = tokens(text).into_iter().map(|t| t.word).collect();
    words.retain(|w| w != "please");
    for frame in [&["i", "mean"][..], &["i", "meant"]] {
        if is(&words, 0, frame) {
            words.drain(..frame.len());
        }
    }
    if YES.iter().any(|y| words == *y) {
        return Answer::Yes;
    }
    if NO.iter().any(|n| words == *n) {
        return Answer::No;
    }
    // "the second one", "second", "the 2nd".
    let body: Vec<&str> = words
        .iter()
        .map(String::as_str)
        .skip_while(|w| *w == "the")
        .filter(|w| *w != "one")
        .collect();
    if let [ordinal] = body.as_slice()
        && let Some(n) = ORDINALS
            .iter()
            .position(|(word, short)| word == ordinal || short == ordinal)
    {
        return Answer::Choice(n);
    }
    if let [id] = words.as_slice()
        && scene.object(id).is_some()
    {
        return Answer::Id(id.clone());
    }
    if words.is_empty() {
        return Answer::Reference(Reference::Nothing { words: String::new() });
    }
    match reference(&words, lexicon).reference {
        // An object spoken of by itself ("it") names nothing in an answer.
        Reference::Pronoun { words } => Answer::Reference(Reference::Nothing { words }),
        other => Answer::Reference(other),
    }
}
