//! Request bodies with a deadline: a body must arrive whole within `--body-timeout-ms` of the
//! handler starting to read it, so a client that stalls half-way cannot hold a request (and its
//! connection) open.
//!
//! Owns: the deadline and the error a stalled read ends in, and telling the connection whether
//! the body was read to its end. Must not: allocate per request (the timer lives in the body,
//! which axum boxes once anyway; the flag is the connection's) or limit sizes (that is the REST
//! layer's, and gRPC's own).

use std::fmt;
use std::pin::Pin;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::task::{Context, Poll, ready};
use std::time::Duration;

use bytes::Bytes;
use http_body::{Body, Frame, SizeHint};
use tokio::time::Sleep;

/// What a read of a body that missed its deadline ends in; `rest` answers it with 408.
#[derive(Debug)]
pub struct BodyTimeout(pub Duration);

impl fmt::Display for BodyTimeout {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "the request body did not arrive within {} ms", self.0.as_millis())
    }
}

impl std::error::Error for BodyTimeout {}

/// Whether `error`, or any error it wraps, is a `BodyTimeout`.
pub fn timed_out<'a>(error: &'a (dyn std::error::Error + 'static)) -> Option<&'a BodyTimeout> {
    let mut current = Some(error);
    while let Some(error) = current {
        if let Some(timeout) = error.downcast_ref::<BodyTimeout>() {
            return Some(timeout);
        }
        current = error.source();
    }
    None
}

pin_project_lite::pin_project! {
    /// `inner` with a deadline, set when the body is first read.
    pub struct TimedBody<B> {
        #[pin]
        inner: B,
        #[pin]
        deadline: Option<Sleep>,
        limit: Duration,
        // Set once the body has been read to its end (an HTTP/1.1 connection's, which carries one
        // request at a time; none for HTTP/2).
        read: Option<Arc<AtomicBool>>,
    }
}

impl<B> TimedBody<B> {
    pub fn new(inner: B, limit: Duration, read: Option<Arc<AtomicBool>>) -> TimedBody<B> {
        TimedBody {
            inner,
            deadline: None,
            limit,
            read,
        }
    }
}

impl<B> Body for TimedBody<B>
where
    B: Body<Data = Bytes>,
    B::Error: Into<Box<dyn std::error::Error + Send + Sync>>,
{
    type Data = Bytes;
    type Error = Box<dyn std::error::Error + Send + Sync>;

    fn poll_frame(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Option<Result<Frame<Bytes>, Self::Error>>> {
        let mut this = self.project();
        if this.deadline.is_none() {
            this.deadline.set(Some(tokio::time::sleep(*this.limit)));
        }
        if let Poll::Ready(frame) = this.inner.as_mut().poll_frame(cx) {
            if let Some(read) = this.read
                && (frame.is_none() || this.inner.is_end_stream())
            {
                read.store(true, Ordering::Relaxed);
            }
            return Poll::Ready(frame.map(|f| f.map_err(Into::into)));
        }
        if let Some(deadline) = this.deadline.as_pin_mut() {
            ready!(deadline.poll(cx));
            return Poll::Ready(Some(Err(Box::new(BodyTimeout(*this.limit)))));
        }
        Poll::Pending
    }

    fn is_end_stream(&self) -> bool {
        self.inner.is_end_stream()
    }

    fn size_hint(&self) -> SizeHint {
        self.inner.size_hint()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use http_body_util::BodyExt;

    /// A body that sends its one chunk, if it has one, then nothing ever again.
    struct Stalls(Option<Bytes>);

    impl Body for Stalls {
        type Data = Bytes;
        type Error = std::convert::Infallible;

        fn poll_frame(
            mut self: Pin<&mut Self>,
            _: &mut Context<'_>,
        ) -> Poll<Option<Result<Frame<Bytes>, Self::Error>>> {
            match self.0.take() {
                Some(chunk) => Poll::Ready(Some(Ok(Frame::data(chunk)))),
                None => Poll::Pending,
            }
        }
    }

    /// The deadline runs from the first read, also while the handler is not reading: a read
    /// after it fails as soon as the timer is looked at, rather than waiting a limit again.
    #[tokio::test]
    async fn the_deadline_runs_from_the_first_read_while_the_handler_is_not_reading() {
        let limit = Duration::from_millis(200);
        let mut body = std::pin::pin!(TimedBody::new(Stalls(Some(Bytes::from_static(b"{"))), limit, None));
        assert!(matches!(body.frame().await, Some(Ok(_))));
        // The handler does other work past the deadline before it reads again.
        std::thread::sleep(limit + Duration::from_millis(50));
        match tokio::time::timeout(limit / 2, body.frame()).await {
            Ok(Some(Err(error))) => assert!(timed_out(&*error).is_some(), "{error}"),
            Ok(other) => panic!("the second read should time out: {other:?}"),
            Err(_) => panic!("the second read waited as if its deadline had started again"),
        }
    }

    #[tokio::test]
    async fn a_stalled_body_fails_at_its_deadline_and_a_whole_one_does_not() {
        let error = TimedBody::new(Stalls(None), Duration::from_millis(30), None)
            .collect()
            .await
            .expect_err("the read fails");
        let timeout = timed_out(&*error).expect("a BodyTimeout");
        assert_eq!(timeout.0, Duration::from_millis(30));
        assert_eq!(error.to_string(), "the request body did not arrive within 30 ms");

        let read = Arc::new(AtomicBool::new(false));
        let whole = TimedBody::new(
            http_body_util::Full::new(Bytes::from_static(b"{}")),
            Duration::from_secs(1),
            Some(read.clone()),
        );
        assert_eq!(whole.collect().await.unwrap().to_bytes(), Bytes::from_static(b"{}"));
        assert!(read.load(Ordering::Relaxed), "read to its end");
    }
}
