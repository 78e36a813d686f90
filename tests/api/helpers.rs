//! `spawn_app()`: the real service on a free port, with its own database file.

use std::path::PathBuf;

use reqwest::{Client, Response, StatusCode};
use scruple::app::{Application, Config, DEFAULT_MAX_BODY_BYTES, Secret};
use serde_json::{Value, json};
use tempfile::TempDir;
use tokio::sync::oneshot;

pub use crate::support::http_client;

pub struct TestApp {
    pub base: String,
    pub client: Client,
    pub db_path: PathBuf,
    /// Keeps the database directory alive as long as the app.
    pub dir: std::sync::Arc<TempDir>,
    stop: Option<oneshot::Sender<()>>,
    task: Option<tokio::task::JoinHandle<()>>,
}

/// Changes one or more settings of a test server.
pub type Tweak = Box<dyn FnOnce(&mut Config) + Send>;

pub struct Options {
    pub admin_token: Option<String>,
    pub max_body_bytes: usize,
    /// Any other setting, applied last.
    pub tweak: Option<Tweak>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            admin_token: None,
            max_body_bytes: DEFAULT_MAX_BODY_BYTES,
            tweak: None,
        }
    }
}

/// A server with one setting changed.
pub async fn spawn_tweaked(tweak: impl FnOnce(&mut Config) + Send + 'static) -> TestApp {
    spawn_with(Options {
        tweak: Some(Box::new(tweak)),
        ..Options::default()
    })
    .await
}

pub async fn spawn_app() -> TestApp {
    spawn_with(Options::default()).await
}

pub async fn spawn_with(options: Options) -> TestApp {
    let dir = std::sync::Arc::new(tempfile::tempdir().expect("temp dir"));
    spawn_on(dir, options).await
}

/// Waits as a write through the service does before its answer: a change made behind the
/// service's back (by hand, on the file) is seen once the lease on the stored versions taken
/// before it has run out, not before.
pub async fn after_the_lease() {
    let lease = std::time::Duration::from_millis(scruple::core::DEFAULT_LEASE_MS);
    tokio::time::sleep(lease + scruple::core::lease_margin(lease)).await;
}

/// Runs `sql` straight on a stopped server's SQLite file, as an older build or a hand edit
/// would have left it; `Err` is the database's refusal.
pub async fn raw_sql_on(db_path: &std::path::Path, sql: &'static str) -> Result<(), sqlx::Error> {
    use sqlx::ConnectOptions;
    let mut connection = sqlx::sqlite::SqliteConnectOptions::new()
        .filename(db_path)
        .connect()
        .await?;
    sqlx::raw_sql(sql).execute(&mut connection).await.map(drop)
}

/// Another server on the same database directory: a restart, or a second process sharing it.
pub async fn spawn_on(dir: std::sync::Arc<TempDir>, options: Options) -> TestApp {
    let db_path = dir.path().join("scruple.db");
    let mut config = Config::new("127.0.0.1:0", format!("sqlite://{}", db_path.display()));
    config.admin_token = options.admin_token.map(Secret);
    config.max_body_bytes = options.max_body_bytes;
    if let Some(tweak) = options.tweak {
        tweak(&mut config);
    }
    let app = Application::build(config).await.expect("the service starts");
    let addr = app.local_addr().expect("bound");
    let (stop, stopped) = oneshot::channel::<()>();
    let task = tokio::spawn(async move {
        app.run_until(async {
            let _ = stopped.await;
        })
        .await
        .expect("serves");
    });
    TestApp {
        base: format!("http://{addr}"),
        client: http_client(),
        db_path,
        dir,
        stop: Some(stop),
        task: Some(task),
    }
}

impl TestApp {
    pub fn url(&self, path: &str) -> String {
        format!("{}{path}", self.base)
    }

    pub async fn post(&self, path: &str, body: &Value) -> Response {
        self.client
            .post(self.url(path))
            .json(body)
            .send()
            .await
            .expect("request sent")
    }

    pub async fn get(&self, path: &str) -> Response {
        self.client.get(self.url(path)).send().await.expect("request sent")
    }

