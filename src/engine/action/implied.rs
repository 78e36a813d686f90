//! Parameters a directive may leave unsaid: those a verb implies by facts ("heat the soup":
//! something that is a heater) and a recipient, who is the speaker when unnamed ("bring the mug").
//!
//! Owns: the checks on `implied` and which parameters may be left out. Must not: look at a
//! scene (resolution finds the objects that meet the facts).

use std::collections::BTreeMap;

use super::{ActionDef, MAX_ITEMS, Method};
use crate::engine::input::{Invalid, pointer_segment};
use crate::engine::scene::PERSON;
use crate::engine::term::{Sym, Term};

/// What stands for a parameter a directive leaves unsaid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Unsaid<'a> {
    /// Any object of the scene for which these facts hold, the parameter bound to it.
    Implied(&'a Sym, &'a [Term]),
    /// The speaker: the parameter is a person in every method ("bring the mug": to me).
    Speaker,
}

impl ActionDef {
    /// What stands for each parameter from `given` on when a directive gives only the first
    /// `given` arguments; `None` when some of them may not be left unsaid (or none is missing).
    pub fn unsaid(&self, given: usize) -> Option<Vec<Unsaid<'_>>> {
        if given == 0 || given >= self.params.len() {
            return None;
        }
        (self.params[given..].iter())
            .map(|param| match self.implied.iter().find(|(p, _)| p == param) {
                Some((p, facts)) => Some(Unsaid::Implied(p, facts)),
                None => (self.methods.iter())
                    .all(|m| m.takes_person(param))
                    .then_some(Unsaid::Speaker),
            })
            .collect()
    }
}

impl Method {
    /// Whether the method takes a person as `param`: `person(P)` is among its preconditions.
    pub fn takes_person(&self, param: &Sym) -> bool {
        (self.preconditions.iter())
            .any(|f| f.name().is_some_and(|n| &**n == PERSON) && matches!(f.args(), [Term::Var(v)] if v == param))
    }
}

/// The implied parameters as written, checked: each a later parameter of the verb, after every
/// parameter that is not implied, with 1 to [`MAX_ITEMS`] facts over it alone.
pub(super) fn implied_of(
    written: &BTreeMap<String, Vec<String>>,
    params: &[Sym],
) -> Result<Vec<(Sym, Vec<Term>)>, Invalid> {
    let mut implied: Vec<(usize, Sym, Vec<Term>)> = Vec::with_capacity(written.len());
    for (name, facts) in written {
        let at = format!("/implied/{}", pointer_segment(name));
        let Some(index) = params.iter().position(|p| &**p == name.as_str()) else {
            return Err(Invalid::new(at, format!("`{name}` is not a parameter of the verb")));
        };
        if index == 0 {
            return Err(Invalid::new(
                at,
                format!("`{name}` is the verb's first parameter; only a later one may be left unsaid"),
            ));
        }
        if facts.is_empty() || facts.len() > MAX_ITEMS {
            return Err(Invalid::new(at, format!("give 1 to {MAX_ITEMS} facts")));
        }
        let param = params[index].clone();
        let mut terms = Vec::with_capacity(facts.len());
        for (i, text) in facts.iter().enumerate() {
            let field = format!("{at}/{i}");
            let term = Term::parse(text).map_err(|e| Invalid::new(&field, format!("not a term: {e}")))?;
            if term.is_var() {
                return Err(Invalid::new(field, "must start with a name, not a variable"));
            }
            let variables = term.variables();
            if variables.iter().any(|v| *v != param) || !variables.contains(&param) {
                return Err(Invalid::new(
                    field,
                    format!("an implied fact is about `{name}` and no other variable: `{text}`"),
                ));
            }
            terms.push(term);
        }
        implied.push((index, param, terms));
    }
    implied.sort_by_key(|(index, ..)| *index);
    // Left out, the arguments missing are the last ones: every parameter after an implied one
    // is implied too.
    if let Some((first, ..)) = implied.first()
        && implied.len() != params.len() - first
    {
        let later = &params[*first..];
        let plain = later
            .iter()
            .find(|p| !implied.iter().any(|(_, q, _)| q == *p))
            .expect("one is not implied");
        return Err(Invalid::new(
            format!("/implied/{}", pointer_segment(&implied[0].1)),
            format!("`{plain}` comes after it and is not implied: only the verb's last parameters may be left unsaid"),
        ));
    }
    Ok(implied.into_iter().map(|(_, p, t)| (p, t)).collect())
}
