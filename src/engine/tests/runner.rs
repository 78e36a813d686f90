//! What a case expects, and the runner that reports every difference.

use super::*;

// Expectations and the table runner

/// A reason as the contract shows it: kind, detail, norm id.
pub(super) type R = (&'static str, &'static str, Option<i64>);

pub(super) struct Interp {
    action: &'static str,
    description: &'static str,
    reasons: Vec<R>,
    plan: Vec<&'static str>,
}

/// An expected interpretation; `permissible` and `feasible` follow from the reasons' kinds, as the
/// contract defines them.
pub(super) fn interp(
    action: &'static str,
    description: &'static str,
    reasons: Vec<R>,
    plan: &[&'static str],
) -> Interp {
    Interp {
        action,
        description,
        reasons,
        plan: plan.to_vec(),
    }
}

pub(super) struct Expect {
    kind: DecisionKind,
    goal: Option<&'static str>,
    utterance: &'static str,
    speech_act: Option<&'static str>,
    /// `None`: not checked.
    interpretations: Option<Vec<Interp>>,
}

pub(super) fn expect(kind: DecisionKind, goal: Option<&'static str>, utterance: &'static str) -> Expect {
    Expect {
        kind,
        goal,
        utterance,
        speech_act: None,
        interpretations: None,
    }
}

impl Expect {
    pub(super) fn act(self, speech_act: &'static str) -> Expect {
        Expect {
            speech_act: Some(speech_act),
            ..self
        }
    }

    pub(super) fn interps(self, interpretations: Vec<Interp>) -> Expect {
        Expect {
            interpretations: Some(interpretations),
            ..self
        }
    }
}

pub(super) struct Case {
    name: &'static str,
    scene: Scene,
    norms: CompiledNorms,
    request: Request,
    expect: Expect,
}

pub(super) fn case(name: &'static str, scene: Scene, norms: CompiledNorms, request: Request, expect: Expect) -> Case {
    Case {
        name,
        scene,
        norms,
        request,
        expect,
    }
}

pub(super) fn is_forbidden(kind: &str) -> bool {
    kind.starts_with("forbidden_")
}

pub(super) fn is_soft(kind: &str) -> bool {
    kind.starts_with("discouraged_") || kind.starts_with("preferred_")
}

/// Every difference between the decision and the expectation, each naming the case.
pub(super) fn mismatches(name: &str, d: &Decision, e: &Expect) -> Vec<String> {
    let mut out = Vec::new();
    let mut differ = |what: &str, got: String, want: String| {
        if got != want {
            out.push(format!("[{name}] {what}:\n     got: {got}\n    want: {want}"));
        }
    };
    differ("decision", d.kind.as_str().into(), e.kind.as_str().into());
    differ(
        "goal",
        format!("{:?}", d.goal.as_ref().map(Term::to_string)),
        format!("{:?}", e.goal),
    );
    differ("utterance", d.utterance.clone(), e.utterance.into());
    if let Some(speech_act) = e.speech_act {
        differ("speech_act", d.speech_act.to_string(), speech_act.into());
    }
    if let Some(want) = &e.interpretations {
        let got_actions: Vec<String> = d.interpretations.iter().map(|i| i.action.to_string()).collect();
        let want_actions: Vec<String> = want.iter().map(|i| i.action.to_string()).collect();
        differ(
            "interpretations' order",
            format!("{got_actions:?}"),
            format!("{want_actions:?}"),
        );
        for (got, want) in d.interpretations.iter().zip(want) {
            let at = format!("interpretation {}", want.action);
            differ(
                &format!("{at} description"),
                got.description.clone(),
                want.description.into(),
            );
            let got_reasons: Vec<(String, String, Option<i64>)> = got
                .outcome
                .reasons
                .iter()
                .map(|r| (r.kind().to_owned(), r.detail(), r.norm_id))
                .collect();
            let want_reasons: Vec<(String, String, Option<i64>)> = want
                .reasons
                .iter()
                .map(|(k, d, n)| (k.to_string(), d.to_string(), *n))
                .collect();
            differ(
                &format!("{at} reasons"),
                format!("{got_reasons:?}"),
                format!("{want_reasons:?}"),
            );
            let got_plan: Vec<String> = got.outcome.plan.iter().map(Term::to_string).collect();
            differ(
                &format!("{at} plan"),
                format!("{got_plan:?}"),
                format!("{:?}", want.plan),
            );
            let permissible = !want.reasons.iter().any(|(k, _, _)| is_forbidden(k));
            let feasible = (want.reasons.iter()).all(|(k, _, _)| is_forbidden(k) || is_soft(k));
            differ(
                &format!("{at} permissible"),
                got.permissible().to_string(),
                permissible.to_string(),
            );
            differ(
                &format!("{at} feasible"),
                got.feasible().to_string(),
                feasible.to_string(),
            );
        }
    }
    out
}

pub(super) fn run_cases(cases: Vec<Case>) {
    let mut failures = Vec::new();
    for c in &cases {
        match clarify(&c.request, &c.scene, &c.norms, &Library::default_library(), &|| false) {
            Ok(d) => failures.extend(mismatches(c.name, &d, &c.expect)),
            Err(e) => failures.push(format!("[{}] clarify failed: {e}", c.name)),
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases differ:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

pub(super) const FA: &str = "forbidden_action";
pub(super) const FS: &str = "forbidden_state";