    pub async fn delete(&self, path: &str) -> Response {
        self.client.delete(self.url(path)).send().await.expect("request sent")
    }

    /// Adds a norm and returns its id; panics unless the service answers 201.
    pub async fn add_norm(&self, norm: &Value) -> i64 {
        let response = self.post("/v1/norms", norm).await;
        assert_eq!(response.status(), StatusCode::CREATED, "adding {norm}");
        let body: Value = response.json().await.unwrap();
        body["id"].as_i64().expect("an integer id")
    }

    pub async fn clarify(&self, request: &Value) -> Value {
        let response = self.post("/v1/clarify", request).await;
        assert_eq!(response.status(), StatusCode::OK, "clarify {request}");
        response.json().await.unwrap()
    }

    pub async fn norms(&self) -> Vec<Value> {
        let response = self.get("/v1/norms").await;
        assert_eq!(response.status(), StatusCode::OK);
        response.json().await.unwrap()
    }

    /// Stops serving and waits until in-flight requests are drained.
    pub async fn stop(mut self) {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
        if let Some(task) = self.task.take() {
            task.await.expect("server task ends cleanly");
        }
    }
}

/// The paper's scenario file, read from `../shared` as the project's tests must.
pub fn paper_demo() -> Value {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/scenarios/paper-demo.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
    serde_json::from_str(&text).expect("paper-demo.json is JSON")
}

pub fn lab_scene() -> Value {
    paper_demo()["scenes"]["lab"].clone()
}

/// "Get the vase." on the lab scene.
pub fn get_vase() -> Value {
    json!({
        "directive": {"action": "get", "arguments": [{"type": "vase"}], "text": "Get the vase."},
        "scene": lab_scene(),
    })
}

/// Asserts an RFC 9457 answer with the given status and, when given, the field pointer.
pub async fn assert_problem(response: Response, status: StatusCode, field: Option<&str>) -> Value {
    assert_eq!(response.status(), status);
    let content_type = response
        .headers()
        .get("content-type")
        .map(|v| v.to_str().unwrap().to_owned());
    assert_eq!(content_type.as_deref(), Some("application/problem+json"));
    let body: Value = response.json().await.expect("a JSON problem");
    assert_eq!(body["status"].as_u64(), Some(u64::from(status.as_u16())), "{body}");
    assert!(
        body["type"].is_string() && body["title"].is_string() && body["detail"].is_string(),
        "{body}"
    );
    if let Some(field) = field {
        assert_eq!(body["field"].as_str(), Some(field), "{body}");
    }
    body
}

/// The real `scruple serve` process on a free loopback port.
pub struct Served {
    pub child: std::process::Child,
    /// `127.0.0.1:PORT`, from the `listening on` line.
    pub addr: String,
}

/// Starts `scruple serve --listen 127.0.0.1:0 --database-url URL ARGS...` with `envs` (and
/// `RUST_LOG=error` unless given) and none of the caller's other `SCRUPLE_*` variables, its
/// stderr to `stderr`; returns once it prints its address.
pub fn serve_binary(database_url: &str, args: &[&str], envs: &[(&str, &str)], stderr: std::process::Stdio) -> Served {
    use std::io::{BufRead, BufReader};
    let mut command = crate::support::scruple();
    command
        .args(["serve", "--listen", "127.0.0.1:0", "--database-url", database_url])
        .args(args)
        .env("RUST_LOG", "error")
        .stdout(std::process::Stdio::piped())
        .stderr(stderr);
    for (name, value) in envs {
        command.env(name, value);
    }
    let mut child = command.spawn().expect("the binary starts");
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let addr = line
        .trim()
        .strip_prefix("listening on ")
        .unwrap_or_else(|| panic!("the server did not start: first line was {line:?}"))
        .to_owned();
    Served { child, addr }
}

