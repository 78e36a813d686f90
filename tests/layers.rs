//! The layers of `src/`, checked from the source: what each top-level module may name of the
//! crate (`crate::...` paths), that no two modules import each other round a cycle, and that the
//! error table has no catch-all arm. DESIGN.md lists the layers, inward to outward; a module may
//! use only those inward of it.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn src() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// Every `.rs` file under `dir`, with its path relative to `src/`.
fn files(dir: &Path, out: &mut Vec<(String, String)>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let relative = path.strip_prefix(src()).unwrap().to_string_lossy().into_owned();
            out.push((relative, std::fs::read_to_string(&path).unwrap()));
        }
    }
}

/// The top-level module a file belongs to: `engine/clarify.rs` → `engine`, `core.rs` → `core`.
fn module_of(relative: &str) -> String {
    let first = relative.split('/').next().unwrap();
    first.trim_end_matches(".rs").to_owned()
}

/// The code of a file without its comments, so that a path in a doc comment is not an import.
fn code(text: &str) -> String {
    text.lines()
        .map(|l| match l.find("//") {
            Some(i) => &l[..i],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The top-level modules a file names as `crate::module`, including `use crate::{a, b}` lists.
fn named(text: &str) -> BTreeSet<String> {
    let code = code(text);
    let mut out = BTreeSet::new();
    let mut rest = code.as_str();
    while let Some(i) = rest.find("crate::") {
        rest = &rest[i + "crate::".len()..];
        if let Some(list) = rest.strip_prefix('{') {
            let end = list.find('}').unwrap_or(list.len());
            for item in list[..end].split(',') {
                let name: String = item
                    .trim()
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if !name.is_empty() {
                    out.insert(name);
                }
            }
        } else {
            let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
            out.insert(name);
        }
    }
    out
}

/// Module → the other top-level modules it names.
fn graph() -> BTreeMap<String, BTreeSet<String>> {
    let mut all = Vec::new();
    files(&src(), &mut all);
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (relative, text) in &all {
        let module = module_of(relative);
        let names: Vec<String> = named(text).into_iter().filter(|n| n != &module).collect();
        graph.entry(module).or_default().extend(names);
    }
    graph
}

#[test]
fn the_engine_names_nothing_of_the_crate_outside_itself_nor_a_web_db_async_or_schema_crate() {
    let mut all = Vec::new();
    files(&src().join("engine"), &mut all);
    assert!(all.len() > 5, "the engine's files were found");
    for (relative, text) in &all {
        let outside: Vec<String> = named(text).into_iter().filter(|n| n != "engine").collect();
        assert!(outside.is_empty(), "src/{relative} names crate::{outside:?}");
        let code = code(text);
        for forbidden in [
            "axum::", "tonic::", "prost::", "hyper::", "sqlx::", "tokio::", "utoipa::",
        ] {
            assert!(!code.contains(forbidden), "src/{relative} names {forbidden}");
        }
    }
}

#[test]
fn core_storage_error_and_metrics_name_no_wire_transport_app_or_offline() {
    let graph = graph();
    let outer = ["wire", "transport", "app", "offline", "main"];
    for module in ["engine", "core", "storage", "error", "metrics"] {
        let names = graph.get(module).cloned().unwrap_or_default();
        let wrong: Vec<&String> = names.iter().filter(|n| outer.contains(&n.as_str())).collect();
        assert!(wrong.is_empty(), "{module} names {wrong:?}");
    }
    let error = graph.get("error").cloned().unwrap_or_default();
    assert!(!error.contains("storage"), "error names the store");
}

#[test]
fn no_import_cycle_among_the_top_level_modules() {
    let graph = graph();
    // Depth-first search for a path from a module back to itself.
    fn reach(
        graph: &BTreeMap<String, BTreeSet<String>>,
        from: &str,
        target: &str,
        seen: &mut BTreeSet<String>,
        path: &mut Vec<String>,
    ) -> bool {
        for next in graph.get(from).into_iter().flatten() {
            if next == target {
                path.push(next.clone());
                return true;
            }
            if seen.insert(next.clone()) {
                path.push(next.clone());
                if reach(graph, next, target, seen, path) {
                    return true;
                }
                path.pop();
            }
        }
        false
    }
    for module in graph.keys() {
        let mut path = vec![module.clone()];
        let cycle = reach(&graph, module, module, &mut BTreeSet::new(), &mut path);
        assert!(!cycle, "an import cycle: {}", path.join(" → "));
    }
}

#[test]
fn the_error_table_has_no_catch_all_arm() {
    let text = std::fs::read_to_string(src().join("error.rs")).unwrap();
    let code = code(&text);
    let row = code.find("pub fn row(").expect("Error::row is the table");
    let body = &code[row..code[row..].find("\n    }\n").map_or(code.len(), |e| row + e)];
    for line in body.lines() {
        let arm = line.trim_start();
        let Some((pattern, _)) = arm.split_once("=>") else {
            continue;
        };
        let pattern = pattern.trim();
        let bare = !pattern.is_empty() && pattern.chars().all(|c| c.is_ascii_lowercase() || c == '_');
        assert!(!bare, "a catch-all arm in Error::row: {arm}");
    }
}

#[test]
fn no_file_under_src_is_over_700_lines() {
    let mut all = Vec::new();
    files(&src(), &mut all);
    let long: Vec<String> = all
        .iter()
        .filter(|(_, text)| text.lines().count() > 700)
        .map(|(relative, text)| format!("src/{relative}: {} lines", text.lines().count()))
        .collect();
    assert!(long.is_empty(), "files over 700 lines: {long:?}");
}

/// The engine's functions that decide or simulate: only core calls them.
const DECIDING: [&str; 4] = ["clarify", "check", "algorithm", "simulate"];

#[test]
fn the_offline_commands_decide_through_core_and_call_no_engine_decision_function() {
    let mut all = Vec::new();
    files(&src().join("offline"), &mut all);
    assert!(!all.is_empty(), "the offline commands were found");
    let mut through_core = false;
    for (relative, text) in &all {
        let code = code(text);
        // Every path into the engine, `use` lists included: none may reach a deciding function.
        let mut rest = code.as_str();
        while let Some(i) = rest.find("engine::") {
            rest = &rest[i + "engine::".len()..];
            let path: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || "_:{}, ".contains(*c))
                .collect();
            for name in DECIDING {
                let named = path
                    .split(|c: char| !(c.is_alphanumeric() || c == '_'))
                    .any(|word| word == name);
                assert!(!named, "src/{relative} reaches the engine's `{name}`: engine::{path}");
            }
        }
        through_core |= code.contains("Core::fixed") && code.contains(".clarify(");
    }
    assert!(
        through_core,
        "the offline commands decide with Core::fixed(..).clarify(..)"
    );
}

#[test]
fn the_transports_call_core_for_decisions_not_the_engine() {
    let mut all = Vec::new();
    files(&src().join("transport"), &mut all);
    for (relative, text) in &all {
        let code = code(text);
        for name in DECIDING {
            for call in [format!("engine::{name}::"), format!("engine::{name}(")] {
                assert!(!code.contains(&call), "src/{relative} calls the engine's {name} itself");
            }
        }
    }
}
