//! The request span's fields (method, path, request id) are formatted when the first line
//! inside the span is written, not when the span is made: most requests write no line, and
//! formatting them for every request cost about a fortieth of its work.
//!
//! Owns: holding a deferred span's text values until a line needs them. Must not: change what
//! a line says: a line written inside a deferred span reads as the log formatter wrote it when
//! the values were given as `%` (Display) fields (a test compares the two).

use std::any::TypeId;

use tracing::field::{DisplayValue, Field, Value, Visit};
use tracing::span::{Attributes, Id, Record};
use tracing::subscriber::Interest;
use tracing::{Event, Metadata, Subscriber};
use tracing_subscriber::fmt::{FormatFields, FormattedFields};
use tracing_subscriber::layer::{Context, Layer};
use tracing_subscriber::registry::{LookupSpan, SpanRef};

/// The most fields a deferred span holds; the request span has three. A span with more, or
/// with a field that is not text, is formatted at once, as any other span.
const MOST: usize = 4;

/// Wraps the log formatter `L`, whose span fields are formatted by `N`: the spans `defer`
/// picks keep their text values as given, and become `FormattedFields<N>` only when an event
/// inside them, or a value recorded on them later, is about to be formatted.
pub struct Deferred<L, N> {
    inner: L,
    fields: N,
    defer: fn(&Metadata<'_>) -> bool,
}

impl<L, N> Deferred<L, N> {
    /// `fields` must be the formatter `inner` formats span fields with (it makes the same
    /// text): `DefaultFields` for plain text, `JsonFields` for JSON.
    pub fn new(inner: L, fields: N, defer: fn(&Metadata<'_>) -> bool) -> Deferred<L, N> {
        Deferred { inner, fields, defer }
    }
}

/// A deferred span's values, in the order given: all their text in one buffer, and each
/// field with the end of its text there.
struct Pending {
    text: String,
    ends: [Option<(Field, usize)>; MOST],
}

/// Takes a span's values while they are all text and there are at most [`MOST`] of them.
struct Capture {
    pending: Pending,
    count: usize,
    deferrable: bool,
}

impl Visit for Capture {
    fn record_str(&mut self, field: &Field, value: &str) {
        if self.count == MOST {
            self.deferrable = false;
            return;
        }
        self.pending.text.push_str(value);
        self.pending.ends[self.count] = Some((field.clone(), self.pending.text.len()));
        self.count += 1;
    }

