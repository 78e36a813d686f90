//! Several steps in one directive: where one clause ends and the next begins ("and", "then",
//! "and then", ", then", "after that", "first …, then …", sentences in a row), what a pronoun
//! in a later step stands for, and the task the clauses make.
//!
//! Owns: the clauses' boundaries, lists under one verb ("the mug and the plate"), binding
//! "it", "them", "that" to the first argument of the nearest earlier step, a first sentence
//! that says what something is ("It is too sweet."), and assembling the task. Must not: read a
//! clause's inside (`grammar` does), or leave a clause out: every clause is a step or the
//! words are not understood.

use std::borrow::Cow;

use super::grammar::{DETERMINERS, PRONOUNS, manner_at, reference, reference_or_adjectives, verb_at};
use super::lexicon::Lexicon;
use super::purpose::PurposeClause;
use super::tokens::Token;
use super::{ArgumentRead, Parse, Phrase, PurposeRead, StepRead, Understanding};
use crate::engine::decision::{Act, Unclear};
use crate::engine::request::Directive;
use crate::engine::resolve::Reference;
use crate::engine::task::{Argument, MAX_STEPS, Purpose, Step, Task};

/// A comma, kept as a word of its own where it parts the items of a list.
pub(super) const COMMA: &str = ",";

/// One clause read by the grammar: a verb and the steps it gives (one, or one per item of a
/// list as its first argument).
pub(super) struct Clause {
    pub(super) act: Act,
    pub(super) verb: String,
    /// Each step's references, in argument order; the steps after the first of a list carry
    /// only their first argument and share the others with the first (`shares` of them).
    pub(super) steps: Vec<Vec<Phrase>>,
    pub(super) shares: usize,
    pub(super) joiner: Option<String>,
    pub(super) purposes: Vec<PurposeClause>,
    pub(super) ignored: Vec<String>,
}

/// What a first sentence "It is ADJ." or "The N is ADJ." says: the object it speaks of, for a
/// later pronoun with no antecedent in the words.
pub(super) struct Topic {
    /// "it is too sweet".
    words: String,
    /// The noun phrase ("the soup"), or `None` for "it".
    subject: Option<Phrase>,
    /// What it is: adjectives, or words that name nothing.
    what: Phrase,
}

/// The sentence's words with a comma as a word where one stood.
pub(super) fn with_commas(sentence: Vec<Token>) -> Vec<String> {
    let mut words = Vec::with_capacity(sentence.len() + 2);
    for token in sentence {
        let comma = token.comma;
        words.push(token.word);
        if comma {
            words.push(COMMA.to_owned());
        }
    }
    words
}

/// A clause's words parted at its commas.
pub(super) fn comma_segments(words: Vec<String>) -> Vec<Vec<String>> {
    let mut out: Vec<Vec<String>> = vec![Vec::new()];
    for word in words {
        match word == COMMA {
            true => out.push(Vec::new()),
            false => out.last_mut().expect("never empty").push(word),
        }
    }
    out.retain(|s| !s.is_empty());
    out
}

/// `words` without its commas, borrowed when it has none.
pub(super) fn without_commas(words: &[String]) -> Cow<'_, [String]> {
    match words.iter().any(|w| w == COMMA) {
        true => Cow::Owned(words.iter().filter(|w| *w != COMMA).cloned().collect()),
        false => Cow::Borrowed(words),
    }
}

/// The items of a list: "the mug, the plate and the cup" is three; "the mug or the cup" is one
/// item whose alternatives `reference` reads ("or" takes the commas as its own).
pub(super) fn listed(span: &[String]) -> Vec<Cow<'_, [String]>> {
    // "any mug except the red one and the blue one": an "and" after an exclusion is the
    // exclusion's, never a second item (which would act on what the words leave out).
    let first_and = span.iter().position(|w| w == "and");
    let excluding = |w: &String| ["except", "but", "other"].contains(&w.as_str());
    if first_and.is_some_and(|at| span[..at].iter().any(excluding)) {
        return vec![without_commas(span)];
    }
    if first_and.is_some() {
        let items: Vec<&[String]> = span.split(|w| w == "and" || w == COMMA).collect();
        // "the mug and and the cup" is not a list of two: an empty item names nothing.
        let last = items.len() - 1;
        return (items.into_iter().enumerate())
            .filter(|(i, item)| !item.is_empty() || *i == last)
            .map(|(_, item)| Cow::Borrowed(item))
            .collect();
    }
    if span.iter().any(|w| w == "or") {
        let either = span
            .iter()
            .map(|w| if w == COMMA { "or".to_owned() } else { w.clone() })
            .collect();
        return vec![Cow::Owned(either)];
    }
    vec![without_commas(span)]
}

