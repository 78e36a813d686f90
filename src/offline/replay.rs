//! `scruple replay`: the line format, reading lines within the body limit, deciding every line,
//! the answers and the summary (what it prints of a line's text escaped, see `escape_unseen`).

use std::collections::BTreeMap;
use std::fmt;
use std::io::BufRead;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use serde::{Deserialize, Serialize};

use super::conditions::{Condition, with_scene};
use super::{Failure, Knowledge, Limits, core_over, decide};
use crate::core::Core;
use crate::engine::input::escape_unseen;
use crate::error::{Error, Problem};
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
#[derive(Clone, Debug)]
pub struct Line {
    /// 1-based, counting every line of the file, blank ones included.
    pub number: usize,
    /// Without its line end (and a `\r` before it); `None` for a line longer than the limit,
    /// which was not read to its end.
    pub bytes: Option<Vec<u8>>,
}

/// A line read: its request, or why it is not one (pointers are into the line's JSON).
struct Parsed {
    id: Option<String>,
    condition: Option<String>,
    /// Whether the request came in an envelope: its pointers then start with `/request`.
    enveloped: bool,
    request: Result<ClarifyBody, Problem>,
}

/// How the reading of one line ended.
enum Ended {
    Newline,
    End,
    /// The most it may hold was read before a line end.
    Full,
}

/// Reads a replay file's lines in order, one at a time, none further than the body limit, so
/// that an endless line (`/dev/zero`) is never held: it is reported, and the file is read no
/// further (there is no next line to go on with). Lines end at `\n` (a `\r` before it is
/// dropped); blank lines are skipped but counted; bytes that are not UTF-8 make their own line
/// malformed, not the file. A line whose object has a `request` member is an envelope
/// `{"id"?: string, "condition"?: string, "request": body}` (nothing else allowed); any other
/// line is a bare `POST /v1/clarify` body (which has no `request` member, so the two never
/// clash).
pub struct Lines {
    input: Box<dyn BufRead + Send>,
    /// The number of the last line read.
    number: usize,
    /// The most bytes a line may hold (`--max-body-bytes`).
    limit: usize,
    /// Set at the end of the input, or after a line past the limit: nothing more is read.
    ended: bool,
}

impl Lines {
    pub fn new(input: impl BufRead + Send + 'static, limit: usize) -> Lines {
        Lines {
            input: Box::new(input),
            number: 0,
            limit,
            ended: false,
        }
    }

    /// The lines of a file; `-` is standard input.
    pub fn open(path: &Path, limit: usize) -> Result<Lines, Failure> {
        if path == Path::new("-") {
            return Ok(Lines::new(std::io::BufReader::new(std::io::stdin()), limit));
        }
        let file = std::fs::File::open(path).map_err(|e| Failure::Unreadable {
            file: path.display().to_string(),
            detail: e.to_string(),
        })?;
        Ok(Lines::new(std::io::BufReader::new(file), limit))
    }

    /// The next non-blank line, or `None` once there is none.
    pub fn next_line(&mut self) -> std::io::Result<Option<Line>> {
        while !self.ended {
            let mut bytes = Vec::new();
            // A line of the limit may still carry a `\r` before its `\n`.
            let ended = read_line_within(&mut *self.input, &mut bytes, self.limit.saturating_add(2))?;
            if matches!(ended, Ended::End) {
                self.ended = true;
                if bytes.is_empty() {
                    return Ok(None);
                }
            }
            self.number += 1;
            if bytes.last() == Some(&b'\r') && !matches!(ended, Ended::Full) {
                bytes.pop();
            }
            if matches!(ended, Ended::Full) || bytes.len() > self.limit {
                self.ended = true;
                return Ok(Some(Line {
                    number: self.number,
                    bytes: None,
                }));
            }
            if !bytes.iter().all(u8::is_ascii_whitespace) {
                return Ok(Some(Line {
                    number: self.number,
                    bytes: Some(bytes),
                }));
            }
        }
        Ok(None)
    }
}

