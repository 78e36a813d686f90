//! The words of soft norms and of the notes and facts reasons name: "the mug is dirty", "I'd
//! rather not get the red mug: it is less preferred than getting the blue mug".
//!
//! Owns: those words. Must not: explain a reading by another reading's reasons, or say a note's
//! invisible characters.

use super::{Describer, Force, Interpretation, Reason, doing, listed, reading, unique};
use crate::engine::scene::{invisible, person_predicate, spoken_onto};
use crate::engine::simulate::Cause;
use crate::engine::term::Term;

/// A soft reason in words, the same in both styles: the norm's `when` facts about the reading's
/// objects ("the mug is dirty"), else its note, else "it is discouraged" / "it is preferred".
pub(super) fn soft_words(reason: &Reason, describer: &mut Describer<'_>) -> String {
    soft_words_named(reason, describer).unwrap_or_else(|| match reason.force() {
        Some(Force::Preferred) => "it is preferred".to_owned(),
        _ => "it is discouraged".to_owned(),
    })
}

/// The words a soft reason names: its facts about the reading's objects, else its note; `None`
/// when it has neither.
pub(super) fn soft_words_named(reason: &Reason, describer: &mut Describer<'_>) -> Option<String> {
    let Cause::Soft { about, note, .. } = &reason.cause else {
        return None;
    };
    let mut facts = (about.iter()).filter_map(|fact| fact_words(fact, describer));
    let Some(first) = facts.next() else {
        return note.as_deref().and_then(note_words);
    };
    let Some(second) = facts.next() else {
        return Some(first);
    };
    let all: Vec<String> = [first, second].into_iter().chain(facts).collect();
    Some(listed(&unique(all), "and"))
}

/// A norm's note as words inside a sentence. The note is the operator's text, stored as written;
/// what is spoken of it carries no control or direction-changing characters (a NUL or a U+202E
/// would reach a listener's screen or speech engine), its spaces are single and it loses its
/// closing marks (a full stop, "!" or "?"), since the sentence supplies its own. `None` when nothing is left.
pub(super) fn note_words(note: &str) -> Option<String> {
    let mut words = String::with_capacity(note.len());
    for c in note.chars() {
        // Whitespace and control characters become one space; what shows nothing is left out.
        if c.is_whitespace() || c.is_control() {
            if !words.is_empty() && !words.ends_with(' ') {
                words.push(' ');
            }
        } else if !invisible(c) {
            words.push(c);
        }
    }
    // The sentence around the note closes it: its own closing marks would double ("careful!.").
    let kept = (words.trim_end())
        .trim_end_matches(['.', '!', '?', '…'])
        .trim_end()
        .len();
    words.truncate(kept);
    (!words.is_empty()).then_some(words)
}

/// A fact about an object, in words: `dirty(mug1)` → "the mug is dirty", `color(mug1,red)` →
/// "the color of the mug is red", `on(plate1,floor1)` → "the plate is on the floor". (An
/// object's own type is never among them: the simulation leaves it out.)
pub(super) fn fact_words(fact: &Term, describer: &mut Describer<'_>) -> Option<String> {
    let functor = fact.name()?;
    let subject_id = fact.args().first()?.name()?;
    let mut words = String::with_capacity(48);
    // The robot speaks of itself in the first person: "I am holding the mug".
    let me = describer.is_agent(subject_id);
    // "Bob is a child", not "Bob is role child".
    if let Some(predicate) = person_predicate(fact).filter(|_| !me) {
        describer.argument_into(&fact.args()[0], &mut words);
        words.push_str(describer.copula(&fact.args()[0]));
        words.push_str(&predicate);
        return Some(words);
    }
    match fact.args() {
        [_] if me => {
            words.push_str("I am ");
            spoken_onto(functor, &mut words);
        }
        [_, other] if me => {
            words.push_str("I am ");
            spoken_onto(functor, &mut words);
            words.push(' ');
            describer.argument_into(other, &mut words);
        }
        [subject] => {
            describer.argument_into(subject, &mut words);
            words.push_str(describer.copula(subject));
            spoken_onto(functor, &mut words);
        }
        [subject, value] if describer.has_attribute(subject_id, functor) => {
            words.push_str("the ");
            spoken_onto(functor, &mut words);
            words.push_str(" of ");
            describer.argument_into(subject, &mut words);
            words.push_str(" is ");
            describer.argument_into(value, &mut words);
        }
        [subject, other] => {
            describer.argument_into(subject, &mut words);
            words.push_str(describer.copula(subject));
            spoken_onto(functor, &mut words);
            words.push(' ');
            describer.argument_into(other, &mut words);
        }
        _ => return Some(fact.to_string()),
    }
    Some(words)
}

