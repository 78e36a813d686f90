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