/// Words that open a new clause after "and": a verb, a frame, a manner word, a negation, or an
/// unknown verb before a reference ("and juggle it").
fn opens_clause(words: &[String], at: usize, lexicon: &Lexicon) -> bool {
    const OPENERS: &[&str] = &[
        "then", "can", "could", "will", "would", "just", "go", "don't", "dont", "never", "do", "i", "after", "first",
    ];
    let Some(word) = words.get(at) else {
        return false;
    };
    // "and, put it …": a comma after the connective changes nothing.
    if word == COMMA {
        return opens_clause(words, at + 1, lexicon);
    }
    if OPENERS.contains(&word.as_str()) || manner_at(words, at).is_some() || verb_at(words, at, lexicon).is_some() {
        // "and then", "and please put …" open a clause; "and now the plate" is still a list.
        return manner_at(words, at).is_none_or(|_| {
            let after = at + manner_at(words, at).map_or(0, |(_, n)| n);
            opens_clause(words, after, lexicon) || words.get(after).is_none_or(|w| w == COMMA)
        });
    }
    // An unknown verb before a reference, or before "me" and a reference ("tell me a joke").
    let opens_reference = |w: &String| DETERMINERS.contains(&w.as_str()) || PRONOUNS.contains(&w.as_str());
    let beneficiary = words.get(at + 1).is_some_and(|w| w == "me" || w == "us");
    let next_opens_reference = words
        .get(at + 1 + usize::from(beneficiary))
        .is_some_and(opens_reference);
    next_opens_reference
        && !DETERMINERS.contains(&word.as_str())
        && super::number::quantifier(&words[at..]).is_none()
        && !PRONOUNS.contains(&word.as_str())
        && word != COMMA
        && !lexicon.knows(word)
}

/// Splits a sentence's words (commas as words) into clauses at "and" before a new clause,
/// "then", "and then", ", then", "after that"; a leading "first" is the order said, not a word
/// of the clause. The clause's commas stay.
pub(super) fn split_clauses(mut words: Vec<String>, lexicon: &Lexicon) -> Vec<Vec<String>> {
    let mut clauses: Vec<Vec<String>> = Vec::new();
    let mut current: Vec<String> = Vec::new();
    let mut i = 0;
    let boundary = |current: &mut Vec<String>, clauses: &mut Vec<Vec<String>>| {
        while current.last().is_some_and(|w| w == COMMA || w == "and") {
            current.pop();
        }
        clauses.push(std::mem::take(current));
    };
    // A connective with nothing after it ("Get the mug and then."): the human was cut short.
    let last = words.iter().rev().find(|w| *w != COMMA).map(String::as_str);
    let dangling = matches!(last, Some("and" | "then")).then(|| last.unwrap_or_default().to_owned());
    while i < words.len() {
        let word = words[i].as_str();
        let starts = current.iter().all(|w| w == COMMA);
        if starts
            && word == "first"
            && (opens_clause(&words, i + 1, lexicon) || words.get(i + 1).is_some_and(|w| w == COMMA))
        {
            i += 1;
            continue;
        }
        // A sentence that opens with its connective: "Then put it in the sink.", "After that, …".
        if starts && (word == "then" || word == "and") {
            i += 1;
            continue;
        }
        if starts && super::grammar::is(&words, i, &["after", "that"]) {
            i += 2;
            continue;
        }
        if !starts && word == "then" {
            boundary(&mut current, &mut clauses);
            i += 1;
            continue;
        }
        if !starts && super::grammar::is(&words, i, &["after", "that"]) && i + 2 < words.len() {
            boundary(&mut current, &mut clauses);
            i += 2;
            continue;
        }
        // "go and fetch the mug" is one clause: "go and" is a frame.
        let after_go = current.last().is_some_and(|w| w == "go");
        if !starts && !after_go && word == "and" && opens_clause(&words, i + 1, lexicon) {
            boundary(&mut current, &mut clauses);
            i += 1;
            // "and then", "and after that": one boundary.
            if words.get(i).is_some_and(|w| w == "then") {
                i += 1;
            } else if super::grammar::is(&words, i, &["after", "that"]) {
                i += 2;
            }
            continue;
        }
        // "Get the plate, get the knife": a comma before a verb, after a clause that has one.
        if !starts
            && word == COMMA
            && verb_at(&words, i + 1, lexicon).is_some()
            && (0..current.len()).any(|k| verb_at(&current, k, lexicon).is_some())
        {
            boundary(&mut current, &mut clauses);
            i += 1;
            continue;
        }
        if !(starts && word == COMMA) {
            // Taken, not copied: only the words ahead are looked at again.
            current.push(std::mem::take(&mut words[i]));
        }
        i += 1;
    }
    if !current.is_empty() || clauses.is_empty() {
        boundary(&mut current, &mut clauses);
    }
    // What was cut short is said back as not understood, never acted on in part.
    if let Some(connective) = dangling
        && words.len() > 1
    {
        clauses.push(vec![connective]);
    }
    clauses
}

