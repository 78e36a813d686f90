//! Decisions without a server: one request from a file, a batch replayed from JSON Lines, and
//! the difference a proposed norm set would make to a batch.
//!
//! Owns: reading requests and norm sets from files, the replay line format, the replay summary
//! and the norm diff. Must not: write norms or verbs (opening a store only migrates it), listen
//! on a port, or decide anything differently from `POST /v1/clarify`: the same parsing, the same
//! default limits, the same engine call and the same response body.

use std::collections::BTreeMap;
use std::fmt;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::api::{ClarifyBody, DecisionDto, NormBody, NormSetBody, RequestLimits, parse_json};
use crate::core::ClarifyInput;
use crate::core::validate_norm_set;
use crate::engine::norms::{CompiledNorms, Norm, NormSpec};
use crate::engine::{Library, clarify};
use crate::error::{Error, Problem};
use crate::storage::{NormStore, SqliteStore};

/// The version a freshly migrated store gives the default library: offline answers without a
/// store then carry the `library_version` a fresh server's would.
const FRESH_LIBRARY_VERSION: i64 = 1;

/// What a run of the CLI failed on, and where.
#[derive(Debug)]
pub enum Failure {
    /// A file's content is at fault; `error` carries the JSON Pointer into it.
    Input { file: String, error: Error },
    /// A file cannot be read at all.
    Unreadable { file: String, detail: String },
    /// The flags ask for something that cannot be done (a store that does not exist).
    Usage { detail: String },
    /// The store named by `--database-url` cannot be opened or read, or an output cannot be written.
    Run { detail: String },
}

impl Failure {
    /// 2 when the caller's input is at fault (as for any usage error), 1 otherwise.
    pub fn exit_code(&self) -> u8 {
        match self {
            Failure::Input { error, .. } if (400..500).contains(&error.row().http) => 2,
            Failure::Unreadable { .. } | Failure::Usage { .. } => 2,
            Failure::Input { .. } | Failure::Run { .. } => 1,
        }
    }

    /// One JSON line: the problem body a server would answer with, plus the file at fault
    /// (RFC 9457 allows extension members).
    pub fn report(&self) -> String {
        let report = match self {
            Failure::Input { file, error } => {
                let problem = error.problem();
                Report {
                    kind: problem.kind,
                    title: problem.title,
                    status: Some(problem.status),
                    detail: problem.detail,
                    field: problem.field,
                    file: Some(file),
                }
            }
            Failure::Unreadable { file, detail } => {
                Report::new("unreadable-file", "Unreadable file", detail, Some(file))
            }
            Failure::Usage { detail } => Report::new("usage", "Usage", detail, None),
            Failure::Run { detail } => Report::new("run-failed", "Run failed", detail, None),
        };
        // Plain strings and numbers: serializing cannot fail.
        serde_json::to_string(&report).unwrap_or_default()
    }
}

/// A problem as the CLI reports it: members in the order of a server's problem body.
#[derive(Serialize)]
struct Report<'a> {
    #[serde(rename = "type")]
    kind: String,
    title: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    status: Option<u16>,
    detail: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    field: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    file: Option<&'a str>,
}

impl<'a> Report<'a> {
    fn new(slug: &str, title: &str, detail: &str, file: Option<&'a str>) -> Report<'a> {
        Report {
            kind: format!("/problems/{slug}"),
            title: title.to_owned(),
            status: None,
            detail: detail.to_owned(),
            field: None,
            file,
        }
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.report())
    }
}

/// A file's bytes; `-` is standard input.
pub fn read_input(path: &Path) -> Result<Vec<u8>, Failure> {
    let unreadable = |e: std::io::Error| Failure::Unreadable {
        file: path.display().to_string(),
        detail: e.to_string(),
    };
    if path == Path::new("-") {
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(&mut std::io::stdin(), &mut bytes).map_err(unreadable)?;
        Ok(bytes)
    } else {
        std::fs::read(path).map_err(unreadable)
    }
}

// ---------------------------------------------------------------------------------------------
// What decisions are made under

/// The norms and verbs a batch is decided under.
#[derive(Clone, Debug)]
pub struct Knowledge {
    pub norms: Arc<CompiledNorms>,
    pub library: Arc<Library>,
}

/// Where the norms and the library come from: a store, if one is named, else no norms and the
/// default library; a norms file replaces the store's norms.
pub struct Sources {
    store: Option<SqliteStore>,
}

impl Sources {
    /// Opens the store at `database_url`, which must already exist: a store created here would
    /// be empty and silently decide under no norms. Opening migrates an older store.
    pub async fn open(database_url: Option<&str>) -> Result<Sources, Failure> {
        let Some(url) = database_url else {
            return Ok(Sources { store: None });
        };
        if let Some(path) = sqlite_file(url)
            && !path.exists()
        {
            return Err(Failure::Usage {
                detail: format!("no database at `{}` (from --database-url {url})", path.display()),
            });
        }
        let store = SqliteStore::open(url)
            .await
            .map_err(|e| Failure::Run { detail: e.to_string() })?;
        Ok(Sources { store: Some(store) })
    }

