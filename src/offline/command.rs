//! `scruple replay` as a command: where its norms, conditions and scene come from, the run with
//! a counter for a person watching, and where its answers, summary and report go.
//!
//! Must not: decide (the replay's workers do, through the core) or read a file past the body
//! limit.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};

use super::{
    Answer, Comparison, Failure, Limits, Lines, Setup, Sources, Summary, conditions, diff, diff_report, emit, jsonl,
    replay, report_html, scene_file,
};

/// What `scruple replay` was asked, its flags read.
pub struct ReplayCommand {
    /// The lines; `-` is standard input.
    pub file: PathBuf,
    pub norms: Option<PathBuf>,
    pub database_url: Option<String>,
    pub out: Option<PathBuf>,
    pub diff: bool,
    pub baseline_norms: Option<PathBuf>,
    pub conditions: Option<String>,
    pub conditions_file: Option<PathBuf>,
    pub scene: Option<PathBuf>,
    pub report: Option<PathBuf>,
    pub limits: Limits,
}

/// What a replay made: its summary (of the answers under the first knowledge), and its answers
/// under each knowledge when asked to keep them (for `--diff`: the proposed norms', then the
/// baseline's).
struct Replayed {
    summary: Summary,
    answers: Vec<Vec<Answer>>,
    /// With conditions: how their decisions compare.
    comparison: Comparison,
}

/// Runs a replay under each of the setup's knowledge (or conditions) in one pass over the input,
/// with a counter on stderr when a person is watching. Each answer under the first knowledge
/// (under conditions, each line's answer under each condition in turn) is written to `out` (a
/// file, by its path) as a JSON line, in line order, while later lines are still being decided;
/// the answers are kept only when `keep`. Fails with the first error reading the input or writing `out`
/// (the replay still runs to its end, so the failure comes with nothing half-decided).
fn replay_with_progress(
    lines: &mut Lines,
    file: &Path,
    setup: &Setup,
    limits: &Limits,
    mut out: Option<(&Path, &mut dyn Write)>,
    keep: bool,
) -> Result<Replayed, Failure> {
    let watching = std::io::stderr().is_terminal();
    // The count is not known before the end: every hundredth line, as a terminal is slow to
    // redraw.
    let progress = |done: usize| {
        if watching && done.is_multiple_of(100) {
            let _ = write!(std::io::stderr(), "\rreplayed: {done}");
        }
    };
    let writing = out.is_some();
    let compared = !setup.conditions.is_empty();
    // On the worker that decided them: the lines' counts, their JSON and (when kept) themselves;
    // under conditions, every condition's answers (line by line, each condition in turn) and
    // how they compare.
    let each = |answers: Vec<Vec<Answer>>| {
        let (summary, text, comparison) = if compared {
            let lines = answers.first().map_or(0, Vec::len);
            let interleaved: Vec<Answer> = (0..lines)
                .flat_map(|l| answers.iter().map(move |arm| arm[l].clone()))
                .collect();
            let text = writing.then(|| jsonl(&interleaved));
            (Summary::of(&interleaved), text, Comparison::of(&answers))
        } else {
            let first = answers.first().map_or(&[][..], Vec::as_slice);
            let text = writing.then(|| jsonl(first));
            (Summary::of(first), text, Comparison::default())
        };
        (summary, text, if keep { answers } else { Vec::new() }, comparison)
    };
    let arms = if compared {
        setup.conditions.len()
    } else {
        setup.knowledge.len()
    };
    let mut replayed = Replayed {
        summary: Summary::default(),
        answers: (0..arms).map(|_| Vec::new()).collect(),
        comparison: Comparison::default(),
    };
    let mut failed = None;
    type Made = (Summary, Option<String>, Vec<Vec<Answer>>, Comparison);
    let mut then = |(summary, text, answers, comparison): Made| {
        replayed.summary.merge(summary);
        replayed.comparison.merge(comparison);
        for (kept, more) in replayed.answers.iter_mut().zip(answers) {
            kept.extend(more);
        }
        if let (Some((_, out)), Some(text), None) = (out.as_mut(), text, &failed) {
            failed = out.write_all(text.as_bytes()).err();
        }
    };
    // The replay's threads decide through this runtime; this one only waits for them.
    let runtime = tokio::runtime::Handle::current();
    let read = tokio::task::block_in_place(|| replay(lines, setup, limits, &runtime, &progress, &each, &mut then));
    if watching {
        let _ = writeln!(std::io::stderr(), "\rreplayed: {}", replayed.summary.total);
    }
    read.map_err(|e| Failure::Unreadable {
        file: file.display().to_string(),
        detail: e.to_string(),
    })?;
    if let Some((path, out)) = out {
        failed
            .map_or_else(|| out.flush(), Err)
            .map_err(|e| cannot_write(path, e))?;
    }
    Ok(replayed)
}

