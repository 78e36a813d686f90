//! The connection layer in front of the router: the accept loop, and each connection's life
//! from its first byte to its close.
//!
//! Owns: how many connections are open at once (and accepting on when file descriptors run
//! out), which protocol a connection speaks (HTTP/1.1, or HTTP/2 by prior knowledge; over TCP or
//! TLS), how long a client may take over a head, a body, its next request or reading an answer,
//! the problem+json answers to heads hyper cannot parse, and draining on shutdown within a hard
//! deadline.
//! Must not: look at what a request asks (routes, bodies, tokens): that is the router's.
//!
//! A connection's timeouts: from its first byte (or its accept), the head must be whole within
//! the header timeout; between requests, the next one must begin within the idle timeout; a
//! body must arrive within the body timeout of the handler starting to read it (`body`); and a
//! write the client does not read for the body timeout ends the connection.

pub mod body;
mod io;
pub mod problem;

use std::convert::Infallible;
use std::future::Future;
use std::net::SocketAddr;
use std::pin::Pin;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::task::{Context, Poll};
use std::time::{Duration, Instant};

use bytes::Bytes;
use http_body::{Frame, SizeHint};
use hyper::body::Incoming;
use hyper::server::conn::{http1, http2};
use hyper_util::rt::{TokioExecutor, TokioIo, TokioTimer};
use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{OwnedSemaphorePermit, Semaphore, watch};
use tokio::task::JoinSet;
use tower::ServiceExt;
use tower::util::Either;
use tower_http::cors::Cors;

use crate::transport::admission::Admit;
use crate::transport::observe::Observe;
use crate::transport::tls::{Handshakes, Tls};
use body::TimedBody;
use io::{Activity, InFlight, Mode, State, Watched};
use problem::Protocol;

/// Defaults of `--header-timeout-ms`, `--body-timeout-ms`, `--idle-timeout-ms`,
/// `--max-connections` and `--drain-timeout-ms`.
pub const DEFAULT_HEADER_TIMEOUT_MS: u64 = 10_000;
pub const DEFAULT_BODY_TIMEOUT_MS: u64 = 30_000;
pub const DEFAULT_IDLE_TIMEOUT_MS: u64 = 60_000;
pub const DEFAULT_MAX_CONNECTIONS: usize = 4_096;
/// Inside Kubernetes' default 30 s grace period, with room for the pod's own shutdown.
pub const DEFAULT_DRAIN_TIMEOUT_MS: u64 = 10_000;

/// The HTTP/2 connection preface (RFC 9113 §3.4): a connection that starts with it speaks HTTP/2.
const PREFACE: &[u8; 24] = b"PRI * HTTP/2.0\r\n\r\nSM\r\n\r\n";

/// Waits after a failed accept: from the first to the last, doubling.
const ACCEPT_BACKOFF: (Duration, Duration) = (Duration::from_millis(10), Duration::from_secs(1));

/// Longest time spent writing a problem on a connection and lingering before closing it.
const ANSWER_BOUND: Duration = Duration::from_secs(2);

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ConnConfig {
    /// From a connection's accept (or the end of its last answer's wait), the whole head of a
    /// request must arrive within this.
    pub header_timeout: Duration,
    /// A request body must arrive whole within this of the handler starting to read it; a
    /// write the client does not read for this long ends the connection.
    pub body_timeout: Duration,
    /// A connection with no request open is closed when no next request begins within this.
    pub idle_timeout: Duration,
    /// Connections open at once (TLS handshakes included); beyond, new ones wait in the
    /// kernel's backlog. Lowered to what the open-file limit allows.
    pub max_connections: usize,
    /// After the shutdown signal, connections still open after this are closed and serving ends.
    pub drain_timeout: Duration,
}

impl Default for ConnConfig {
    fn default() -> Self {
        ConnConfig {
            header_timeout: Duration::from_millis(DEFAULT_HEADER_TIMEOUT_MS),
            body_timeout: Duration::from_millis(DEFAULT_BODY_TIMEOUT_MS),
            idle_timeout: Duration::from_millis(DEFAULT_IDLE_TIMEOUT_MS),
            max_connections: DEFAULT_MAX_CONNECTIONS,
            drain_timeout: Duration::from_millis(DEFAULT_DRAIN_TIMEOUT_MS),
        }
    }
}

