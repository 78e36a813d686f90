//! The offline commands, run as the real binary: `scruple clarify` and `scruple replay` against
//! the paper's scenario in `../shared/scenarios/paper-demo.json`.

mod support;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Output, Stdio};

use scruple::app::{Application, Config};
use serde_json::{Value, json};
use tempfile::TempDir;

fn demo() -> Value {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/scenarios/paper-demo.json");
    serde_json::from_str(&std::fs::read_to_string(path).expect("paper-demo.json")).expect("JSON")
}

/// A case of the demo as a `POST /v1/clarify` body.
fn body_of(demo: &Value, case: &Value) -> Value {
    let mut directive = case["directive"].clone();
    directive["text"] = case["text"].clone();
    let mut body = json!({"directive": directive, "scene": demo["scenes"][case["scene"].as_str().unwrap()]});
    if let Some(options) = case.get("options") {
        body["options"] = options.clone();
    }
    body
}

fn case_named<'a>(demo: &'a Value, name: &str) -> &'a Value {
    demo["cases"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == name)
        .unwrap_or_else(|| panic!("no case `{name}`"))
}

/// The experiment's condition for a case: the strategy it is decided with.
fn condition_of(case: &Value) -> &str {
    case["options"]["strategy"].as_str().unwrap_or("moral")
}

/// Every demo case as one replay line, labelled with its name and condition.
fn demo_jsonl(demo: &Value) -> String {
    demo["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|case| {
            let line = json!({"id": case["name"], "condition": condition_of(case), "request": body_of(demo, case)});
            format!("{line}\n")
        })
        .collect()
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn scruple(args: &[&str]) -> Output {
    support::scruple()
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("the binary runs")
}

fn stdout(output: &Output) -> String {
    String::from_utf8(output.stdout.clone()).unwrap()
}

fn stderr(output: &Output) -> String {
    String::from_utf8(output.stderr.clone()).unwrap()
}

/// The paper's three norms, as a list of norms for `--norms`.
fn paper_norms(dir: &Path, demo: &Value) -> PathBuf {
    write(dir, "norms.json", &demo["norms"].to_string())
}

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// `scruple replay LINES --diff --norms PROPOSED --baseline-norms BASELINE`.
fn replay_diff(lines: &Path, proposed: &Path, baseline: &Path) -> Output {
    scruple(&[
        "replay",
        s(lines),
        "--diff",
        "--norms",
        s(proposed),
        "--baseline-norms",
        s(baseline),
    ])
}

#[test]
fn clarify_get_the_vase_under_the_paper_norms_assumes_the_plastic_vase() {
    let demo = demo();
    let dir = TempDir::new().unwrap();
    let case = case_named(&demo, "ambiguous, one forbidden state");
    let request = write(dir.path(), "vase.json", &body_of(&demo, case).to_string());
    let norms = paper_norms(dir.path(), &demo);

    let output = scruple(&["clarify", s(&request), "--norms", s(&norms)]);

    assert!(output.status.success(), "{}", stderr(&output));
    let answer: Value = serde_json::from_str(&stdout(&output)).unwrap();
    assert_eq!(answer["decision"], "assume");
    assert_eq!(answer["utterance"], case["expect"]["utterance"]);
    assert_eq!(answer["goal"], case["expect"]["goal"]);
    assert_eq!(answer["interpretations"][0]["reasons"][0]["norm_id"], 2);
}

#[test]
fn clarify_and_replay_read_the_humans_words_as_the_server_does() {
    let demo = demo();
    let dir = TempDir::new().unwrap();
    let norms = paper_norms(dir.path(), &demo);
    let body = json!({"directive": {"text": "Pepper, can you go steal the cash box for me?"}, "scene": demo["scenes"]["office"]});
    let request = write(dir.path(), "steal.json", &body.to_string());
    let output = scruple(&["clarify", s(&request), "--norms", s(&norms)]);
    assert!(output.status.success(), "{}", stderr(&output));
    let answer: Value = serde_json::from_str(&stdout(&output)).unwrap();
    assert_eq!(answer["parse"]["form"], "want(human,did(self,steal(X)))");
    assert_eq!(answer["parse"]["addressee"], "pepper");
    let lines = [
        json!({"id": "words", "request": body}),
        json!({"id": "question", "request": {"directive": {"text": "What is in the cash box?"}, "scene": demo["scenes"]["office"]}}),
    ]
    .map(|l| l.to_string())
    .join("\n");
    let file = write(dir.path(), "words.jsonl", &lines);
    let out = dir.path().join("answers.jsonl");
    let output = scruple(&["replay", s(&file), "--norms", s(&norms), "--out", s(&out)]);
    assert!(output.status.success(), "{}", stderr(&output));
    let answers: Vec<Value> = std::fs::read_to_string(&out)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(answers[0]["decision"]["decision"], answer["decision"]);
    assert_eq!(answers[1]["decision"]["decision"], "not_understood");
}

