//! The `scruple` binary as an operator runs it: flags, environment, the `listening on` line,
//! and a clean exit on SIGTERM.

use std::process::Stdio;

use reqwest::StatusCode;
use serde_json::json;

use crate::helpers::serve_binary;

#[tokio::test]
async fn serve_prints_its_address_enforces_the_env_token_and_exits_0_on_sigterm() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("bin.db");
    let served = serve_binary(
        &format!("sqlite://{}", db.display()),
        &[],
        &[("SCRUPLE_ADMIN_TOKEN", "from-env"), ("RUST_LOG", "warn")],
        Stdio::null(),
    );
    let addr = served.addr.clone();
    assert!(addr.starts_with("127.0.0.1:") && !addr.ends_with(":0"), "{addr}");

    let client = crate::helpers::http_client();
    let health = client.get(format!("http://{addr}/healthz")).send().await.unwrap();
    assert_eq!(health.status(), StatusCode::OK);
    let norm = json!({"kind": "forbidden_action", "action": "destroy"});
    let denied = client
        .post(format!("http://{addr}/v1/norms"))
        .json(&norm)
        .send()
        .await
        .unwrap();
    assert_eq!(denied.status(), StatusCode::UNAUTHORIZED);
    let created = client
        .post(format!("http://{addr}/v1/norms"))
        .bearer_auth("from-env")
        .json(&norm)
        .send()
        .await
        .unwrap();
    assert_eq!(created.status(), StatusCode::CREATED);
    assert!(db.exists(), "the SQLite file is created");

    let status = tokio::task::spawn_blocking(move || served.terminate()).await.unwrap();
    assert_eq!(status.code(), Some(0), "SIGTERM drains and exits 0");
}

/// The server keeps its heap in 4 KiB pages (main.rs, `no_huge_pages`), so that what a burst
/// of heavy requests frees goes back to the OS: the kernel reports transparent huge pages off
/// for the serving process, whatever the system's setting.
#[cfg(target_os = "linux")]
#[test]
fn the_server_runs_without_transparent_huge_pages() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("pages.db");
    let served = serve_binary(&format!("sqlite://{}", db.display()), &[], &[], Stdio::null());
    let status = std::fs::read_to_string(format!("/proc/{}/status", served.child.id()));
    served.terminate();
    let status = status.expect("the server's /proc status is readable");
    let thp = status.lines().find_map(|line| line.strip_prefix("THP_enabled:"));
    assert_eq!(
        thp.map(str::trim),
        Some("0"),
        "THP_enabled in /proc/PID/status:\n{status}"
    );
}

/// Marks the child run of the test below, whose environment carries a developer's settings.
const HOSTILE: &str = "SCRUPLE_TEST_HOSTILE_ENVIRONMENT";

/// A developer's shell may hold `SCRUPLE_*` settings; none of them reaches a process a test
/// starts. Run in a child process whose environment holds settings that would each change what
/// a served binary does (a write token, another database, a body limit too small for any norm,
/// an unusable address): the launcher removes every one of them, and the binary
/// [`serve_binary`] starts serves its own database, open to writes of any size.
#[test]
fn launchers_pass_none_of_the_callers_scruple_variables() {
    if std::env::var_os(HOSTILE).is_none() {
        crate::helpers::pass_alone_in_a_child(
            "binary::launchers_pass_none_of_the_callers_scruple_variables",
            &[
                (HOSTILE, "1"),
                ("SCRUPLE_ADMIN_TOKEN", "a-developers-token-from-the-shell"),
                ("SCRUPLE_DATABASE_URL", "postgres://nobody@127.0.0.1:1/nowhere"),
                ("SCRUPLE_MAX_BODY_BYTES", "16"),
                ("SCRUPLE_LISTEN", "127.0.0.1:1"),
            ],
        );
        return;
    }
    let inherited: Vec<std::ffi::OsString> = std::env::vars_os()
        .map(|(name, _)| name)
        .filter(|name| crate::support::is_scruple_variable(name))
        .collect();
    assert!(
        inherited.len() >= 5,
        "the hostile settings are in this process: {inherited:?}"
    );
    for command in [crate::support::scruple(), crate::support::command("sh")] {
        let removed: Vec<&std::ffi::OsStr> = command
            .get_envs()
            .filter(|(_, value)| value.is_none())
            .map(|(name, _)| name)
            .collect();
        for name in &inherited {
            assert!(removed.contains(&name.as_os_str()), "{name:?} is passed to {command:?}");
        }
    }

    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("own.db");
    let served = serve_binary(&format!("sqlite://{}", db.display()), &[], &[], Stdio::null());
    let runtime = tokio::runtime::Runtime::new().unwrap();
    let created = runtime.block_on(async {
        crate::helpers::http_client()
            .post(format!("http://{}/v1/norms", served.addr))
            .json(&json!({"kind": "forbidden_action", "action": "destroy", "note": "no token needed"}))
            .send()
            .await
            .unwrap()
            .status()
    });
    assert!(served.terminate().success());
    assert_eq!(
        created,
        StatusCode::CREATED,
        "the shell's token or body limit was in force"
    );
    assert!(db.exists(), "the shell's database was used");
}

/// Every test file starts processes through `tests/support` (so without the caller's `SCRUPLE_*`
/// variables): none names the binary or makes a `Command` of its own.
#[test]
fn every_process_a_test_starts_is_made_by_the_one_launcher() {
    let tests = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let mut pending = vec![tests.clone()];
    let mut offenders = Vec::new();
    let mut seen = 0;
    while let Some(dir) = pending.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") && !path.ends_with("support/mod.rs") {
                seen += 1;
                let text = std::fs::read_to_string(&path).unwrap();
                for needle in [concat!("CARGO_BIN_", "EXE_"), concat!("Command", "::new(")] {
                    if text.contains(needle) {
                        offenders.push(format!("{}: {needle}", path.display()));
                    }
                }
            }
        }
    }
    assert!(seen > 20, "only {seen} test files found under {}", tests.display());
    assert!(
        offenders.is_empty(),
        "use tests/support's command or scruple:\n{}",
        offenders.join("\n")
    );
}
