//! Connections against the real binary, as a hostile client holds them: silent, half a head,
//! half a body, idle keep-alive, more connections than allowed, too few file descriptors, and
//! SIGTERM with connections that will not finish (HTTP/1.1 and HTTP/2). Each is closed within
//! its configured timeout, and the process exits 0 within its drain deadline.
//!
//! Timeouts here are 1 s. A wait that a configured timeout ends is bounded by [`CONFIGURED`]:
//! generous for a slow machine, yet below every default it replaces, so a setting that is
//! ignored fails the test. Other waits are bounded by [`BOUND`].

use std::process::Stdio;
use std::time::Duration;

use reqwest::StatusCode;
use serde_json::Value;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;

use crate::helpers::{Served, serve_binary};

/// The server, killed when a test fails before it ends it.
struct Server(Served);

impl Drop for Server {
    fn drop(&mut self) {
        if matches!(self.0.child.try_wait(), Ok(None)) {
            let _ = self.0.child.kill();
            let _ = self.0.child.wait();
        }
    }
}

impl Server {
    fn addr(&self) -> &str {
        &self.0.addr
    }

    /// SIGTERM, then the exit code; panics if the process is still running after
    /// [`CONFIGURED`], so only the configured 1 s drain deadline (not the default 10 s) passes.
    async fn terminate_within_bound(&mut self, what: &str) -> Option<i32> {
        self.0.sigterm();
        let status = self.0.exit_within(CONFIGURED).await;
        status
            .unwrap_or_else(|| panic!("{what}: still running {CONFIGURED:?} after SIGTERM"))
            .code()
    }
}

/// Far above anything the server should take, for waits no configured timeout ends.
const BOUND: Duration = Duration::from_secs(15);

/// For waits a configured 1 s timeout ends: four seconds to spare, and below the defaults the
/// tests' settings replace (header timeout and drain deadline 10 s, body 30 s, idle 60 s).
const CONFIGURED: Duration = Duration::from_secs(5);

fn sqlite(dir: &tempfile::TempDir) -> String {
    format!("sqlite://{}", dir.path().join("conn.db").display())
}

/// The binary with 1 s header, body and idle timeouts and a 1 s drain deadline, set through the
/// environment, plus `envs`.
fn serve_short(dir: &tempfile::TempDir, envs: &[(&str, &str)]) -> Server {
    let mut all = vec![
        ("SCRUPLE_HEADER_TIMEOUT_MS", "1000"),
        ("SCRUPLE_BODY_TIMEOUT_MS", "1000"),
        ("SCRUPLE_IDLE_TIMEOUT_MS", "1000"),
        ("SCRUPLE_DRAIN_TIMEOUT_MS", "1000"),
    ];
    all.retain(|(name, _)| !envs.iter().any(|(n, _)| n == name));
    all.extend_from_slice(envs);
    Server(serve_binary(&sqlite(dir), &[], &all, Stdio::null()))
}

/// What the server sent on `stream` until it closed the connection, or `None` if it was still
/// open after `bound`.
async fn read_until_closed(stream: &mut TcpStream, bound: Duration) -> Option<Vec<u8>> {
    let mut received = Vec::new();
    let mut chunk = [0u8; 8192];
    let deadline = tokio::time::Instant::now() + bound;
    loop {
        match tokio::time::timeout_at(deadline, stream.read(&mut chunk)).await {
            Err(_) => return None,
            Ok(Ok(0)) => return Some(received),
            Ok(Ok(n)) => received.extend_from_slice(&chunk[..n]),
            // A reset is a close too.
            Ok(Err(_)) => return Some(received),
        }
    }
}

/// One HTTP/1.1 response: status, lower-cased headers and body (by Content-Length).
struct Raw {
    status: u16,
    headers: Vec<(String, String)>,
    body: Vec<u8>,
}

impl Raw {
    fn header(&self, name: &str) -> Option<&str> {
        self.headers.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_str())
    }
}

