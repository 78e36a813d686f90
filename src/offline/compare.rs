//! How an experiment's conditions compare over the lines replayed: decisions agreed on, pair by
//! pair, and the lines whose decisions differ, with the summary `replay --conditions` prints.
//!
//! Must not: decide, or print a line's text unescaped (a report goes to a terminal).

use super::replay::{Answer, Summary};
use crate::engine::input::escape_unseen;

/// A line whose decision differs between conditions.
#[derive(Clone, Debug, PartialEq)]
pub struct Differs {
    pub line: usize,
    pub id: Option<String>,
    /// Each condition's decision kind and utterance (or problem), in the conditions' order.
    pub answers: Vec<(String, String)>,
}

/// How the conditions' decisions compare over the lines replayed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Comparison {
    pub lines: usize,
    /// For each pair of conditions `(i, j)`, `i < j`, in order: the lines on which their
    /// decisions are the same kind.
    pub agreed: Vec<usize>,
    /// The lines whose decision kinds are not all the same, in line order.
    pub differ: Vec<Differs>,
}

impl Comparison {
    /// The comparison of a run of lines: `arms[c][l]` is condition `c`'s answer to line `l`.
    pub fn of(arms: &[Vec<Answer>]) -> Comparison {
        let conditions = arms.len();
        let lines = arms.first().map_or(0, Vec::len);
        let mut comparison = Comparison {
            lines,
            agreed: vec![0; conditions * conditions.saturating_sub(1) / 2],
            differ: Vec::new(),
        };
        for l in 0..lines {
            let mut pair = 0;
            for i in 0..conditions {
                for j in i + 1..conditions {
                    if arms[i][l].kind() == arms[j][l].kind() {
                        comparison.agreed[pair] += 1;
                    }
                    pair += 1;
                }
            }
            let first = arms[0][l].kind();
            if arms.iter().any(|arm| arm[l].kind() != first) {
                comparison.differ.push(Differs {
                    line: arms[0][l].line,
                    id: arms[0][l].id.clone(),
                    answers: arms
                        .iter()
                        .map(|arm| (arm[l].kind().to_owned(), arm[l].words().to_owned()))
                        .collect(),
                });
            }
        }
        comparison
    }

    /// Adds the comparison of `later`, whose lines all come after this one's.
    pub fn merge(&mut self, later: Comparison) {
        self.lines += later.lines;
        if self.agreed.is_empty() {
            self.agreed = later.agreed;
        } else {
            for (sum, more) in self.agreed.iter_mut().zip(later.agreed) {
                *sum += more;
            }
        }
        self.differ.extend(later.differ);
    }

    /// The pairs of condition positions, in the order of `agreed`.
    pub fn pairs(conditions: usize) -> impl Iterator<Item = (usize, usize)> {
        (0..conditions).flat_map(move |i| (i + 1..conditions).map(move |j| (i, j)))
    }

    /// An experiment's summary: the lines, answers and errors; decisions by kind under each
    /// condition; the agreement and the lines that differ (the file's text escaped: a report
    /// goes to a terminal).
    pub fn report(&self, names: &[String], summary: &Summary) -> String {
        let errors = summary.errors.len();
        let listed: Vec<String> = names.iter().map(|n| escape_unseen(n).into_owned()).collect();
        let mut out = format!(
            "{} lines under {} conditions ({}): {} answers, {} decided, {errors} {}\n\n",
            self.lines,
            names.len(),
            listed.join(", "),
            summary.total,
            summary.total - errors,
            if errors == 1 { "error" } else { "errors" }
        );
        out.push_str(&summary.condition_table(names.iter()));
        out.push_str("\nagreement (same decision)\n");
        for ((i, j), agreed) in Comparison::pairs(names.len()).zip(&self.agreed) {
            out.push_str(&format!(
                "{} = {}: {agreed} of {} lines ({})\n",
                escape_unseen(&names[i]),
                escape_unseen(&names[j]),
                self.lines,
                percent(*agreed, self.lines)
            ));
        }
        out.push_str(&format!("\nlines that differ: {}\n", self.differ.len()));
        for differs in &self.differ {
            let label = differs.id.as_deref().map(|id| format!(" ({})", escape_unseen(id)));
            let kinds: Vec<String> = (names.iter().zip(&differs.answers))
                .map(|(name, (kind, _))| format!("{} {kind}", escape_unseen(name)))
                .collect();
            out.push_str(&format!(
                "line {}{}: {}\n",
                differs.line,
                label.unwrap_or_default(),
                kinds.join(", ")
            ));
        }
        if errors > 0 {
            out.push('\n');
            out.push_str(&summary.errors_report());
        }
        out
    }
}

/// `part` of `whole` as a whole percentage ("33%"); "-" of nothing.
pub fn percent(part: usize, whole: usize) -> String {
    match whole {
        0 => "-".to_owned(),
        _ => format!("{}%", (part * 100 + whole / 2) / whole),
    }
}