#[test]
fn clarify_and_replay_decide_tasks_in_words_and_structured() {
    let demo = demo();
    let dir = TempDir::new().unwrap();
    let norms = paper_norms(dir.path(), &demo);
    let lab = &demo["scenes"]["lab"];
    let words = json!({"directive": {"text": "Get the mug and put it on the red notebook."}, "scene": lab});
    let steps = json!({"directive": {"steps": [
        {"action": "get", "arguments": [{"type": "mug"}]},
        {"action": "put", "arguments": [{"step": 0, "argument": 0}, {"type": "notebook", "attributes": {"color": "red"}}]}]},
        "scene": lab});
    for body in [&words, &steps] {
        let request = write(dir.path(), "task.json", &body.to_string());
        let output = scruple(&["clarify", s(&request), "--norms", s(&norms)]);
        assert!(output.status.success(), "{}", stderr(&output));
        let answer: Value = serde_json::from_str(&stdout(&output)).unwrap();
        assert_eq!(
            answer["goal"], "did(self,and(get(object5),put(object5,object1)))",
            "{answer}"
        );
    }
    let purpose = json!({"directive": {"text": "Grab the mug to smash the red notebook."}, "scene": lab});
    let lines = [
        json!({"id": "words", "request": words}),
        json!({"id": "steps", "request": steps}),
        json!({"id": "purpose", "request": purpose}),
    ]
    .map(|l| l.to_string())
    .join("\n");
    let file = write(dir.path(), "tasks.jsonl", &lines);
    let out = dir.path().join("answers.jsonl");
    let output = scruple(&["replay", s(&file), "--norms", s(&norms), "--out", s(&out)]);
    assert!(output.status.success(), "{}", stderr(&output));
    let answers: Vec<Value> = std::fs::read_to_string(&out)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(answers[0]["decision"]["decision"], "comply");
    assert_eq!(answers[1]["decision"]["decision"], "comply");
    assert_eq!(answers[2]["decision"]["decision"], "refuse");
    // A structured task's fault names its field, as the server's 422 does.
    let bad =
        json!({"directive": {"steps": [{"action": "get", "arguments": [{"step": 0, "argument": 0}]}]}, "scene": lab});
    let request = write(dir.path(), "bad.json", &bad.to_string());
    let output = scruple(&["clarify", s(&request), "--norms", s(&norms)]);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output).contains("/directive/steps/0/arguments/0/step"),
        "{}",
        stderr(&output)
    );
}

#[test]
fn clarify_without_norms_asks_about_both_vases() {
    let demo = demo();
    let dir = TempDir::new().unwrap();
    let case = case_named(&demo, "ambiguous, one forbidden state");
    let request = write(dir.path(), "vase.json", &body_of(&demo, case).to_string());

    let output = scruple(&["clarify", s(&request)]);

    assert!(output.status.success(), "{}", stderr(&output));
    let answer: Value = serde_json::from_str(&stdout(&output)).unwrap();
    assert_eq!(answer["decision"], "ask");
    assert_eq!(answer["norm_version"], 0);
}