/// "It is too sweet." / "The soup is too sweet.": what a first sentence says of an object,
/// when that is all it says.
pub(super) fn topic(words: &[String], lexicon: &Lexicon) -> Option<Topic> {
    const DEGREE: &[&str] = &[
        "too",
        "very",
        "really",
        "so",
        "quite",
        "rather",
        "extremely",
        "a",
        "bit",
        "little",
    ];
    let (subject, after) = match words {
        [it, rest @ ..] if it == "it's" => (None, rest),
        [it, is, rest @ ..] if it == "it" && is == "is" => (None, rest),
        _ => {
            let at = words.iter().position(|w| w == "is")?;
            let subject = reference(&words[..at], lexicon);
            if !matches!(subject.reference, Reference::Spoken { .. }) || !DETERMINERS.contains(&words[0].as_str()) {
                return None;
            }
            (Some(subject), &words[at + 1..])
        }
    };
    let adjectives: Vec<String> = after
        .iter()
        .skip_while(|w| DEGREE.contains(&w.as_str()))
        .cloned()
        .collect();
    if adjectives.is_empty() || adjectives.iter().any(|w| DETERMINERS.contains(&w.as_str())) {
        return None;
    }
    Some(Topic {
        words: words.join(" "),
        subject,
        what: reference_or_adjectives(&adjectives, lexicon),
    })
}

/// The nearest step before `before` (not counting it) that has an argument.
fn antecedent(steps: &[StepRead], before: usize) -> Option<usize> {
    (0..before.min(steps.len()))
        .rev()
        .find(|&s| !steps[s].arguments.is_empty())
}

fn is_pronoun(phrase: &Phrase) -> bool {
    matches!(phrase.reference, Reference::Pronoun { .. })
}