    pub fn has_store(&self) -> bool {
        self.store.is_some()
    }

    /// The norms of `norms_file` when given, else the store's, else none (version 0); with the
    /// store's library, else the default one.
    pub async fn knowledge(&self, norms_file: Option<&Path>) -> Result<Knowledge, Failure> {
        let unavailable = |e: crate::storage::StoreError| Failure::Run { detail: e.to_string() };
        let library = match &self.store {
            Some(store) => {
                let (version, verbs) = store.load_actions().await.map_err(unavailable)?;
                Library::from_written(version, &verbs).map_err(|(name, e)| Failure::Run {
                    detail: format!("the stored verb `{name}` is invalid: {e}"),
                })?
            }
            None => {
                let mut library = Library::default_library();
                library.version = FRESH_LIBRARY_VERSION;
                library
            }
        };
        let norms = match (norms_file, &self.store) {
            (Some(path), _) => norms_from_file(path)?,
            (None, Some(store)) => {
                let (version, norms) = store.load().await.map_err(unavailable)?;
                CompiledNorms::compile(version, norms)
            }
            (None, None) => CompiledNorms::compile(0, Vec::new()),
        };
        Ok(Knowledge {
            norms: Arc::new(norms),
            library: Arc::new(library),
        })
    }
}

/// The file behind a SQLite URL, unless it names an in-memory database.
fn sqlite_file(url: &str) -> Option<&Path> {
    let rest = url.strip_prefix("sqlite://").or_else(|| url.strip_prefix("sqlite:"))?;
    let (path, query) = rest.split_once('?').unwrap_or((rest, ""));
    if path.is_empty() || path == ":memory:" || query.split('&').any(|p| p == "mode=memory") {
        return None;
    }
    Some(Path::new(path))
}

/// Reads a norms file: a JSON list of norms as `POST /v1/norms` takes them, or a norm set as
/// `GET /v1/norm-set` gives it. Numbered as the server would number them on an empty store.
pub fn norms_from_file(path: &Path) -> Result<CompiledNorms, Failure> {
    let bytes = read_input(path)?;
    norms_from_bytes(&bytes).map_err(|error| Failure::Input {
        file: path.display().to_string(),
        error,
    })
}

/// A list is taken as if each norm were posted in turn to an empty store: ids 1, 2, ... and the
/// version the last post leaves (the count). A norm set is taken as an import on an empty store:
/// ids given are kept, the others numbered after the largest, in file order; its `version` (an
/// export's) is kept, else 1.
pub fn norms_from_bytes(bytes: &[u8]) -> Result<CompiledNorms, Error> {
    let value: serde_json::Value = parse_json(bytes)?;
    match value {
        serde_json::Value::Array(_) => {
            let bodies: Vec<NormBody> = parse_json(bytes)?;
            let mut norms = Vec::with_capacity(bodies.len());
            for (i, body) in bodies.into_iter().enumerate() {
                let at = |e: Error| match e {
                    Error::Invalid { field, detail } => Error::invalid(format!("/{i}{field}"), detail),
                    other => other,
                };
                let spec = body
                    .for_create()
                    .map_err(at)?
                    .validate()
                    .map_err(|e| Error::invalid(format!("/{i}{}", e.field), e.message))?;
                let id = i as i64 + 1;
                norms.push(Norm { id, revision: id, spec });
            }
            Ok(CompiledNorms::compile(norms.len() as i64, norms))
        }
        serde_json::Value::Object(_) => {
            let set: NormSetBody = parse_json(bytes)?;
            let version = set.version.unwrap_or(1);
            let inputs = set.norms.into_iter().map(|n| (n.id, n.into_input())).collect();
            let specs: Vec<(Option<i64>, NormSpec)> = validate_norm_set(inputs)?;
            let mut next = specs.iter().filter_map(|(id, _)| *id).max().unwrap_or(0);
            let norms = specs
                .into_iter()
                .map(|(id, spec)| {
                    let id = id.unwrap_or_else(|| {
                        next += 1;
                        next
                    });
                    Norm {
                        id,
                        revision: version,
                        spec,
                    }
                })
                .collect();
            Ok(CompiledNorms::compile(version, norms))
        }
        _ => Err(Error::invalid(
            "",
            "a norms file is a list of norms or a norm set {\"version\": N, \"norms\": [...]}",
        )),
    }
}

// ---------------------------------------------------------------------------------------------
// Deciding