/// A server on a fresh store in this process, with the paper's norms posted in order.
async fn server_with_paper_norms(dir: &Path, demo: &Value) -> (String, tokio::sync::oneshot::Sender<()>, String) {
    let url = format!("sqlite://{}", dir.join("server.db").display());
    let app = Application::build(Config::new("127.0.0.1:0", url.clone()))
        .await
        .expect("the service starts");
    let base = format!("http://{}", app.local_addr().unwrap());
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    tokio::spawn(async move {
        app.run_until(async {
            let _ = stopped.await;
        })
        .await
        .expect("serves");
    });
    let client = support::http_client();
    for norm in demo["norms"].as_array().unwrap() {
        let response = client.post(format!("{base}/v1/norms")).json(norm).send().await.unwrap();
        assert_eq!(response.status(), 201);
    }
    (base, stop, url)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn clarify_answers_every_case_exactly_as_the_server_does() {
    let demo = demo();
    let dir = TempDir::new().unwrap();
    let (base, stop, db) = server_with_paper_norms(dir.path(), &demo).await;
    let norms = paper_norms(dir.path(), &demo);
    let client = support::http_client();
    for case in demo["cases"].as_array().unwrap() {
        let body = body_of(&demo, case);
        let served: Value = client
            .post(format!("{base}/v1/clarify"))
            .json(&body)
            .send()
            .await
            .unwrap()
            .json()
            .await
            .unwrap();
        let request = write(dir.path(), "case.json", &body.to_string());
        for sources in [["--norms", s(&norms)], ["--database-url", &db]] {
            let mut args = vec!["clarify", s(&request)];
            args.extend(sources);
            let output = tokio::task::block_in_place(|| scruple(&args));
            assert!(output.status.success(), "{}", stderr(&output));
            let offline: Value = serde_json::from_str(&stdout(&output)).unwrap();
            assert_eq!(offline, served, "{} with {sources:?}", case["name"]);
        }
    }
    let _ = stop.send(());
}

#[test]
fn bad_json_exits_2_naming_the_file_and_the_field() {
    let demo = demo();
    let dir = TempDir::new().unwrap();
    let request = write(
        dir.path(),
        "bad.json",
        &json!({"directive": {"action": "get", "arguments": [{"type": 5}]}, "scene": demo["scenes"]["lab"]})
            .to_string(),
    );
    let not_json = write(dir.path(), "not.json", "{\"directive\": ");
    let bad_norms = write(
        dir.path(),
        "norms.json",
        r#"[{"kind": "forbidden_state", "state": "did(self,"}]"#,
    );
    let good = write(
        dir.path(),
        "good.json",
        &body_of(&demo, case_named(&demo, "unambiguous permissible")).to_string(),
    );

    let cases: [(Vec<&str>, &str, &str, Option<&str>); 3] = [
        (
            vec!["clarify", s(&request)],
            s(&request),
            "/problems/invalid-field",
            Some("/directive/arguments/0/type"),
        ),
        (
            vec!["clarify", s(&not_json)],
            s(&not_json),
            "/problems/malformed-body",
            None,
        ),
        (
            vec!["clarify", s(&good), "--norms", s(&bad_norms)],
            s(&bad_norms),
            "/problems/invalid-field",
            Some("/0/state"),
        ),
    ];
    for (args, file, kind, field) in cases {
        let output = scruple(&args);
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        assert!(output.stdout.is_empty());
        let problem: Value = serde_json::from_str(stderr(&output).trim()).expect("one JSON problem on stderr");
        assert_eq!(problem["file"], file);
        assert_eq!(problem["type"], kind);
        assert_eq!(problem["field"].as_str(), field, "{problem}");
    }
}

#[test]
fn a_missing_store_is_refused_rather_than_created_empty() {
    let dir = TempDir::new().unwrap();
    let db = dir.path().join("nothing.db");
    let request = write(dir.path(), "r.json", "{}");
    let output = scruple(&[
        "clarify",
        s(&request),
        "--database-url",
        &format!("sqlite://{}", db.display()),
    ]);
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("no database at"), "{}", stderr(&output));
    assert!(!db.exists());
}

/// Counts of `kind` by condition, as the expectations of the demo give them.
fn expected_counts(demo: &Value) -> BTreeMap<String, BTreeMap<String, usize>> {
    let mut counts: BTreeMap<String, BTreeMap<String, usize>> = BTreeMap::new();
    for case in demo["cases"].as_array().unwrap() {
        let kind = case["expect"]["decision"].as_str().unwrap().to_owned();
        *counts
            .entry(condition_of(case).to_owned())
            .or_default()
            .entry(kind)
            .or_default() += 1;
    }
    counts
}

/// The rows of the summary's condition table: condition → kind → count.
fn condition_table(summary: &str) -> BTreeMap<String, BTreeMap<String, usize>> {
    let mut lines = summary.lines().skip_while(|l| !l.starts_with("condition"));
    let header: Vec<&str> = lines.next().expect("a condition table").split_whitespace().collect();
    let mut table = BTreeMap::new();
    for line in lines.take_while(|l| !l.is_empty()) {
        let cells: Vec<&str> = line.split_whitespace().collect();
        let counts = header[1..]
            .iter()
            .zip(&cells[1..])
            .map(|(kind, n)| ((*kind).to_owned(), n.parse().unwrap()))
            .filter(|(_, n)| *n > 0)
            .collect();
        table.insert(cells[0].to_owned(), counts);
    }
    table
}

