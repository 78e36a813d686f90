//! The safety invariant, property-tested.

use super::*;

// The safety invariant, property-tested

const TYPES: [&str; 3] = ["vase", "mug", "cash_box"];
const VERBS: [&str; 6] = ["get", "destroy", "steal", "pointTo", "juggle", "put"];

/// One random object: type index, fragile, heavy, colour, out of reach, y offset, has a shape.
type ObjGen = (usize, bool, bool, Option<&'static str>, bool, f64, bool);

fn arb_object() -> impl Strategy<Value = ObjGen> {
    (
        0..3usize,
        any::<bool>(),
        any::<bool>(),
        prop_oneof![Just(None), Just(Some("red")), Just(Some("green"))],
        prop::bool::weighted(0.3),
        -0.4..0.4f64,
        any::<bool>(),
    )
}

fn arb_context() -> impl Strategy<Value = Option<&'static str>> {
    prop_oneof![Just(None), Just(Some("default")), Just(Some("hospital"))]
}

fn arb_when() -> impl Strategy<Value = Option<&'static str>> {
    prop_oneof![
        2 => Just(None),
        1 => Just(Some("fragile(X)")),
        1 => Just(Some("heavy(X)")),
        1 => Just(Some("color(X,red)")),
        1 => Just(Some("holding(self,X)")),
        1 => Just(Some("on(X,Y)")),
    ]
}

fn arb_norm() -> impl Strategy<Value = NormInput> {
    prop_oneof![arb_forbidden(), arb_soft()]
}

/// A soft norm, usually on a property that tells readings apart, so that scores differ.
fn arb_soft() -> impl Strategy<Value = NormInput> {
    let cond = prop_oneof![
        1 => Just(None),
        2 => Just(Some("fragile(X)")),
        2 => Just(Some("color(X,red)")),
        1 => Just(Some("heavy(X)")),
    ];
    (0..4usize, 0..7usize, 1..=5i64, cond, arb_context()).prop_map(|(kind, term, severity, cond, context)| {
        let kind = [
            "discouraged_action",
            "preferred_action",
            "discouraged_state",
            "preferred_state",
        ][kind];
        let term = if kind.ends_with("_action") {
            [
                "get(X)",
                "destroy(X)",
                "steal(X)",
                "put(X,Y)",
                "pointTo(X)",
                "get",
                "put(Y,X)",
            ][term]
        } else {
            [
                "holding(self,X)",
                "destroyed(X)",
                "on(X,Y)",
                "holding(self,X)",
                "destroyed(X)",
                "on(Y,X)",
                "did(self,get(X))",
            ][term]
        };
        let (action, state) = match kind.ends_with("_action") {
            true => (Some(term.to_owned()), None),
            false => (None, Some(term.to_owned())),
        };
        let norm = NormInput {
            kind: Some(kind.to_owned()),
            action,
            state,
            severity: Some(severity),
            ..NormInput::default()
        };
        finish(norm, cond, context)
    })
}

fn arb_forbidden() -> impl Strategy<Value = NormInput> {
    let action =
        (0..5usize, any::<bool>(), arb_when(), arb_context()).prop_map(|(verb, with_variable, cond, context)| {
            let name = ["get", "destroy", "steal", "put", "pointTo"][verb];
            let text = match (with_variable, name) {
                (false, _) => name.to_owned(),
                (true, "put") => "put(X,Y)".to_owned(),
                (true, _) => format!("{name}(X)"),
            };
            finish(fa(&text), cond, context)
        });
    let state = (0..3usize, 1..=6usize, arb_when(), arb_context()).prop_map(|(which, n, cond, context)| {
        let text = match which {
            0 => "holding(self,X)".to_owned(),
            1 => "destroyed(X)".to_owned(),
            _ => format!("did(self,get(object{n}))"),
        };
        finish(fs(&text), cond, context)
    });
    prop_oneof![action, state]
}

