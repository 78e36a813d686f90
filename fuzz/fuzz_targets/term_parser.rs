//! Fuzzes the term parser with arbitrary text.
//!
//! Owns: the parser's promises: it never panics, and whatever it accepts prints in canonical
//! form that reads back as the same term. Must not: test anything beyond `engine::term`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use scruple::engine::term::{MAX_LEN, Term, unify};

fuzz_target!(|text: &str| {
    let Ok(term) = Term::parse(text) else {
        return;
    };
    let printed = term.to_string();
    // Printing drops spaces and types and adds nothing, so the canonical form is never past
    // the parser's length limit when the input was within it.
    assert!(printed.len() <= MAX_LEN, "canonical form of {text:?} is too long");
    let again = Term::parse(&printed).unwrap_or_else(|e| panic!("{text:?} printed as {printed:?}, which fails: {e}"));
    assert_eq!(
        again, term,
        "{text:?} printed as {printed:?}, which reads back differently"
    );
    assert_eq!(again.to_string(), printed, "the canonical form is not a fixed point");
    assert!(unify(&term, &term).is_some(), "{printed} does not unify with itself");
});
