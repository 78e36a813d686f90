//! The socket as hyper sees it: the bytes read to tell the protocol handed back first, what the
//! connection is doing noted for its watchdog, and hyper's bodiless error answers held back so
//! that a problem+json can be written in their place.
//!
//! Owns: `Activity` (requests open, when the connection went idle, when a next head began, since
//! when a write has been blocked) and the recognition of hyper's own error heads.
//! Must not: parse requests or time anything itself: the watchdog reads `Activity`.

use std::io;
use std::pin::Pin;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::task::{Context, Poll, ready};
use std::time::{Duration, Instant};

use bytes::{Buf, Bytes};
use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt, ReadBuf};

/// What one connection is doing, shared by its socket, its requests and its watchdog. Times are
/// nanoseconds after `base`, plus one: 0 means never.
pub struct Activity {
    base: Instant,
    /// Requests whose answer has not been sent in full.
    open: AtomicUsize,
    /// When `open` last fell to 0 (0: never yet).
    idle_since: AtomicU64,
    /// When the first byte of a head arrived while no request was open (a head is being read
    /// when this is later than `idle_since`).
    head_since: AtomicU64,
    /// When a write started waiting for the client to read (0: no write is waiting).
    write_blocked_since: AtomicU64,
}

/// What the watchdog sees.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum State {
    /// A request is being worked on or answered.
    Busy,
    /// Waiting for a next request since then.
    Idle(Instant),
    /// Part of a head has arrived, the first byte then.
    Head(Instant),
}

impl Activity {
    /// A connection accepted at `base`; `head_begun`: the bytes read so far are the start of a
    /// head (HTTP/1), which must then be whole within the header timeout of `base`.
    pub fn new(base: Instant, head_begun: bool) -> Arc<Activity> {
        Arc::new(Activity {
            base,
            open: AtomicUsize::new(0),
            idle_since: AtomicU64::new(if head_begun { 0 } else { 1 }),
            head_since: AtomicU64::new(if head_begun { 1 } else { 0 }),
            write_blocked_since: AtomicU64::new(0),
        })
    }

    fn now(&self) -> u64 {
        u64::try_from(self.base.elapsed().as_nanos()).unwrap_or(u64::MAX - 1) + 1
    }

    fn instant(&self, stamp: u64) -> Instant {
        self.base + Duration::from_nanos(stamp.saturating_sub(1))
    }

    /// A request has arrived; its answer is sent in full when the guard drops.
    pub fn begin(self: &Arc<Self>) -> InFlight {
        self.open.fetch_add(1, Ordering::AcqRel);
        InFlight(self.clone())
    }

    pub fn state(&self) -> State {
        if self.open.load(Ordering::Acquire) > 0 {
            return State::Busy;
        }
        let idle = self.idle_since.load(Ordering::Acquire);
        let head = self.head_since.load(Ordering::Acquire);
        if head > idle {
            State::Head(self.instant(head))
        } else {
            State::Idle(self.instant(idle))
        }
    }

    /// Since when a write has waited for the client to read, if one is waiting.
    pub fn write_blocked_since(&self) -> Option<Instant> {
        match self.write_blocked_since.load(Ordering::Acquire) {
            0 => None,
            stamp => Some(self.instant(stamp)),
        }
    }

    fn read_some(&self) {
        if self.open.load(Ordering::Acquire) == 0 {
            let idle = self.idle_since.load(Ordering::Acquire);
            if self.head_since.load(Ordering::Acquire) <= idle {
                self.head_since.store(self.now(), Ordering::Release);
            }
        }
    }

    fn wrote<T>(&self, poll: &Poll<T>) {
        let blocked = self.write_blocked_since.load(Ordering::Relaxed);
        match (poll.is_pending(), blocked) {
            (true, 0) => self.write_blocked_since.store(self.now(), Ordering::Release),
            (false, stamp) if stamp != 0 => self.write_blocked_since.store(0, Ordering::Release),
            _ => {}
        }
    }
}

/// One request open on the connection, until its answer has been sent (hyper drops the body).
pub struct InFlight(Arc<Activity>);

impl Drop for InFlight {
    fn drop(&mut self) {
        if self.0.open.fetch_sub(1, Ordering::AcqRel) == 1 {
            self.0.idle_since.store(self.0.now(), Ordering::Release);
        }
    }
}

/// How the socket is read and written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Heads are noted for the header timeout, and hyper's bodiless error answers held back.
    Http1,
    Http2,
}