fn finish(norm: NormInput, cond: Option<&str>, context: Option<&str>) -> NormInput {
    let norm = match cond {
        Some(c) => when(norm, &[c]),
        None => norm,
    };
    match context {
        Some(c) => in_context(norm, c),
        None => norm,
    }
}

fn random_scene(objects: &[ObjGen], type_count: usize, on_table: &[bool]) -> Scene {
    let objects: Vec<Object> = objects
        .iter()
        .enumerate()
        .map(|(i, &(kind, fragile, heavy, color, far, y, shaped))| {
            let mut properties = Vec::new();
            if fragile {
                properties.push("fragile");
            }
            if heavy {
                properties.push("heavy");
            }
            let attributes: Vec<(&str, &str)> = color.map(|c| ("color", c)).into_iter().collect();
            let x = if far { 2.5 } else { 0.5 };
            let shape = shaped.then_some(Shape::Ball { radius: 0.05 });
            obj(
                &format!("object{}", i + 1),
                TYPES[kind % type_count],
                &properties,
                &attributes,
                [x, y, 0.8],
                shape,
            )
        })
        .collect();
    let facts: Vec<String> = (0..objects.len())
        .filter(|i| on_table.get(*i).copied().unwrap_or(false))
        .map(|i| format!("on(object{},table1)", i + 1))
        .collect();
    let facts: Vec<&str> = facts.iter().map(String::as_str).collect();
    scene(objects, &facts)
}

