//! Decisions without a server: one request from a file (`scruple clarify`), a batch replayed
//! from JSON Lines (`scruple replay`), and the difference a proposed norm set would make to a
//! batch (`replay --diff`).
//!
//! Owns: the CLI's failures and how they are reported, and each command's files and formats
//! (`knowledge`: norms and verbs; `replay`: lines, answers, summary; `diff`). Must not: write
//! norms or verbs (opening a store only migrates it), listen on a port, or decide anything
//! itself: every decision is `Core::clarify` over fixed knowledge, under the default limits,
//! with the response body `POST /v1/clarify` gives.

mod diff;
mod knowledge;
mod replay;

use std::fmt;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use serde::Serialize;

pub use crate::core::Knowledge;
use crate::core::{Core, Settings};
use crate::error::Error;
use crate::wire::{ClarifyBody, DecisionDto, parse_json};

pub use diff::{Change, diff, diff_report};
pub use knowledge::{Sources, norms_from_bytes, norms_from_file};
pub use replay::{Answer, Line, NO_CONDITION, Summary, jsonl, parse_lines, replay};

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

/// Writes a command's output to standard output. A reader that has gone away (`| head`) is no
/// failure of the command: the rest is dropped quietly, and the command ends with the status it
/// would have had.
pub fn emit(text: &str) -> Result<(), Failure> {
    let mut stdout = std::io::stdout().lock();
    match std::io::Write::write_all(&mut stdout, text.as_bytes()).and_then(|()| std::io::Write::flush(&mut stdout)) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(Failure::Run {
            detail: format!("cannot write the standard output: {e}"),
        }),
        _ => Ok(()),
    }
}

// ---------------------------------------------------------------------------------------------
// Deciding

/// Decides one request as `POST /v1/clarify` does, through the same core operation, over
/// `core`'s fixed knowledge; the deadline counts from here.
pub async fn decide(body: ClarifyBody, core: &Core) -> Result<DecisionDto, Error> {
    let text = body.directive.text.clone();
    let decision = core.clarify(body.into(), text.as_deref(), Instant::now()).await?;
    Ok(DecisionDto::new(&decision, text))
}

/// A core that decides under `knowledge` with the server's default limits.
pub fn core_over(knowledge: Knowledge) -> Arc<Core> {
    Arc::new(Core::fixed(knowledge, Settings::default()))
}

/// `scruple clarify FILE`: one request body, as `POST /v1/clarify` takes it.
pub async fn clarify_file(path: &Path, knowledge: Knowledge) -> Result<DecisionDto, Failure> {
    let bytes = read_input(path)?;
    let input = |error| Failure::Input {
        file: path.display().to_string(),
        error,
    };
    let body = parse_json(&bytes).map_err(input)?;
    decide(body, &core_over(knowledge)).await.map_err(input)
}