/// Reads up to the next `\n` (consumed, not kept) into `into`, holding at most `most` bytes.
fn read_line_within(input: &mut dyn BufRead, into: &mut Vec<u8>, most: usize) -> std::io::Result<Ended> {
    loop {
        let available = match input.fill_buf() {
            Ok(available) => available,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        };
        if available.is_empty() {
            return Ok(Ended::End);
        }
        let room = most.saturating_sub(into.len()).min(available.len());
        if let Some(at) = available[..room].iter().position(|b| *b == b'\n') {
            into.extend_from_slice(&available[..at]);
            input.consume(at + 1);
            return Ok(Ended::Newline);
        }
        into.extend_from_slice(&available[..room]);
        input.consume(room);
        if into.len() >= most {
            return Ok(Ended::Full);
        }
    }
}

/// What every line is decided under beside its own words: the norms and verbs (one knowledge,
/// or for `--diff` the proposed and the baseline), the conditions of an experiment (each line
/// decided once under each, on the first knowledge), and the scene of a line that has none.
#[derive(Clone, Debug)]
pub struct Setup {
    pub knowledge: Vec<Knowledge>,
    pub conditions: Vec<Condition>,
    pub scene: Option<serde_json::Value>,
}

fn parse_line(bytes: &[u8], scene: Option<&serde_json::Value>) -> Parsed {
    // A line that cannot take the scene is parsed as it is, and its problem says why.
    let filled = scene.and_then(|scene| with_scene(bytes, scene));
    let bytes = filled.as_deref().unwrap_or(bytes);
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

/// Bytes of lines a worker takes at a time, at most (past one line): what the workers hold of
/// the input stays small whatever the lines' size.
const CHUNK_BYTES: usize = 1 << 20;

/// Where the workers take their lines from, one of them at a time.
struct Source<'a> {
    lines: &'a mut Lines,
    /// The number of the next chunk taken.
    next: usize,
    /// The first error reading the input: no more lines are taken after it.
    failed: Option<std::io::Error>,
}

impl Source<'_> {
    /// The next chunk of lines and its number; `None` at the end of the input or after an
    /// error reading it.
    fn take(&mut self) -> Option<(usize, Vec<Line>)> {
        let mut taken = Vec::new();
        let mut bytes = 0;
        while self.failed.is_none() && taken.len() < CHUNK && bytes < CHUNK_BYTES {
            match self.lines.next_line() {
                Ok(Some(line)) => {
                    bytes += line.bytes.as_ref().map_or(0, Vec::len);
                    taken.push(line);
                }
                Ok(None) => break,
                Err(e) => self.failed = Some(e),
            }
        }
        if taken.is_empty() {
            return None;
        }
        self.next += 1;
        Some((self.next - 1, taken))
    }
}

