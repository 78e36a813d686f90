//! The joiner a directive was said with between its two arguments ("put the fork in the
//! microwave"): checked against the verb, spoken, and the relation it makes true.
//!
//! Owns: that choice. Must not: simulate; the relation is applied by `simulate`.

use super::{Describer, Directive, EngineError, Library};
use crate::engine::term::Sym;

/// The relation a joiner the human said makes true instead of the verb's own ("put X in Y"),
/// set on `describer` to be spoken; a structured directive's joiner the verb does not take is
/// the client's error.
pub(super) fn joined(
    directive: &Directive,
    library: &Library,
    describer: &mut Describer<'_>,
) -> Result<Option<(Sym, Sym)>, EngineError> {
    let Directive::Action {
        verb,
        arguments,
        joiner: Some(said),
    } = directive
    else {
        return Ok(None);
    };
    let Some(def) = library.get(verb, arguments.len()) else {
        return Ok(None);
    };
    if !def.takes_joiner(said) {
        return Err(EngineError::BadJoiner {
            verb: verb.clone(),
            joiner: said.clone(),
        });
    }
    if def.joiner.as_deref() != Some(said.as_str()) {
        describer.say_joiner(def.name.clone(), said.clone());
    }
    Ok(def.relation_for(said))
}
