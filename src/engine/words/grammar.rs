//! The grammar of a directive in words, hand-written and deterministic: each step looks at the
//! words in front of it and either takes them or stops; nothing is tried twice.
//!
//! ```text
//! sentence  := vocative? clause (, narrowing)* (, manner)* (, vocative)?
//! clause    := manner* frame? verb-phrase purpose? manner*
//! frame     := "can"|"could"|"will"|"would" "you" | "would you mind" | "i want/need/'d like you to"
//!              | "go" "and"?
//! verb-phrase := verb "me"? reference exclusion? (joiner reference exclusion?)? particle?
//! reference := pronoun | determiner? adjective* noun | determiner? adjective* "one"
//! narrowing := "not"? reference | "not"? adjective+        ("the cup, the blue one", ", not red")
//! purpose   := "to" verb ... | "in order to" verb ... | "so" "that"? subject modal verb ...
//!              | "for" verb-ing ...
//! ```
//!
//! Owns: the sentence's shape. Must not: place a word it does not know inside a reference as
//! anything but unknown, or leave out any word but those of how and when (`MANNER`): a word
//! that narrows a reference, a negation, another step or a purpose is read or the words are
//! not understood.

use std::borrow::Cow;

use super::lexicon::{Lexicon, inflects};
use super::purpose::{Purposed, need_at, purpose_at, read_purpose};
pub(super) use super::reference::{reference, reference_or_adjectives};
use super::splits::Splits;
use super::steps::{
    COMMA, Clause, assemble, comma_segments, listed, split_clauses, topic, with_commas, without_commas,
};
use super::tokens::{sentences, tokens};
pub(super) use super::vocabulary::{DETERMINERS, FUNCTION_WORDS, NEGATIONS, PRONOUNS};
use super::vocabulary::{MANNER, QUESTION_WORDS, STEP_WORDS, STRUCTURE};
use super::{Phrase, Understanding};
use crate::engine::action::VerbPhrase;
use crate::engine::action::verb_name;
use crate::engine::decision::{Act, Unclear};
use crate::engine::resolve::Reference;
use crate::engine::task::MAX_STEPS;

/// Whether `word` is one the grammar reads as itself (a determiner, a pronoun, a frame, a
/// question, a negation, a manner word, a joiner of steps): it cannot be the first word of a
/// verb's phrase, or "the mug" and "please" would read as verbs.
pub fn grammar_word(word: &str) -> bool {
    [
        DETERMINERS,
        PRONOUNS,
        QUESTION_WORDS,
        FUNCTION_WORDS,
        STEP_WORDS,
        &[
            "can", "could", "will", "would", "just", "go", "don't", "dont", "never", "one", "then", "so",
        ][..],
    ]
    .iter()
    .any(|list| list.contains(&word))
        || MANNER.iter().any(|m| m[0] == word)
}

pub(super) fn is(words: &[String], at: usize, expected: &[&str]) -> bool {
    expected.len() <= words.len().saturating_sub(at) && expected.iter().zip(&words[at..]).all(|(e, w)| e == w)
}

/// The manner phrase at `at`, and how many words it takes.
pub(super) fn manner_at(words: &[String], at: usize) -> Option<(&'static [&'static str], usize)> {
    MANNER.iter().find(|m| is(words, at, m)).map(|m| (*m, m.len()))
}

/// Whether every word of `words` is a manner word, left out; those worth showing are noted.
fn all_manner(words: &[String]) -> bool {
    let mut at = 0;
    while let Some((_, n)) = manner_at(words, at) {
        at += n;
    }
    at == words.len() && at > 0
}

/// Left out, and worth showing as left out: every manner word but the politeness.
fn shown(manner: &[&str]) -> bool {
    !matches!(
        manner,
        ["please"] | ["for", "me"] | ["for", "us"] | ["thanks"] | ["thank", "you"]
    )
}

/// Takes manner words off the end of `words`, noting those worth showing (in the order said).
pub(super) fn strip_trailing_manner(words: &mut Vec<String>, ignored: &mut Vec<String>) {
    let mut taken = Vec::new();
    'strip: while !words.is_empty() {
        for manner in MANNER {
            let n = manner.len();
            if words.len() >= n && is(words, words.len() - n, manner) {
                words.truncate(words.len() - n);
                if shown(manner) {
                    taken.push(manner.join(" "));
                }
                continue 'strip;
            }
        }
        break;
    }
    ignored.extend(taken.into_iter().rev());
}

