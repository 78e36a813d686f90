//! Decisions without a server: one request from a file (`scruple clarify`), a batch replayed
//! from JSON Lines (`scruple replay`), the difference a proposed norm set would make to a
//! batch (`replay --diff`), and an experiment's conditions compared (`replay --conditions`,
//! `--report`).
//!
//! Owns: the CLI's failures and how they are reported, and each command's files and formats
//! (`knowledge`: norms and verbs; `replay`: lines, answers, summary; `diff`), read no further
//! than the body limit. Must not: write norms or verbs (opening a store only migrates it),
//! listen on a port, print a file's text unescaped to a terminal, or decide anything itself:
//! every decision is `Core::clarify` over fixed knowledge, under the service's limits, with the
//! response body `POST /v1/clarify` gives.

mod command;
mod compare;
mod conditions;
mod diff;
mod knowledge;
mod replay;
mod report;

use std::fmt;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use serde::Serialize;

pub use crate::core::Knowledge;
use crate::core::{Core, DEFAULT_MAX_BODY_BYTES, RequestLimits, Settings};
use crate::error::Error;
use crate::wire::{ClarifyBody, DecisionDto, parse_json};

pub use command::{ReplayCommand, replay_command};
pub use compare::{Comparison, Differs};
pub use conditions::{Condition, conditions, scene_file};
pub use diff::{Change, diff, diff_report};
pub use knowledge::{Sources, norms_from_bytes, norms_from_file};
pub use replay::{Answer, Line, Lines, NO_CONDITION, Setup, Summary, jsonl, replay};
pub use report::report_html;

/// The limits an offline decision is held to: the service's, set by the same flags.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// The largest request (a `clarify` file, a `replay` line) or norms file, in bytes.
    pub max_body_bytes: usize,
    /// What one request may ask.
    pub request: RequestLimits,
}

impl Default for Limits {
    /// The service's defaults.
    fn default() -> Self {
        Limits {
            max_body_bytes: DEFAULT_MAX_BODY_BYTES,
            request: RequestLimits::default(),
        }
    }
}

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

/// A file's bytes, `-` standard input, read no further than `limit` bytes: a longer one is
/// the problem a server answers a body over its limit with (413), naming the file.
pub fn read_input(path: &Path, limit: usize) -> Result<Vec<u8>, Failure> {
    let file = path.display().to_string();
    let unreadable = |e: std::io::Error| Failure::Unreadable {
        file: file.clone(),
        detail: e.to_string(),
    };
    let most = u64::try_from(limit).unwrap_or(u64::MAX).saturating_add(1);
    let mut bytes = Vec::new();
    let read = if path == Path::new("-") {
        std::io::Read::read_to_end(&mut std::io::Read::take(std::io::stdin().lock(), most), &mut bytes)
    } else {
        let opened = std::fs::File::open(path).map_err(unreadable)?;
        std::io::Read::read_to_end(&mut std::io::Read::take(opened, most), &mut bytes)
    };
    read.map_err(unreadable)?;
    if bytes.len() > limit {
        return Err(Failure::Input {
            file,
            error: Error::PayloadTooLarge { limit },
        });
    }
    Ok(bytes)
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

/// A core that decides under `knowledge` with the service's request limits.
pub fn core_over(knowledge: Knowledge, limits: &Limits) -> Arc<Core> {
    let settings = Settings {
        limits: limits.request,
        ..Settings::default()
    };
    Arc::new(Core::fixed(knowledge, settings))
}

/// `scruple clarify FILE`: one request body, as `POST /v1/clarify` takes it, within the limits.
pub async fn clarify_file(path: &Path, knowledge: Knowledge, limits: &Limits) -> Result<DecisionDto, Failure> {
    let bytes = read_input(path, limits.max_body_bytes)?;
    let input = |error| Failure::Input {
        file: path.display().to_string(),
        error,
    };
    let body = parse_json(&bytes).map_err(input)?;
    decide(body, &core_over(knowledge, limits)).await.map_err(input)
}
