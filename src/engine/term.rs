//! Logical terms in DIARC's syntax: parsing, the canonical printer, and unification.
//!
//! Owns: `name(arg,...)`, variables (`X`, `?x`), `name:type` annotations (dropped at parse time),
//! substitutions and matching. Must not: know about worlds, norms or any transport.

use std::borrow::Cow;
use std::hash::{Hash, Hasher};
use std::sync::Arc;

pub use super::sym::Sym;

mod text;

/// Nesting deeper than this is refused by default, so that no input can exhaust the stack.
pub const MAX_DEPTH: usize = 32;
/// Longest term text accepted by default, in bytes.
pub const MAX_LEN: usize = 4096;

/// How deep and how long a term may be. Norms, verbs and stored rows use the defaults; an
/// operator may set other limits for requests, up to `CEILING`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TermLimits {
    /// Most nesting levels: `a` is 1, `f(a)` is 2.
    pub depth: usize,
    /// Most bytes of text.
    pub len: usize,
}

impl TermLimits {
    pub const DEFAULT: TermLimits = TermLimits {
        depth: MAX_DEPTH,
        len: MAX_LEN,
    };
    /// The most any configuration may allow: deep enough for any real logical form, shallow
    /// enough that parsing, printing and unifying stay far from the stack's end.
    pub const CEILING: TermLimits = TermLimits {
        depth: 128,
        len: 65_536,
    };
}

impl Default for TermLimits {
    fn default() -> Self {
        TermLimits::DEFAULT
    }
}

/// A logical term. Constants and compounds are ground unless an argument holds a variable.
/// Its hash is [`term_hash`]'s, so that a term under a substitution ([`Bound`]) is looked up in
/// a set of terms without being built.
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord)]
pub enum Term {
    /// A constant such as `object3` or `self`.
    Const(Sym),
    /// A variable such as `X` or `?x`; its name keeps the leading `?` when written with one.
    Var(Sym),
    /// `name(args...)` with at least one argument.
    Compound(Sym, Arc<[Term]>),
}

impl Term {
    pub fn constant(name: &str) -> Term {
        Term::Const(Sym::from(name))
    }

    pub fn compound(name: &str, args: Vec<Term>) -> Term {
        if args.is_empty() {
            Term::constant(name)
        } else {
            Term::Compound(Sym::from(name), args.into())
        }
    }

    /// Parses one term within the default limits; see [`ParseError`] for what can go wrong.
    pub fn parse(text: &str) -> Result<Term, ParseError> {
        Term::parse_within(text, TermLimits::DEFAULT)
    }

    /// Parses one term within `limits` (each capped at [`TermLimits::CEILING`]).
    pub fn parse_within(text: &str, limits: TermLimits) -> Result<Term, ParseError> {
        let max_len = limits.len.min(TermLimits::CEILING.len);
        let max_depth = limits.depth.min(TermLimits::CEILING.depth);
        if text.len() > max_len {
            return Err(ParseError {
                position: max_len,
                message: format!("term is longer than {max_len} bytes"),
            });
        }
        let mut parser = Parser {
            text,
            pos: 0,
            max_depth,
        };
        parser.skip_space();
        let term = parser.term(0)?;
        parser.skip_space();
        if parser.pos < text.len() {
            return Err(parser.error(format!(
                "unexpected `{}` after the end of the term",
                parser.peek_char().unwrap_or(' ')
            )));
        }
        Ok(term)
    }

    /// The functor name: a constant's own name, a compound's name; `None` for a variable.
    pub fn name(&self) -> Option<&Sym> {
        match self {
            Term::Const(name) | Term::Compound(name, _) => Some(name),
            Term::Var(_) => None,
        }
    }

    pub fn args(&self) -> &[Term] {
        match self {
            Term::Compound(_, args) => args,
            _ => &[],
        }
    }

    pub fn arity(&self) -> usize {
        self.args().len()
    }