/// Decides every line on one thread per core, each reading (one at a time), parsing and
/// deciding the lines it takes, once under each of the setup's knowledge (the proposed norms,
/// then for `--diff` the baseline), or, with conditions, once under each condition on the first
/// knowledge: an arm each. Each run of consecutive lines a worker decided is handed to `each`
/// on that worker (to serialize or count it there, beside the deciding) as its answers under
/// each knowledge in turn, and what `each` made goes to `then` on the calling thread in line
/// order, as soon as every line before it is in: the same order and answers whatever the
/// thread count, written while later lines are still being read and decided, and no more of
/// the input held than the workers have in hand. `runtime` runs the core's operation (and its
/// blocking pool, for costly decisions); this call blocks, so call it outside the runtime's own
/// threads (or under `block_in_place`). `done` is called once per line as it finishes, with
/// the count so far (for a progress counter). Fails with the first error reading the input,
/// after handing on every line read before it.
pub fn replay<T: Send>(
    lines: &mut Lines,
    setup: &Setup,
    limits: &Limits,
    runtime: &tokio::runtime::Handle,
    done: &(dyn Fn(usize) + Sync),
    each: &(dyn Fn(Vec<Vec<Answer>>) -> T + Sync),
    then: &mut dyn FnMut(T),
) -> std::io::Result<()> {
    let cores: Vec<_> = match setup.conditions.as_slice() {
        [] => setup.knowledge.iter().map(|k| core_over(k.clone(), limits)).collect(),
        conditions => match setup.knowledge.first() {
            Some(first) => {
                let core = core_over(first.clone(), limits);
                conditions.iter().map(|_| core.clone()).collect()
            }
            None => Vec::new(),
        },
    };
    let too_long = too_long(limits.max_body_bytes);
    // No more at once than the core has turns for costly decisions, so none waits for a turn
    // (a server would answer such a wait as overload).
    let workers = std::thread::available_parallelism().map_or(2, usize::from);
    let source = std::sync::Mutex::new(Source {
        lines,
        next: 0,
        failed: None,
    });
    let finished = AtomicUsize::new(0);
    // Bounded, so a slow `then` (a slow disk) holds the workers back instead of their answers
    // piling up. The caller drains it whatever order chunks come in, so a full queue never
    // waits on a chunk still to be sent.
    let (sender, received) = std::sync::mpsc::sync_channel::<(usize, T)>(2 * workers);
    std::thread::scope(|scope| {
        let running: Vec<_> = (0..workers)
            .map(|_| {
                let sender = sender.clone();
                let (source, finished, cores, too_long) = (&source, &finished, &cores, &too_long);
                scope.spawn(move || {
                    loop {
                        // A worker that panicked held no line half-read: the source is whole.
                        let taken = source.lock().unwrap_or_else(std::sync::PoisonError::into_inner).take();
                        let Some((chunk, taken)) = taken else { return };
                        let mut decided: Vec<Vec<Answer>> =
                            cores.iter().map(|_| Vec::with_capacity(taken.len())).collect();
                        for line in &taken {
                            let answers = runtime.block_on(answers(line, cores, setup, too_long));
                            for (kept, answer) in decided.iter_mut().zip(answers) {
                                kept.push(answer);
                            }
                            done(finished.fetch_add(1, Ordering::Relaxed) + 1);
                        }
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
    match source
        .into_inner()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
        .failed
    {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// The problem of a line longer than the body limit, which ends the replay.
fn too_long(limit: usize) -> Problem {
    let mut problem = Error::PayloadTooLarge { limit }.problem();
    problem.detail = format!(
        "the line is longer than the limit of {limit} bytes (--max-body-bytes); the lines after it were not read"
    );
    problem
}

/// One line parsed once and decided by each arm in turn: under each core's knowledge, or each
/// condition's options (the answer then names the condition).
async fn answers(line: &Line, cores: &[std::sync::Arc<Core>], setup: &Setup, too_long: &Problem) -> Vec<Answer> {
    let unanswered = |error: Problem, id: Option<String>, condition: Option<String>| Answer {
        line: line.number,
        id,
        condition,
        decision: None,
        error: Some(error),
    };
    let Some(bytes) = &line.bytes else {
        return cores.iter().map(|_| unanswered(too_long.clone(), None, None)).collect();
    };
    let Parsed {
        id,
        condition,
        enveloped,
        request,
    } = parse_line(bytes, setup.scene.as_ref());
    // Under conditions, each arm's answer is labelled by its condition, and a line may name none.
    let label = |arm: usize| match setup.conditions.get(arm) {
        Some(c) => Some(c.name.clone()),
        None => condition.clone(),
    };
    let request = match (request, &condition) {
        (Ok(_), Some(own)) if !setup.conditions.is_empty() => Err(Error::invalid(
            "/condition",
            format!(
                "the line names its own condition `{}`, and --conditions decides every line under each condition: drop one",
                escape_unseen(own)
            ),
        )
        .problem()),
        (request, _) => request,
    };
    let body = match request {
        Ok(body) => body,
        Err(problem) => {
            return (0..cores.len())
                .map(|arm| unanswered(problem.clone(), id.clone(), label(arm)))
                .collect();
        }
    };
    let mut answers = Vec::with_capacity(cores.len());
    for (arm, core) in cores.iter().enumerate() {
        let body = match setup.conditions.get(arm) {
            Some(condition) => condition.over(&body),
            None => Ok(body.clone()),
        };
        let decided = match body {
            Ok(body) => decide(body, core).await.map_err(|e| e.problem()),
            Err(problem) => Err(problem),
        };
        let (decision, error) = match decided {
            Ok(d) => (Some(d), None),
            Err(mut problem) => {
                // Pointers in a report are into the line, whatever wraps the request.
                if enveloped {
                    problem.field = problem.field.map(|f| format!("/request{f}"));
                }
                (None, Some(problem))
            }
        };
        answers.push(Answer {
            line: line.number,
            id: id.clone(),
            condition: label(arm),
            decision,
            error,
        });
    }
    answers
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

    /// Decisions by kind for each of `conditions`, in their order (the file's text shown
    /// escaped: a report goes to a terminal).
    pub(super) fn condition_table<'a>(&self, conditions: impl Iterator<Item = &'a String>) -> String {
        let kinds = self.kinds();
        let mut header = vec!["condition"];
        header.extend(kinds.iter().copied());
        let rows: Vec<Vec<String>> = conditions
            .map(|condition| {
                let counts = self.by_condition.get(condition);
                let mut row = vec![escape_unseen(condition).into_owned()];
                row.extend(kinds.iter().map(|k| {
                    let count = counts.and_then(|c| c.get(*k)).copied().unwrap_or(0);
                    count.to_string()
                }));
                row
            })
            .collect();
        table(&header, &rows)
    }

    /// The kinds that occur, in byte order, with `error` last.
    pub(super) fn kinds(&self) -> Vec<&str> {
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
        writeln!(f)?;
        write!(f, "{}", self.condition_table(self.by_condition.keys()))?;
        if !self.errors.is_empty() {
            writeln!(f)?;
            write!(f, "{}", self.errors_report())?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::{CHUNK, Knowledge, Limits, Lines, Setup, replay};

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
        let limits = Limits::default();
        let mut lines = Lines::new(std::io::Cursor::new(text.into_bytes()), limits.max_body_bytes);
        let knowledge = Knowledge {
            norms: Default::default(),
            library: Default::default(),
        };
        let raised = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            replay(
                &mut lines,
                &Setup {
                    knowledge: vec![knowledge],
                    conditions: Vec::new(),
                    scene: None,
                },
                &limits,
                runtime.handle(),
                &|_| {},
                &|chunk| chunk.len(),
                &mut |_| panic!("then failed"),
            )
        }));
        let raised = raised.expect_err("the panic is raised");
        assert_eq!(raised.downcast_ref::<&str>(), Some(&"then failed"));
    }

    /// Lines are counted blank ones and all, lose a `\r` before their end, and one past the
    /// limit is not read to its end and ends the file.
    #[test]
    fn lines_are_numbered_and_none_is_read_past_the_limit() {
        let text = b"{\"a\": 1}\r\n\n  \n12345\n123456789\nnever read\n".to_vec();
        let mut lines = Lines::new(std::io::Cursor::new(text), 8);
        let mut read = Vec::new();
        while let Some(line) = lines.next_line().unwrap() {
            read.push((line.number, line.bytes));
        }
        assert_eq!(
            read,
            [
                (1, Some(b"{\"a\": 1}".to_vec())),
                (4, Some(b"12345".to_vec())),
                (5, None)
            ]
        );
        assert!(lines.next_line().unwrap().is_none(), "nothing after it is read");
    }
}
