//! A forbidden norm's reason in its own words, where the kind's words would say more than the
//! norm does: its note, or what made a conditional norm apply ("getting the knife is forbidden
//! for a child").
//!
//! Owns: those words. Must not: speak a conditional norm as if it forbade the action outright,
//! or say a condition its object's own description already says.

use super::{Describer, Reason, Style, fact_words, gerund, listed, note_words, unique};
use crate::engine::scene::spoken;
use crate::engine::simulate::Cause;
use crate::engine::term::Term;

/// A forbidden norm's reason in the words of the norm itself, where its kind alone would say
/// more than it does: a conditional norm is spoken by its note, else by what made it apply
/// ("getting the knife is forbidden for a child"); in the natural style an unconditional norm
/// with a note is spoken by its note too. `None`: the kind's own words say exactly the norm.
pub(super) fn said_of(reason: &Reason, style: Style, describer: &mut Describer<'_>) -> Option<String> {
    let (words, subject) = match &reason.cause {
        Cause::ForbiddenAction { step, words, .. } => (words.as_deref()?, doing_step(step, describer)),
        Cause::ForbiddenState { fact, words } => (words.as_deref()?, state_words(fact, describer)),
        _ => return None,
    };
    if !words.conditional && style == Style::Diarc {
        return None;
    }
    if let Some(note) = words.note.as_deref().and_then(note_words) {
        return Some(note);
    }
    if !words.conditional {
        return None;
    }
    let grave = reason.severity.unwrap_or(3) >= 4;
    let rule = match style {
        Style::Natural if !grave => "is not allowed",
        _ => "is forbidden",
    };
    let mut said = format!("{subject} {rule}");
    // A fact the object's own description already says ("the fragile vase" is fragile) is not
    // said again.
    let mut facts = Vec::new();
    for fact in &words.about {
        if !described_by(fact, describer)
            && let Some(said) = fact_words(fact, describer)
        {
            facts.push(said);
        }
    }
    if !facts.is_empty() {
        said.push_str(" when ");
        said.push_str(&listed(&unique(facts), "and"));
    }
    if let Some(role) = words.roles.first() {
        said.push_str(&format!(" for {}", with_article(&spoken(role))));
    }
    if let Some(role) = words.exempt_roles.first() {
        said.push_str(&format!(" except for {}", with_article(&spoken(role))));
    }
    if let Some(context) = &words.context {
        // A context is any name ("tidy", "ward"): said as a context, never as a place.
        said.push_str(&format!(" in the {} context", spoken(context)));
    }
    Some(said)
}

/// Whether a fact is a word of its object's description: `fragile(vase1)` of "the fragile vase",
/// `color(mug1,red)` of "the red mug" (an attribute's value).
fn described_by(fact: &Term, describer: &mut Describer<'_>) -> bool {
    let (word, object) = match (fact.name(), fact.args()) {
        (Some(functor), [object]) => (spoken(functor), object),
        (Some(functor), [object, value]) if object.name().is_some_and(|id| describer.has_attribute(id, functor)) => {
            (describer.argument(value), object)
        }
        _ => return false,
    };
    let said = describer.argument(object);
    let words: Vec<&str> = said.split(' ').collect();
    words.windows(word.split(' ').count()).any(|w| w.join(" ") == word)
}

/// "a child", "an owner".
fn with_article(noun: &str) -> String {
    match noun.starts_with(['a', 'e', 'i', 'o', 'u']) {
        true => format!("an {noun}"),
        false => format!("a {noun}"),
    }
}

/// A step as a gerund with its arguments described: "getting the knife", "putting the fork in
/// the microwave".
fn doing_step(step: &Term, describer: &mut Describer<'_>) -> String {
    let verb = step.name().map(|n| gerund(n)).unwrap_or_else(|| step.to_string());
    let arguments = describer.arguments(step);
    match arguments.is_empty() {
        true => verb,
        false => format!("{verb} {arguments}"),
    }
}

/// A forbidden state as the subject of a sentence: `did(self,get(knife1))` as the step it says
/// was done ("getting the knife"), `holding(self,X)` as what the robot would be doing
/// ("holding the vase"), any other fact as what would be ("the fork being in the microwave").
fn state_words(fact: &Term, describer: &mut Describer<'_>) -> String {
    let mine = |t: &Term| t.name().is_some_and(|id| describer.is_agent(id));
    match (fact.name().map(|n| &**n), fact.args()) {
        (Some("did"), [_, step]) => doing_step(step, describer),
        // `holding(self,X)`: "holding the vase".
        (Some(functor), [me, other]) if mine(me) => format!("{} {}", spoken(functor), describer.argument(other)),
        // "the box is open" as a subject: "the box being open".
        _ => match fact_words(fact, describer) {
            Some(words) => words.replacen(" is ", " being ", 1),
            None => fact.to_string(),
        },
    }
}