impl ConnConfig {
    /// Every setting must be at least 1 (ms, or connection); the error names the flag.
    pub fn check(&self) -> Result<(), String> {
        let durations = [
            ("--header-timeout-ms", self.header_timeout),
            ("--body-timeout-ms", self.body_timeout),
            ("--idle-timeout-ms", self.idle_timeout),
            ("--drain-timeout-ms", self.drain_timeout),
        ];
        for (flag, duration) in durations {
            if duration.is_zero() {
                return Err(format!("{flag} must be at least 1"));
            }
        }
        if self.max_connections == 0 {
            return Err("--max-connections must be at least 1".to_owned());
        }
        Ok(())
    }
}

/// What every request is given to: the router, inside the observing and admission layers, and
/// between them the browsers' cross-origin layer when `--cors-origin` is set (preflights are
/// answered there, never queued).
pub type Served = Observe<Either<Cors<Admit<axum::Router>>, Admit<axum::Router>>>;

/// What every connection task shares.
struct Shared {
    router: Served,
    config: ConnConfig,
    tls: Option<Handshakes>,
}

/// Serves `listener` until `shutdown` completes; then stops accepting, lets open requests finish
/// and closes idle connections (HTTP/2: GOAWAY), and returns once every connection is closed or
/// the drain deadline has passed, whichever is first.
pub async fn serve(
    listener: TcpListener,
    tls: Option<Tls>,
    router: Served,
    config: ConnConfig,
    shutdown: impl Future<Output = ()>,
) -> std::io::Result<()> {
    let slots = Arc::new(Semaphore::new(open_file_budget(config.max_connections)));
    let shared = Arc::new(Shared {
        router,
        config,
        tls: tls.map(Tls::start),
    });
    let (drain_tx, drain_rx) = watch::channel(false);
    let mut connections = JoinSet::new();
    let mut backoff = ACCEPT_BACKOFF.0;
    tokio::pin!(shutdown);
    loop {
        let accepted = tokio::select! {
            biased;
            () = &mut shutdown => break,
            Some(_) = connections.join_next(), if !connections.is_empty() => continue,
            accepted = accept(&listener, &slots, &shared) => accepted,
        };
        match accepted {
            Ok(accepted) => {
                backoff = ACCEPT_BACKOFF.0;
                connections.spawn(connection(accepted, shared.clone(), drain_rx.clone()));
            }
            Err(error) if peer_gone(&error) => {}
            Err(error) => {
                // Out of file descriptors (EMFILE, ENFILE) or buffers: connections closing will
                // free some. Accepting again at once would spin; giving up would kill a
                // service that is only busy.
                tracing::warn!(%error, wait_ms = backoff.as_millis() as u64, "cannot accept a connection; waiting");
                tokio::select! {
                    () = &mut shutdown => break,
                    () = tokio::time::sleep(backoff) => {}
                }
                backoff = (backoff * 2).min(ACCEPT_BACKOFF.1);
            }
        }
    }
    drop(listener);
    let _ = drain_tx.send(true);
    let open = connections.len();
    if open > 0 {
        tracing::info!(connections = open, "draining");
    }
    let drained = tokio::time::timeout(config.drain_timeout, async {
        while connections.join_next().await.is_some() {}
    })
    .await;
    if drained.is_err() {
        tracing::warn!(
            connections = connections.len(),
            drain_timeout_ms = config.drain_timeout.as_millis() as u64,
            "drain deadline passed; closing the connections still open"
        );
        connections.shutdown().await;
    }
    Ok(())
}

/// A connection taken from the backlog, with its slot (and its turn to handshake, over TLS).
struct Accepted {
    stream: TcpStream,
    peer: SocketAddr,
    slot: OwnedSemaphorePermit,
    turn: Option<OwnedSemaphorePermit>,
}