/// Every response in `bytes`, in order.
fn responses(mut bytes: &[u8]) -> Vec<Raw> {
    let mut all = Vec::new();
    while !bytes.is_empty() {
        let end = bytes
            .windows(4)
            .position(|w| w == b"\r\n\r\n")
            .unwrap_or_else(|| panic!("no end of head in {:?}", String::from_utf8_lossy(bytes)));
        let head = std::str::from_utf8(&bytes[..end]).expect("a UTF-8 head");
        let mut lines = head.split("\r\n");
        let status = lines
            .next()
            .and_then(|l| l.split(' ').nth(1))
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("no status line in {head:?}"));
        let headers: Vec<(String, String)> = lines
            .filter_map(|l| l.split_once(':'))
            .map(|(n, v)| (n.trim().to_ascii_lowercase(), v.trim().to_owned()))
            .collect();
        let length: usize = headers
            .iter()
            .find(|(n, _)| n == "content-length")
            .map_or(0, |(_, v)| v.parse().unwrap());
        let body_start = end + 4;
        let body = bytes[body_start..(body_start + length).min(bytes.len())].to_vec();
        bytes = &bytes[(body_start + length).min(bytes.len())..];
        all.push(Raw { status, headers, body });
    }
    all
}

/// Asserts an RFC 9457 problem with this status, and returns it.
fn assert_raw_problem(response: &Raw, status: u16, what: &str) -> Value {
    assert_eq!(response.status, status, "{what}");
    assert_eq!(
        response.header("content-type"),
        Some("application/problem+json"),
        "{what}: {:?}",
        response.headers
    );
    let problem: Value = serde_json::from_slice(&response.body)
        .unwrap_or_else(|e| panic!("{what}: the body is not JSON ({e}): {:?}", response.body));
    assert_eq!(problem["status"], status, "{what}: {problem}");
    for member in ["type", "title", "detail"] {
        assert!(problem[member].is_string(), "{what}: no {member} in {problem}");
    }
    problem
}

/// Reads one whole response (head and Content-Length body) from a kept-alive connection.
async fn read_response(stream: &mut TcpStream) -> Raw {
    let mut bytes = Vec::new();
    let mut chunk = [0u8; 4096];
    loop {
        let n = tokio::time::timeout(BOUND, stream.read(&mut chunk))
            .await
            .expect("an answer")
            .unwrap();
        assert!(
            n > 0,
            "closed before a whole answer: {:?}",
            String::from_utf8_lossy(&bytes)
        );
        bytes.extend_from_slice(&chunk[..n]);
        if let Some(end) = bytes.windows(4).position(|w| w == b"\r\n\r\n") {
            let head = String::from_utf8_lossy(&bytes[..end]).to_ascii_lowercase();
            let length: usize = head
                .lines()
                .find_map(|l| l.strip_prefix("content-length:"))
                .map_or(0, |v| v.trim().parse().unwrap());
            if bytes.len() >= end + 4 + length {
                return responses(&bytes).remove(0);
            }
        }
    }
}

#[tokio::test]
async fn a_silent_connection_and_a_half_sent_head_are_closed_after_the_header_timeout() {
    let dir = tempfile::tempdir().unwrap();
    let served = serve_short(&dir, &[]);
    let mut silent = TcpStream::connect(served.addr()).await.unwrap();
    let mut half = TcpStream::connect(served.addr()).await.unwrap();
    half.write_all(b"GET /healthz HTTP/1.1\r\nHost: x\r\nX-Slow:")
        .await
        .unwrap();

    let nothing = read_until_closed(&mut silent, CONFIGURED).await;
    assert_eq!(
        nothing.as_deref(),
        Some(&b""[..]),
        "a silent connection is closed, unanswered"
    );
    let answer = read_until_closed(&mut half, CONFIGURED)
        .await
        .expect("a half-sent head is closed after the header timeout");
    // Something was said, so it is answered: 408 as a problem.
    let all = responses(&answer);
    assert_eq!(all.len(), 1);
    let problem = assert_raw_problem(&all[0], 408, "a half head");
    assert_eq!(problem["type"], "/problems/request-timeout");
    assert_eq!(all[0].header("connection"), Some("close"));
    drop(served);
}

#[tokio::test]
async fn a_half_sent_body_is_answered_408_and_closed_after_the_body_timeout() {
    let dir = tempfile::tempdir().unwrap();
    let served = serve_short(&dir, &[]);
    let mut stream = TcpStream::connect(served.addr()).await.unwrap();
    stream
        .write_all(
            b"POST /v1/clarify HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n\
              Content-Length: 1000\r\n\r\n{\"directive\": ",
        )
        .await
        .unwrap();
    let answer = read_until_closed(&mut stream, CONFIGURED)
        .await
        .expect("a stalled body is closed after the body timeout");
    let all = responses(&answer);
    assert_eq!(all.len(), 1);
    let problem = assert_raw_problem(&all[0], 408, "a half body");
    assert_eq!(problem["type"], "/problems/request-timeout");
    assert_eq!(all[0].header("connection"), Some("close"));
    drop(served);
}

