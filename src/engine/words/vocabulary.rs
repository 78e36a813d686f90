//! The closed lists of the grammar: determiners, pronouns, question and function words, the
//! manner words that alone may be left out, negations, and the words of shapes it knows.
//!
//! Owns: those lists. Must not: grow a list by guessing; a word left out is one of `MANNER`.

pub(super) const DETERMINERS: &[&str] = &["the", "a", "an", "any", "this", "that", "these", "those", "my", "your"];
/// Determiners said with a noun in the plural: "the cups" is every cup; "a cups" is not said.
pub(super) const PLURAL_DETERMINERS: &[&str] = &["the", "these", "those", "my", "your"];
pub(super) const PRONOUNS: &[&str] = &["it", "them", "this", "that"];
/// Words that open a question asking for information rather than action.
pub(super) const QUESTION_WORDS: &[&str] = &[
    "what", "which", "who", "whom", "whose", "where", "when", "why", "how", "is", "are", "was", "were", "does", "did",
    "do", "has", "have", "am", "should", "shall", "may", "might", "must",
];
/// Words that are never a verb, so never the unknown verb an imperative names: "on the mug"
/// is not a request to "on" it.
pub(super) const FUNCTION_WORDS: &[&str] = &[
    "the", "a", "an", "my", "your", "on", "onto", "in", "into", "inside", "upon", "at", "to", "with", "from", "of",
    "by", "under", "over", "off", "up", "down", "for", "me", "us", "you", "i", "we", "and", "or", "not", "yes", "no",
];
/// The only words ever left out: how and when, never what or which. Each is a phrase; "please"
/// and the beneficiary "for me" are left out without being shown as ignored.
pub(super) const MANNER: &[&[&str]] = &[
    &["please"],
    &["for", "me"],
    &["for", "us"],
    &["right", "now"],
    &["right", "away"],
    &["now"],
    &["quickly"],
    &["carefully"],
    &["gently"],
    &["slowly"],
    &["immediately"],
    &["again"],
    &["soon"],
    &["asap"],
    &["instead"],
    &["thanks"],
    &["thank", "you"],
];
/// Words that open another step of the task ("and destroy the vase", "then smash").
pub(super) const STEP_WORDS: &[&str] = &["and", "then", "after", "afterwards", "next", "also"];
/// Words that negate what follows.
pub(super) const NEGATIONS: &[&[&str]] = &[&["don't"], &["dont"], &["do", "not"], &["never"], &["not"]];
/// Words the grammar knows as the shape of a reference it does not read yet: order, number,
/// degree, relations and clauses. Found where a reference fails, they are the words said back
/// as not understood ("second" in "the second notebook"), rather than "nothing is there".
pub(super) const STRUCTURE: &[&str] = &[
    "first",
    "second",
    "third",
    "fourth",
    "fifth",
    "sixth",
    "seventh",
    "eighth",
    "ninth",
    "tenth",
    "last",
    "next",
    "other",
    "another",
    "two",
    "three",
    "four",
    "five",
    "six",
    "seven",
    "eight",
    "nine",
    "ten",
    "both",
    "all",
    "every",
    "each",
    "some",
    "any",
    "either",
    "neither",
    "biggest",
    "largest",
    "smallest",
    "tallest",
    "shortest",
    "heaviest",
    "lightest",
    "nearest",
    "closest",
    "farthest",
    "furthest",
    "leftmost",
    "rightmost",
    "highest",
    "lowest",
    "on",
    "in",
    "inside",
    "under",
    "below",
    "beneath",
    "above",
    "near",
    "beside",
    "by",
    "behind",
    "left",
    "right",
    "front",
    "from",
    "with",
    "of",
    "at",
    "that",
    "which",
    "who",
    "not",
    "but",
    "except",
    "than",
    "and",
    "or",
    "to",
];