/// Waits for a free slot (and a handshake turn), then accepts: until then, new connections wait
/// in the kernel's backlog.
async fn accept(listener: &TcpListener, slots: &Arc<Semaphore>, shared: &Shared) -> std::io::Result<Accepted> {
    let slot = slots
        .clone()
        .acquire_owned()
        .await
        .unwrap_or_else(|_| unreachable!("the connection semaphore is never closed"));
    let turn = match &shared.tls {
        Some(tls) => Some(tls.turn().await),
        None => None,
    };
    let (stream, peer) = listener.accept().await?;
    Ok(Accepted {
        stream,
        peer,
        slot,
        turn,
    })
}

/// An accept that failed for this one connection (it was reset before it was taken): the next
/// one can be accepted at once.
fn peer_gone(error: &std::io::Error) -> bool {
    use std::io::ErrorKind::{ConnectionAborted, ConnectionRefused, ConnectionReset, Interrupted};
    if matches!(
        error.kind(),
        ConnectionAborted | ConnectionRefused | ConnectionReset | Interrupted
    ) {
        return true;
    }
    // Linux passes on errors of the new connection's network (accept(2), "Error handling").
    #[cfg(target_os = "linux")]
    if let Some(code) = error.raw_os_error() {
        return [
            libc::ENETDOWN,
            libc::EPROTO,
            libc::ENOPROTOOPT,
            libc::EHOSTDOWN,
            libc::ENONET,
            libc::EHOSTUNREACH,
            libc::EOPNOTSUPP,
            libc::ENETUNREACH,
        ]
        .contains(&code);
    }
    false
}

/// How many connections may be open at once: `wanted`, unless the open-file limit would not
/// leave room for them and for the store's files, the listener and the runtime. The soft limit
/// is raised to the hard one first (as Go's runtime does): the usual soft default of 1,024 is a
/// relic of `select(2)`, which nothing here uses.
fn open_file_budget(wanted: usize) -> usize {
    #[cfg(unix)]
    {
        let Some(limit) = raise_open_file_limit() else {
            return wanted;
        };
        // The store's pool keeps a few files per connection; the rest is small and fixed.
        let reserve = (limit / 4).clamp(64, 1024);
        let budget = limit.saturating_sub(reserve).max(1);
        if wanted > budget {
            tracing::warn!(
                max_connections = wanted,
                open_file_limit = limit,
                serving = budget,
                "--max-connections is above what the open-file limit allows; lowered"
            );
            return budget;
        }
    }
    wanted
}

/// The soft `RLIMIT_NOFILE` after raising it to the hard limit, or `None` if it cannot be read.
#[cfg(unix)]
fn raise_open_file_limit() -> Option<usize> {
    let mut limit = libc::rlimit {
        rlim_cur: 0,
        rlim_max: 0,
    };
    // SAFETY: getrlimit writes one rlimit through a valid pointer.
    if unsafe { libc::getrlimit(libc::RLIMIT_NOFILE, &mut limit) } != 0 {
        return None;
    }
    if limit.rlim_cur < limit.rlim_max {
        let raised = libc::rlimit {
            rlim_cur: limit.rlim_max,
            rlim_max: limit.rlim_max,
        };
        // SAFETY: setrlimit reads one rlimit through a valid pointer.
        if unsafe { libc::setrlimit(libc::RLIMIT_NOFILE, &raised) } == 0 {
            limit = raised;
        }
    }
    if limit.rlim_cur == libc::RLIM_INFINITY {
        return Some(usize::MAX);
    }
    Some(usize::try_from(limit.rlim_cur).unwrap_or(usize::MAX))
}

