//! `scruple replay`: the line format, deciding every line, the answers and the summary (what it
//! prints of a line's text shown escaped: `escape_unseen`).

use std::collections::BTreeMap;
use std::fmt;
use std::sync::atomic::{AtomicUsize, Ordering};

use serde::{Deserialize, Serialize};

use super::{Knowledge, core_over, decide};
use crate::core::Core;
use crate::engine::input::escape_unseen;
use crate::error::Problem;
use crate::wire::{ClarifyBody, DecisionDto, parse_json};

/// One request of a replay file, wrapped to carry a label and an experimental condition.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Envelope {
    #[serde(default)]
    id: Option<String>,
    #[serde(default)]
    condition: Option<String>,
    request: ClarifyBody,
}

/// One non-blank line of a replay file, not yet parsed: each is parsed by the thread that
/// decides it, so that parsing is spread over the cores and no parsed scene outlives its line.
#[derive(Clone, Copy, Debug)]
pub struct Line<'a> {
    /// 1-based, counting every line of the file, blank ones included.
    pub number: usize,
    /// Without its line end (and a `\r` before it).
    pub bytes: &'a [u8],
}

/// A line read: its request, or why it is not one (pointers are into the line's JSON).
struct Parsed {
    id: Option<String>,
    condition: Option<String>,
    /// Whether the request came in an envelope: its pointers then start with `/request`.
    enveloped: bool,
    request: Result<ClarifyBody, Problem>,
}

/// Splits a replay file into its lines. A line whose object has a `request` member is an
/// envelope `{"id"?: string, "condition"?: string, "request": body}` (nothing else allowed); any
/// other line is a bare `POST /v1/clarify` body (which has no `request` member, so the two never
/// clash). Lines end at `\n` (a `\r` before it is dropped); blank lines are skipped; bytes that
/// are not UTF-8 make their own line malformed, not the file.
pub fn parse_lines(bytes: &[u8]) -> Vec<Line<'_>> {
    bytes
        .split(|b| *b == b'\n')
        .enumerate()
        .map(|(i, line)| (i + 1, line.strip_suffix(b"\r").unwrap_or(line)))
        .filter(|(_, line)| !line.iter().all(u8::is_ascii_whitespace))
        .map(|(number, bytes)| Line { number, bytes })
        .collect()
}

fn parse_line(bytes: &[u8]) -> Parsed {
    let enveloped = matches!(
        serde_json::from_slice::<serde_json::Value>(bytes),
        Ok(serde_json::Value::Object(ref members)) if members.contains_key("request")
    );
    if enveloped {
        match parse_json::<Envelope>(bytes) {
            Ok(e) => Parsed {
                id: e.id,
                condition: e.condition,
                enveloped,
                request: Ok(e.request),
            },
            Err(error) => Parsed {
                id: None,
                condition: None,
                enveloped,
                request: Err(error.problem()),
            },
        }
    } else {
        Parsed {
            id: None,
            condition: None,
            enveloped,
            request: parse_json::<ClarifyBody>(bytes).map_err(|e| e.problem()),
        }
    }
}

/// What one line came to.
#[derive(Clone, Debug, Serialize)]
pub struct Answer {
    pub line: usize,
    pub id: Option<String>,
    pub condition: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub decision: Option<DecisionDto>,
    /// The problem a server would have answered with; pointers are into the request, or into
    /// the line for an envelope that is itself wrong.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<Problem>,
}

impl Answer {
    /// The decision kind, or `error`.
    pub fn kind(&self) -> &str {
        self.decision.as_ref().map_or("error", |d| d.decision.as_str())
    }

    /// The utterance, or the problem's detail.
    pub(super) fn words(&self) -> &str {
        match (&self.decision, &self.error) {
            (Some(d), _) => &d.utterance,
            (None, Some(p)) => &p.detail,
            (None, None) => "",
        }
    }
}

/// Lines a worker takes at a time: enough that taking them costs nothing beside deciding them,
/// few enough that the workers finish together.
const CHUNK: usize = 64;

