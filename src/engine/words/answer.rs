//! A follow-up answer in words: "yes", "no", "never mind", an ordinal into the question's
//! readings, an object's id as written, "not the red one", a whole new directive, or a reference.
//!
//! Owns: which of these the words are. Must not: read an id other than as written, or take
//! words that name nothing as a choice.

use super::Understanding;
use super::grammar::{is, read, reference, reference_or_adjectives};
use super::lexicon::Lexicon;
use super::tokens::tokens;
use crate::engine::request::Answer;
use crate::engine::resolve::Reference;

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

/// Answers that take back what was asked: nothing is to be done.
const CANCEL: &[&[&str]] = &[
    &["never", "mind"],
    &["nevermind"],
    &["cancel"],
    &["cancel", "that"],
    &["forget", "it"],
    &["neither"],
    &["none"],
    &["none", "of", "them"],
    &["nothing"],
    &["stop"],
];

/// A follow-up answer's words; see `words::understand_answer`.
pub fn read_answer(text: &str, lexicon: &Lexicon) -> Answer {
    // An id answers as written, exactly: never lowered, never stripped inside ("c.1" is not
    // "c1"); only the sentence's closing mark may follow it.
    let trimmed = text.trim();
    for id in [trimmed, trimmed.trim_end_matches(['.', '!', '?'])] {
        if lexicon.scene().object(id).is_some() {
            return Answer::Id(id.to_owned());
        }
    }
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
    if CANCEL.iter().any(|c| words == *c) {
        return Answer::Cancel(words.join(" "));
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
    if words.is_empty() {
        return Answer::Reference(Reference::Nothing {
            words: String::new(),
            unplaced: None,
        });
    }
    // "not the red one": every reading but those it names.
    if words[0] == "not" && words.len() > 1 {
        let by = reference_or_adjectives(&words[1..], lexicon);
        let any = Reference::Described {
            kind: None,
            attributes: Default::default(),
            properties: Vec::new(),
        };
        return Answer::Reference(Reference::Narrowed {
            base: Box::new(any),
            by: Box::new(by.reference),
            keep: false,
            words: words.join(" "),
        });
    }
    // A whole directive of a verb the robot knows ("Get the vase instead."): decided afresh.
    if let Understanding::Directive { parse, .. } = read(text, lexicon, &mut Default::default())
        && lexicon.verbs.iter().any(|p| p.verb == parse.verb)
    {
        return Answer::Directive(text.to_owned());
    }
    match reference(&words, lexicon).reference {
        // An object spoken of by itself ("it") names nothing in an answer.
        Reference::Pronoun { words } => Answer::Reference(Reference::Nothing { words, unplaced: None }),
        other => Answer::Reference(other),
    }
}