/// Algorithm 1 by counts, and the words it must (and must not) say. `good` are the acceptable
/// readings with the highest norm score: the only ones it may offer or act on.
fn check_invariant(d: &Decision, single: SinglePermissible) -> Result<(), TestCaseError> {
    let all = &d.interpretations;
    let acceptable: Vec<_> = all.iter().filter(|i| i.permissible() && i.feasible()).collect();
    let best = acceptable.iter().map(|i| i.norm_score()).max();
    let good: Vec<_> = acceptable
        .iter()
        .copied()
        .filter(|i| Some(i.norm_score()) == best)
        .collect();
    for i in all {
        let forbidden = i.outcome.reasons.iter().any(|r| r.kind().starts_with("forbidden_"));
        let other = (i.outcome.reasons.iter()).any(|r| !r.kind().starts_with("forbidden_") && !is_soft(r.kind()));
        prop_assert_eq!(i.permissible(), !forbidden, "permissible of {}", i.action);
        prop_assert_eq!(i.feasible(), !other, "feasible of {}", i.action);
        let mut score = 0;
        for (n, r) in i.outcome.reasons.iter().enumerate() {
            prop_assert!(
                !i.outcome.reasons[..n].contains(r),
                "{}: reason {:?} listed twice",
                i.action,
                r
            );
            prop_assert_eq!(
                r.norm_id.is_some(),
                r.kind().starts_with("forbidden_") || is_soft(r.kind()),
                "norm id of {:?}",
                r
            );
            if is_soft(r.kind()) {
                // Each soft norm counts once per reading.
                prop_assert!(
                    !i.outcome.reasons[..n].iter().any(|o| o.norm_id == r.norm_id),
                    "{}: soft norm {:?} counted twice",
                    i.action,
                    r.norm_id
                );
                let severity = i32::from(r.severity.expect("a soft reason has a severity"));
                score += if r.kind().starts_with("preferred_") {
                    severity
                } else {
                    -severity
                };
            }
        }
        prop_assert_eq!(i.norm_score(), score, "norm score of {}", i.action);
    }
    let expected = match (all.len(), good.len()) {
        (0, _) => Unresolved,
        (1, 1) => Comply,
        (1, _) => Refuse,
        (_, 0) => Explain,
        (_, 1) => match single {
            SinglePermissible::Assume => Assume,
            SinglePermissible::Confirm => Confirm,
        },
        _ => Ask,
    };
    prop_assert_eq!(d.kind, expected, "utterance: {}", d.utterance);
    match d.kind {
        Comply | Assume => {
            let goal = d.goal.as_ref().expect("comply and assume set a goal");
            prop_assert!(
                good.iter().any(|i| &i.action == goal),
                "goal {} is not acceptable",
                goal
            );
        }
        _ => prop_assert!(d.goal.is_none(), "{} with goal {:?}", d.kind.as_str(), d.goal),
    }
    match d.kind {
        Comply if all[0].outcome.discouraged().next().is_some() => {
            prop_assert!(d.utterance.starts_with("Okay, although "), "{}", d.utterance);
        }
        Comply => prop_assert_eq!(d.utterance.as_str(), "Okay."),
        Refuse => {
            let prefix = format!("I cannot {} because ", speech::reading(&all[0]));
            prop_assert!(d.utterance.starts_with(&prefix), "{}", d.utterance);
        }
        Ask => {
            // Only acceptable readings are ever named, in order: all of them when they fit in
            // `max_spoken`; else the first few and "or something else", or no reading at all
            // but the ambiguous words.
            let offered: Vec<&Interpretation> = d
                .offered
                .iter()
                .map(|a| {
                    all.iter()
                        .find(|i| &i.action == a)
                        .expect("an offered reading is a reading")
                })
                .collect();
            prop_assert!(
                offered.iter().all(|i| i.permissible() && i.feasible()),
                "{}",
                d.utterance
            );
            prop_assert!(
                good.iter()
                    .map(|i| &i.action)
                    .take(offered.len())
                    .eq(offered.iter().map(|i| &i.action))
            );
            let readings: Vec<String> = offered.iter().map(|i| speech::reading(i)).collect();
            if good.len() <= DEFAULT_MAX_SPOKEN {
                prop_assert_eq!(offered.len(), good.len());
                let question = format!(
                    "Do you mean that you want me to {}?",
                    readings.join(" or that you want me to ")
                );
                prop_assert_eq!(&d.utterance, &question);
                let or = Term::compound("or", good.iter().map(|i| i.action.clone()).collect());
                prop_assert_eq!(d.speech_act.to_string(), format!("want_know(self,mean(human,{or}))"));
            } else if offered.is_empty() {
                prop_assert!(d.utterance.starts_with("I do not know which "), "{}", d.utterance);
                prop_assert!(d.utterance.ends_with(" you mean."), "{}", d.utterance);
            } else {
                prop_assert!(offered.len() <= FEW);
                let question = format!(
                    "Do you mean that you want me to {} or something else?",
                    readings.join(" or that you want me to ")
                );
                prop_assert_eq!(&d.utterance, &question);
            }
        }
        Assume | Confirm => {
            let first = match d.kind {
                Assume => format!("I am assuming you want me to {}.", speech::reading(good[0])),
                _ => format!("Do you want me to {}?", speech::reading(good[0])),
            };
            prop_assert!(d.utterance.starts_with(&first), "{}", d.utterance);
            // Every other reading, in order: dispreferred ones would rather not be done, the
            // others cannot.
            let mut at = first.len();
            for other in all.iter().filter(|i| i.action != good[0].action) {
                let sentence = match other.permissible() && other.feasible() {
                    true => format!(" I would rather not {} because ", speech::reading(other)),
                    false => format!(" I cannot {} because ", speech::reading(other)),
                };
                prop_assert!(
                    d.utterance[at..].starts_with(&sentence),
                    "{} at {}: {}",
                    sentence,
                    at,
                    d.utterance
                );
                at += sentence.len();
                at += d.utterance[at..].find('.').map_or(0, |p| p + 1);
            }
            prop_assert_eq!(at, d.utterance.len(), "{}", d.utterance);
        }
        Explain => {
            let mut at = 0;
            for (n, i) in all.iter().enumerate() {
                let clause = if n == 0 {
                    format!("I believe that I cannot {} because ", speech::reading(i))
                } else {
                    format!(" and that I cannot {} because ", speech::reading(i))
                };
                match d.utterance[at..].find(&clause) {
                    Some(p) => at += p + clause.len(),
                    None => {
                        return Err(TestCaseError::fail(format!("{clause:?} missing in {}", d.utterance)));
                    }
                }
            }
            prop_assert!(d.utterance.ends_with('.'));
        }
        Unresolved => prop_assert!(d.utterance.starts_with("I do not know what you mean by the ")),
        NotUnderstood | DecisionKind::Cancelled => {
            return Err(TestCaseError::fail(format!(
                "a structured directive with no answer is always understood: {}",
                d.utterance
            )));
        }
    }
    Ok(())
}

