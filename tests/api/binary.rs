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
        &[("SCRUPLE_ADMIN_TOKEN", "from-env-0123456789"), ("RUST_LOG", "warn")],
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
        .bearer_auth("from-env-0123456789")
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

/// An empty, blank or short admin token stops the start, as a curator secret under 16 bytes
/// always did: `SCRUPLE_ADMIN_TOKEN=""` (a variable set from an unset one) used to leave every
/// write open, with no word. The error names the flag and the variable and never the secret;
/// nothing listens and no database is made.
#[test]
fn an_empty_blank_or_short_admin_token_stops_the_start() {
    let dir = tempfile::tempdir().unwrap();
    let db = dir.path().join("never.db");
    let url = format!("sqlite://{}", db.display());
    // The outcome of a start, or a failure if it is still serving after a while.
    let start = |args: &[&str], envs: &[(&str, &str)]| {
        let mut command = crate::support::scruple();
        command
            .args(["serve", "--listen", "127.0.0.1:0", "--database-url", &url])
            .args(args)
            .env_remove("SCRUPLE_ADMIN_TOKEN")
            .env("RUST_LOG", "off")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        for (name, value) in envs {
            command.env(name, value);
        }
        let mut child = command.spawn().unwrap();
        let began = std::time::Instant::now();
        while child.try_wait().unwrap().is_none() {
            if began.elapsed() > std::time::Duration::from_secs(20) {
                child.kill().unwrap();
                let out = child.wait_with_output().unwrap();
                panic!(
                    "{args:?} {envs:?}: the service started: {}",
                    String::from_utf8_lossy(&out.stdout)
                );
            }
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        child.wait_with_output().unwrap()
    };
    // The flags, then the variables, of each start.
    type Start<'a> = (&'a [&'a str], &'a [(&'a str, &'a str)]);
    let cases: [Start; 6] = [
        (&[], &[("SCRUPLE_ADMIN_TOKEN", "")]),
        (&[], &[("SCRUPLE_ADMIN_TOKEN", "   \t ")]),
        (&[], &[("SCRUPLE_ADMIN_TOKEN", "short-SECRET")]),
        (&["--admin-token", ""], &[]),
        (&["--admin-token", "   "], &[]),
        (&["--admin-token", "short-SECRET"], &[]),
    ];
    for (args, envs) in cases {
        let out = start(args, envs);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && out.status.code().is_some(),
            "{args:?} {envs:?}: {:?} {stderr}",
            out.status
        );
        assert!(
            stderr.contains("--admin-token") && stderr.contains("SCRUPLE_ADMIN_TOKEN"),
            "{args:?} {envs:?}: the error names the flag and the variable: {stderr}"
        );
        assert!(!stderr.contains("SECRET"), "the secret is never echoed: {stderr}");
        assert!(out.stdout.is_empty(), "{args:?} {envs:?} must not listen");
        assert!(!db.exists(), "{args:?} {envs:?}: no database is made");
    }
    // Sixteen bytes start, and guard writes.
    let served = serve_binary(&url, &["--admin-token", "sixteen-byte-tok"], &[], Stdio::null());
    let runtime = tokio::runtime::Runtime::new().unwrap();
    let status = runtime.block_on(async {
        let norm = json!({"kind": "forbidden_action", "action": "destroy"});
        let url = format!("http://{}/v1/norms", served.addr);
        crate::helpers::http_client()
            .post(url)
            .json(&norm)
            .send()
            .await
            .map(|r| r.status())
    });
    assert_eq!(status.unwrap(), StatusCode::UNAUTHORIZED);
    assert!(served.terminate().success());
}

/// The lease's costs as `serve --help` and the README state them agree with each other and
/// with the lease's arithmetic (they said 20 and 27 reads a second): at the default lease L,
/// the versions are read again by the first request past three quarters of it, so at most
/// 1000 / (0.75 L) times a second, and a write is acknowledged L + L/10 + 1 ms after it commits.
#[test]
fn the_lease_help_and_the_readme_state_the_same_costs() {
    let lease = scruple::core::DEFAULT_LEASE_MS;
    let reads = (1000.0 / (0.75 * lease as f64)).round() as u64;
    let wait =
        std::time::Duration::from_millis(lease) + scruple::core::lease_margin(std::time::Duration::from_millis(lease));
    let reads = format!("{reads} times a second");
    let wait = format!("{} ms", wait.as_millis());
    let help = crate::support::scruple().args(["serve", "--help"]).output().unwrap();
    let help = String::from_utf8_lossy(&help.stdout)
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
    let readme = readme.split_whitespace().collect::<Vec<_>>().join(" ");
    for (what, text) in [("serve --help", &help), ("README.md", &readme)] {
        assert!(text.contains(&reads), "{what} should say {reads:?}");
        assert!(text.contains(&wait), "{what} should say {wait:?}");
        for wrong in ["20 reads a second", "20 times a second", "27 reads a second"] {
            assert!(!text.contains(wrong), "{what} still says {wrong:?}");
        }
    }
}

/// Finding: `scruple clarify --database-url postgres://…` answered SQLite's "unable to open
/// database file". The offline commands open a PostgreSQL store as the server does, and, as
/// for a SQLite file, refuse a database that holds no store rather than decide under no norms.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_offline_commands_read_a_postgresql_store() {
    let database = crate::backends::PgDatabase::create().await;
    let dir = tempfile::tempdir().unwrap();
    let vase = dir.path().join("vase.json");
    std::fs::write(&vase, crate::helpers::get_vase().to_string()).unwrap();
    let offline = move |url: String| {
        let vase = vase.clone();
        move || {
            crate::support::scruple()
                .args(["clarify", vase.to_str().unwrap(), "--database-url", &url])
                .env("RUST_LOG", "off")
                .output()
                .unwrap()
        }
    };
    // A database with no store in it is refused.
    let empty = tokio::task::spawn_blocking(offline(database.url.clone()))
        .await
        .unwrap();
    assert_eq!(
        empty.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&empty.stderr)
    );
    assert!(
        String::from_utf8_lossy(&empty.stderr).contains("no Scruple store"),
        "{}",
        String::from_utf8_lossy(&empty.stderr)
    );

    let mut config = scruple::app::Config::new("127.0.0.1:0", database.url.clone());
    config.lease = std::time::Duration::ZERO;
    let app = scruple::app::Application::build(config)
        .await
        .expect("the server starts");
    let base = format!("http://{}", app.local_addr().unwrap());
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let server = tokio::spawn(app.run_until(async {
        let _ = stopped.await;
    }));
    let created = crate::helpers::http_client()
        .post(format!("{base}/v1/norms"))
        .json(&json!({"kind": "forbidden_state", "state": "did(self,get(object3))"}))
        .send()
        .await
        .unwrap();
    assert_eq!(created.status(), StatusCode::CREATED);
    let _ = stop.send(());
    server.await.unwrap().unwrap();

    let output = tokio::task::spawn_blocking(offline(database.url.clone()))
        .await
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let answer: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(answer["decision"], "assume", "{answer}");
    assert_eq!(answer["norm_version"], 1);
}