    /// Every value that is not text comes here: it would need formatting now.
    fn record_debug(&mut self, _: &Field, _: &dyn std::fmt::Debug) {
        self.deferrable = false;
    }
}

impl<L, N> Deferred<L, N>
where
    N: for<'w> FormatFields<'w> + 'static,
{
    /// The span's fields as `inner` would have formatted them, the values shown as Display.
    fn format(&self, pending: &Pending, metadata: &'static Metadata<'static>) -> FormattedFields<N> {
        let mut formatted = FormattedFields::<N>::new(String::new());
        let Some((first, _)) = &pending.ends[0] else {
            return formatted;
        };
        let mut start = 0;
        let shown: [Option<(&Field, DisplayValue<&str>)>; MOST] = std::array::from_fn(|i| {
            let (field, end) = pending.ends[i].as_ref()?;
            let value = tracing::field::display(&pending.text[start..*end]);
            start = *end;
            Some((field, value))
        });
        let values: [(&Field, Option<&dyn Value>); MOST] = std::array::from_fn(|i| match &shown[i] {
            Some((field, value)) => (*field, Some(value as &dyn Value)),
            None => (first, None),
        });
        let set = metadata.fields().value_set(&values);
        // Formatting into a String fails only if a value's Display does, and these are text.
        let _ = self.fields.format_fields(formatted.as_writer(), Record::new(&set));
        formatted
    }

    /// Formats the span's fields now, if they were deferred and not yet formatted.
    fn settle<S>(&self, span: &SpanRef<'_, S>)
    where
        S: for<'a> LookupSpan<'a>,
    {
        let mut extensions = span.extensions_mut();
        if let Some(pending) = extensions.remove::<Pending>() {
            // `replace`, not `insert`, which panics on a value already there: another layer
            // formatting with the same `N` may have put one.
            extensions.replace(self.format(&pending, span.metadata()));
        }
    }
}

impl<S, L, N> Layer<S> for Deferred<L, N>
where
    S: Subscriber + for<'a> LookupSpan<'a>,
    L: Layer<S>,
    N: for<'w> FormatFields<'w> + Send + Sync + 'static,
{
    fn on_register_dispatch(&self, subscriber: &tracing::Dispatch) {
        self.inner.on_register_dispatch(subscriber);
    }

    fn on_layer(&mut self, subscriber: &mut S) {
        self.inner.on_layer(subscriber);
    }

    fn register_callsite(&self, metadata: &'static Metadata<'static>) -> Interest {
        self.inner.register_callsite(metadata)
    }

    fn enabled(&self, metadata: &Metadata<'_>, ctx: Context<'_, S>) -> bool {
        self.inner.enabled(metadata, ctx)
    }

    fn on_new_span(&self, attrs: &Attributes<'_>, id: &Id, ctx: Context<'_, S>) {
        if (self.defer)(attrs.metadata())
            && let Some(span) = ctx.span(id)
        {
            let mut capture = Capture {
                // Sized for the request span: a method, a path and a 36-character id.
                pending: Pending {
                    text: String::with_capacity(96),
                    ends: Default::default(),
                },
                count: 0,
                deferrable: true,
            };
            attrs.record(&mut capture);
            if capture.deferrable {
                span.extensions_mut().insert(capture.pending);
                return;
            }
        }
        self.inner.on_new_span(attrs, id, ctx);
    }

    fn on_record(&self, id: &Id, values: &Record<'_>, ctx: Context<'_, S>) {
        if let Some(span) = ctx.span(id) {
            self.settle(&span);
        }
        self.inner.on_record(id, values, ctx);
    }

    fn on_follows_from(&self, span: &Id, follows: &Id, ctx: Context<'_, S>) {
        self.inner.on_follows_from(span, follows, ctx);
    }

    fn event_enabled(&self, event: &Event<'_>, ctx: Context<'_, S>) -> bool {
        self.inner.event_enabled(event, ctx)
    }

    fn on_event(&self, event: &Event<'_>, ctx: Context<'_, S>) {
        if let Some(scope) = ctx.event_scope(event) {
            for span in scope {
                self.settle(&span);
            }
        }
        self.inner.on_event(event, ctx);
    }

    fn on_enter(&self, id: &Id, ctx: Context<'_, S>) {
        self.inner.on_enter(id, ctx);
    }

    fn on_exit(&self, id: &Id, ctx: Context<'_, S>) {
        self.inner.on_exit(id, ctx);
    }

    fn on_close(&self, id: Id, ctx: Context<'_, S>) {
        self.inner.on_close(id, ctx);
    }

    fn on_id_change(&self, old: &Id, new: &Id, ctx: Context<'_, S>) {
        self.inner.on_id_change(old, new, ctx);
    }

    unsafe fn downcast_raw(&self, id: TypeId) -> Option<*const ()> {
        match id {
            id if id == TypeId::of::<Self>() => Some(self as *const Self as *const ()),
            // SAFETY: the inner layer's own answer to the same question.
            _ => unsafe { self.inner.downcast_raw(id) },
        }
    }
}

#[cfg(test)]
mod tests {
    use std::io::Write;
    use std::sync::{Arc, Mutex};

    use tracing_subscriber::Registry;
    use tracing_subscriber::fmt::format::{DefaultFields, JsonFields};
    use tracing_subscriber::layer::SubscriberExt;
    use tracing_subscriber::registry::{LookupSpan, SpanData};

    use super::Deferred;

    /// Everything written, shared with the test.
    #[derive(Clone, Default)]
    struct Lines(Arc<Mutex<Vec<u8>>>);

    impl Write for Lines {
        fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
            self.0.lock().unwrap().extend_from_slice(bytes);
            Ok(bytes.len())
        }

        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    impl Lines {
        fn text(&self) -> String {
            String::from_utf8(self.0.lock().unwrap().clone()).unwrap()
        }
    }

    fn deferred(metadata: &tracing::Metadata<'_>) -> bool {
        metadata.name() == "request"
    }

    /// Whether the span's fields wait to be formatted.
    fn pending(id: &tracing::Id) -> bool {
        tracing::dispatcher::get_default(|dispatch| {
            let registry = dispatch
                .downcast_ref::<Registry>()
                .expect("a registry below the layers");
            let span = registry.span_data(id).expect("the span is open");
            span.extensions().get::<super::Pending>().is_some()
        })
    }

    /// One request's worth of logging: an event inside the span, one in a child span, a value
    /// recorded on the span afterwards, and another event.
    fn log_a_request(eager: bool) {
        let (method, path, id) = ("POST", "/v1/clarify", "7f0c \"quoted\" \u{1b}[31m");
        let span = match eager {
            true => {
                tracing::info_span!("request", method = %method, path = %path, request_id = %id, later = tracing::field::Empty)
            }
            false => tracing::info_span!("request", method, path, request_id = id, later = tracing::field::Empty),
        };
        let _in = span.enter();
        let waiting = || pending(&span.id().expect("the span is on"));
        assert_eq!(waiting(), !eager, "deferred until a line is written");
        tracing::warn!(readings = 2, "first");
        assert!(!waiting(), "formatted for the first line");
        tracing::info_span!("inner", step = 1).in_scope(|| tracing::warn!("second"));
        span.record("later", 5);
        tracing::warn!("third");
        // Not all text: formatted when made, whichever way.
        tracing::info_span!("request", method, readings = 3).in_scope(|| tracing::warn!("fourth"));
    }

    fn written(json: bool, eager: bool) -> String {
        let lines = Lines::default();
        let writer = {
            let lines = lines.clone();
            move || lines.clone()
        };
        let layer = tracing_subscriber::fmt::layer()
            .with_ansi(false)
            .without_time()
            .with_writer(writer);
        let subscriber = tracing_subscriber::registry();
        match (json, eager) {
            (false, true) => tracing::subscriber::with_default(subscriber.with(layer), || log_a_request(true)),
            (false, false) => tracing::subscriber::with_default(
                subscriber.with(Deferred::new(layer, DefaultFields::new(), deferred)),
                || log_a_request(false),
            ),
            (true, true) => tracing::subscriber::with_default(subscriber.with(layer.json()), || log_a_request(true)),
            (true, false) => tracing::subscriber::with_default(
                subscriber.with(Deferred::new(layer.json(), JsonFields::new(), deferred)),
                || log_a_request(false),
            ),
        }
        lines.text()
    }

    #[test]
    fn deferred_text_fields_are_written_as_the_formatter_writes_display_fields() {
        let eager = written(false, true);
        assert_eq!(eager.lines().count(), 4, "{eager}");
        assert!(eager.contains("method=POST path=/v1/clarify"), "{eager}");
        assert_eq!(written(false, false), eager);
    }

    #[test]
    fn deferred_json_fields_are_written_as_the_formatter_writes_display_fields() {
        let eager = written(true, true);
        assert_eq!(eager.lines().count(), 4, "{eager}");
        assert!(
            eager.contains(r#""request_id":"7f0c \"quoted\" \u001b[31m""#),
            "{eager}"
        );
        assert_eq!(written(true, false), eager);
    }
}