    pub fn is_var(&self) -> bool {
        matches!(self, Term::Var(_))
    }

    pub fn is_ground(&self) -> bool {
        match self {
            Term::Const(_) => true,
            Term::Var(_) => false,
            Term::Compound(_, args) => args.iter().all(Term::is_ground),
        }
    }

    /// Makes every name in the term last for the process (see [`Sym::make_lasting`]): for the
    /// terms of verbs and norms, which every reading copies.
    pub fn make_lasting(&self) {
        match self {
            Term::Const(name) | Term::Var(name) => name.make_lasting(),
            Term::Compound(name, args) => {
                name.make_lasting();
                args.iter().for_each(Term::make_lasting);
            }
        }
    }

    /// Variables in the order they first appear, each once.
    pub fn variables(&self) -> Vec<Sym> {
        fn walk(term: &Term, out: &mut Vec<Sym>) {
            match term {
                Term::Var(v) => {
                    if !out.contains(v) {
                        out.push(v.clone());
                    }
                }
                Term::Compound(_, args) => args.iter().for_each(|a| walk(a, out)),
                Term::Const(_) => {}
            }
        }
        let mut out = Vec::new();
        walk(self, &mut out);
        out
    }

    /// This term with every bound variable replaced by its value (followed through chains).
    pub fn substitute(&self, subst: &Subst) -> Term {
        if subst.bindings.is_empty() || self.is_ground() {
            // Nothing to replace: share the term instead of rebuilding it.
            return self.clone();
        }
        match self {
            Term::Var(_) => {
                let resolved = subst.walk(self);
                if resolved.is_var() {
                    resolved.clone()
                } else {
                    resolved.substitute(subst)
                }
            }
            Term::Const(_) => self.clone(),
            Term::Compound(name, args) => {
                Term::Compound(name.clone(), args.iter().map(|a| a.substitute(subst)).collect())
            }
        }
    }
}

/// Canonical form: no spaces, no types: `did(self,get(object3))`.
/// Why a text is not a term: the byte offset where reading stopped, and what was expected there.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("at byte {position}: {message}")]
pub struct ParseError {
    pub position: usize,
    pub message: String,
}

/// True for a character that may appear inside a name.
fn is_name_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.'
}

/// True when `text` is a name that reads back as a constant (not a variable, no punctuation).
pub fn is_constant_name(text: &str) -> bool {
    // Every character allowed is ASCII, so any byte of a longer character fails as it would.
    let mut bytes = text.bytes();
    match bytes.next() {
        Some(first) if first.is_ascii_lowercase() || first.is_ascii_digit() || first == b'_' => {
            bytes.all(|b| is_name_char(char::from(b)))
        }
        _ => false,
    }
}

struct Parser<'a> {
    text: &'a str,
    pos: usize,
    max_depth: usize,
}