/// Whether `words` (one or two, set off by a comma) can only be a name: none of them is a word
/// of the grammar, a verb's or the scene's. "Pepper" is; "grab it", "blue one", "not red",
/// "then smash" and "don't" are not.
fn is_name(words: &[String], lexicon: &Lexicon) -> bool {
    let closed = |w: &str| {
        [
            DETERMINERS,
            PRONOUNS,
            QUESTION_WORDS,
            FUNCTION_WORDS,
            STEP_WORDS,
            STRUCTURE,
            &[
                "one", "can", "could", "will", "would", "just", "go", "don't", "dont", "never", "ok", "okay",
            ][..],
        ]
        .iter()
        .any(|list| list.contains(&w))
    };
    (1..=2).contains(&words.len())
        && words.iter().all(|w| {
            !closed(w)
                && manner_at(std::slice::from_ref(w), 0).is_none()
                && !lexicon.verbs.iter().any(|p| inflects(w, &p.words[0]))
                && !lexicon.knows(w)
        })
}

/// A narrowing of the last reference, set off after it: the words, and whether they must be
/// true of the object (`keep`) or must not be ("not the red one").
struct Narrowing {
    keep: bool,
    words: Vec<String>,
}

/// The sentence's shape, stage by stage; `words` shrinks from both ends as each stage takes
/// what is its own.
pub fn read(text: &str, lexicon: &Lexicon, splits: &mut Splits) -> Understanding {
    let understood = read_words(text, lexicon, splits);
    // An index cut short, or a reference searched past the deadline, is no reading at all.
    if lexicon.expired() {
        return Understanding::Expired;
    }
    understood
}

fn read_words(text: &str, lexicon: &Lexicon, splits: &mut Splits) -> Understanding {
    let mut sentences = sentences(tokens(text));
    let mut addressee = None;
    // "Pepper! Get the mug.": a first sentence that can only be a name is the addressee.
    let words_of = |tokens: &[super::tokens::Token]| tokens.iter().map(|t| t.word.clone()).collect::<Vec<_>>();
    if sentences.len() >= 2 && is_name(&words_of(&sentences[0]), lexicon) {
        addressee = Some(words_of(&sentences.remove(0)).join(" "));
    }
    // "It is too sweet. Can you throw it away?": a first sentence that says what something is.
    let topic = match sentences.len() {
        2.. => topic(&words_of(&sentences[0]), lexicon),
        _ => None,
    };
    if topic.is_some() {
        sentences.remove(0);
    }
    let mut clauses = Vec::new();
    for sentence in sentences {
        for (n, words) in split_clauses(with_commas(sentence), lexicon).into_iter().enumerate() {
            let at = Parting {
                clause: clauses.len(),
                splits: &mut *splits,
            };
            match clause(comma_segments(words), n == 0, lexicon, &mut addressee, at) {
                Ok(read) => clauses.push(read),
                Err((why, words)) => return Understanding::NotUnderstood { why, words },
            }
        }
    }
    assemble(clauses, addressee, topic)
}

/// Which clause of the words is read, and the joiner each clause is parted at.
struct Parting<'s> {
    clause: usize,
    splits: &'s mut Splits,
}