fn cannot_write(path: &Path, e: std::io::Error) -> Failure {
    Failure::Run {
        detail: format!("cannot write {}: {e}", path.display()),
    }
}

/// `scruple replay`: returns whether every line was decided.
pub async fn replay_command(args: ReplayCommand) -> Result<bool, Failure> {
    let limits = args.limits;
    let sources = Sources::open(args.database_url.as_deref()).await?;
    if args.diff && args.baseline_norms.is_none() && !sources.has_store() {
        return Err(Failure::Usage {
            detail: "--diff compares with the norms in force: give --baseline-norms FILE or --database-url URL"
                .to_owned(),
        });
    }
    let norms_file = |diffed: bool| match diffed {
        false => args.norms.as_deref(),
        true => args.baseline_norms.as_deref(),
    };
    // The proposed norms, then for `--diff` the baseline: one pass decides each line under
    // both, so the input is read once (standard input cannot be read twice).
    let mut knowledge = Vec::new();
    for diffed in [false, true].into_iter().take(1 + usize::from(args.diff)) {
        knowledge.push(sources.knowledge(norms_file(diffed), limits.max_body_bytes).await?);
    }
    let conditions = conditions(args.conditions.as_deref(), args.conditions_file.as_deref(), &limits)?;
    if args.report.is_some() && conditions.is_empty() {
        return Err(Failure::Usage {
            detail: "--report compares conditions: give --conditions or --conditions-file".to_owned(),
        });
    }
    let scene = match &args.scene {
        Some(path) => Some(scene_file(path, limits.max_body_bytes)?),
        None => None,
    };
    let setup = Setup {
        knowledge,
        conditions,
        scene,
    };
    let mut lines = Lines::open(&args.file, limits.max_body_bytes)?;
    // Made before the replay, so a path that cannot be written fails before the work.
    let mut out = match &args.out {
        Some(path) => Some((
            path.as_path(),
            std::io::BufWriter::new(std::fs::File::create(path).map_err(|e| cannot_write(path, e))?),
        )),
        None => None,
    };
    let out = out.as_mut().map(|(path, file)| (*path, file as &mut dyn Write));
    // Made before the replay too; written once it is done.
    let report = match &args.report {
        Some(path) => Some((
            path.as_path(),
            std::fs::File::create(path).map_err(|e| cannot_write(path, e))?,
        )),
        None => None,
    };
    let Replayed {
        summary,
        answers,
        comparison,
    } = replay_with_progress(&mut lines, &args.file, &setup, &limits, out, args.diff)?;
    if !setup.conditions.is_empty() {
        let names: Vec<String> = setup.conditions.iter().map(|c| c.name.clone()).collect();
        if let Some((path, mut file)) = report {
            let page = report_html(&args.file.display().to_string(), &names, &summary, &comparison);
            file.write_all(page.as_bytes())
                .and_then(|()| file.flush())
                .map_err(|e| cannot_write(path, e))?;
        }
        let text = comparison.report(&names, &summary);
        // The experiment's summary goes to stderr: standard output stays for the answers alone.
        let _ = std::io::stderr().write_all(text.as_bytes());
    } else if let [after, before] = answers.as_slice() {
        let changes = diff(before, after);
        let mut report = diff_report(&changes, summary.total);
        if !summary.errors.is_empty() {
            report.push('\n');
            report.push_str(&summary.errors_report());
        }
        emit(&report)?;
    } else {
        emit(&summary.to_string())?;
    }
    Ok(summary.errors.is_empty())
}