impl Parser<'_> {
    fn error(&self, message: String) -> ParseError {
        ParseError {
            position: self.pos,
            message,
        }
    }

    fn peek_char(&self) -> Option<char> {
        self.text[self.pos..].chars().next()
    }

    fn skip_space(&mut self) {
        while let Some(c) = self.peek_char() {
            if c.is_whitespace() {
                self.pos += c.len_utf8();
            } else {
                break;
            }
        }
    }

    fn name(&mut self) -> &str {
        let start = self.pos;
        while let Some(c) = self.peek_char() {
            if is_name_char(c) {
                self.pos += 1;
            } else {
                break;
            }
        }
        &self.text[start..self.pos]
    }

    fn term(&mut self, depth: usize) -> Result<Term, ParseError> {
        if depth >= self.max_depth {
            return Err(self.error(format!("terms may nest at most {} deep", self.max_depth)));
        }
        let is_question_var = self.peek_char() == Some('?');
        if is_question_var {
            self.pos += 1;
        }
        let start = self.pos;
        let name = self.name().to_owned();
        if name.is_empty() {
            return Err(match self.peek_char() {
                None => self.error("expected a name, found the end of the text".into()),
                Some(c) => self.error(format!("expected a name, found `{c}`")),
            });
        }
        let first = name.chars().next().unwrap_or('a');
        let is_var = is_question_var || first.is_ascii_uppercase();
        self.skip_space();
        // `name:type`: the type is read and dropped; matching ignores it.
        if self.peek_char() == Some(':') {
            self.pos += 1;
            self.skip_space();
            if self.name().is_empty() {
                return Err(self.error("expected a type name after `:`".into()));
            }
            self.skip_space();
        }
        if is_var {
            if self.peek_char() == Some('(') {
                return Err(self.error(format!(
                    "`{}` is a variable and cannot take arguments (functor names start lower-case)",
                    &self.text[start.saturating_sub(usize::from(is_question_var))..start + name.len()]
                )));
            }
            let full = if is_question_var { format!("?{name}") } else { name };
            return Ok(Term::Var(Sym::from(full)));
        }
        if self.peek_char() != Some('(') {
            return Ok(Term::Const(Sym::from(name)));
        }
        self.pos += 1;
        let mut args = Vec::new();
        loop {
            self.skip_space();
            args.push(self.term(depth + 1)?);
            self.skip_space();
            match self.peek_char() {
                Some(',') => self.pos += 1,
                Some(')') => {
                    self.pos += 1;
                    break;
                }
                Some(c) => return Err(self.error(format!("expected `,` or `)`, found `{c}`"))),
                None => {
                    return Err(self.error("expected `,` or `)`, found the end of the text".into()));
                }
            }
        }
        Ok(Term::Compound(Sym::from(name), args.into()))
    }
}

impl Hash for Term {
    fn hash<H: Hasher>(&self, state: &mut H) {
        state.write_u64(term_hash(self, None).0);
    }
}

/// The one hashing scheme of terms, written to any hasher as one word, so that a key whose
/// hash is already known ([`Prehashed`]) finds the term: a tag per variant, the name, and for a
/// compound its arity and arguments. Under `subst`, a bound variable hashes as its value does,
/// so a term and the term `substitute` would build from it hash alike. Also says whether the
/// term is ground under `subst`: one walk answers both.
fn term_hash(term: &Term, subst: Option<&Subst>) -> (u64, bool) {
    fn walk(term: &Term, subst: Option<&Subst>, state: &mut rustc_hash::FxHasher) -> bool {
        let term = match (term, subst) {
            (Term::Var(_), Some(s)) => s.walk(term),
            _ => term,
        };
        match term {
            Term::Const(name) => {
                state.write_u8(0);
                name.hash(state);
                true
            }
            Term::Var(name) => {
                state.write_u8(1);
                name.hash(state);
                false
            }
            Term::Compound(name, args) => {
                state.write_u8(2);
                name.hash(state);
                state.write_usize(args.len());
                let mut ground = true;
                for arg in args.iter() {
                    ground &= walk(arg, subst, state);
                }
                ground
            }
        }
    }
    let mut state = rustc_hash::FxHasher::default();
    let ground = walk(term, subst, &mut state);
    (state.finish(), ground)
}

/// A term under a substitution, as a key: it hashes and compares as `term.substitute(subst)`
/// would, without building that term (a `when` literal checked against the world, say).
#[derive(Clone, Copy)]
pub struct Bound<'a> {
    pub term: &'a Term,
    pub subst: &'a Subst,
}

impl<'a> Bound<'a> {
    /// The term itself, or for a bound variable its value (followed through variables): enough
    /// to compare a constant argument.
    pub fn resolved(&self) -> &'a Term {
        self.subst.walk(self.term)
    }

    /// The hash the term would have once built, and whether it is ground under the bindings
    /// (no unbound variable): what a lookup needs, in one walk.
    pub fn hashed(&self) -> (Prehashed<'a>, bool) {
        let (hash, ground) = term_hash(self.term, Some(self.subst));
        (Prehashed { hash, bound: *self }, ground)
    }
}