/// One clause: its verb and references, as the grammar's `clause` rule reads them, with
/// what is set off by commas. `first`: it opens its sentence (a vocative may lead it).
fn clause(
    mut segments: Vec<Vec<String>>,
    first: bool,
    lexicon: &Lexicon,
    addressee: &mut Option<String>,
    parting: Parting<'_>,
) -> Result<Clause, (Unclear, String)> {
    let unclear = |why, words: String| Err((why, words));
    let mut ignored = Vec::new();
    // A vocative at the start: one or two words that can only be a name, set off by a comma.
    if first && addressee.is_none() && segments.len() > 1 && is_name(&segments[0], lexicon) {
        *addressee = Some(segments.remove(0).join(" "));
    }
    // What follows the clause, set off by commas, from the end: manner words, a vocative, a
    // narrowing of the last reference. Anything else set off belongs to the clause.
    let mut narrowings = Vec::new();
    let mut trailing_ignored: Vec<Vec<String>> = Vec::new();
    while segments.len() > 1 {
        let last = segments.last().expect("more than one");
        let listing = last.iter().any(|w| w == "and" || w == "or");
        if all_manner(last) {
            let (mut words, mut shown) = (last.clone(), Vec::new());
            strip_trailing_manner(&mut words, &mut shown);
            trailing_ignored.push(shown);
        } else if addressee.is_none() && is_name(last, lexicon) {
            *addressee = Some(last.join(" "));
        } else if let Some(negation) = NEGATIONS.iter().find(|n| is(last, 0, n)) {
            if *negation != ["not"] || last.len() == 1 {
                return unclear(Unclear::Negated, last.join(" "));
            }
            narrowings.push(Narrowing {
                keep: false,
                words: last[1..].to_vec(),
            });
        } else if !listing && (DETERMINERS.contains(&last[0].as_str()) || last.last().is_some_and(|w| w == "one")) {
            // "..., the red one please": manner after a narrowing is left out as anywhere.
            let (mut words, mut shown) = (last.clone(), Vec::new());
            strip_trailing_manner(&mut words, &mut shown);
            trailing_ignored.push(shown);
            narrowings.push(Narrowing { keep: true, words });
        } else {
            break;
        }
        segments.pop();
    }
    narrowings.reverse();
    // The rest keeps its commas, as words of their own: they part the items of a list.
    let mut words: Vec<String> = Vec::with_capacity(segments.iter().map(|s| s.len() + 1).sum());
    for (n, segment) in segments.into_iter().enumerate() {
        if n > 0 {
            words.push(COMMA.to_owned());
        }
        words.extend(segment);
    }
    if words.iter().all(|w| w == COMMA) {
        return unclear(Unclear::Empty, String::new());
    }
    let mut act = Act::Command;
    let mut needed = false;
    // Frames, politeness and manner at the start, in any order they come: "please can you go
    // and ...", "now get ...".
    loop {
        if is(&words, 0, &[COMMA]) || is(&words, 0, &["just"]) {
            words.remove(0);
        } else if let Some((manner, n)) = manner_at(&words, 0) {
            if shown(manner) {
                ignored.push(manner.join(" "));
            }
            words.drain(..n);
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
        } else if let Some((n, as_act)) = need_at(&words) {
            // "I need the mug", "can I have the mug": a request to bring it.
            words.drain(..n);
            act = as_act;
            needed = true;
            break;
        } else if is(&words, 0, &["go", "and"]) {
            words.drain(..2);
        } else if is(&words, 0, &["go"]) && words.len() > 1 && verb_at(&words, 1, lexicon).is_some() {
            words.remove(0);
        } else {
            break;
        }
    }
    // Manner and politeness at the end: "... for me", "... now, please".
    strip_trailing_manner(&mut words, &mut ignored);
    while words.last().is_some_and(|w| w == COMMA) {
        words.pop();
        strip_trailing_manner(&mut words, &mut ignored);
    }
    ignored.extend(trailing_ignored.into_iter().rev().flatten());
    let said = |words: &[String]| without_commas(words).join(" ");
    if words.is_empty() {
        return unclear(Unclear::Empty, String::new());
    }
    if NEGATIONS.iter().any(|n| is(&words, 0, n)) {
        return unclear(Unclear::Negated, said(&words));
    }
    if !needed
        && (QUESTION_WORDS.contains(&words[0].as_str())
            || ["can", "could", "will", "would"].contains(&words[0].as_str()))
    {
        return unclear(Unclear::Question, said(&words));
    }
    if words.iter().any(|w| w == "then") {
        return unclear(Unclear::Unplaced, said(&words));
    }
    let (verb, arity, joiners, mut rest, (leaves, recipient)) = if needed {
        match lexicon.verbs.iter().find(|p| p.words == ["bring"]) {
            Some(phrase) => (
                phrase.verb.clone(),
                phrase.arity,
                phrase.joiners.clone(),
                words.clone(),
                (phrase.leaves_unsaid, phrase.recipient),
            ),
            None => ("bring".to_owned(), 1, Vec::new(), words.clone(), (false, false)),
        }
    } else {
        match verb_at(&words, 0, lexicon) {
            Some((phrase, taken)) => {
                let rest = split_particle(&words[taken..], phrase);
                (
                    phrase.verb.clone(),
                    phrase.arity,
                    phrase.joiners.clone(),
                    rest,
                    (phrase.leaves_unsaid, phrase.recipient),
                )
            }
            None => {
                // An imperative of a verb no verb's word names: the unknown verb it names, as
                // the structured directive gives it. Anything else is not a directive's shape.
                let opens_reference = words
                    .get(1)
                    .is_some_and(|w| DETERMINERS.contains(&w.as_str()) || PRONOUNS.contains(&w.as_str()));
                let function_word =
                    FUNCTION_WORDS.contains(&words[0].as_str()) || PRONOUNS.contains(&words[0].as_str());
                if !(opens_reference && !function_word && verb_name(&words[0]).is_ok()) {
                    return unclear(Unclear::Unplaced, said(&words));
                }
                (words[0].clone(), 1, Vec::new(), words[1..].to_vec(), (false, false))
            }
        }
    };
    // A beneficiary: "get me the mug", "hand me the mug".
    if rest.len() > 1 && (rest[0] == "me" || rest[0] == "us") {
        rest.remove(0);
    }
    // A purpose after the reference ("to smash the vase") is not the robot's step, but it says
    // what the human wants: one whose verb the robot knows is read and checked against the
    // norms; one whose verb is unknown, or that names no object ("for reheating"), is shown as
    // ignored. A negated one is not understood.
    let mut purposes = Vec::new();
    let plain = without_commas(&rest);
    let plain: &[String] = &plain;
    // Every purpose said, each up to the next ("… for reheating so I can smash it" is two).
    let mut starts: Vec<(usize, usize)> = Vec::new();
    let mut from = 0;
    while from < plain.len()
        && let Some((at, verb_word)) = purpose_at(&plain[from..], &joiners, &|i| {
            verb_at(&plain[from..], i, lexicon).is_some()
        })
    {
        starts.push((from + at, verb_word));
        from += at + verb_word;
    }
    if let Some(&(first, _)) = starts.first() {
        for (k, &(at, verb_word)) in starts.iter().enumerate() {
            let end = starts.get(k + 1).map_or(plain.len(), |&(next, _)| next);
            let words = &plain[at..end];
            if words.iter().any(|w| NEGATIONS.iter().any(|n| n[0] == w)) {
                return unclear(Unclear::Unplaced, words.join(" "));
            }
            match read_purpose(words, verb_word, lexicon) {
                Purposed::Read(read) => purposes.push(read),
                Purposed::Shown => ignored.push(words.join(" ")),
                Purposed::Unplaced => return unclear(Unclear::Unplaced, words.join(" ")),
            }
        }
        // The purposes' words in `rest`, commas and all, are those after the same count of words.
        let mut kept = 0;
        let cut = (rest.iter().position(|w| {
            if w != COMMA {
                kept += 1;
            }
            kept > first
        }))
        .unwrap_or(rest.len());
        rest.truncate(cut);
        while rest.last().is_some_and(|w| w == COMMA) {
            rest.pop();
        }
        strip_trailing_manner(&mut rest, &mut ignored);
    }
    // "get the cup not the red one": the rest excludes.
    // ("that is not red" is a relative clause inside the reference, read there.)
    if let Some(at) = (1..rest.len()).find(|&i| rest[i] == "not" && !["is", "are"].contains(&rest[i - 1].as_str())) {
        narrowings.insert(
            0,
            Narrowing {
                keep: false,
                words: without_commas(&rest[at + 1..]).into_owned(),
            },
        );
        rest.truncate(at);
    }
    // The joiner the human said between two arguments: spoken back, and its relation made true.
    let mut said_joiner = None;
    // "Hand Bob the knife.": the recipient said first; the object, said last, is what a
    // narrowing after it narrows.
    let mut recipient_first = false;
    let spans: Vec<Cow<'_, [String]>> = if arity == 0 {
        // A verb of no arguments ("Wave."): nothing may follow it but what was left out.
        if !rest.is_empty() || !narrowings.is_empty() {
            return unclear(Unclear::Unplaced, said(&words));
        }
        Vec::new()
    } else if rest.is_empty() {
        return unclear(Unclear::Unplaced, said(&words));
    } else if arity == 2 {
        // Each joiner with words on both sides could part them; the reading says which does.
        let at: Vec<usize> = (1..rest.len().saturating_sub(1))
            .filter(|&i| joiners.contains(&rest[i]))
            .collect();
        let double = (recipient && at.is_empty())
            .then(|| recipient_said_first(&rest))
            .flatten();
        match (parting.splits.pick(parting.clause, &at), double) {
            (Some(i), _) => {
                said_joiner = Some(rest[i].clone());
                vec![Cow::Borrowed(&rest[..i]), without_commas(&rest[i + 1..])]
            }
            (None, Some(k)) => {
                recipient_first = true;
                vec![without_commas(&rest[k..]), Cow::Borrowed(&rest[..k])]
            }
            // One argument of a verb that may leave the rest unsaid ("Heat up the soup.").
            (None, None) if leaves && at.is_empty() => vec![Cow::Borrowed(&rest[..])],
            // Two arguments and no joiner between them: the words do not say which is which.
            _ => return unclear(Unclear::Unplaced, said(&words)),
        }
    } else {
        vec![Cow::Borrowed(&rest[..])]
    };
    // "Get the mug and the plate": a list as the first argument is one step for each item,
    // each with the same other arguments.
    let items = spans.first().map(|span| listed(span)).unwrap_or_default();
    let mut steps: Vec<Vec<Phrase>> = Vec::new();
    for (k, item) in items.iter().enumerate().take(MAX_STEPS + 1) {
        let mut phrases = vec![reference(item, lexicon)];
        if k == 0 {
            phrases.extend(spans[1..].iter().map(|span| reference(span, lexicon)));
        }
        steps.push(phrases);
    }
    if arity == 0 {
        steps.push(Vec::new());
    }
    let said_last = match recipient_first {
        true => steps.last_mut().and_then(|s| s.first_mut()),
        false => steps.last_mut().and_then(|s| s.last_mut()),
    };
    if let Some(last) = said_last {
        for narrowing in narrowings {
            *last = narrowed(std::mem::replace(last, placeholder()), narrowing, lexicon);
        }
    }
    Ok(Clause {
        act,
        verb,
        steps,
        shares: spans.len().saturating_sub(1),
        joiner: said_joiner,
        purposes,
        ignored,
    })
}

