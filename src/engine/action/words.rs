//! The phrases that name a verb in words, and the joiners between its two arguments: their
//! shape, and when two verbs' phrases could name one sentence's verb.
//!
//! Owns: those checks. Must not: read a sentence (the grammar does).

use super::ActionDef;
use crate::engine::input::{Invalid, normalise_phrase};
use crate::engine::term::Sym;

/// Words that open or stand for a reference, never a joiner between two.
const DETERMINERS_AND_PRONOUNS: &[&str] = &["the", "a", "an", "this", "that", "my", "your", "it", "me", "us"];

pub(super) fn phrases(field: &str, list: &[String], most: usize, most_words: usize) -> Result<Vec<String>, Invalid> {
    if list.len() > most {
        return Err(Invalid::new(field, format!("at most {most}")));
    }
    let mut out: Vec<String> = Vec::with_capacity(list.len());
    for (i, text) in list.iter().enumerate() {
        let phrase = normalise_phrase(text);
        let count = phrase.split(' ').count();
        let letters = phrase.chars().all(|c| c.is_ascii_lowercase() || c == ' ');
        if phrase.is_empty() || phrase.len() > 32 || count > most_words || !letters {
            let shape = if most_words == 1 { "one word" } else { "1 to 3 words" };
            return Err(Invalid::new(
                format!("{field}/{i}"),
                format!("`{text}` is not {shape} of letters (at most 32 bytes)"),
            ));
        }
        if out.contains(&phrase) {
            return Err(Invalid::new(
                format!("{field}/{i}"),
                format!("`{phrase}` is listed twice"),
            ));
        }
        out.push(phrase);
    }
    Ok(out)
}

/// Whether two verb phrases can name one sentence's verb: the same particles, and a first word
/// one of them may take inflected as the other ("grab" and "grabbed": "Grabbed the cup." would
/// be read as whichever verb came first).
pub(super) fn collide(a: &str, b: &str) -> bool {
    let (a_first, a_rest) = a.split_once(' ').unwrap_or((a, ""));
    let (b_first, b_rest) = b.split_once(' ').unwrap_or((b, ""));
    a_rest == b_rest
        && (crate::engine::words::inflects(a_first, b_first) || crate::engine::words::inflects(b_first, a_first))
}

/// Refuses a verb phrase that starts with a word the grammar reads itself, and a joiner that
/// is one.
pub(super) fn grammar_free(words: &[String], joiners: &[String]) -> Result<(), Invalid> {
    // "the", "please", "can", "go" would make every sentence's frame a verb; "and", "then",
    // "or", "not" between two references would join what the grammar reads as steps,
    // choices and negations.
    for (i, phrase) in words.iter().enumerate() {
        let first = phrase.split(' ').next().unwrap_or_default();
        if crate::engine::words::grammar_word(first) {
            return Err(Invalid::new(
                format!("/words/{i}"),
                format!("`{first}` is a word the grammar reads itself; a verb's phrase cannot start with it"),
            ));
        }
    }
    for (i, joiner) in joiners.iter().enumerate() {
        if ["and", "then", "or", "not", "please", "but", "so"].contains(&joiner.as_str())
            || DETERMINERS_AND_PRONOUNS.contains(&joiner.as_str())
        {
            return Err(Invalid::new(
                format!("/joiners/{i}"),
                format!("`{joiner}` is a word the grammar reads itself; it cannot join two references"),
            ));
        }
    }
    Ok(())
}

/// The relation a joiner says holds between a verb's two arguments once it is done: "put the
/// fork in the microwave" leaves it `in`, "on the plate" `on`. `None` for a joiner that names
/// no relation ("with", "to").
pub fn relation_of(joiner: &str) -> Option<&'static str> {
    match joiner {
        "on" | "onto" | "upon" | "atop" => Some("on"),
        "in" | "into" | "inside" | "within" => Some("in"),
        "under" | "beneath" | "below" | "underneath" => Some("under"),
        "near" | "beside" | "by" => Some("near"),
        "behind" => Some("behind"),
        _ => None,
    }
}

impl ActionDef {
    /// What saying the verb with `said` (one of its joiners) changes in its own effects: the
    /// relation its default joiner makes true becomes the one `said` names ("put X in Y" makes
    /// `in(X,Y)` where "on" makes `on(X,Y)`). `None` when they name the same relation, or either
    /// names none.
    pub fn relation_for(&self, said: &str) -> Option<(Sym, Sym)> {
        let from = relation_of(self.joiner.as_deref()?)?;
        let to = relation_of(said)?;
        (from != to).then(|| (Sym::from(from), Sym::from(to)))
    }

    /// Whether `said` joins this verb's arguments: its spoken joiner or one of its joiners.
    pub fn takes_joiner(&self, said: &str) -> bool {
        self.joiner.as_deref() == Some(said) || self.joiners.iter().any(|j| j == said)
    }
}
