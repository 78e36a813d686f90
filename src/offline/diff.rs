//! `scruple replay --diff`: which answers a proposed norm set would change.

use super::Answer;

/// A request whose decision kind or utterance differs between two norm sets.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Change {
    pub line: usize,
    pub id: Option<String>,
    pub before_kind: String,
    pub after_kind: String,
    pub before: String,
    pub after: String,
}

/// Every line whose answer differs in kind or words, in line order. `before` and `after` are
/// answers to the same lines.
pub fn diff(before: &[Answer], after: &[Answer]) -> Vec<Change> {
    before
        .iter()
        .zip(after)
        .filter(|(b, a)| b.kind() != a.kind() || b.words() != a.words())
        .map(|(b, a)| Change {
            line: b.line,
            id: b.id.clone(),
            before_kind: b.kind().to_owned(),
            after_kind: a.kind().to_owned(),
            before: b.words().to_owned(),
            after: a.words().to_owned(),
        })
        .collect()
}

/// The changes, one block each, then the count.
pub fn diff_report(changes: &[Change], total: usize) -> String {
    let mut out = String::new();
    for c in changes {
        let id = c.id.as_deref().map(|id| format!(" ({id})")).unwrap_or_default();
        out.push_str(&format!("line {}{id}: {} → {}\n", c.line, c.before_kind, c.after_kind));
        out.push_str(&format!("  before: {}\n", c.before));
        out.push_str(&format!("  after:  {}\n", c.after));
    }
    out.push_str(&format!(
        "{} of {} {} would change\n",
        changes.len(),
        total,
        if total == 1 { "request" } else { "requests" }
    ));
    out
}
