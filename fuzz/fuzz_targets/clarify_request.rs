//! Fuzzes `POST /v1/clarify` below HTTP: body bytes through the REST decoding, the boundary
//! validation, the engine and the response body, as the handler chains them.
//!
//! Owns: the promise that no body makes any of those panic or run past its deadline. Errors
//! are expected answers. Must not: open a store or a socket (the norms are fixed here).
#![no_main]

use std::sync::LazyLock;
use std::time::{Duration, Instant};

use libfuzzer_sys::fuzz_target;
use scruple::api::{ClarifyBody, ClarifyInput, DecisionDto, parse_json};
use scruple::engine::action::Library;
use scruple::engine::clarify;
use scruple::engine::norms::{CompiledNorms, Norm, NormInput};

/// The longest one decision may take here, whatever the body asks: a body cannot slow the
/// fuzzer down by asking for the service's full 60 s.
const DEADLINE_CAP: Duration = Duration::from_secs(1);

/// The paper's norms plus ones with variables, conditions, a context and roles, so that every
/// kind of check the engine has is reachable from a body.
static NORMS: LazyLock<CompiledNorms> = LazyLock::new(|| {
    let norm = |kind: &str, term: &str| {
        let mut input = NormInput {
            kind: Some(kind.into()),
            ..NormInput::default()
        };
        if kind == "forbidden_action" {
            input.action = Some(term.into());
        } else {
            input.state = Some(term.into());
        }
        input
    };
    let inputs = vec![
        norm("forbidden_action", "destroy"),
        norm("forbidden_state", "did(self,get(object3))"),
        norm("forbidden_action", "steal"),
        NormInput {
            when: Some(vec!["fragile(X)".into()]),
            ..norm("forbidden_state", "holding(self,X)")
        },
        NormInput {
            context: Some("hospital".into()),
            exempt_roles: Some(vec!["owner".into()]),
            ..norm("forbidden_action", "pointTo(X)")
        },
        NormInput {
            roles: Some(vec!["child".into()]),
            severity: Some(5),
            ..norm("forbidden_state", "on(X,Y)")
        },
    ];
    let norms = inputs
        .into_iter()
        .enumerate()
        .map(|(i, input)| Norm {
            id: i as i64 + 1,
            revision: 0,
            spec: input.validate().expect("the fuzzer's own norms are valid"),
        })
        .collect();
    CompiledNorms::compile(6, norms)
});

static LIBRARY: LazyLock<Library> = LazyLock::new(Library::default_library);

fuzz_target!(|bytes: &[u8]| {
    let Ok(body) = parse_json::<ClarifyBody>(bytes) else {
        return;
    };
    let Ok(mut input) = ClarifyInput::try_from(body) else {
        return;
    };
    let started = Instant::now();
    let deadline = started + input.deadline.min(DEADLINE_CAP);
    let expired = || Instant::now() >= deadline;
    let text = input.text.take();
    let Ok(decision) = clarify(&input.request, &input.scene, &NORMS, &LIBRARY, &expired) else {
        return;
    };
    // The deadline is checked between readings, so one reading may run past it, but not by much.
    let took = started.elapsed();
    assert!(
        took < DEADLINE_CAP * 3,
        "a decision took {took:?} against a deadline of {:?}",
        input.deadline.min(DEADLINE_CAP)
    );
    let answer = DecisionDto::new(&decision, text);
    serde_json::to_vec(&answer).expect("a decision always serializes");
});
