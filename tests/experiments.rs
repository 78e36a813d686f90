//! `scruple replay` as an experiment: every line under each condition (`--conditions`,
//! `--conditions-file`), a scene for lines that name none (`--scene`), the summary on stderr and
//! the HTML report, checked against the `--out` answers they summarise.

#[allow(dead_code)] // the reqwest helpers of the launcher are not needed here
mod support;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use serde_json::{Value, json};
use tempfile::TempDir;

fn demo() -> Value {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/scenarios/paper-demo.json");
    serde_json::from_str(&std::fs::read_to_string(path).expect("paper-demo.json")).expect("JSON")
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

fn run(command: &mut Command) -> Output {
    command.stdin(Stdio::null()).output().expect("the binary runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8(bytes.to_vec()).unwrap()
}

/// The paper's cases as replay lines with ids and no condition of their own; `scene: false`
/// leaves the lab's scene out of the lab's lines (for `--scene`).
fn paper_lines(demo: &Value, scene: bool) -> String {
    let mut lines = String::new();
    for case in demo["cases"].as_array().unwrap() {
        let mut directive = case["directive"].clone();
        directive["text"] = case["text"].clone();
        let mut body = json!({"directive": directive});
        let named = case["scene"].as_str().unwrap();
        if scene || named != "lab" {
            body["scene"] = demo["scenes"][named].clone();
        }
        if let Some(options) = case.get("options") {
            body["options"] = options.clone();
        }
        lines.push_str(&format!("{}\n", json!({"id": case["name"], "request": body})));
    }
    lines
}

/// The `--out` answers: (line, condition, decision kind) in file order.
fn answers(out: &Path) -> Vec<(u64, String, String)> {
    let text = std::fs::read_to_string(out).unwrap();
    text.lines()
        .map(|line| {
            let answer: Value = serde_json::from_str(line).unwrap();
            let kind = answer["decision"]["decision"].as_str().unwrap_or("error").to_owned();
            let condition = answer["condition"].as_str().unwrap().to_owned();
            (answer["line"].as_u64().unwrap(), condition, kind)
        })
        .collect()
}

/// Counts by condition, then kind.
fn counts(answers: &[(u64, String, String)]) -> BTreeMap<String, BTreeMap<String, usize>> {
    let mut counts: BTreeMap<String, BTreeMap<String, usize>> = BTreeMap::new();
    for (_, condition, kind) in answers {
        *counts
            .entry(condition.clone())
            .or_default()
            .entry(kind.clone())
            .or_default() += 1;
    }
    counts
}

/// The lines whose kinds are not the same under every condition.
fn differing(answers: &[(u64, String, String)]) -> BTreeSet<u64> {
    let mut by_line: BTreeMap<u64, BTreeSet<&str>> = BTreeMap::new();
    for (line, _, kind) in answers {
        by_line.entry(*line).or_default().insert(kind);
    }
    by_line
        .into_iter()
        .filter(|(_, kinds)| kinds.len() > 1)
        .map(|(line, _)| line)
        .collect()
}

fn experiment(dir: &Path, lines: &Path, extra: &[&str]) -> (Output, PathBuf, PathBuf) {
    let norms = write(dir, "norms.json", &demo()["norms"].to_string());
    let (out, report) = (dir.join("answers.jsonl"), dir.join("report.html"));
    let mut command = support::scruple();
    command.args([
        "replay",
        s(lines),
        "--norms",
        s(&norms),
        "--out",
        s(&out),
        "--report",
        s(&report),
    ]);
    command.args(extra);
    (run(&mut command), out, report)
}

#[test]
fn every_line_is_decided_under_each_condition_and_the_summary_and_report_count_the_answers() {
    let dir = TempDir::new().unwrap();
    let demo = demo();
    let lines = write(dir.path(), "cases.jsonl", &paper_lines(&demo, true));
    let (output, out, report) = experiment(dir.path(), &lines, &["--conditions", "moral,reflexive"]);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    assert!(
        output.stdout.is_empty(),
        "the summary goes to stderr: {}",
        text(&output.stdout)
    );

    let answers = answers(&out);
    let cases = demo["cases"].as_array().unwrap().len();
    assert_eq!(answers.len(), 2 * cases, "each line once under each condition");
    for (i, (line, condition, _)) in answers.iter().enumerate() {
        assert_eq!(*line, (i / 2 + 1) as u64, "line by line");
        assert_eq!(condition, ["moral", "reflexive"][i % 2], "each condition in turn");
    }
    // The paper's experiment: the reflexive strategy asks where the moral one explains or assumes.
    let counts = counts(&answers);
    assert_eq!(counts["reflexive"]["ask"], 8, "{counts:?}");
    assert_eq!(counts["moral"].get("explain"), Some(&4), "{counts:?}");
    let differ = differing(&answers);

    let summary = text(&output.stderr);
    assert!(
        summary.starts_with(&format!(
            "{cases} lines under 2 conditions (moral, reflexive): {} answers, {} decided, 0 errors\n",
            2 * cases,
            2 * cases
        )),
        "{summary}"
    );
    let agreed = cases - differ.len();
    assert!(
        summary.contains(&format!("moral = reflexive: {agreed} of {cases} lines")),
        "{summary}"
    );
    assert!(
        summary.contains(&format!("lines that differ: {}\n", differ.len())),
        "{summary}"
    );
    for line in &differ {
        assert!(
            summary.contains(&format!("\nline {line} (")),
            "line {line} listed: {summary}"
        );
    }
    // The condition table's rows, as the --out answers count them.
    for (condition, kinds) in &counts {
        let row = summary
            .lines()
            .find(|l| l.starts_with(&format!("{condition} ")))
            .unwrap_or_else(|| panic!("no row for {condition}: {summary}"));
        let total: usize = row
            .split_whitespace()
            .skip(1)
            .map(|n| n.parse::<usize>().unwrap())
            .sum();
        assert_eq!(total, kinds.values().sum::<usize>(), "{row}");
    }

    // The report parses as XML, and its numbers are the answers'.
    let page = std::fs::read_to_string(&report).unwrap();
    let options = roxmltree::ParsingOptions {
        allow_dtd: true,
        ..roxmltree::ParsingOptions::default()
    };
    let document = roxmltree::Document::parse_with_options(&page, options).expect("the report is well-formed");
    let mut bars = BTreeMap::new();
    let mut cells = BTreeMap::new();
    for node in document.descendants() {
        let (Some(condition), Some(kind)) = (node.attribute("data-condition"), node.attribute("data-decision")) else {
            continue;
        };
        let key = (condition.to_owned(), kind.to_owned());
        match node.tag_name().name() {
            "rect" => bars.insert(key, node.attribute("data-count").unwrap().parse::<usize>().unwrap()),
            "td" => cells.insert(key, node.text().unwrap().parse::<usize>().unwrap()),
            other => panic!("unexpected <{other}> with data-condition"),
        };
    }
    let expected: BTreeMap<(String, String), usize> = ["moral", "reflexive"]
        .iter()
        .flat_map(|c| {
            let kinds: BTreeSet<&String> = counts.values().flat_map(BTreeMap::keys).collect();
            let counts = &counts;
            kinds
                .into_iter()
                .map(move |k| (((*c).to_owned(), k.clone()), counts[*c].get(k).copied().unwrap_or(0)))
        })
        .collect();
    assert_eq!(bars, expected, "the chart's bars");
    assert_eq!(cells, expected, "the table's counts");
    let rows: BTreeSet<u64> = document
        .descendants()
        .filter_map(|n| n.attribute("data-line"))
        .map(|l| l.parse().unwrap())
        .collect();
    assert_eq!(rows, differ, "the lines whose decisions differ");
    let totals = document
        .descendants()
        .find(|n| n.attribute("id") == Some("totals"))
        .unwrap();
    assert_eq!(totals.attribute("data-answers"), Some(&*(2 * cases).to_string()));
    assert!(!page.contains("<script") && !page.contains("src="), "self-contained");
}

#[test]
fn a_conditions_file_sets_any_options_and_its_mistakes_are_named() {
    let dir = TempDir::new().unwrap();
    let demo = demo();
    let lines = write(dir.path(), "cases.jsonl", &paper_lines(&demo, true));
    let conditions = write(
        dir.path(),
        "conditions.json",
        r#"{"terse": {"strategy": "moral", "style": "natural", "max_spoken": 2}, "moral": {"strategy": "moral"}}"#,
    );
    let (output, out, _) = experiment(dir.path(), &lines, &["--conditions-file", s(&conditions)]);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    let answers = answers(&out);
    assert_eq!(answers[0].1, "terse", "the file's order");
    assert_eq!(answers[1].1, "moral");
    // The natural style words the notebook explanation differently: the same decisions, other words.
    let all: Vec<Value> = std::fs::read_to_string(&out)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let notebooks = &all[6..8];
    assert_eq!(
        notebooks[0]["decision"]["decision"],
        notebooks[1]["decision"]["decision"]
    );
    assert_ne!(
        notebooks[0]["decision"]["utterance"],
        notebooks[1]["decision"]["utterance"]
    );

    let refused = |extra: &[&str], why: &str| {
        let (output, _, _) = experiment(dir.path(), &lines, extra);
        let stderr = text(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{extra:?}: {stderr}");
        assert!(stderr.contains(why), "{extra:?}: {stderr}");
    };
    refused(&["--conditions", "moral,cautious"], "no condition `cautious`");
    refused(&["--conditions", "moral,moral"], "twice");
    let bad = write(dir.path(), "bad.json", r#"{"terse": {"style": "curt"}}"#);
    refused(&["--conditions-file", s(&bad)], r#""field":"/terse/style""#);
    let range = write(dir.path(), "range.json", r#"{"a/b": {"max_spoken": 1}}"#);
    refused(&["--conditions-file", s(&range)], r#""field":"/a~1b/max_spoken""#);
    let empty = write(dir.path(), "empty.json", "{}");
    refused(&["--conditions-file", s(&empty)], "defines no condition");
    refused(&[], "--report compares conditions");
    let mut diff = support::scruple();
    diff.args([
        "replay",
        s(&lines),
        "--norms",
        s(&conditions),
        "--diff",
        "--conditions",
        "moral",
    ]);
    assert_eq!(
        run(&mut diff).status.code(),
        Some(2),
        "--diff and --conditions do not mix"
    );

    // A line that names its own condition is an error under --conditions, naming the member.
    let own = write(
        dir.path(),
        "own.jsonl",
        &paper_lines(&demo, true).replacen("{\"id\"", "{\"condition\":\"moral\",\"id\"", 1),
    );
    let (output, out, _) = experiment(dir.path(), &own, &["--conditions", "moral,reflexive"]);
    assert_eq!(output.status.code(), Some(2), "{}", text(&output.stderr));
    let first: Value = serde_json::from_str(std::fs::read_to_string(&out).unwrap().lines().next().unwrap()).unwrap();
    assert_eq!(first["error"]["field"], "/condition", "{first}");
    assert_eq!(answers_of(&out).len(), 2 * demo["cases"].as_array().unwrap().len());
}

fn answers_of(out: &Path) -> Vec<String> {
    std::fs::read_to_string(out)
        .unwrap()
        .lines()
        .map(str::to_owned)
        .collect()
}

#[test]
fn a_scene_file_serves_the_lines_that_name_none_and_no_other() {
    let dir = TempDir::new().unwrap();
    let demo = demo();
    let whole = write(dir.path(), "whole.jsonl", &paper_lines(&demo, true));
    let partial = write(dir.path(), "partial.jsonl", &paper_lines(&demo, false));
    let lab = write(dir.path(), "lab.json", &demo["scenes"]["lab"].to_string());
    let conditions = ["--conditions", "moral,reflexive"];
    let (_, whole_out, _) = experiment(dir.path(), &whole, &conditions);
    let whole_answers = std::fs::read(&whole_out).unwrap();
    let (output, partial_out, _) = experiment(dir.path(), &partial, &[&conditions[..], &["--scene", s(&lab)]].concat());
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    assert_eq!(
        std::fs::read(&partial_out).unwrap(),
        whole_answers,
        "the lab's lines take the scene file; the office's keep their own"
    );

    // Without it, those lines lack a scene; a scene file that is not one is named.
    let (output, out, _) = experiment(dir.path(), &partial, &conditions);
    assert_eq!(output.status.code(), Some(2));
    assert!(std::fs::read_to_string(&out).unwrap().contains("missing field `scene`"));
    let bad = write(
        dir.path(),
        "bad.json",
        r#"{"agent": {"id": "self", "position": [0, 0], "reach": 1}, "objects": []}"#,
    );
    let (output, _, _) = experiment(dir.path(), &partial, &[&conditions[..], &["--scene", s(&bad)]].concat());
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("bad.json") && stderr.contains("/agent/position"),
        "{stderr}"
    );
}

/// The experiment's answers, summary and report are the same bytes pinned to one core as on
/// every core (a pool of at least four threads).
#[test]
fn an_experiment_is_the_same_bytes_on_one_core_as_on_all() {
    let dir = TempDir::new().unwrap();
    let demo = demo();
    let lines = write(dir.path(), "cases.jsonl", &paper_lines(&demo, true).repeat(30));
    let norms = write(dir.path(), "norms.json", &demo["norms"].to_string());
    let experiment = |name: &str, one_core: bool| {
        let (out, report) = (
            dir.path().join(format!("{name}.jsonl")),
            dir.path().join(format!("{name}.html")),
        );
        let mut command = support::scruple();
        command
            .args([
                "replay",
                s(&lines),
                "--norms",
                s(&norms),
                "--conditions",
                "reflexive,moral",
            ])
            .args(["--out", s(&out), "--report", s(&report)])
            .env_remove("RAYON_NUM_THREADS");
        if one_core {
            support::on_one_core(&mut command);
        } else {
            support::on_every_core(&mut command);
        }
        let output = run(&mut command);
        assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
        (
            output.stderr,
            std::fs::read(&out).unwrap(),
            std::fs::read(&report).unwrap(),
        )
    };
    let all = experiment("all", false);
    let one = experiment("one", true);
    assert!(text(&all.0).starts_with("300 lines under 2 conditions (reflexive, moral): 600 answers"));
    assert!(all == one, "the same summary, answers and report on one core as on all");
}