#[tokio::test]
async fn an_idle_keep_alive_connection_is_closed_after_the_idle_timeout_and_a_busy_one_is_not() {
    let dir = tempfile::tempdir().unwrap();
    // The idle timeout, not the header timeout, governs the wait for a next request.
    let served = serve_short(
        &dir,
        &[
            ("SCRUPLE_HEADER_TIMEOUT_MS", "60000"),
            ("SCRUPLE_IDLE_TIMEOUT_MS", "1000"),
        ],
    );
    let mut stream = TcpStream::connect(served.addr()).await.unwrap();
    stream
        .write_all(b"GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n")
        .await
        .unwrap();
    let answer = read_until_closed(&mut stream, CONFIGURED)
        .await
        .expect("the idle connection is closed after the idle timeout");
    let all = responses(&answer);
    assert_eq!(all.len(), 1, "one answer, then the close");
    assert_eq!(all[0].status, 200);

    // Requests in a row, each within the idle timeout of the last (300 ms apart), keep one
    // connection for longer than the timeout (1.2 s): each answer starts the wait again.
    let mut stream = TcpStream::connect(served.addr()).await.unwrap();
    for n in 0..5 {
        if n > 0 {
            tokio::time::sleep(Duration::from_millis(300)).await;
        }
        stream
            .write_all(b"GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n")
            .await
            .unwrap();
        assert_eq!(read_response(&mut stream).await.status, 200, "request {n}");
    }
    drop(served);
}

#[tokio::test]
async fn past_max_connections_a_new_connection_waits_and_is_served_once_a_slot_frees() {
    let dir = tempfile::tempdir().unwrap();
    let served = serve_short(
        &dir,
        &[
            ("SCRUPLE_MAX_CONNECTIONS", "2"),
            ("SCRUPLE_HEADER_TIMEOUT_MS", "60000"),
            ("SCRUPLE_IDLE_TIMEOUT_MS", "60000"),
        ],
    );
    let first = TcpStream::connect(served.addr()).await.unwrap();
    let _second = TcpStream::connect(served.addr()).await.unwrap();
    // Give the server time to take both before the third arrives.
    tokio::time::sleep(Duration::from_millis(300)).await;
    let mut third = TcpStream::connect(served.addr()).await.unwrap();
    third
        .write_all(b"GET /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n")
        .await
        .unwrap();
    let mut byte = [0u8; 1];
    let early = tokio::time::timeout(Duration::from_millis(700), third.read(&mut byte)).await;
    assert!(early.is_err(), "the third connection is not served while two are open");

    drop(first);
    let answer = read_until_closed(&mut third, BOUND)
        .await
        .expect("the third connection is served once a slot frees");
    let all = responses(&answer);
    assert_eq!(all.len(), 1);
    assert_eq!(all[0].status, 200);
    drop(served);
}

#[tokio::test]
async fn with_few_file_descriptors_idle_sockets_do_not_starve_healthz() {
    let dir = tempfile::tempdir().unwrap();
    // The default --max-connections (4,096) is far above this limit: the server must keep its
    // connections below it, close the silent ones after the header timeout, and keep accepting.
    let script = format!(
        "ulimit -n 256 && exec {} serve --listen 127.0.0.1:0 --database-url {}",
        crate::support::SCRUPLE,
        sqlite(&dir)
    );
    let mut child = crate::support::command("sh")
        .args(["-c", &script])
        .env("SCRUPLE_HEADER_TIMEOUT_MS", "1000")
        .env("SCRUPLE_DRAIN_TIMEOUT_MS", "1000")
        .env("RUST_LOG", "error")
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut line = String::new();
    std::io::BufRead::read_line(&mut std::io::BufReader::new(child.stdout.take().unwrap()), &mut line).unwrap();
    let addr = line.trim().strip_prefix("listening on ").expect("started").to_owned();
    let mut served = Server(Served {
        child,
        addr: addr.clone(),
    });

    let mut idle = Vec::new();
    for _ in 0..400 {
        idle.push(TcpStream::connect(&addr).await.unwrap());
    }
    // The silent sockets the server took are closed after the configured 1 s header timeout
    // (not the default 10 s), and then the next ones it takes from the backlog.
    crate::support::install_ring();
    let client = reqwest::Client::builder().timeout(CONFIGURED).build().unwrap();
    let health = client.get(format!("http://{addr}/healthz")).send().await;
    let status = health.map(|r| r.status());
    assert_eq!(
        status.as_ref().ok(),
        Some(&StatusCode::OK),
        "/healthz while 400 sockets sit idle: {status:?}"
    );
    drop(idle);
    let code = served
        .terminate_within_bound("a server short of file descriptors")
        .await;
    assert_eq!(code, Some(0));
}

