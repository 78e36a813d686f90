//! The canonical text of a term (`name(arg,...)`, no spaces), which parsing reads back.
//!
//! Owns: printing a term, through `Display` and into one allocation of its exact length. Must
//! not: print anything a parse would read otherwise.

use std::fmt;

use super::Term;

impl Term {
    /// The canonical text, as `Display` writes it, in one allocation of its exact length: an
    /// answer carries every reading's action and plan as text, and growing a `String` through
    /// `to_string` reallocated each a few times.
    pub fn text(&self) -> String {
        let mut out = String::with_capacity(self.text_len());
        // Writing to a String never fails.
        let _ = self.write_to(&mut out);
        out
    }

    /// The length of [`Term::text`] in bytes.
    fn text_len(&self) -> usize {
        match self {
            Term::Const(name) | Term::Var(name) => name.len(),
            // The name, the parentheses, a comma between arguments.
            Term::Compound(name, args) => {
                name.len() + 2 + args.len().saturating_sub(1) + args.iter().map(Term::text_len).sum::<usize>()
            }
        }
    }

    /// Writes the canonical text to `out`: `Display` writes it to a formatter, `text` to a
    /// `String` of the right size, so the two cannot differ.
    fn write_to<W: fmt::Write>(&self, out: &mut W) -> fmt::Result {
        match self {
            Term::Const(name) | Term::Var(name) => out.write_str(name),
            Term::Compound(name, args) => {
                out.write_str(name)?;
                out.write_char('(')?;
                for (i, arg) in args.iter().enumerate() {
                    if i > 0 {
                        out.write_char(',')?;
                    }
                    arg.write_to(out)?;
                }
                out.write_char(')')
            }
        }
    }
}

impl fmt::Display for Term {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.write_to(f)
    }
}

impl fmt::Debug for Term {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{self}")
    }
}