/// As [`serve_binary`] with no other flag, for a start that may fail: `Err` holds what the
/// process wrote to stderr before it exited without printing its address. Its stderr is read
/// to the end on a thread of its own, so a server that keeps running never blocks on it.
pub fn try_serve_binary(database_url: &str) -> Result<Served, String> {
    use std::io::{BufRead, BufReader, Read};
    let mut child = crate::support::scruple()
        .args(["serve", "--listen", "127.0.0.1:0", "--database-url", database_url])
        .env("RUST_LOG", "error")
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("the binary starts");
    let mut stderr = child.stderr.take().unwrap();
    let said = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = stderr.read_to_string(&mut text);
        text
    });
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    match line.trim().strip_prefix("listening on ") {
        Some(addr) => Ok(Served {
            addr: addr.to_owned(),
            child,
        }),
        None => {
            // Without its address it serves nobody: ended, if it has not ended already.
            let _ = child.kill();
            let status = child.wait().unwrap();
            Err(format!("{status}: {}", said.join().unwrap().trim()))
        }
    }
}

/// A server a failed assertion left running is killed, so no test leaves a process behind.
impl Drop for Served {
    fn drop(&mut self) {
        if matches!(self.child.try_wait(), Ok(None)) {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

impl Served {
    /// SIGTERM, then the exit status once it has drained.
    pub fn terminate(mut self) -> std::process::ExitStatus {
        self.sigterm();
        self.child.wait().unwrap()
    }

    /// Sends SIGTERM and returns at once.
    pub fn sigterm(&self) {
        let sent = crate::support::command("kill")
            .args(["-TERM", &self.child.id().to_string()])
            .status()
            .unwrap();
        assert!(sent.success());
    }

    /// The exit status, if the process ends within `bound`; `None` if it is still running then.
    pub async fn exit_within(&mut self, bound: std::time::Duration) -> Option<std::process::ExitStatus> {
        let deadline = tokio::time::Instant::now() + bound;
        loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                return Some(status);
            }
            if tokio::time::Instant::now() > deadline {
                return None;
            }
            tokio::time::sleep(std::time::Duration::from_millis(50)).await;
        }
    }
}

/// Asks `get_vase` at `base` in a loop until dropped, so that the server always holds a fresh
/// lease on the stored versions: the condition under which a stale one would show.
pub struct KeepAsking {
    stop: std::sync::Arc<std::sync::atomic::AtomicBool>,
    task: Option<tokio::task::JoinHandle<u64>>,
}

impl KeepAsking {
    pub fn at(base: &str) -> KeepAsking {
        let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let (flag, url, client) = (stop.clone(), format!("{base}/v1/clarify"), http_client());
        let task = tokio::spawn(async move {
            let mut asked = 0;
            while !flag.load(std::sync::atomic::Ordering::Relaxed) {
                let response = client.post(&url).json(&get_vase()).send().await.expect("asked");
                assert_eq!(response.status(), StatusCode::OK);
                asked += 1;
            }
            asked
        });
        KeepAsking { stop, task: Some(task) }
    }

    /// Stops asking; how many answers came meanwhile (so a test can tell the load was there).
    pub async fn stop(mut self) -> u64 {
        self.stop.store(true, std::sync::atomic::Ordering::Relaxed);
        self.task.take().expect("running").await.expect("the asking task")
    }
}

impl Drop for KeepAsking {
    fn drop(&mut self) {
        self.stop.store(true, std::sync::atomic::Ordering::Relaxed);
    }
}

/// Runs the test `path` (its path below the crate, `module::name`) alone in a fresh process of
/// this test binary, with `envs` added to its environment, and asserts that it ran and passed.
/// For a test that must change what a whole process sees (its environment), which threads of
/// this one would otherwise share.
pub fn pass_alone_in_a_child(path: &str, envs: &[(&str, &str)]) {
    let exe = std::env::current_exe().expect("the test binary's path");
    let output = crate::support::command(exe)
        .args([path, "--exact", "--nocapture", "--test-threads=1"])
        .envs(envs.iter().copied())
        .stdin(std::process::Stdio::null())
        .output()
        .expect("the test binary runs again");
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success() && stdout.contains("test result: ok. 1 passed"),
        "{path} in a child process: {}\n{stdout}\n{stderr}",
        output.status
    );
}
