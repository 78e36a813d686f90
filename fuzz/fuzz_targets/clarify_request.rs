//! Fuzzes `POST /v1/clarify` below HTTP: body bytes through the JSON decoding, the engine's
//! constructors, the engine and the response body, as core chains them. An input may also
//! define verbs first, `{"verbs": {"name": VERB, ...}, "request": BODY}`: each is stored as
//! `PUT /v1/actions/{name}` would store it (refused when invalid, looping or over the expansion
//! bound), so that expansion is fuzzed too; any other input is the body itself.
//!
//! Owns: the promise that no body makes any of those panic or run past its deadline. Errors
//! are expected answers. Must not: open a store or a socket (the norms are fixed here).
#![no_main]

use std::sync::LazyLock;
use std::time::{Duration, Instant};

use libfuzzer_sys::fuzz_target;
use scruple::engine::action::{ActionInput, Library};
use scruple::engine::clarify;
use scruple::engine::input::RequestLimits;
use scruple::engine::norms::{CompiledNorms, Norm, NormInput};
use scruple::engine::request::Request;
use scruple::wire::{ClarifyBody, DecisionDto, parse_json};

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

/// The default library with each verb of `verbs` added as the store would take it: a verb that
/// is invalid, loops, or would make some verb expand past the bound is refused, the rest kept.
fn library_with(verbs: &serde_json::Map<String, serde_json::Value>) -> Library {
    let mut written: Vec<(String, ActionInput)> = LIBRARY
        .verbs()
        .into_iter()
        .map(|d| (d.name.to_string(), d.to_input()))
        .collect();
    for (name, verb) in verbs {
        let Ok(input) = serde_json::from_value::<ActionInput>(verb.clone()) else {
            continue;
        };
        if input.validate(name).is_err() {
            continue;
        }
        let mut candidate = written.clone();
        candidate.retain(|(n, _)| n != name);
        candidate.push((name.clone(), input));
        if Library::from_written(1, &candidate)
            .and_then(|l| l.check_expansion(name))
            .is_ok()
        {
            written = candidate;
        }
    }
    Library::from_written(1, &written).expect("every verb kept was accepted with the others")
}

fuzz_target!(|bytes: &[u8]| {
    let defined = serde_json::from_slice::<serde_json::Value>(bytes).ok().and_then(|v| {
        match (v.get("verbs"), v.get("request")) {
            (Some(serde_json::Value::Object(verbs)), Some(request)) => Some((verbs.clone(), request.clone())),
            _ => None,
        }
    });
    let (library, body) = match &defined {
        Some((verbs, request)) => (
            Some(library_with(verbs)),
            serde_json::to_vec(request).unwrap_or_default(),
        ),
        None => (None, bytes.to_vec()),
    };
    let library = library.as_ref().unwrap_or(&LIBRARY);
    let Ok(body) = parse_json::<ClarifyBody>(&body) else {
        return;
    };
    let text = body.directive.text.clone();
    let Ok(input) = Request::from_input(body.into(), &RequestLimits::default()) else {
        return;
    };
    let started = Instant::now();
    let deadline = started + input.deadline.min(DEADLINE_CAP);
    let expired = || Instant::now() >= deadline;
    let Ok(decision) = clarify(&input.request, &input.scene, &NORMS, library, &expired) else {
        return;
    };
    // The deadline is asked before every step a plan expands: a decision ends soon after it.
    let took = started.elapsed();
    assert!(
        took < DEADLINE_CAP * 3,
        "a decision took {took:?} against a deadline of {:?}",
        input.deadline.min(DEADLINE_CAP)
    );
    let answer = DecisionDto::new(&decision, text);
    serde_json::to_vec(&answer).expect("a decision always serializes");
});