/// Everything one random request needs; the scene is rebuilt from it on demand.
#[derive(Clone, Debug)]
struct RandomCase {
    objects: Vec<ObjGen>,
    type_count: usize,
    on_table: Vec<bool>,
    norms: Vec<NormInput>,
    verb: &'static str,
    /// Indices into TYPES; `put` uses both, the others the first.
    references: (usize, usize),
    context: &'static str,
    single: SinglePermissible,
}

impl RandomCase {
    fn scene(&self) -> Scene {
        random_scene(&self.objects, self.type_count, &self.on_table)
    }

    fn request(&self) -> Request {
        let (first, second) = self.references;
        let arguments = if self.verb == "put" {
            vec![ty(TYPES[first]), ty(TYPES[second])]
        } else {
            vec![ty(TYPES[first])]
        };
        Request {
            context: self.context.into(),
            options: Options {
                strategy: ClarifyStrategy::Moral,
                single_permissible: self.single,
                ..Options::default()
            },
            ..act(self.verb, arguments)
        }
    }
}

fn arb_case() -> impl Strategy<Value = RandomCase> {
    (
        prop::collection::vec(arb_object(), 1..=6),
        1..=3usize,
        prop::collection::vec(any::<bool>(), 6),
        prop::collection::vec(arb_norm(), 0..=4),
        prop::sample::select(VERBS.to_vec()),
        (0..3usize, 0..3usize),
        prop::sample::select(vec!["default", "hospital"]),
        prop_oneof![Just(SinglePermissible::Assume), Just(SinglePermissible::Confirm)],
    )
        .prop_map(
            |(objects, type_count, on_table, norms, verb, references, context, single)| RandomCase {
                objects,
                type_count,
                on_table,
                norms,
                verb,
                references,
                context,
                single,
            },
        )
}

/// Cases where soft norms have something to choose: several objects of one type, soft norms on
/// properties that tell them apart, and now and then a forbidden norm beside them.
fn arb_soft_case() -> impl Strategy<Value = RandomCase> {
    (
        prop::collection::vec(arb_object(), 1..=6),
        prop::collection::vec(arb_soft(), 1..=4),
        prop::collection::vec(arb_forbidden(), 0..=1),
        prop::sample::select(vec!["get", "pointTo", "put", "destroy"]),
        prop_oneof![Just(SinglePermissible::Assume), Just(SinglePermissible::Confirm)],
    )
        .prop_map(|(objects, soft, forbidden, verb, single)| RandomCase {
            objects,
            type_count: 1,
            on_table: vec![true, false, true, false, true, false],
            norms: soft.into_iter().chain(forbidden).collect(),
            verb,
            references: (0, 0),
            context: "default",
            single,
        })
}