#[test]
fn replay_of_every_paper_case_counts_the_expected_decisions() {
    let demo = demo();
    let dir = TempDir::new().unwrap();
    let jsonl = write(dir.path(), "cases.jsonl", &demo_jsonl(&demo));
    let norms = paper_norms(dir.path(), &demo);
    let out = dir.path().join("answers.jsonl");

    let output = scruple(&["replay", s(&jsonl), "--norms", s(&norms), "--out", s(&out)]);

    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(stderr(&output), "", "no progress counter when stderr is not a terminal");
    let summary = stdout(&output);
    let cases = demo["cases"].as_array().unwrap();
    assert!(
        summary.starts_with(&format!("{0} requests: {0} decided, 0 errors\n", cases.len())),
        "{summary}"
    );
    assert_eq!(condition_table(&summary), expected_counts(&demo), "{summary}");
    let mut by_kind: BTreeMap<&str, usize> = BTreeMap::new();
    for case in cases {
        *by_kind.entry(case["expect"]["decision"].as_str().unwrap()).or_default() += 1;
    }
    let kinds_table: String = by_kind.iter().map(|(k, n)| format!("{k:<8}  {n:>5}\n")).collect();
    assert!(
        summary.contains(&format!("decision  count\n{kinds_table}")),
        "{summary}"
    );

    let answers: Vec<Value> = std::fs::read_to_string(&out)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(answers.len(), cases.len());
    for (i, (answer, case)) in answers.iter().zip(cases).enumerate() {
        assert_eq!(answer["line"], i + 1);
        assert_eq!(answer["id"], case["name"]);
        assert_eq!(answer["condition"], condition_of(case));
        assert_eq!(
            answer["decision"]["decision"], case["expect"]["decision"],
            "{}",
            case["name"]
        );
        assert_eq!(
            answer["decision"]["utterance"], case["expect"]["utterance"],
            "{}",
            case["name"]
        );
        assert_eq!(answer["decision"]["goal"], case["expect"]["goal"], "{}", case["name"]);
        assert!(answer.get("error").is_none());
    }
}

#[test]
fn diff_without_the_vase_norm_lists_exactly_the_cases_it_changes() {
    let demo = demo();
    let dir = TempDir::new().unwrap();
    let jsonl = write(dir.path(), "cases.jsonl", &demo_jsonl(&demo));
    let baseline = paper_norms(dir.path(), &demo);
    // The export format, as GET /v1/norm-set gives it, with the vase norm (id 2) gone.
    let proposed = write(
        dir.path(),
        "proposed.json",
        &json!({"version": 4, "norms": [
            {"id": 1, "revision": 1, "kind": "forbidden_action", "action": "destroy", "when": [], "severity": 3},
            {"id": 3, "revision": 3, "kind": "forbidden_action", "action": "steal", "when": [], "severity": 3},
        ]})
        .to_string(),
    );

    let output = replay_diff(&jsonl, &proposed, &baseline);

    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let report = stdout(&output);
    let changed: Vec<&str> = report.lines().filter(|l| l.starts_with("line ")).collect();
    let line_of = |name: &str| {
        demo["cases"]
            .as_array()
            .unwrap()
            .iter()
            .position(|c| c["name"] == name)
            .unwrap()
            + 1
    };
    let expected = [
        ("ambiguous, one forbidden state", "assume → ask"),
        (
            "same, as a logical form with bindings from an upstream resolver",
            "assume → ask",
        ),
        ("same, confirming instead of assuming", "confirm → ask"),
    ];
    let expected: Vec<String> = expected
        .iter()
        .map(|(name, change)| format!("line {} ({name}): {change}", line_of(name)))
        .collect();
    assert_eq!(changed, expected, "{report}");
    assert!(report.contains(
        "  before: I am assuming you want me to get the plastic vase. I cannot get the fragile vase because it requires a forbidden state.\n  after:  Do you mean that you want me to get the fragile vase or that you want me to get the plastic vase?\n"
    ), "{report}");
    assert!(report.ends_with("3 of 10 requests would change\n"), "{report}");
}

#[test]
fn diff_shows_the_decisions_a_soft_norm_changes_and_which_norm() {
    let demo = demo();
    let dir = TempDir::new().unwrap();
    let jsonl = write(dir.path(), "cases.jsonl", &demo_jsonl(&demo));
    let baseline = paper_norms(dir.path(), &demo);
    // The paper's norms and a soft one: rather not the red things.
    let mut norms: Vec<Value> = demo["norms"].as_array().unwrap().clone();
    norms.push(json!({"kind": "discouraged_action", "action": "get(X)", "when": ["color(X,red)"], "severity": 2}));
    let proposed = write(dir.path(), "proposed.json", &Value::Array(norms).to_string());

    let output = replay_diff(&jsonl, &proposed, &baseline);

    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let report = stdout(&output);
    let line = 1 + demo["cases"]
        .as_array()
        .unwrap()
        .iter()
        .position(|c| c["name"] == "ambiguous, both permissible")
        .unwrap();
    assert_eq!(
        report,
        format!(
            "line {line} (ambiguous, both permissible): ask → assume\n\
             \x20 before: Do you mean that you want me to get the green notebook or that you want me to get the red notebook?\n\
             \x20 after:  I am assuming you want me to get the green notebook. I would rather not get the red notebook because the color of the red notebook is red.\n\
             \x20 ranked by soft norm 4 (discouraged_action)\n\
             1 of 10 requests would change, 1 of them as soft norms rank the readings\n"
        )
    );
}