/// The socket under hyper.
pub struct Watched<IO> {
    inner: IO,
    /// Read before hyper took over, handed to it first.
    prefix: Bytes,
    activity: Arc<Activity>,
    mode: Mode,
    /// The status of the error answer hyper wrote (and this held back), if it did.
    held_back: Option<u16>,
}

impl<IO> Watched<IO> {
    pub fn new(inner: IO, prefix: Bytes, activity: Arc<Activity>, mode: Mode) -> Watched<IO> {
        Watched {
            inner,
            prefix,
            activity,
            mode,
            held_back: None,
        }
    }

    /// The status of hyper's error answer that was held back: 400, 414 or 431.
    pub fn held_back(&self) -> Option<u16> {
        self.held_back
    }

    /// Whether hyper's next write may be its error answer: only on HTTP/1, and only when no
    /// request is open (hyper answers a head it cannot parse before any handler sees it).
    fn may_be_hyper_error(&self) -> bool {
        self.mode == Mode::Http1 && self.held_back.is_none() && self.activity.open.load(Ordering::Acquire) == 0
    }
}

impl<IO: AsyncRead + AsyncWrite + Unpin> Watched<IO> {
    /// Writes `answer`, closes the sending side, and reads (and drops) what the client still
    /// sends for a moment, so that closing does not reset the connection before the client has
    /// read the answer. All within `bound`.
    pub async fn answer_and_close(mut self, answer: &[u8], bound: Duration) {
        const LINGER_BYTES: usize = 1 << 20;
        let _ = tokio::time::timeout(bound, async {
            self.inner.write_all(answer).await?;
            self.inner.flush().await?;
            self.inner.shutdown().await?;
            let mut sink = [0u8; 4096];
            let mut drained = 0;
            while drained < LINGER_BYTES {
                match self.inner.read(&mut sink).await? {
                    0 => break,
                    n => drained += n,
                }
            }
            Ok::<(), io::Error>(())
        })
        .await;
    }
}

/// hyper answers a head it cannot parse with a head of its own and no body: `HTTP/1.1 400 Bad
/// Request` (or 414, 431), then `connection: close`, `content-length: 0` and `date` only, as
/// the last bytes it ever writes on the connection. This finds such a head at the end of
/// `bytes`: where it starts and its status. Nothing else the service writes ends so: its own
/// 4xx answers always carry a problem body and a content type.
pub fn hyper_error_head(bytes: &[u8]) -> Option<(usize, u16)> {
    if !bytes.ends_with(b"\r\n\r\n") {
        return None;
    }
    let from = bytes.len().saturating_sub(192);
    let tail = &bytes[from..];
    let at = tail.windows(7).rposition(|w| w == b"HTTP/1.")?;
    let head = std::str::from_utf8(&tail[at..tail.len() - 4]).ok()?;
    let mut lines = head.split("\r\n");
    let status_line = lines.next()?;
    if !(status_line.starts_with("HTTP/1.1 ") || status_line.starts_with("HTTP/1.0 ")) {
        return None;
    }
    let status = match status_line.get(9..13)? {
        "400 " => 400,
        "414 " => 414,
        "431 " => 431,
        _ => return None,
    };
    let mut empty = false;
    for line in lines {
        let (name, value) = line.split_once(':')?;
        if name.eq_ignore_ascii_case("content-length") {
            empty = value.trim() == "0";
        } else if !(name.eq_ignore_ascii_case("connection") || name.eq_ignore_ascii_case("date")) {
            return None;
        }
    }
    empty.then_some((from + at, status))
}

impl<IO: AsyncRead + Unpin> AsyncRead for Watched<IO> {
    fn poll_read(self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &mut ReadBuf<'_>) -> Poll<io::Result<()>> {
        let this = self.get_mut();
        if this.prefix.has_remaining() {
            let n = this.prefix.len().min(buf.remaining());
            buf.put_slice(&this.prefix[..n]);
            this.prefix.advance(n);
            return Poll::Ready(Ok(()));
        }
        let before = buf.filled().len();
        ready!(Pin::new(&mut this.inner).poll_read(cx, buf))?;
        if this.mode == Mode::Http1 && buf.filled().len() > before {
            this.activity.read_some();
        }
        Poll::Ready(Ok(()))
    }
}

