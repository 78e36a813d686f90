//! `scruple replay --diff`: which answers a proposed norm set would change, and which soft
//! norms ranked the readings differently.

use std::collections::BTreeSet;

use super::Answer;
use crate::engine::input::escape_unseen;

/// A request whose decision kind or utterance differs between two norm sets.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Change {
    pub line: usize,
    pub id: Option<String>,
    pub before_kind: String,
    pub after_kind: String,
    pub before: String,
    pub after: String,
    /// Soft norms (id, kind) that counted in some reading after the change and not before:
    /// those the change made rank this request's readings.
    pub soft_added: Vec<(i64, String)>,
    /// Soft norms that counted before and no longer do.
    pub soft_removed: Vec<(i64, String)>,
}

/// The soft norms that counted in any reading of the answer, by id.
fn soft_norms(answer: &Answer) -> BTreeSet<(i64, String)> {
    let readings = answer.decision.iter().flat_map(|d| &d.interpretations);
    readings
        .flat_map(|i| &i.reasons)
        .filter(|r| r.kind.starts_with("discouraged_") || r.kind.starts_with("preferred_"))
        .filter_map(|r| Some((r.norm_id?, r.kind.clone())))
        .collect()
}

/// Every line whose answer differs in kind or words, in line order. `before` and `after` are
/// answers to the same lines.
pub fn diff(before: &[Answer], after: &[Answer]) -> Vec<Change> {
    before
        .iter()
        .zip(after)
        .filter(|(b, a)| b.kind() != a.kind() || b.words() != a.words())
        .map(|(b, a)| {
            let (was, is) = (soft_norms(b), soft_norms(a));
            Change {
                line: b.line,
                id: b.id.clone(),
                before_kind: b.kind().to_owned(),
                after_kind: a.kind().to_owned(),
                before: b.words().to_owned(),
                after: a.words().to_owned(),
                soft_added: is.difference(&was).cloned().collect(),
                soft_removed: was.difference(&is).cloned().collect(),
            }
        })
        .collect()
}

/// "norm 4 (discouraged_action), norm 7 (preferred_state)".
fn listed(norms: &[(i64, String)]) -> String {
    let named: Vec<String> = norms.iter().map(|(id, kind)| format!("norm {id} ({kind})")).collect();
    named.join(", ")
}

/// The changes, one block each, then the count.
pub fn diff_report(changes: &[Change], total: usize) -> String {
    let mut out = String::new();
    for c in changes {
        // The file's text and the words said of it, shown escaped: a report goes to a terminal.
        let id = (c.id.as_deref())
            .map(|id| format!(" ({})", escape_unseen(id)))
            .unwrap_or_default();
        out.push_str(&format!("line {}{id}: {} → {}\n", c.line, c.before_kind, c.after_kind));
        out.push_str(&format!("  before: {}\n", escape_unseen(&c.before)));
        out.push_str(&format!("  after:  {}\n", escape_unseen(&c.after)));
        if !c.soft_added.is_empty() {
            out.push_str(&format!("  ranked by soft {}\n", listed(&c.soft_added)));
        }
        if !c.soft_removed.is_empty() {
            out.push_str(&format!("  no longer ranked by soft {}\n", listed(&c.soft_removed)));
        }
    }
    let by_soft = changes
        .iter()
        .filter(|c| !(c.soft_added.is_empty() && c.soft_removed.is_empty()))
        .count();
    out.push_str(&format!(
        "{} of {} {} would change",
        changes.len(),
        total,
        if total == 1 { "request" } else { "requests" }
    ));
    if by_soft > 0 {
        out.push_str(&format!(", {by_soft} of them as soft norms rank the readings"));
    }
    out.push('\n');
    out
}