/// One connection, from the accept to the close; its slot frees when this ends.
async fn connection(accepted: Accepted, shared: Arc<Shared>, mut drain: watch::Receiver<bool>) {
    let Accepted {
        stream,
        peer,
        slot: _slot,
        turn,
    } = accepted;
    let started = Instant::now();
    // Small request/response exchanges must not wait on Nagle's algorithm: without
    // TCP_NODELAY, gRPC calls stall ~40 ms on delayed ACKs.
    if let Err(error) = stream.set_nodelay(true) {
        tracing::debug!(%error, "cannot set TCP_NODELAY");
    }
    match (&shared.tls, turn) {
        (Some(tls), Some(turn)) => {
            let tls = tokio::select! {
                tls = tls.handshake(stream, peer, turn) => tls,
                _ = drain.wait_for(|draining| *draining) => None,
            };
            if let Some(tls) = tls {
                // The handshake has its own timeout; the head's starts after it.
                serve_io(tls, Instant::now(), &shared, drain).await;
            }
        }
        _ => serve_io(stream, started, &shared, drain).await,
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Speaks {
    Http1,
    Http2,
}

/// Reads until the first bytes tell the protocol: the HTTP/2 preface, or anything else (HTTP/1).
/// `None`: the client closed first.
async fn sniff<IO: AsyncRead + Unpin>(io: &mut IO, first: &mut [u8; 24], filled: &mut usize) -> Option<Speaks> {
    loop {
        let n = io.read(&mut first[*filled..]).await.ok()?;
        if n == 0 {
            return None;
        }
        *filled += n;
        if first[..*filled] != PREFACE[..*filled] {
            return Some(Speaks::Http1);
        }
        if *filled == PREFACE.len() {
            return Some(Speaks::Http2);
        }
    }
}

async fn serve_io<IO>(mut io: IO, started: Instant, shared: &Arc<Shared>, mut drain: watch::Receiver<bool>)
where
    IO: AsyncRead + AsyncWrite + Unpin + Send + 'static,
{
    let config = &shared.config;
    let mut first = [0u8; 24];
    let mut filled = 0;
    let deadline = tokio::time::Instant::from_std(started + config.header_timeout);
    let protocol = tokio::select! {
        sniffed = tokio::time::timeout_at(deadline, sniff(&mut io, &mut first, &mut filled)) => sniffed,
        _ = drain.wait_for(|draining| *draining) => return,
    };
    let prefix = Bytes::copy_from_slice(&first[..filled]);
    match protocol {
        Ok(Some(Speaks::Http1)) => serve_http1(io, prefix, started, shared, drain).await,
        Ok(Some(Speaks::Http2)) => serve_http2(io, prefix, shared, drain).await,
        // The client closed, or its read failed.
        Ok(None) => {}
        // Silent: closed unanswered. Part of a head: answered.
        Err(_) if filled == 0 => {}
        Err(_) => {
            let activity = Activity::new(started, true);
            Watched::new(io, prefix, activity, Mode::Http1)
                .answer_and_close(&header_timeout_problem(config), ANSWER_BOUND)
                .await;
        }
    }
}

fn header_timeout_problem(config: &ConnConfig) -> Vec<u8> {
    Protocol::RequestTimeout.raw(format!(
        "the request head did not arrive within {} ms",
        config.header_timeout.as_millis()
    ))
}

/// Why the watchdog ended a connection.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Expired {
    /// No request began within the idle timeout.
    Idle,
    /// A head began but did not end within the header timeout.
    Head,
    /// The client did not read an answer for the body timeout.
    Unread,
}

/// Resolves when a timeout of the connection has passed. It looks at `activity` at each of its
/// deadlines and at least every `min(timeouts)`: requests do not wake it.
async fn watchdog(activity: &Activity, config: &ConnConfig) -> Expired {
    let period = config.header_timeout.min(config.idle_timeout).min(config.body_timeout);
    loop {
        let now = Instant::now();
        let mut wake = now + period;
        if let Some(since) = activity.write_blocked_since() {
            let deadline = since + config.body_timeout;
            if deadline <= now {
                return Expired::Unread;
            }
            wake = wake.min(deadline);
        }
        let (deadline, why) = match activity.state() {
            State::Busy => (None, Expired::Idle),
            State::Idle(since) => (Some(since + config.idle_timeout), Expired::Idle),
            State::Head(since) => (Some(since + config.header_timeout), Expired::Head),
        };
        if let Some(deadline) = deadline {
            if deadline <= now {
                return why;
            }
            wake = wake.min(deadline);
        }
        tokio::time::sleep_until(tokio::time::Instant::from_std(wake)).await;
    }
}

/// The router as hyper's service on one connection: each request's body timed, each open
/// request counted until its answer has been sent.
#[derive(Clone)]
struct Service {
    router: Served,
    body_timeout: Duration,
    activity: Arc<Activity>,
    /// HTTP/1.1 only: whether the request in hand has had its body read to the end. One request
    /// is in hand at a time on such a connection, so one flag serves them all.
    read: Option<Arc<AtomicBool>>,
}

impl Service {
    fn new(shared: &Shared, activity: &Arc<Activity>, mode: Mode) -> Service {
        Service {
            router: shared.router.clone(),
            body_timeout: shared.config.body_timeout,
            activity: activity.clone(),
            read: matches!(mode, Mode::Http1).then(|| Arc::new(AtomicBool::new(true))),
        }
    }
}

impl hyper::service::Service<hyper::Request<Incoming>> for Service {
    type Response = hyper::Response<Tracked>;
    type Error = Infallible;
    type Future = Answer;

    fn call(&self, request: hyper::Request<Incoming>) -> Answer {
        let in_flight = self.activity.begin();
        if let Some(read) = &self.read {
            read.store(http_body::Body::is_end_stream(request.body()), Ordering::Relaxed);
        }
        let read = self.read.clone();
        let request = request.map(|body| axum::body::Body::new(TimedBody::new(body, self.body_timeout, read)));
        Answer {
            inner: self.router.clone().oneshot(request),
            in_flight: Some(in_flight),
            read: self.read.clone(),
        }
    }
}

pin_project_lite::pin_project! {
    /// The router's answer to one request, its body tracked.
    struct Answer {
        #[pin]
        inner: tower::util::Oneshot<Served, axum::extract::Request>,
        in_flight: Option<InFlight>,
        read: Option<Arc<AtomicBool>>,
    }
}

impl Future for Answer {
    type Output = Result<hyper::Response<Tracked>, Infallible>;

    fn poll(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Self::Output> {
        let this = self.project();
        let mut response = match std::task::ready!(this.inner.poll(cx)) {
            Ok(response) => response,
            Err(never) => match never {},
        };
        // Answered before its body was read (a refused write, an overload): hyper closes the
        // connection rather than read the rest, so the answer says so, and a client does not
        // send its next request down a connection about to close.
        if this.read.as_ref().is_some_and(|read| !read.load(Ordering::Relaxed)) {
            (response.headers_mut()).insert(
                hyper::header::CONNECTION,
                hyper::header::HeaderValue::from_static("close"),
            );
        }
        let in_flight = this.in_flight.take();
        Poll::Ready(Ok(response.map(|body| Tracked {
            body,
            _in_flight: in_flight,
        })))
    }
}

/// An answer's body, holding its request open on the connection until hyper drops it (sent in
/// full, or the connection gone).
pub struct Tracked {
    body: axum::body::Body,
    _in_flight: Option<InFlight>,
}

impl http_body::Body for Tracked {
    type Data = Bytes;
    type Error = axum::Error;

    fn poll_frame(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Option<Result<Frame<Bytes>, axum::Error>>> {
        Pin::new(&mut self.body).poll_frame(cx)
    }

    fn is_end_stream(&self) -> bool {
        self.body.is_end_stream()
    }

    fn size_hint(&self) -> SizeHint {
        self.body.size_hint()
    }
}

async fn serve_http1<IO>(
    io: IO,
    prefix: Bytes,
    started: Instant,
    shared: &Arc<Shared>,
    mut drain: watch::Receiver<bool>,
) where
    IO: AsyncRead + AsyncWrite + Unpin + Send + 'static,
{
    let config = &shared.config;
    let tls_on_cleartext = shared.tls.is_none() && prefix.first() == Some(&0x16);
    let activity = Activity::new(started, true);
    let watched = Watched::new(io, prefix, activity.clone(), Mode::Http1);
    let mut connection = http1::Builder::new()
        .timer(TokioTimer::new())
        // The watchdog's header timeout, which leaves the wait between requests to the idle one.
        .header_read_timeout(None)
        .serve_connection(TokioIo::new(watched), Service::new(shared, &activity, Mode::Http1));
    let mut draining = false;
    let ended = loop {
        tokio::select! {
            result = &mut connection => break Ok(result),
            expired = watchdog(&activity, config) => break Err(expired),
            _ = drain.wait_for(|draining| *draining), if !draining => {
                // Idle: closed now; busy: closed after the answer.
                Pin::new(&mut connection).graceful_shutdown();
                draining = true;
            }
        }
    };
    match ended {
        Ok(result) => {
            let watched = connection.into_parts().io.into_inner();
            if let Some(status) = watched.held_back() {
                let answer = hyper_error_problem(status, result.err(), tls_on_cleartext);
                watched.answer_and_close(&answer, ANSWER_BOUND).await;
            } else if let Err(error) = result {
                // A client gone mid-answer, mostly: not worth more than debug.
                tracing::debug!(%error, "HTTP/1 connection ended");
            }
        }
        Err(Expired::Head) => {
            let watched = connection.into_parts().io.into_inner();
            watched
                .answer_and_close(&header_timeout_problem(config), ANSWER_BOUND)
                .await;
        }
        // Dropping the connection closes it.
        Err(Expired::Idle | Expired::Unread) => {}
    }
}

/// The problem in place of hyper's bodiless answer with `status`, in words from its error.
fn hyper_error_problem(status: u16, error: Option<hyper::Error>, tls_on_cleartext: bool) -> Vec<u8> {
    match status {
        414 => Protocol::UriTooLong.raw("the request target is longer than 65,534 bytes"),
        431 => Protocol::HeadersTooLarge.raw("the request has more than 100 header fields, or a head larger than this service reads"),
        _ if tls_on_cleartext => Protocol::BadRequest.raw(
            "this port speaks cleartext HTTP, and a TLS handshake was sent: use http://, or start the service with --tls-cert and --tls-key",
        ),
        _ => {
            let why = error.map_or_else(|| "unparsable".to_owned(), |e| e.to_string());
            Protocol::BadRequest.raw(format!("the request is not valid HTTP/1.1: {why}"))
        }
    }
}

async fn serve_http2<IO>(io: IO, prefix: Bytes, shared: &Arc<Shared>, mut drain: watch::Receiver<bool>)
where
    IO: AsyncRead + AsyncWrite + Unpin + Send + 'static,
{
    let config = &shared.config;
    let activity = Activity::new(Instant::now(), false);
    let watched = Watched::new(io, prefix, activity.clone(), Mode::Http2);
    let mut connection = http2::Builder::new(TokioExecutor::new())
        .timer(TokioTimer::new())
        .serve_connection(TokioIo::new(watched), Service::new(shared, &activity, Mode::Http2));
    let mut connection = Pin::new(&mut connection);
    let mut draining = false;
    // After an idle GOAWAY, the client has the header timeout to let the connection close.
    let mut closing: Option<tokio::time::Instant> = None;
    loop {
        tokio::select! {
            _ = &mut connection => return,
            expired = watchdog(&activity, config), if closing.is_none() => match expired {
                Expired::Idle => {
                    connection.as_mut().graceful_shutdown();
                    closing = Some(tokio::time::Instant::now() + config.header_timeout);
                }
                Expired::Head | Expired::Unread => return,
            },
            _ = drain.wait_for(|draining| *draining), if !draining => {
                // GOAWAY: open streams finish, no new ones start. A client that never reads it
                // is cut off by the drain deadline.
                connection.as_mut().graceful_shutdown();
                draining = true;
            }
            () = sleep_until_some(closing) => return,
        }
    }
}

async fn sleep_until_some(deadline: Option<tokio::time::Instant>) {
    match deadline {
        Some(deadline) => tokio::time::sleep_until(deadline).await,
        None => std::future::pending().await,
    }
}