/// A [`Bound`] with its hash already computed, as a key.
#[derive(Clone, Copy)]
pub struct Prehashed<'a> {
    hash: u64,
    pub bound: Bound<'a>,
}

impl Hash for Prehashed<'_> {
    fn hash<H: Hasher>(&self, state: &mut H) {
        state.write_u64(self.hash);
    }
}

impl indexmap::Equivalent<Term> for Prehashed<'_> {
    fn equivalent(&self, key: &Term) -> bool {
        self.bound.equivalent(key)
    }
}

impl Hash for Bound<'_> {
    fn hash<H: Hasher>(&self, state: &mut H) {
        state.write_u64(term_hash(self.term, Some(self.subst)).0);
    }
}

impl indexmap::Equivalent<Term> for Bound<'_> {
    fn equivalent(&self, key: &Term) -> bool {
        fn same(term: &Term, subst: &Subst, key: &Term) -> bool {
            match (subst.walk(term), key) {
                (Term::Const(a), Term::Const(b)) | (Term::Var(a), Term::Var(b)) => a == b,
                (Term::Compound(f, xs), Term::Compound(g, ys)) => {
                    f == g && xs.len() == ys.len() && xs.iter().zip(ys.iter()).all(|(x, y)| same(x, subst, y))
                }
                _ => false,
            }
        }
        same(self.term, self.subst, key)
    }
}

/// Variable bindings. Small by construction (a norm has a handful of variables), so a vector,
/// kept inline for the usual one or two: matching a norm against a step allocates nothing, and
/// at 96 bytes a substitution is moved without a call to `memcpy` (at three inline it was 136,
/// and moving it was a tenth of what soft norms cost).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Subst {
    bindings: smallvec::SmallVec<[(Sym, Term); 2]>,
}

impl Subst {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn get(&self, var: &Sym) -> Option<&Term> {
        self.bindings.iter().find(|(v, _)| v == var).map(|(_, t)| t)
    }

    pub fn bind(&mut self, var: Sym, value: Term) {
        self.bindings.push((var, value));
    }

    /// Follows variable-to-variable bindings until a non-variable or an unbound variable.
    #[inline]
    fn walk<'a>(&'a self, mut term: &'a Term) -> &'a Term {
        while let Term::Var(v) = term {
            match self.get(v) {
                Some(next) => term = next,
                None => break,
            }
        }
        term
    }

    fn resolve<'t>(&self, term: &'t Term) -> Cow<'t, Term> {
        match term {
            Term::Var(v) if self.get(v).is_some() => Cow::Owned(self.walk(term).clone()),
            _ => Cow::Borrowed(term),
        }
    }

    fn occurs(&self, var: &Sym, term: &Term) -> bool {
        match self.walk(term) {
            Term::Var(v) => v == var,
            Term::Const(_) => false,
            Term::Compound(_, args) => args.iter().any(|a| self.occurs(var, a)),
        }
    }

    /// Extends the substitution so that `a` and `b` become equal; on failure the substitution may
    /// hold partial bindings, so callers unify into a copy they can drop.
    pub fn unify(&mut self, a: &Term, b: &Term) -> bool {
        // Only a bound variable is replaced by (a copy of) its value; everything else is unified
        // in place, so matching a pattern against ground facts copies nothing.
        let a = self.resolve(a);
        let b = self.resolve(b);
        match (a.as_ref(), b.as_ref()) {
            (Term::Var(x), Term::Var(y)) if x == y => true,
            (Term::Var(x), other) | (other, Term::Var(x)) => {
                if self.occurs(x, other) {
                    return false;
                }
                self.bind(x.clone(), other.clone());
                true
            }
            (Term::Const(x), Term::Const(y)) => x == y,
            (Term::Compound(f, xs), Term::Compound(g, ys)) => {
                f == g && xs.len() == ys.len() && xs.iter().zip(ys.iter()).all(|(x, y)| self.unify(x, y))
            }
            _ => false,
        }
    }
}