/// 1,000 cases on every `cargo test`; the long run sets `SCRUPLE_PROPTEST_CASES` (e.g. 10000,
/// see README "Hostile input").
fn safety_cases() -> u32 {
    std::env::var("SCRUPLE_PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1000)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(safety_cases()))]

    #[test]
    fn moral_strategy_never_offers_assumes_confirms_or_obeys_a_bad_reading(case in arb_case()) {
        let scene = case.scene();
        let norms = norms(&case.norms);
        let request = case.request();
        let library = Library::default_library();
        let d = clarify(&request, &scene, &norms, &library, &|| false).expect("clarify");
        check_invariant(&d, case.single)?;
        // The same inputs, again and on a freshly built scene: the same decision.
        prop_assert_eq!(&clarify(&request, &scene, &norms, &library, &|| false).expect("clarify"), &d);
        prop_assert_eq!(&clarify(&request, &case.scene(), &norms, &library, &|| false).expect("clarify"), &d);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(safety_cases()))]

    /// With soft norms choosing: nothing forbidden or infeasible is offered or acted on, and a
    /// dispreferred reading is never offered while a better-scored acceptable one exists.
    #[test]
    fn soft_norms_never_let_a_bad_or_dispreferred_reading_through(case in arb_soft_case()) {
        let d = run(&case.request(), &case.scene(), &norms(&case.norms));
        check_invariant(&d, case.single)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(safety_cases() / 4))]

    /// The deadline may fall anywhere, even inside a reading's plan: whatever was cut short is
    /// never offered, assumed, confirmed or obeyed, and the answer says a limit was hit.
    #[test]
    fn a_deadline_anywhere_never_lets_an_unchecked_reading_through(case in arb_case(), after in 0..40usize) {
        use std::sync::atomic::{AtomicUsize, Ordering};
        let scene = case.scene();
        let norms = norms(&case.norms);
        let request = case.request();
        let library = Library::default_library();
        let calls = AtomicUsize::new(0);
        let expired = || calls.fetch_add(1, Ordering::Relaxed) >= after;
        let d = clarify(&request, &scene, &norms, &library, &expired).expect("clarify");
        let unfinished = d.interpretations.iter().any(|i| i.outcome.unfinished());
        if unfinished {
            prop_assert!(d.limits.is_some(), "a reading was cut short and the answer does not say so");
        }
        if d.limits.is_some() {
            prop_assert!(d.goal.is_none(), "{}: acted on a partial view", d.utterance);
            prop_assert!(matches!(d.kind, Ask | Refuse), "{:?}: {}", d.kind, d.utterance);
        }
        let offered: Vec<_> = d.interpretations.iter().filter(|i| d.offered.contains(&i.action)).collect();
        let best = (d.interpretations.iter())
            .filter(|i| i.permissible() && i.feasible())
            .map(|i| i.norm_score())
            .max();
        for i in offered {
            prop_assert!(i.permissible() && i.feasible(), "offered {} ({})", i.action, d.utterance);
            prop_assert_eq!(Some(i.norm_score()), best, "offered {}, dispreferred ({})", &i.action, &d.utterance);
        }
        for words in d.interpretations.iter().flat_map(|i| &i.reason_words) {
            prop_assert!(!words.trim().is_empty(), "a reason with no words: {}", d.utterance);
        }
    }
}

/// The properties above are only as strong as their inputs: they must reach every decision,
/// every reason kind the default library can produce, and both of soft norms' sentences.
#[test]
fn random_cases_reach_every_decision_and_reason_kind() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    use std::collections::BTreeMap;

    let mut runner = TestRunner::deterministic();
    let strategy = arb_case();
    let mut decisions: BTreeMap<&str, usize> = BTreeMap::new();
    let mut reasons: BTreeMap<&str, usize> = BTreeMap::new();
    // Half the cases from each generator; the soft one is built to give soft norms a choice.
    let (mut rather_not, mut although, mut dispreferred) = (0, 0, 0);
    let soft = arb_soft_case();
    for n in 0..2000 {
        let case = match n % 2 {
            0 => strategy.new_tree(&mut runner).expect("a case").current(),
            _ => soft.new_tree(&mut runner).expect("a case").current(),
        };
        let d = run(&case.request(), &case.scene(), &norms(&case.norms));
        *decisions.entry(d.kind.as_str()).or_default() += 1;
        rather_not += usize::from(d.utterance.contains(" I would rather not "));
        let acceptable = || d.interpretations.iter().filter(|i| i.acceptable());
        let best = acceptable().map(|i| i.norm_score()).max();
        dispreferred += usize::from(acceptable().any(|i| Some(i.norm_score()) < best));
        although += usize::from(d.utterance.starts_with("Okay, although "));
        for i in &d.interpretations {
            for r in &i.outcome.reasons {
                *reasons.entry(r.kind()).or_default() += 1;
            }
        }
    }
    for kind in ["comply", "refuse", "ask", "assume", "confirm", "explain", "unresolved"] {
        assert!(decisions.get(kind).is_some_and(|&n| n >= 10), "{kind}: {decisions:?}");
    }
    for kind in [
        "forbidden_action",
        "forbidden_state",
        "unknown_action",
        "unreachable",
        "discouraged_action",
        "discouraged_state",
        "preferred_action",
        "preferred_state",
    ] {
        assert!(reasons.get(kind).is_some_and(|&n| n >= 10), "{kind}: {reasons:?}");
    }
    // Soft norms choose among readings and are spoken: both of their sentences are reached.
    assert!(
        rather_not >= 10 && although >= 10 && dispreferred >= 10,
        "rather not {rather_not}, although {although}, dispreferred {dispreferred}"
    );
}