impl<IO: AsyncWrite + Unpin> AsyncWrite for Watched<IO> {
    fn poll_write(self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &[u8]) -> Poll<io::Result<usize>> {
        let this = self.get_mut();
        let mut to_write = buf;
        if this.may_be_hyper_error()
            && let Some((start, status)) = hyper_error_head(buf)
        {
            if start == 0 {
                this.held_back = Some(status);
                return Poll::Ready(Ok(buf.len()));
            }
            // The end of an earlier answer comes first; hyper writes the rest again after it.
            to_write = &buf[..start];
        }
        let poll = Pin::new(&mut this.inner).poll_write(cx, to_write);
        this.activity.wrote(&poll);
        poll
    }

    fn poll_write_vectored(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        bufs: &[io::IoSlice<'_>],
    ) -> Poll<io::Result<usize>> {
        let this = self.get_mut();
        if this.may_be_hyper_error()
            && let Some(last) = bufs.iter().rposition(|b| !b.is_empty())
            && let Some((start, status)) = hyper_error_head(&bufs[last])
        {
            let before: usize = bufs[..last].iter().map(|b| b.len()).sum();
            if before + start == 0 {
                this.held_back = Some(status);
                return Poll::Ready(Ok(bufs[last].len()));
            }
            // Only what precedes hyper's head; hyper writes the rest again after it.
            let mut slices: Vec<io::IoSlice<'_>> = bufs[..last].to_vec();
            slices.push(io::IoSlice::new(&bufs[last][..start]));
            let poll = Pin::new(&mut this.inner).poll_write_vectored(cx, &slices);
            this.activity.wrote(&poll);
            return poll;
        }
        let poll = Pin::new(&mut this.inner).poll_write_vectored(cx, bufs);
        this.activity.wrote(&poll);
        poll
    }

    fn is_write_vectored(&self) -> bool {
        self.inner.is_write_vectored()
    }

    fn poll_flush(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        let this = self.get_mut();
        let poll = Pin::new(&mut this.inner).poll_flush(cx);
        this.activity.wrote(&poll);
        poll
    }

    fn poll_shutdown(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        let this = self.get_mut();
        if this.held_back.is_some() {
            // The problem is written in place of hyper's answer before the connection closes.
            return Poll::Ready(Ok(()));
        }
        Pin::new(&mut this.inner).poll_shutdown(cx)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hypers_error_heads_are_found_at_the_end_and_nothing_else_is() {
        let hyper = b"HTTP/1.1 400 Bad Request\r\nconnection: close\r\ncontent-length: 0\r\ndate: Tue, 01 Dec 2026 09:00:36 GMT\r\n\r\n";
        assert_eq!(hyper_error_head(hyper), Some((0, 400)));
        let answer = b"HTTP/1.1 200 OK\r\ncontent-length: 2\r\n\r\n{}";
        let after_an_answer = [&answer[..], hyper].concat();
        assert_eq!(hyper_error_head(&after_an_answer), Some((answer.len(), 400)));
        let long = b"HTTP/1.1 431 Request Header Fields Too Large\r\nconnection: close\r\ncontent-length: 0\r\ndate: Tue, 01 Dec 2026 09:00:36 GMT\r\n\r\n";
        assert_eq!(hyper_error_head(long), Some((0, 431)));
        for ours in [
            &b"HTTP/1.1 400 Bad Request\r\ncontent-type: application/problem+json\r\ncontent-length: 0\r\n\r\n"[..],
            b"HTTP/1.1 204 No Content\r\ndate: Tue, 01 Dec 2026 09:00:36 GMT\r\n\r\n",
            b"HTTP/1.1 400 Bad Request\r\ncontent-length: 12\r\n\r\n",
            b"{\"status\":\"ok\"}",
        ] {
            assert_eq!(hyper_error_head(ours), None, "{}", String::from_utf8_lossy(ours));
        }
    }

    #[test]
    fn activity_tells_busy_idle_and_a_head_begun() {
        let base = Instant::now();
        let activity = Activity::new(base, true);
        assert!(matches!(activity.state(), State::Head(t) if t == base));
        let request = activity.begin();
        activity.read_some();
        assert_eq!(activity.state(), State::Busy);
        drop(request);
        assert!(matches!(activity.state(), State::Idle(_)));
        activity.read_some();
        assert!(matches!(activity.state(), State::Head(_)));
        assert_eq!(Activity::new(base, false).state(), State::Idle(base));
    }
}