impl Subst {
    /// [`Subst::unify`] for a pattern against a term that is (usually) ground, as a norm's
    /// literal against a step or a fact: the same result, without the occurs check or the
    /// copies a general unification needs. A `term` with a variable is left to `unify`.
    pub fn unify_ground(&mut self, pattern: &Term, term: &Term) -> bool {
        if term.is_ground() {
            self.match_ground(pattern, term)
        } else {
            self.unify(pattern, term)
        }
    }

    /// `unify` where `term` is ground: a variable is bound to it, or compared with its value.
    fn match_ground(&mut self, pattern: &Term, term: &Term) -> bool {
        match (pattern, term) {
            (Term::Var(x), _) => match self.get(x) {
                Some(bound) if bound.is_ground() => bound == term,
                Some(bound) => {
                    let bound = bound.clone();
                    self.unify(&bound, term)
                }
                None => {
                    self.bind(x.clone(), term.clone());
                    true
                }
            },
            (Term::Const(a), Term::Const(b)) => a == b,
            (Term::Compound(f, xs), Term::Compound(g, ys)) => {
                f == g && xs.len() == ys.len() && xs.iter().zip(ys.iter()).all(|(x, y)| self.match_ground(x, y))
            }
            _ => false,
        }
    }
}

/// The most general unifier of two terms, if any.
pub fn unify(a: &Term, b: &Term) -> Option<Subst> {
    let mut subst = Subst::new();
    subst.unify(a, b).then_some(subst)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(s: &str) -> Term {
        Term::parse(s).unwrap()
    }

    #[test]
    fn parses_and_prints_canonically() {
        let cases = [
            ("did(self,get(object3))", "did(self,get(object3))"),
            ("  did( self , get( X ) ) ", "did(self,get(X))"),
            (
                "want(human:agent, did(self:agent, get(?x:physobj)))",
                "want(human,did(self,get(?x)))",
            ),
            ("destroy", "destroy"),
            ("on(object3, table1)", "on(object3,table1)"),
            ("mass(box1,0.5)", "mass(box1,0.5)"),
        ];
        for (input, canonical) in cases {
            assert_eq!(t(input).to_string(), canonical, "{input}");
        }
    }

    #[test]
    fn variables_are_upper_case_or_question_marked() {
        assert!(t("X").is_var());
        assert!(t("?thing").is_var());
        assert!(!t("x").is_var());
        assert_eq!(
            t("p(X, f(?y, X), Z)").variables(),
            vec![Sym::from("X"), Sym::from("?y"), Sym::from("Z")]
        );
    }

    #[test]
    fn parse_errors_say_where_and_why() {
        let cases = [
            ("get(", 4, "expected a name, found the end of the text"),
            ("get(a b)", 6, "expected `,` or `)`, found `b`"),
            ("get(a))", 6, "unexpected `)` after the end of the term"),
            ("", 0, "expected a name, found the end of the text"),
            ("X(a)", 1, "is a variable and cannot take arguments"),
            ("get(,)", 4, "expected a name, found `,`"),
            ("a:", 2, "expected a type name after `:`"),
        ];
        for (input, position, message) in cases {
            let err = Term::parse(input).unwrap_err();
            assert_eq!(err.position, position, "{input}: {err}");
            assert!(err.message.contains(message), "{input}: {err}");
        }
    }

    #[test]
    fn deep_nesting_is_refused_not_a_stack_overflow() {
        let deep = format!("{}a{}", "f(".repeat(10_000), ")".repeat(10_000));
        assert!(Term::parse(&deep).is_err());
        let ok = format!("{}a{}", "f(".repeat(MAX_DEPTH - 1), ")".repeat(MAX_DEPTH - 1));
        assert!(Term::parse(&ok).is_ok());
    }

    #[test]
    fn unification_binds_both_sides_and_respects_occurs_check() {
        let s = unify(&t("get(X, b)"), &t("get(a, Y)")).unwrap();
        assert_eq!(t("p(X,Y)").substitute(&s).to_string(), "p(a,b)");
        assert!(unify(&t("get(a)"), &t("get(b)")).is_none());
        assert!(unify(&t("get(a)"), &t("put(a)")).is_none());
        assert!(unify(&t("X"), &t("f(X)")).is_none());
        let s = unify(&t("p(X, X)"), &t("p(Y, c)")).unwrap();
        assert_eq!(t("X").substitute(&s).to_string(), "c");
    }

    #[test]
    fn constant_names() {
        assert!(is_constant_name("object3"));
        assert!(is_constant_name("cash_box"));
        assert!(!is_constant_name("Object3"));
        assert!(!is_constant_name("a b"));
        assert!(!is_constant_name(""));
        assert!(!is_constant_name("?x"));
    }

    /// Terms over `a`, `b`, the given variables, `f/1` and `g/2`, at most three deep.
    fn arb_term(vars: &'static [&'static str]) -> impl proptest::strategy::Strategy<Value = Term> {
        use proptest::prelude::*;
        let leaf = prop_oneof![
            prop::sample::select(vec!["a", "b"]).prop_map(Term::constant),
            prop::sample::select(vars.to_vec()).prop_map(|v| Term::Var(Sym::from(v))),
        ];
        leaf.prop_recursive(3, 12, 2, |inner| {
            prop_oneof![
                inner.clone().prop_map(|x| Term::compound("f", vec![x])),
                (inner.clone(), inner).prop_map(|(x, y)| Term::compound("g", vec![x, y])),
            ]
        })
    }

    proptest::proptest! {
        #[test]
        fn the_text_of_a_term_is_what_display_writes_and_reads_back(term in arb_term(&["X", "Y"])) {
            let text = term.text();
            proptest::prop_assert_eq!(&text, &term.to_string());
            proptest::prop_assert_eq!(text.len(), text.capacity());
            proptest::prop_assert_eq!(Term::parse(&text).unwrap(), term);
        }

        /// A term under a substitution hashes, compares and is ground exactly as the term
        /// `substitute` builds from it: the world looks up `when` literals through it.
        #[test]
        fn a_bound_term_stands_for_the_term_it_would_build(
            term in arb_term(&["X", "Y", "Z"]),
            x in proptest::option::of(arb_term(&["Z"])),
            y in proptest::option::of(arb_term(&["X", "Z"])),
            other in arb_term(&["Z"]),
        ) {
            use std::hash::BuildHasher;
            let mut subst = Subst::new();
            if let Some(x) = x {
                subst.bind(Sym::from("X"), x);
            }
            if let Some(y) = y {
                subst.bind(Sym::from("Y"), y);
            }
            let built = term.substitute(&subst);
            let bound = Bound { term: &term, subst: &subst };
            let hasher = rustc_hash::FxBuildHasher;
            proptest::prop_assert_eq!(hasher.hash_one(&built), hasher.hash_one(bound));
            proptest::prop_assert!(indexmap::Equivalent::equivalent(&bound, &built));
            proptest::prop_assert_eq!(indexmap::Equivalent::equivalent(&bound, &other), built == other);
            let (prehashed, ground) = bound.hashed();
            proptest::prop_assert_eq!(hasher.hash_one(prehashed), hasher.hash_one(&built));
            proptest::prop_assert_eq!(ground, built.is_ground());
            // Matching a pattern against a term: the same outcome and bindings as unifying.
            let (mut general, mut ground) = (subst.clone(), subst.clone());
            let unified = general.unify(&term, &other);
            proptest::prop_assert_eq!(ground.unify_ground(&term, &other), unified);
            if unified {
                proptest::prop_assert_eq!(term.substitute(&ground), term.substitute(&general));
            }
        }
    }
}