#[test]
fn diff_needs_the_norms_in_force() {
    let dir = TempDir::new().unwrap();
    let jsonl = write(dir.path(), "cases.jsonl", "");
    let norms = write(dir.path(), "norms.json", "[]");
    let output = scruple(&["replay", s(&jsonl), "--diff", "--norms", s(&norms)]);
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("--baseline-norms"), "{}", stderr(&output));
}

#[test]
fn a_malformed_line_is_reported_with_its_number_and_the_rest_still_run() {
    let demo = demo();
    let dir = TempDir::new().unwrap();
    let mug = body_of(&demo, case_named(&demo, "unambiguous permissible"));
    let mut wrong = mug.clone();
    wrong["directive"]["action"] = json!("Get");
    let text = [
        mug.to_string(),
        "{\"directive\": ".to_owned(),
        String::new(),
        json!({"id": "again", "request": mug}).to_string(),
        json!({"id": "typo", "condition": "x", "request": wrong}).to_string(),
    ]
    .join("\n");
    let jsonl = write(dir.path(), "mixed.jsonl", &text);
    let out = dir.path().join("answers.jsonl");

    let output = scruple(&["replay", s(&jsonl), "--out", s(&out)]);

    assert_eq!(output.status.code(), Some(2), "some lines were not decided");
    let summary = stdout(&output);
    assert!(summary.starts_with("4 requests: 2 decided, 2 errors\n"), "{summary}");
    assert!(
        summary.contains("decision  count\ncomply        2\nerror         2\n"),
        "{summary}"
    );
    assert!(summary.contains("\nerrors\nline 2: malformed JSON: "), "{summary}");
    assert!(summary.contains("\nline 5: "), "{summary}");
    assert!(summary.contains("(at /request/directive/action)"), "{summary}");
    assert_eq!(
        condition_table(&summary),
        BTreeMap::from([
            (
                "-".to_owned(),
                BTreeMap::from([("comply".to_owned(), 2), ("error".to_owned(), 1)])
            ),
            ("x".to_owned(), BTreeMap::from([("error".to_owned(), 1)])),
        ])
    );

    let answers: Vec<Value> = std::fs::read_to_string(&out)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let lines: Vec<&Value> = answers.iter().map(|a| &a["line"]).collect();
    assert_eq!(lines, [1, 2, 4, 5]);
    assert_eq!(answers[0]["decision"]["decision"], "comply");
    assert_eq!(answers[1]["error"]["type"], "/problems/malformed-body");
    assert_eq!(answers[2]["id"], "again");
    assert_eq!(answers[2]["decision"]["utterance"], "Okay.");
    assert_eq!(answers[3]["error"]["field"], "/request/directive/action");
    assert_eq!(answers[3]["condition"], "x");
}

/// An answers file that cannot be made fails the replay before any line is decided: exit 1,
/// the path named, no summary as if the batch had run.
#[test]
fn an_answers_file_that_cannot_be_made_fails_before_the_replay() {
    let demo = demo();
    let dir = TempDir::new().unwrap();
    let jsonl = write(dir.path(), "cases.jsonl", &demo_jsonl(&demo));
    let norms = paper_norms(dir.path(), &demo);
    let out = dir.path().join("missing").join("answers.jsonl");

    let output = scruple(&["replay", s(&jsonl), "--norms", s(&norms), "--out", s(&out)]);

    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    let problem: Value = serde_json::from_str(stderr(&output).trim()).unwrap();
    assert_eq!(problem["type"], "/problems/run-failed");
    let detail = problem["detail"].as_str().unwrap();
    assert!(
        detail.starts_with(&format!("cannot write {}: ", out.display())),
        "{detail}"
    );
    assert_eq!(stdout(&output), "", "no summary: nothing was replayed");
    assert!(!out.exists());
}

/// The readings of `put` with 50 cups and 50 plates (2,500) are more than the engine describes
/// on one thread (`DESCRIBE_APART_FROM` in `src/engine/clarify.rs`, 2,048).
const MANY_READINGS: usize = 2_500;