/// What a reading that breaks a discouraged norm is still done "although": the words of each
/// discouraged reason, and the greatest severity among them.
pub(super) fn although(i: &Interpretation, describer: &mut Describer<'_>) -> Option<(String, u8)> {
    let broken: Vec<&Reason> = i.outcome.discouraged().collect();
    let severity = broken.iter().filter_map(|r| r.severity).max()?;
    let words: Vec<String> = broken.iter().map(|r| soft_words(r, describer)).collect();
    Some((listed(&unique(words), "and"), severity))
}

/// Why `dispreferred` scores below `chosen`, and how strongly: the discouraged norms it breaks
/// that `chosen` does not, else the preferred norms `chosen` meets that it does not ("the blue
/// mug is clean"), else every discouraged norm it breaks.
pub(super) fn dispreferred_reasons<'a>(
    dispreferred: &'a Interpretation,
    chosen: &'a Interpretation,
) -> Vec<&'a Reason> {
    let has = |i: &Interpretation, r: &Reason| i.outcome.reasons.iter().any(|s| s.is_soft() && s.norm_id == r.norm_id);
    let own: Vec<&Reason> = dispreferred.outcome.discouraged().filter(|r| !has(chosen, r)).collect();
    if !own.is_empty() {
        return own;
    }
    let missed: Vec<&Reason> = (chosen.outcome.reasons.iter())
        .filter(|r| r.force() == Some(Force::Preferred) && !has(dispreferred, r))
        .collect();
    if !missed.is_empty() {
        return missed;
    }
    dispreferred.outcome.discouraged().collect()
}

/// The words of `reasons` (from [`dispreferred_reasons`]), said of the dispreferred reading
/// itself: its own discouraged norms ("the dirty mug is dirty"); when what sets it below is a
/// preference the chosen reading meets, only that it is less preferred than that reading ("it
/// is less preferred than getting the plate"), never the chosen reading's reasons as its own.
pub(super) fn dispreferred_words(
    reasons: &[&Reason],
    chosen: &Interpretation,
    describer: &mut Describer<'_>,
) -> String {
    if reasons.iter().any(|r| r.force() == Some(Force::Preferred)) {
        return format!("it is less preferred than {}", doing(chosen));
    }
    let words: Vec<String> = (reasons.iter())
        .map(|r| soft_words_named(r, describer).unwrap_or_else(|| "it is discouraged".to_owned()))
        .collect();
    if words.is_empty() {
        return "it is discouraged".to_owned();
    }
    listed(&unique(words), "and")
}

/// A dispreferred reading in fluent words; the strength of the norms behind it sets the tone
/// (1–2 mild, 3 plain, 4–5 strong).
pub(super) fn natural_rather_not(
    dispreferred: &Interpretation,
    chosen: &Interpretation,
    describer: &mut Describer<'_>,
) -> String {
    let reasons = dispreferred_reasons(dispreferred, chosen);
    let why = dispreferred_words(&reasons, chosen, describer);
    let strength = (reasons.iter()).filter_map(|r| r.severity).max().unwrap_or(3);
    match strength {
        1 | 2 => format!("I'd slightly prefer not to {}: {why}.", reading(dispreferred)),
        3 => format!("I'd rather not {}: {why}.", reading(dispreferred)),
        _ => format!("I really shouldn't {}: {why}.", reading(dispreferred)),
    }
}