/// Enough readings to be simulated, described and worded on rayon's pool (more than 2,048): one
/// thread or four, the same decision, byte for byte.
#[test]
fn the_decision_is_the_same_whatever_the_thread_count() {
    let objects = cups_and_plates(50, |i| {
        let far = if i % 7 == 0 { 3.0 } else { 0.5 };
        obj(&format!("cup{i}"), "cup", &[], &[], [far, 0.01 * i as f64, 0.8], None)
    });
    let scene = scene(objects, &["fragile(cup3)", "fragile(cup5)"]);
    let norms = norms(&[when(fa("put(X,Y)"), &["fragile(X)"]), fs("on(cup8,plate9)")]);
    let request = act("put", vec![ty("cup"), ty("plate")]);
    let run_on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| clarify(&request, &scene, &norms, &Library::default_library(), &|| false).unwrap())
    };
    let one = run_on(1);
    assert_eq!(one.interpretations.len(), 2500);
    assert!(one.interpretations.len() >= crate::engine::clarify::DESCRIBE_APART_FROM);
    assert_eq!(one, run_on(4));
    assert_eq!(one, run_on(2));
}

/// A deadline during a parallel run keeps a prefix of the contract's order, whatever the
/// threads: the likeliest readings, each as a run without a deadline finds it, and the answer
/// says how many were simulated.
#[test]
fn a_deadline_on_the_pool_keeps_the_likeliest_readings() {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let objects = cups_and_plates(40, |i| {
        obj(&format!("cup{i}"), "cup", &[], &[], [0.5, 0.01 * i as f64, 0.8], None)
    });
    let scene = scene(objects, &["fragile(cup3)"]);
    let norms = norms(&[when(fa("put(X,Y)"), &["fragile(X)"])]);
    let request = act("put", vec![ty("cup"), ty("plate")]);
    let library = Library::default_library();
    let full = clarify(&request, &scene, &norms, &library, &|| false).unwrap();
    for (threads, after) in [(4, 5), (4, 300), (2, 300), (4, 1500), (1, 300), (1, 1500)] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let calls = AtomicUsize::new(0);
        let expired = || calls.fetch_add(1, Ordering::Relaxed) >= after;
        let d = pool.install(|| clarify(&request, &scene, &norms, &library, &expired).unwrap());
        let kept = d.interpretations.len();
        let limits = d.limits.expect("the deadline passed: the answer says so");
        assert_eq!(
            (limits.readings, limits.simulated),
            (1600, kept),
            "{threads} threads, after {after}"
        );
        let seen = |i: &Interpretation| (i.action.clone(), i.description.clone(), i.outcome.clone());
        assert_eq!(
            d.interpretations.iter().map(seen).collect::<Vec<_>>(),
            full.interpretations[..kept].iter().map(seen).collect::<Vec<_>>(),
            "{threads} threads, after {after}: not the likeliest {kept}"
        );

        // On one thread the deadline is looked at in the same order every run, so whether
        // anything is kept is fixed, and for these deadlines something is. On more, a thread
        // preempted early lets the others use up the looks first (while the readings are still
        // being described, say), and then none is kept: a prefix still, but nothing to compare.
        if threads == 1 {
            assert!(kept > 0, "after {after}: the deadline left nothing to compare");
        }
    }
}