/// Where the object starts after a recipient said first ("Hand Bob the knife.", "Give the
/// child a cup."): at the first determiner after one short reference (a name, or a determiner
/// and its nouns) that holds no relation, clause or list; `None` when the words are not so.
fn recipient_said_first(rest: &[String]) -> Option<usize> {
    const NOT_IN_A_RECIPIENT: &[&str] = &[
        "near", "next", "beside", "behind", "left", "right", "front", "below", "above", "between", "that", "which",
        "who", "but", "except", "than", "not", COMMA,
    ];
    let k = (1..rest.len()).find(|&k| DETERMINERS.contains(&rest[k].as_str()))?;
    let within = |w: &String| {
        !(FUNCTION_WORDS.contains(&w.as_str())
            || DETERMINERS.contains(&w.as_str())
            || NOT_IN_A_RECIPIENT.contains(&w.as_str()))
    };
    let opens = usize::from(DETERMINERS.contains(&rest[0].as_str()));
    (k + 1 < rest.len() && k - opens <= 3 && k > opens && rest[opens..k].iter().all(within)).then_some(k)
}

/// A phrase that names nothing, held while the one in its place is rebuilt.
fn placeholder() -> Phrase {
    Phrase {
        words: String::new(),
        reference: Reference::Nothing {
            words: String::new(),
            unplaced: None,
        },
    }
}

/// `base` narrowed by what the human added: a reference ("the blue one"), or adjectives alone
/// ("not red").
fn narrowed(base: Phrase, narrowing: Narrowing, lexicon: &Lexicon) -> Phrase {
    let by = reference_or_adjectives(&narrowing.words, lexicon);
    let words = format!(
        "{}, {}{}",
        base.words,
        if narrowing.keep { "" } else { "not " },
        by.words
    );
    Phrase {
        reference: Reference::Narrowed {
            base: Box::new(base.reference),
            by: Box::new(by.reference),
            keep: narrowing.keep,
            words: words.clone(),
        },
        words,
    }
}

/// The verb phrase at `at`, and how many words it takes there: the first word inflected, the
/// rest (particles) either next to it or, split, after the reference ("pick the sponge up").
pub(super) fn verb_at<'l>(words: &[String], at: usize, lexicon: &'l Lexicon) -> Option<(&'l VerbPhrase, usize)> {
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
pub(super) fn split_particle(rest: &[String], phrase: &VerbPhrase) -> Vec<String> {
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