#[tokio::test]
async fn sigterm_with_a_half_sent_post_exits_0_within_the_drain_deadline() {
    let dir = tempfile::tempdir().unwrap();
    // The body timeout is long, so only the drain deadline can end this request.
    let mut served = serve_short(&dir, &[("SCRUPLE_BODY_TIMEOUT_MS", "600000")]);
    let mut stream = TcpStream::connect(served.addr()).await.unwrap();
    stream
        .write_all(
            b"POST /v1/norms HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n\
              Content-Length: 100\r\n\r\n{\"kind\":",
        )
        .await
        .unwrap();
    tokio::time::sleep(Duration::from_millis(300)).await;
    let code = served.terminate_within_bound("a half-sent POST").await;
    assert_eq!(code, Some(0), "the drain deadline passes and the process exits 0");
    drop(stream);
}

/// An HTTP/2 frame header: length, type, flags, stream id.
fn frame(kind: u8, flags: u8, stream: u32, payload: &[u8]) -> Vec<u8> {
    let len = payload.len() as u32;
    let mut bytes = vec![(len >> 16) as u8, (len >> 8) as u8, len as u8, kind, flags];
    bytes.extend_from_slice(&stream.to_be_bytes());
    bytes.extend_from_slice(payload);
    bytes
}

/// A literal header field without indexing, its name from the HPACK static table.
fn literal(name_index: u8, value: &str) -> Vec<u8> {
    assert!(name_index < 15 && value.len() < 127);
    let mut bytes = vec![name_index, value.len() as u8];
    bytes.extend_from_slice(value.as_bytes());
    bytes
}

#[tokio::test]
async fn sigterm_with_an_http2_client_that_never_reads_exits_0_within_the_drain_deadline() {
    let dir = tempfile::tempdir().unwrap();
    let mut served = serve_short(&dir, &[("SCRUPLE_BODY_TIMEOUT_MS", "600000")]);
    let mut stream = TcpStream::connect(served.addr()).await.unwrap();
    // Prior knowledge: the preface, empty SETTINGS, and a POST whose body never ends.
    let mut bytes = b"PRI * HTTP/2.0\r\n\r\nSM\r\n\r\n".to_vec();
    bytes.extend(frame(0x4, 0, 0, &[]));
    let mut block = vec![0x83, 0x86]; // :method POST, :scheme http
    block.extend(literal(4, "/v1/norms")); // :path
    block.extend(literal(1, "x")); // :authority
    block.extend([0x0f, 0x10, 16]); // content-type (static 31), 16 bytes:
    block.extend(b"application/json");
    bytes.extend(frame(0x1, 0x4, 1, &block)); // HEADERS, END_HEADERS, no END_STREAM
    bytes.extend(frame(0x0, 0, 1, b"{\"kind\":")); // DATA, no END_STREAM
    stream.write_all(&bytes).await.unwrap();
    tokio::time::sleep(Duration::from_millis(300)).await;
    // From here on the client reads nothing: not the GOAWAY, not the PING.
    let code = served.terminate_within_bound("an HTTP/2 client that never reads").await;
    assert_eq!(code, Some(0));
    drop(stream);
}

/// Sends `request` on a fresh connection and returns every response until the server closes.
async fn exchange(addr: &str, request: &[u8]) -> Vec<Raw> {
    let mut stream = TcpStream::connect(addr).await.unwrap();
    stream.write_all(request).await.unwrap();
    let bytes = read_until_closed(&mut stream, BOUND).await.unwrap_or_else(|| {
        panic!(
            "no close after {:?}",
            String::from_utf8_lossy(&request[..request.len().min(80)])
        )
    });
    responses(&bytes)
}