/// Decides every line on one thread per core, each parsing and deciding the lines it takes.
/// Each run of consecutive lines a worker decided is handed to `each` on that worker (to
/// serialize or count it there, beside the deciding), and what `each` made goes to `then` on
/// the calling thread in line order, as soon as every line before it is in: the same order and
/// answers whatever the thread count, written while later lines are still being decided, and
/// no more answers held than the workers have in hand. `runtime` runs the core's operation (and
/// its blocking pool, for costly decisions); this call blocks, so call it outside the runtime's
/// own threads (or under `block_in_place`). `done` is called once per line as it finishes, with
/// the count so far (for a progress counter).
pub fn replay<T: Send>(
    lines: &[Line<'_>],
    knowledge: Knowledge,
    runtime: &tokio::runtime::Handle,
    done: &(dyn Fn(usize) + Sync),
    each: &(dyn Fn(Vec<Answer>) -> T + Sync),
    then: &mut dyn FnMut(T),
) {
    let core = core_over(knowledge);
    // No more at once than the core has turns for costly decisions, so none waits for a turn
    // (a server would answer such a wait as overload).
    let workers = std::thread::available_parallelism().map_or(2, usize::from);
    let next = AtomicUsize::new(0);
    let finished = AtomicUsize::new(0);
    // Bounded, so a slow `then` (a slow disk) holds the workers back instead of their answers
    // piling up. The caller drains it whatever order chunks come in, so a full queue never
    // waits on a chunk still to be sent.
    let (sender, received) = std::sync::mpsc::sync_channel::<(usize, T)>(2 * workers);
    std::thread::scope(|scope| {
        let running: Vec<_> = (0..workers)
            .map(|_| {
                let sender = sender.clone();
                let (next, finished, core) = (&next, &finished, &core);
                scope.spawn(move || {
                    loop {
                        let chunk = next.fetch_add(1, Ordering::Relaxed);
                        let from = chunk.saturating_mul(CHUNK);
                        if from >= lines.len() {
                            return;
                        }
                        let decided = (lines.iter().skip(from).take(CHUNK))
                            .map(|line| {
                                let answer = runtime.block_on(answer(line, core));
                                done(finished.fetch_add(1, Ordering::Relaxed) + 1);
                                answer
                            })
                            .collect();
                        // Refused only once the caller has stopped taking chunks (a panic).
                        if sender.send((chunk, each(decided))).is_err() {
                            return;
                        }
                    }
                })
            })
            .collect();
        drop(sender);
        // Chunks in by number; each handed on once all those before it are. The queue is owned
        // here, so a panic in `then` drops it and frees any worker waiting to send: the scope
        // can then join them and raise the panic.
        let mut waiting = BTreeMap::new();
        let mut due = 0;
        for (chunk, made) in received {
            waiting.insert(chunk, made);
            while let Some(made) = waiting.remove(&due) {
                then(made);
                due += 1;
            }
        }
        for worker in running {
            // A worker ends only by returning or by a panic of the engine, which is a bug: it
            // is raised here as it would have been on one thread.
            worker.join().unwrap_or_else(|e| std::panic::resume_unwind(e));
        }
    });
}

/// One line parsed and decided.
async fn answer(line: &Line<'_>, core: &Core) -> Answer {
    let Parsed {
        id,
        condition,
        enveloped,
        request,
    } = parse_line(line.bytes);
    let outcome = match request {
        Ok(body) => decide(body, core).await.map_err(|e| {
            let mut problem = e.problem();
            // Pointers in a report are into the line, whatever wraps the request.
            if enveloped {
                problem.field = problem.field.map(|f| format!("/request{f}"));
            }
            problem
        }),
        Err(problem) => Err(problem),
    };
    let (decision, error) = match outcome {
        Ok(d) => (Some(d), None),
        Err(p) => (None, Some(p)),
    };
    Answer {
        line: line.number,
        id,
        condition,
        decision,
        error,
    }
}

/// `answers` as JSON Lines, one per answer, in their order.
pub fn jsonl(answers: &[Answer]) -> String {
    let mut out = String::new();
    for answer in answers {
        // An answer is plain data (strings, numbers, lists): it always serializes.
        out.push_str(&serde_json::to_string(answer).unwrap_or_default());
        out.push('\n');
    }
    out
}

/// The condition column for a line that names none.
pub const NO_CONDITION: &str = "-";

/// Decisions by kind, overall and per condition; kinds and conditions in byte order, `error`
/// last.
#[derive(Debug, Default)]
pub struct Summary {
    pub total: usize,
    pub by_kind: BTreeMap<String, usize>,
    pub by_condition: BTreeMap<String, BTreeMap<String, usize>>,
    /// Lines that got no decision: line number and the problem.
    pub errors: Vec<(usize, Problem)>,
}

impl Summary {
    pub fn of(answers: &[Answer]) -> Summary {
        let mut summary = Summary {
            total: answers.len(),
            ..Summary::default()
        };
        for answer in answers {
            let kind = answer.kind().to_owned();
            let condition = answer.condition.clone().unwrap_or_else(|| NO_CONDITION.to_owned());
            *summary.by_kind.entry(kind.clone()).or_default() += 1;
            *summary
                .by_condition
                .entry(condition)
                .or_default()
                .entry(kind)
                .or_default() += 1;
            if let Some(problem) = &answer.error {
                summary.errors.push((answer.line, problem.clone()));
            }
        }
        summary
    }

    /// Adds the counts of `later`, whose lines all come after this summary's.
    pub fn merge(&mut self, later: Summary) {
        self.total += later.total;
        for (kind, count) in later.by_kind {
            *self.by_kind.entry(kind).or_default() += count;
        }
        for (condition, kinds) in later.by_condition {
            let row = self.by_condition.entry(condition).or_default();
            for (kind, count) in kinds {
                *row.entry(kind).or_default() += count;
            }
        }
        self.errors.extend(later.errors);
    }

    /// `errors`, then one line per line that got no decision; empty when every line did.
    pub fn errors_report(&self) -> String {
        if self.errors.is_empty() {
            return String::new();
        }
        let mut out = "errors\n".to_owned();
        for (line, problem) in &self.errors {
            out.push_str(&format!("line {line}: {}\n", problem_words(problem)));
        }
        out
    }

    /// The kinds that occur, in byte order, with `error` last.
    fn kinds(&self) -> Vec<&str> {
        let mut kinds: Vec<&str> = self
            .by_kind
            .keys()
            .map(String::as_str)
            .filter(|k| *k != "error")
            .collect();
        if self.by_kind.contains_key("error") {
            kinds.push("error");
        }
        kinds
    }
}

/// Left-aligned first column, right-aligned counts, two spaces between columns.
fn table(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut widths: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for row in rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let line = |cells: &[&str]| {
        let mut text = String::new();
        for (i, (cell, w)) in cells.iter().zip(&widths).enumerate() {
            if i == 0 {
                text.push_str(&format!("{cell:<w$}"));
            } else {
                text.push_str(&format!("  {cell:>w$}"));
            }
        }
        text.trim_end().to_owned() + "\n"
    };
    let mut out = line(header);
    for row in rows {
        out.push_str(&line(&row.iter().map(String::as_str).collect::<Vec<_>>()));
    }
    out
}

/// A problem on one line of a report: its detail, and the field when one is at fault (both may
/// echo the line, so they are shown escaped).
fn problem_words(problem: &Problem) -> String {
    let detail = escape_unseen(&problem.detail);
    match problem.field.as_deref() {
        Some("") => format!("{detail} (at /)"),
        Some(field) => format!("{detail} (at {})", escape_unseen(field)),
        None => detail.into_owned(),
    }
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let errors = self.errors.len();
        writeln!(
            f,
            "{} requests: {} decided, {} {}",
            self.total,
            self.total - errors,
            errors,
            if errors == 1 { "error" } else { "errors" }
        )?;
        let kinds = self.kinds();
        let rows: Vec<Vec<String>> = kinds
            .iter()
            .map(|k| vec![(*k).to_owned(), self.by_kind[*k].to_string()])
            .collect();
        writeln!(f)?;
        write!(f, "{}", table(&["decision", "count"], &rows))?;
        let mut header = vec!["condition"];
        header.extend(kinds.iter().copied());
        let rows: Vec<Vec<String>> = self
            .by_condition
            .iter()
            .map(|(condition, counts)| {
                // The file's text, shown escaped: a report goes to a terminal.
                let mut row = vec![escape_unseen(condition).into_owned()];
                row.extend(kinds.iter().map(|k| counts.get(*k).copied().unwrap_or(0).to_string()));
                row
            })
            .collect();
        writeln!(f)?;
        write!(f, "{}", table(&header, &rows))?;
        if !self.errors.is_empty() {
            writeln!(f)?;
            write!(f, "{}", self.errors_report())?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::{CHUNK, Knowledge, parse_lines, replay};

    /// A `then` that panics ends the replay with that panic, never a hang: the workers waiting
    /// to hand on their chunks (far more chunks than the queue holds) are let go.
    #[test]
    fn a_panic_in_then_is_raised_not_a_hang() {
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .build()
            .unwrap();
        // Each line a body without its directive: an error answer, at once.
        let text = "{}\n".repeat(CHUNK * 40);
        let lines = parse_lines(text.as_bytes());
        let knowledge = Knowledge {
            norms: Default::default(),
            library: Default::default(),
        };
        let raised = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            replay(
                &lines,
                knowledge,
                runtime.handle(),
                &|_| {},
                &|chunk| chunk.len(),
                &mut |_| panic!("then failed"),
            )
        }));
        let raised = raised.expect_err("the panic is raised");
        assert_eq!(raised.downcast_ref::<&str>(), Some(&"then failed"));
    }
}