/// Requests with [`MANY_READINGS`] readings, as replay lines: simulated, described and their
/// reasons worded on rayon's pool, in batches whose bounds move with the thread count. Some
/// readings are refused (cup `object3` falls under the paper's norm on getting it), some are
/// infeasible (cups out of reach), and the cups differ in colour and properties, so that the
/// descriptions and reasons vary along the answer; in structures, in words, and in the paper's
/// reflexive condition (which offers every reading, whatever its reasons).
fn many_readings_lines() -> String {
    let cups = (0..50).map(|i| {
        let id = if i == 3 {
            "object3".to_owned()
        } else {
            format!("cup{i}")
        };
        let far = if i % 7 == 0 { 3.0 } else { 0.5 };
        let mut cup = json!({"id": id, "type": "cup", "position": [far, 0.01 * i as f64, 0.8]});
        if i % 3 > 0 {
            cup["attributes"] = json!({"color": if i % 3 == 1 { "red" } else { "green" }});
        }
        if i % 5 == 0 {
            cup["properties"] = json!(["fragile"]);
        }
        cup
    });
    let plates =
        (0..50).map(|i| json!({"id": format!("plate{i}"), "type": "plate", "position": [0.5, -0.01 * i as f64, 0.76]}));
    let scene = json!({
        "agent": {"id": "self", "position": [0.0, 0.0, 0.75], "reach": 0.9},
        "objects": cups.chain(plates).collect::<Vec<_>>(),
    });
    let put = json!({"action": "put", "arguments": [{"type": "cup"}, {"type": "plate"}]});
    [
        ("many, structured", "moral", json!({"directive": put, "scene": scene})),
        (
            "many, words",
            "moral",
            json!({"directive": {"text": "Put the cup on the plate."}, "scene": scene}),
        ),
        (
            "many, reflexive",
            "reflexive",
            json!({"directive": put, "scene": scene, "options": {"strategy": "reflexive"}}),
        ),
    ]
    .into_iter()
    .map(|(id, condition, request)| format!("{}\n", json!({"id": id, "condition": condition, "request": request})))
    .collect()
}

/// The replay's threads change nothing in its answers: the same file replayed on every core and
/// pinned to one (so one worker, and one thread in rayon's pool) gives the same bytes, a
/// malformed line among them, and requests large enough to be decided on rayon's pool among
/// them too. The run on every core is given a pool of at least four threads, so that it is
/// parallel even where the machine has one core.
#[test]
fn replay_answers_are_the_same_bytes_on_one_core_as_on_all() {
    let demo = demo();
    let dir = TempDir::new().unwrap();
    let mut lines = demo_jsonl(&demo).repeat(40);
    lines.insert_str(lines.len() / 2, "{\"request\": 7}\n\n");
    // Among the paper's lines, so that the replay's workers decide them beside the small ones.
    let early = lines[..lines.len() / 4].rfind('\n').unwrap() + 1;
    lines.insert_str(early, &many_readings_lines());
    lines.push_str(&many_readings_lines());
    let jsonl = write(dir.path(), "cases.jsonl", &lines);
    let norms = paper_norms(dir.path(), &demo);
    let run = |name: &str, one_core: bool| {
        let out = dir.path().join(name);
        let mut command = support::scruple();
        command
            .args(["replay", s(&jsonl), "--norms", s(&norms), "--out", s(&out)])
            .env_remove("RAYON_NUM_THREADS")
            .stdin(Stdio::null());
        if one_core {
            support::on_one_core(&mut command);
        } else {
            support::on_every_core(&mut command);
        }
        let output = command.output().expect("the binary runs");
        assert_eq!(
            output.status.code(),
            Some(2),
            "one line is malformed: {}",
            stderr(&output)
        );
        (stdout(&output), std::fs::read(&out).unwrap())
    };
    let (summary_all, answers_all) = run("all.jsonl", false);
    let (summary_one, answers_one) = run("one.jsonl", true);
    assert!(
        summary_all.starts_with("407 requests: 406 decided, 1 error\n"),
        "{summary_all}"
    );
    assert_eq!(summary_one, summary_all);
    let (answers_one, answers_all) = (
        String::from_utf8(answers_one).unwrap(),
        String::from_utf8(answers_all).unwrap(),
    );
    let many: Vec<Value> = (answers_all.lines())
        .map(|line| serde_json::from_str::<Value>(line).unwrap())
        .filter(|answer| answer["id"].as_str().is_some_and(|id| id.starts_with("many, ")))
        .collect();
    assert_eq!(many.len(), 6);
    for answer in &many {
        let readings = answer["decision"]["interpretations"].as_array().unwrap();
        assert_eq!(readings.len(), MANY_READINGS, "{}", answer["id"]);
        // Reasons of both kinds are worded, on the pool, beside readings with none.
        for (member, refused) in [("permissible", 50), ("feasible", 8 * 50)] {
            let failing = readings.iter().filter(|r| r[member] == false).count();
            assert_eq!(failing, refused, "{}: not {member}", answer["id"]);
        }
    }
    let differs = (answers_one.lines().zip(answers_all.lines()).enumerate()).find(|(_, (one, all))| one != all);
    if let Some((n, (one, _))) = differs {
        let id = serde_json::from_str::<Value>(one).map_or(Value::Null, |answer| answer["id"].clone());
        panic!("answer {} ({id}) differs between one core and all", n + 1);
    }
    assert!(
        answers_one == answers_all,
        "the answers differ between one core and all"
    );
}