/// The task the clauses make, or the one directive of one step they are.
pub(super) fn assemble(clauses: Vec<Clause>, addressee: Option<String>, topic: Option<Topic>) -> Understanding {
    let count: usize = clauses.iter().map(|c| c.steps.len()).sum();
    if clauses.is_empty() {
        return Understanding::NotUnderstood {
            why: Unclear::Empty,
            words: String::new(),
        };
    }
    if count > MAX_STEPS {
        return Understanding::NotUnderstood {
            why: Unclear::Several,
            words: String::new(),
        };
    }
    let mut steps: Vec<StepRead> = Vec::with_capacity(count);
    let mut purposes: Vec<PurposeRead> = Vec::new();
    let mut joiners: Vec<Option<String>> = Vec::with_capacity(count);
    let mut ignored = Vec::new();
    for clause in clauses {
        let first = steps.len();
        for (k, phrases) in clause.steps.into_iter().enumerate() {
            let mut arguments: Vec<ArgumentRead> = phrases.into_iter().map(ArgumentRead::said).collect();
            if k > 0 {
                for j in 1..=clause.shares {
                    let shared = steps[first].arguments[j].phrase.clone();
                    arguments.push(ArgumentRead {
                        phrase: shared,
                        bound: Some((first, j)),
                    });
                }
            }
            // "it" in a later step: the first argument of the nearest earlier step.
            let here = steps.len();
            for argument in &mut arguments {
                if argument.bound.is_none() && is_pronoun(&argument.phrase) {
                    argument.bound = antecedent(&steps, here).map(|s| (s, 0));
                }
            }
            steps.push(StepRead {
                act: clause.act,
                verb: clause.verb.clone(),
                arguments,
            });
            joiners.push(clause.joiner.clone());
        }
        for purpose in clause.purposes {
            let after = steps.len() - 1;
            let arguments = (purpose.phrases.into_iter())
                .map(|phrase| {
                    let bound = match is_pronoun(&phrase) {
                        true => antecedent(&steps, after + 1).map(|s| (s, 0)),
                        false => None,
                    };
                    ArgumentRead { phrase, bound }
                })
                .collect();
            purposes.push(PurposeRead {
                words: purpose.words,
                verb: purpose.verb,
                arguments,
                after,
            });
        }
        ignored.extend(clause.ignored);
    }
    // A pronoun with no antecedent in the words is what the first sentence spoke of, as it
    // described it; with no such sentence, the object in focus.
    let mut topic_used = false;
    if let Some(topic) = &topic {
        let arguments =
            (steps.iter_mut().flat_map(|s| &mut s.arguments)).chain(purposes.iter_mut().flat_map(|p| &mut p.arguments));
        for argument in arguments.filter(|a| a.bound.is_none() && is_pronoun(&a.phrase)) {
            // "It is too sweet.": whatever is so described; the sentence says which, not the focus.
            let base = match &topic.subject {
                Some(subject) => subject.reference.clone(),
                None => Reference::Described {
                    kind: None,
                    attributes: Default::default(),
                    properties: Vec::new(),
                },
            };
            let words = format!("{} ({})", argument.phrase.words, topic.words);
            argument.phrase = Phrase {
                reference: Reference::Narrowed {
                    base: Box::new(base),
                    by: Box::new(topic.what.reference.clone()),
                    keep: true,
                    words: words.clone(),
                },
                words,
            };
            topic_used = true;
        }
    }
    if let Some(topic) = topic
        && !topic_used
    {
        ignored.insert(0, topic.words);
    }
    let references: Vec<Phrase> = (steps.iter().flat_map(|s| &s.arguments))
        .filter(|a| a.bound.is_none())
        .map(|a| a.phrase.clone())
        .collect();
    let verb = steps[0].verb.clone();
    let act = steps[0].act;
    // One step said for itself is the directive of one action it always was, its parse without
    // steps; anything more is a task.
    let one_step = steps.len() == 1 && purposes.is_empty();
    let directive = if one_step {
        Directive::Action {
            verb: verb.clone(),
            arguments: references.iter().map(|p| p.reference.clone()).collect(),
            joiner: joiners.pop().flatten(),
        }
    } else {
        let argument = |a: &ArgumentRead| match a.bound {
            Some((step, argument)) => Argument::Earlier { step, argument },
            None => Argument::Reference(a.phrase.reference.clone()),
        };
        Directive::Task(Task {
            steps: (steps.iter().zip(joiners))
                .map(|(s, joiner)| Step {
                    verb: s.verb.clone(),
                    arguments: s.arguments.iter().map(argument).collect(),
                    joiner,
                })
                .collect(),
            purposes: (purposes.iter())
                .map(|p| Purpose {
                    words: p.words.clone(),
                    verb: p.verb.clone(),
                    arguments: p.arguments.iter().map(argument).collect(),
                    after: p.after,
                })
                .collect(),
        })
    };
    // "Put the cups on the plates.": which cup goes on which plate is not guessed.
    if let Some((i, j)) = directive.second_plural() {
        return Understanding::NotUnderstood {
            why: Unclear::Unplaced,
            words: steps[i].arguments[j].phrase.words.clone(),
        };
    }
    let (steps, purposes) = match one_step {
        true => (Vec::new(), Vec::new()),
        false => (steps, purposes),
    };
    let parse = Parse {
        act,
        addressee,
        verb,
        references,
        ignored,
        steps,
        purposes,
    };
    Understanding::Directive { directive, parse }
}