#[tokio::test]
async fn requests_hyper_cannot_parse_are_answered_with_problem_json() {
    let dir = tempfile::tempdir().unwrap();
    let served = serve_short(&dir, &[]);
    let head = |extra: &str| format!("POST /v1/clarify HTTP/1.1\r\nHost: x\r\n{extra}\r\n").into_bytes();
    let long_url = format!("GET /{} HTTP/1.1\r\nHost: x\r\n\r\n", "a".repeat(100_000)).into_bytes();
    let mut many_headers = b"GET /healthz HTTP/1.1\r\nHost: x\r\n".to_vec();
    for i in 0..1000 {
        many_headers.extend(format!("X-H{i}: v\r\n").into_bytes());
    }
    many_headers.extend(b"\r\n");
    let cases: Vec<(&str, Vec<u8>, u16, &str)> = vec![
        (
            "duplicate Content-Length",
            head("Content-Length: 5\r\nContent-Length: 6\r\n"),
            400,
            "/problems/bad-request",
        ),
        (
            "Transfer-Encoding: xchunked",
            head("Transfer-Encoding: xchunked\r\n"),
            400,
            "/problems/bad-request",
        ),
        (
            "a negative Content-Length",
            head("Content-Length: -1\r\n"),
            400,
            "/problems/bad-request",
        ),
        (
            "a huge Content-Length",
            head("Content-Length: 99999999999999999999999\r\n"),
            400,
            "/problems/bad-request",
        ),
        ("HTTP/0.9", b"GET /\r\n".to_vec(), 400, "/problems/bad-request"),
        (
            "a NUL in a header",
            b"GET /healthz HTTP/1.1\r\nHost: x\r\nX-A: a\0b\r\n\r\n".to_vec(),
            400,
            "/problems/bad-request",
        ),
        (
            "TLS on the cleartext port",
            vec![0x16, 0x03, 0x01, 0x00, 0xc8, 0x01, 0x00, 0x00, 0xc4, 0x03, 0x03],
            400,
            "/problems/bad-request",
        ),
        ("a 100 KB URL", long_url, 414, "/problems/uri-too-long"),
        ("1,000 headers", many_headers, 431, "/problems/headers-too-large"),
    ];
    for (what, request, status, kind) in cases {
        let all = exchange(served.addr(), &request).await;
        assert_eq!(all.len(), 1, "{what}: one answer");
        let problem = assert_raw_problem(&all[0], status, what);
        assert_eq!(problem["type"], kind, "{what}: {problem}");
        assert_eq!(all[0].header("connection"), Some("close"), "{what}");
        if what.starts_with("TLS") {
            assert!(problem["detail"].as_str().unwrap().contains("TLS"), "{problem}");
        }
    }

    // The same on a kept-alive connection, after a good request; pipelined good requests are
    // all answered.
    let mut pipelined = b"GET /healthz HTTP/1.1\r\nHost: x\r\n\r\n".repeat(3);
    pipelined.extend(head("Content-Length: -1\r\n"));
    let all = exchange(served.addr(), &pipelined).await;
    assert_eq!(all.len(), 4, "three answers and the problem");
    for ok in &all[..3] {
        assert_eq!(ok.status, 200);
        assert_eq!(ok.body, br#"{"status":"ok"}"#);
    }
    let problem = assert_raw_problem(&all[3], 400, "a bad request after good ones");
    assert_eq!(problem["type"], "/problems/bad-request");
    drop(served);
}

/// A write refused before its body is read (here: no token) closes an HTTP/1.1 connection, and
/// says so (`Connection: close`), so a client never sends its next request down a connection
/// about to close; an answer after a body read to its end keeps the connection for the next.
#[tokio::test]
async fn an_answer_given_before_the_body_was_read_says_the_connection_closes() {
    let dir = tempfile::tempdir().unwrap();
    let served = serve_short(&dir, &[("SCRUPLE_ADMIN_TOKEN", "0123456789abcdef-admin")]);
    let body = r#"{"kind": "forbidden_action", "action": "destroy"}"#;
    let request = |path: &str| {
        format!(
            "POST {path} HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
            body.len()
        )
    };
    let mut stream = TcpStream::connect(served.addr()).await.unwrap();
    // Read whole (a problem about the body's shape): the connection stays open for the next.
    stream.write_all(request("/v1/clarify").as_bytes()).await.unwrap();
    let read = read_response(&mut stream).await;
    assert_raw_problem(&read, 422, "a body that is no request");
    assert_eq!(read.header("connection"), None, "{:?}", read.headers);
    stream.write_all(request("/v1/norms").as_bytes()).await.unwrap();
    let refused = read_response(&mut stream).await;
    assert_raw_problem(&refused, 401, "a write without the token");
    assert_eq!(refused.header("connection"), Some("close"), "{:?}", refused.headers);
    let rest = read_until_closed(&mut stream, BOUND).await;
    assert_eq!(
        rest.as_deref(),
        Some(&b""[..]),
        "closed after the refusal, nothing more sent"
    );
}