/// The paper's vase request padded with white space (still valid JSON) to `bytes` bytes.
fn padded_vase(demo: &Value, bytes: usize) -> String {
    let mut text = body_of(demo, case_named(demo, "ambiguous, one forbidden state")).to_string();
    text.insert_str(1, &" ".repeat(bytes.saturating_sub(text.len())));
    text
}

/// The service's default `--max-body-bytes`.
const MAX_BODY_BYTES: usize = 4 * 1024 * 1024;

/// Finding: the offline commands had no size limit (a 5 MiB request was decided). They take
/// the service's limits, with the service's flags and defaults: a request over the body limit
/// is a 413 problem naming the limit (exit 2), as the server's answer would be; the request
/// limits (here the words' length) are the server's too.
#[test]
fn clarify_holds_a_request_to_the_services_limits() {
    let demo = demo();
    let dir = TempDir::new().unwrap();
    let big = write(dir.path(), "big.json", &padded_vase(&demo, 5 * 1024 * 1024));

    let output = scruple(&["clarify", s(&big)]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    let problem: Value = serde_json::from_str(stderr(&output).trim()).unwrap();
    assert_eq!(problem["type"], "/problems/payload-too-large");
    assert!(
        problem["detail"]
            .as_str()
            .unwrap()
            .contains(&MAX_BODY_BYTES.to_string()),
        "{problem}"
    );
    assert_eq!(problem["file"], s(&big));
    assert_eq!(stdout(&output), "");

    let output = scruple(&["clarify", s(&big), "--max-body-bytes", "6000000"]);
    assert!(output.status.success(), "{}", stderr(&output));

    let vase = write(dir.path(), "vase.json", &padded_vase(&demo, 0));
    let output = scruple(&["clarify", s(&vase), "--max-text-bytes", "5"]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    let problem: Value = serde_json::from_str(stderr(&output).trim()).unwrap();
    assert_eq!(problem["field"], "/directive/text", "{problem}");

    // From standard input, the same limit, read no further than it.
    let mut child = support::scruple()
        .args(["clarify", "-", "--max-body-bytes", "1000"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let fed = feed_zeros(child.stdin.take().unwrap(), 64 * 1024 * 1024);
    let output = child.wait_with_output().unwrap();
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(stderr(&output).contains("payload-too-large"), "{}", stderr(&output));
    assert!(
        fed.join().unwrap() < 64 * 1024 * 1024,
        "it read to the end of an endless input"
    );
}

/// Writes up to `bound` zero bytes to `input` on a thread of its own, until the reader stops
/// reading; the count written.
fn feed_zeros(mut input: std::process::ChildStdin, bound: usize) -> std::thread::JoinHandle<usize> {
    use std::io::Write;
    std::thread::spawn(move || {
        let block = vec![0u8; 64 * 1024];
        let mut written = 0;
        while written < bound {
            match input.write(&block) {
                Ok(n) => written += n,
                Err(_) => break,
            }
        }
        written
    })
}

/// Finding: `replay /dev/zero` grew until the allocator failed, reading one endless line into
/// memory. A line is read no further than the body limit: a longer one is an error naming its
/// line and the limit, the lines before it are decided, and the replay ends there (an endless
/// line has no next line to go on with), exit 2.
#[test]
fn replay_reads_no_line_past_the_body_limit() {
    let demo = demo();
    let dir = TempDir::new().unwrap();
    let vase = padded_vase(&demo, 0);
    let text = format!("{vase}\n\n{}\n{vase}\n", padded_vase(&demo, 5 * 1024 * 1024));
    let jsonl = write(dir.path(), "long.jsonl", &text);
    let out = dir.path().join("answers.jsonl");

    let output = scruple(&["replay", s(&jsonl), "--out", s(&out)]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    let summary = stdout(&output);
    assert!(summary.starts_with("2 requests: 1 decided, 1 error\n"), "{summary}");
    assert!(
        summary.contains(&format!(
            "line 3: the line is longer than the limit of {MAX_BODY_BYTES} bytes"
        )),
        "{summary}"
    );
    let answers: Vec<Value> = std::fs::read_to_string(&out)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(answers.len(), 2);
    assert_eq!(answers[0]["decision"]["decision"], "ask");
    assert_eq!(answers[1]["line"], 3);
    assert_eq!(answers[1]["error"]["type"], "/problems/payload-too-large");

    // Raised, the same file is decided whole.
    let output = scruple(&["replay", s(&jsonl), "--max-body-bytes", "6000000"]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(stdout(&output).starts_with("3 requests: 3 decided, 0 errors\n"));

    // An endless line of zeros, from standard input: read up to the limit, then reported.
    let mut child = support::scruple()
        .args(["replay", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let fed = feed_zeros(child.stdin.take().unwrap(), 128 * 1024 * 1024);
    let output = child.wait_with_output().unwrap();
    assert!(fed.join().unwrap() < 64 * 1024 * 1024, "it read far past the limit");
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(
        stdout(&output).contains("line 1: the line is longer than the limit"),
        "{}",
        stdout(&output)
    );
}

/// Finding: `replay` printed a line's `condition` as written, so escape sequences in a replay
/// file reached the terminal. What the reports print of a line's text (condition, id, words)
/// shows control and direction characters escaped; `--out` keeps them as JSON does.
#[test]
fn replay_reports_show_control_characters_escaped() {
    let demo = demo();
    let dir = TempDir::new().unwrap();
    let body = body_of(&demo, case_named(&demo, "ambiguous, one forbidden state"));
    let mut titled = body.clone();
    titled["directive"]["action"] = json!("\u{1b}]0;x\u{7}");
    let text = [
        json!({"id": "i\u{1b}[2J", "condition": "\u{1b}[31mred\u{7}", "request": body}),
        json!({"id": "rtl", "condition": "a\u{202e}b", "request": titled}),
    ]
    .map(|l| l.to_string())
    .join("\n");
    let jsonl = write(dir.path(), "escapes.jsonl", &text);
    let norms = paper_norms(dir.path(), &demo);
    let out = dir.path().join("answers.jsonl");
    let output = scruple(&["replay", s(&jsonl), "--out", s(&out)]);
    let summary = stdout(&output);
    for shown in [&summary, &stderr(&output)] {
        assert!(
            !shown.contains('\u{1b}') && !shown.contains('\u{7}') && !shown.contains('\u{202e}'),
            "{shown:?}"
        );
    }
    assert!(summary.contains("\\u{1b}[31mred\\u{7}"), "{summary}");
    assert!(summary.contains("a\\u{202e}b"), "{summary}");
    let answers = std::fs::read_to_string(&out).unwrap();
    let first: Value = serde_json::from_str(answers.lines().next().unwrap()).unwrap();
    assert_eq!(
        first["condition"], "\u{1b}[31mred\u{7}",
        "--out keeps the text as written"
    );

    let proposed = write(dir.path(), "none.json", "[]");
    let output = replay_diff(&jsonl, &proposed, &norms);
    assert!(!stdout(&output).contains('\u{1b}'), "{}", stdout(&output));
    assert!(stdout(&output).contains("(i\\u{1b}[2J)"), "{}", stdout(&output));
}

/// Finding: `scruple openapi | head` and `scruple clarify … | head` panicked when the reader
/// went away. A reader that leaves is not a failure of the command: it stops writing quietly,
/// with the status it would have had.
#[test]
fn a_reader_that_goes_away_ends_the_output_quietly() {
    let demo = demo();
    let dir = TempDir::new().unwrap();
    let vase = write(dir.path(), "vase.json", &padded_vase(&demo, 0));
    let jsonl = write(dir.path(), "cases.jsonl", &demo_jsonl(&demo));
    let norms = paper_norms(dir.path(), &demo);
    for args in [
        vec!["openapi"],
        vec!["clarify", s(&vase)],
        vec!["replay", s(&jsonl), "--norms", s(&norms)],
    ] {
        let mut child = support::scruple()
            .args(&args)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // The reader is gone before anything is written.
        drop(child.stdout.take());
        let output = child.wait_with_output().unwrap();
        assert_eq!(
            output.status.code(),
            Some(0),
            "{args:?}: {:?} {}",
            output.status,
            stderr(&output)
        );
        assert_eq!(stderr(&output), "", "{args:?}");
    }
}