/// Decides one request exactly as the REST handler does: the same validation under the default
/// limits, a deadline counted from here, the same response body.
pub fn decide(body: ClarifyBody, knowledge: &Knowledge) -> Result<DecisionDto, Error> {
    let mut input = ClarifyInput::from_body(body, &RequestLimits::default())?;
    let text = input.text.take();
    let deadline = Instant::now() + input.deadline;
    let expired = || Instant::now() >= deadline;
    let decision = clarify(
        &input.request,
        &input.scene,
        &knowledge.norms,
        &knowledge.library,
        &expired,
    )?;
    Ok(DecisionDto::new(&decision, text))
}

/// `scruple clarify FILE`: one request body, as `POST /v1/clarify` takes it.
pub fn clarify_file(path: &Path, knowledge: &Knowledge) -> Result<DecisionDto, Failure> {
    let bytes = read_input(path)?;
    let input = |error| Failure::Input {
        file: path.display().to_string(),
        error,
    };
    decide(parse_json(&bytes).map_err(input)?, knowledge).map_err(input)
}

// ---------------------------------------------------------------------------------------------
// Replay

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

/// One non-blank line of a replay file, parsed.
#[derive(Debug)]
pub struct Line {
    /// 1-based, counting every line of the file, blank ones included.
    pub number: usize,
    pub id: Option<String>,
    pub condition: Option<String>,
    /// Whether the request came in an envelope: its pointers then start with `/request`.
    pub enveloped: bool,
    /// The request, or why the line is not one (pointers are into the line's JSON).
    pub request: Result<ClarifyBody, Problem>,
}

/// Parses a replay file. A line whose object has a `request` member is an envelope
/// `{"id"?: string, "condition"?: string, "request": body}` (nothing else allowed); any other line
/// is a bare `POST /v1/clarify` body (which has no `request` member, so the two never clash).
/// Lines end at `\n` (a `\r` before it is dropped); blank lines are skipped; bytes that are not
/// UTF-8 make their own line malformed, not the file.
pub fn parse_lines(bytes: &[u8]) -> Vec<Line> {
    bytes
        .split(|b| *b == b'\n')
        .enumerate()
        .map(|(i, line)| (i + 1, line.strip_suffix(b"\r").unwrap_or(line)))
        .filter(|(_, line)| !line.iter().all(u8::is_ascii_whitespace))
        .map(|(number, line)| parse_line(number, line))
        .collect()
}

fn parse_line(number: usize, bytes: &[u8]) -> Line {
    let enveloped = matches!(
        serde_json::from_slice::<serde_json::Value>(bytes),
        Ok(serde_json::Value::Object(ref members)) if members.contains_key("request")
    );
    if enveloped {
        match parse_json::<Envelope>(bytes) {
            Ok(e) => Line {
                number,
                id: e.id,
                condition: e.condition,
                enveloped,
                request: Ok(e.request),
            },
            Err(error) => Line {
                number,
                id: None,
                condition: None,
                enveloped,
                request: Err(error.problem()),
            },
        }
    } else {
        Line {
            number,
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
    fn words(&self) -> &str {
        match (&self.decision, &self.error) {
            (Some(d), _) => &d.utterance,
            (None, Some(p)) => &p.detail,
            (None, None) => "",
        }
    }
}

/// Decides every line in parallel; answers come back in line order. `done` is called once per
/// line as it finishes, with the count so far (for a progress counter).
pub fn replay(lines: &[Line], knowledge: &Knowledge, done: &(dyn Fn(usize) + Sync)) -> Vec<Answer> {
    let finished = std::sync::atomic::AtomicUsize::new(0);
    lines
        .par_iter()
        .map(|line| {
            let outcome = match &line.request {
                Ok(body) => decide(body.clone(), knowledge).map_err(|e| {
                    let mut problem = e.problem();
                    // Pointers in a report are into the line, whatever wraps the request.
                    if line.enveloped {
                        problem.field = problem.field.map(|f| format!("/request{f}"));
                    }
                    problem
                }),
                Err(problem) => Err(problem.clone()),
            };
            done(finished.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
            let (decision, error) = match outcome {
                Ok(d) => (Some(d), None),
                Err(p) => (None, Some(p)),
            };
            Answer {
                line: line.number,
                id: line.id.clone(),
                condition: line.condition.clone(),
                decision,
                error,
            }
        })
        .collect()
}

/// Answers as JSON Lines, one per request, in line order.
pub fn answers_jsonl(answers: &[Answer]) -> String {
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

/// A problem on one line of a report: its detail, and the field when one is at fault.
fn problem_words(problem: &Problem) -> String {
    match &problem.field {
        Some(field) => format!("{} (at {})", problem.detail, if field.is_empty() { "/" } else { field }),
        None => problem.detail.clone(),
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
                let mut row = vec![condition.clone()];
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

// ---------------------------------------------------------------------------------------------
// Diff

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
