//! The safety invariant over every shape of input a client can send: words (the scene's own and
//! words it does not know, with narrowings, purposes and steps), references by type, by id and
//! by attribute, forms with scored bindings, every kind of answer, roles and contexts, norms
//! for roles, a custom verb of several methods with preconditions, the geometry checks (grasp,
//! payload, clearance, placing), soft norms, `confirm_above_ratio`, `max_spoken`, requests of
//! more than 2,048 readings, and tasks of several steps (in words and structured, with
//! pronouns, back-references and purposes). Under the moral strategy, whatever the shape,
//! nothing forbidden or infeasible is offered, assumed, confirmed or obeyed; no step of a task
//! so treated fails when its steps are checked alone in order (`/v1/check`'s path), and a
//! purpose the norms forbid outright is never obeyed.

use super::shape_tasks::{Said, arb_steps, arb_task_words, check_tasks};
use super::*;
use crate::engine::action::ActionInput;
use crate::engine::describe::is_task;
use crate::engine::request::Answer;
use crate::engine::task::{Argument, Step, Task};

pub(super) const KINDS: [&str; 3] = ["vase", "mug", "box"];
const COLOURS: [&str; 3] = ["red", "green", "blue"];

/// One random object: kind, fragile, colour, clean, far, y offset, shape (0 none, 1 small ball,
/// 2 wide cuboid), mass (0 none, 1 light, 2 heavy).
type Thing = (usize, bool, usize, bool, bool, f64, usize, usize);

fn arb_thing() -> impl Strategy<Value = Thing> {
    (
        0..3usize,
        any::<bool>(),
        0..4usize,
        any::<bool>(),
        prop::bool::weighted(0.2),
        -0.45..0.45f64,
        0..3usize,
        0..3usize,
    )
}

/// A directive in every shape a client can send it.
#[derive(Clone, Debug)]
enum Shaped {
    Types {
        verb: &'static str,
        kinds: (usize, usize),
    },
    Ids {
        verb: &'static str,
        ids: (usize, usize),
    },
    Attributes {
        verb: &'static str,
        kind: usize,
        colour: usize,
        fragile: bool,
    },
    Form {
        verb: &'static str,
        candidates: Vec<(usize, Option<u8>)>,
    },
    Words(String),
    /// A structured task: each step a verb and, per argument, a kind or a back-reference to
    /// argument 0 of the step before.
    Steps(Vec<(&'static str, usize, bool)>),
}

const VERBS: [&str; 6] = ["get", "destroy", "put", "tidy", "pointTo", "steal"];

fn arb_words() -> impl Strategy<Value = String> {
    let verb = prop::sample::select(vec![
        "get",
        "grab",
        "take",
        "smash",
        "destroy",
        "tidy up",
        "put",
        "could you get",
        "please fetch",
        "steal",
        "juggle",
        "juggle",
    ]);
    let determiner = prop::sample::select(vec!["the", "a", "", "that"]);
    let adjective = prop::sample::select(vec![
        "", "red", "green", "blue", "fragile", "clean", "wet", "★", "second",
    ]);
    let noun = prop::sample::select(vec!["vase", "mug", "box", "one", "cup", "mugs", "it"]);
    let tail = prop::sample::select(vec![
        "",
        ".",
        " now",
        ", please",
        ", not the red one",
        ", the green one",
        ", not red",
        " to smash it",
        " for reheating",
        ", then smash it",
        " on the box",
        " in the box",
        ", Pepper",
        " pls",
    ]);
    // Another step, or a purpose, after the first clause; "on" only, so that the steps checked
    // alone (which know no joiner) are the steps the task simulated.
    let then = prop::sample::select(vec![
        "",
        "",
        " and put it on the box",
        ", then destroy it",
        " and then get the mug",
        ". Put it on the red box.",
        " and the box",
        " or the box",
        " so I can smash it",
        " so I can smash it",
        " to smash the box",
        " for smashing the vase",
        " to put it on the box",
        " and juggle it",
        " and juggle it",
        " and tidy up the vase",
        ". It is fragile. Get it.",
        " and get it, the green one",
    ]);
    let need = prop::sample::select(vec!["", "", "", "I need ", "Can I have "]);
    (verb, determiner, adjective, noun, tail, then, need).prop_map(
        |(verb, determiner, adjective, noun, tail, then, need)| {
            let words: Vec<&str> = [verb, determiner, adjective, noun]
                .into_iter()
                .filter(|w| !w.is_empty())
                .collect();
            match need {
                "" => format!("{}{tail}{then}", words.join(" ")),
                need => format!("{need}{}{then}", words[1..].join(" ")),
            }
        },
    )
}

fn arb_shaped() -> impl Strategy<Value = Shaped> {
    let verb = || prop::sample::select(VERBS.to_vec());
    prop_oneof![
        2 => (verb(), (0..3usize, 0..3usize)).prop_map(|(verb, kinds)| Shaped::Types { verb, kinds }),
        2 => (verb(), (0..6usize, 0..6usize)).prop_map(|(verb, ids)| Shaped::Ids { verb, ids }),
        2 => (verb(), 0..3usize, 0..3usize, any::<bool>()).prop_map(|(verb, kind, colour, fragile)| Shaped::Attributes {
            verb,
            kind,
            colour,
            fragile
        }),
        2 => (
            prop::sample::select(vec!["get", "destroy", "tidy"]),
            prop::collection::vec((0..6usize, prop::option::of(0..=10u8)), 1..4)
        )
            .prop_map(|(verb, candidates)| Shaped::Form { verb, candidates }),
        2 => arb_words().prop_map(Shaped::Words),
        3 => arb_task_words().prop_map(Shaped::Words),
        2 => arb_steps().prop_map(Shaped::Steps),
    ]
}

/// Every kind of answer, in structure and in words.
fn arb_answer() -> impl Strategy<Value = Option<Answer>> {
    prop_oneof![
        3 => Just(None),
        1 => (0..4usize).prop_map(|n| Some(Answer::Choice(n))),
        1 => (0..6usize).prop_map(|n| Some(Answer::Id(format!("t{n}")))),
        1 => (0..3usize).prop_map(|c| Some(Answer::Reference(ty_with("vase", &[], &[("color", COLOURS[c])])))),
        1 => Just(Some(Answer::Yes)),
        1 => Just(Some(Answer::No)),
        2 => prop::sample::select(vec![
            "yes", "no", "never mind", "the red one", "the second one", "not the red one", "t1", "T1",
            "Get the vase.", "Destroy the mug.", "the ★ one", "first",
        ])
        .prop_map(|w| Some(Answer::Words(w.to_owned()))),
    ]
}

fn arb_norm() -> impl Strategy<Value = NormInput> {
    let term = prop::sample::select(vec![
        ("forbidden_action", "get(X)"),
        ("forbidden_action", "destroy"),
        ("forbidden_action", "destroy"),
        ("forbidden_state", "destroyed(X)"),
        ("forbidden_action", "put(X,Y)"),
        ("forbidden_action", "pointTo(X)"),
        ("forbidden_state", "holding(self,X)"),
        ("forbidden_state", "on(X,Y)"),
        ("forbidden_state", "did(self,get(t2))"),
        ("discouraged_action", "get(X)"),
        ("preferred_action", "get(X)"),
        ("preferred_state", "holding(self,X)"),
        ("discouraged_state", "on(X,Y)"),
        ("discouraged_state", "holding(self,X)"),
    ]);
    let when = prop::sample::select(vec![
        None,
        Some("fragile(X)"),
        Some("clean(X)"),
        Some("color(X,red)"),
        Some("box(Y)"),
    ]);
    let roles = prop::sample::select(vec![None, Some("child"), Some("owner")]);
    let exempt = prop::sample::select(vec![None, Some("owner"), Some("child")]);
    let context = prop::sample::select(vec![None, Some("hospital")]);
    (term, when, roles, exempt, context, 1..=5i64, any::<bool>()).prop_map(
        |((kind, term), when_fact, role, exempt, context, severity, note)| {
            let on_action = kind.ends_with("_action");
            NormInput {
                kind: Some(kind.to_owned()),
                action: on_action.then(|| term.to_owned()),
                state: (!on_action).then(|| term.to_owned()),
                when: when_fact.map(|w| vec![w.to_owned()]),
                roles: role.map(|r| vec![r.to_owned()]),
                exempt_roles: exempt.filter(|e| Some(*e) != role).map(|r| vec![r.to_owned()]),
                context: context.map(str::to_owned),
                severity: Some(severity),
                note: note.then(|| "a curator's note!".to_owned()),
            }
        },
    )
}

#[derive(Clone, Debug)]
struct Case {
    things: Vec<Thing>,
    geometry: (bool, bool, bool),
    directive: Shaped,
    answer: Option<Answer>,
    norms: Vec<NormInput>,
    roles: Vec<&'static str>,
    context: &'static str,
    single: SinglePermissible,
    ratio: Option<f64>,
    max_spoken: usize,
}

impl Case {
    fn scene(&self) -> Scene {
        let (aperture, payload, size) = self.geometry;
        let objects = (self.things.iter().enumerate())
            .map(|(i, &(kind, fragile, colour, clean, far, y, shape, mass))| {
                let mut properties = Vec::new();
                fragile.then(|| properties.push("fragile"));
                clean.then(|| properties.push("clean"));
                let attributes: Vec<(&str, &str)> = COLOURS.get(colour).map(|c| ("color", *c)).into_iter().collect();
                let shape = match shape {
                    1 => Some(Shape::Ball { radius: 0.03 }),
                    2 => Some(Shape::Cuboid {
                        half_extents: [0.12, 0.12, 0.08],
                    }),
                    _ => None,
                };
                let mut object = obj(
                    &format!("t{i}"),
                    KINDS[kind],
                    &properties,
                    &attributes,
                    [if far { 2.5 } else { 0.5 }, y, 0.8],
                    shape,
                );
                object.mass = [None, Some(0.3), Some(4.0)][mass];
                object
            })
            .collect();
        let agent = Agent {
            gripper_aperture: aperture.then_some(0.1),
            payload: payload.then_some(1.0),
            gripper_size: size.then_some(0.02),
            rotation: None,
            ..agent()
        };
        Scene::new(agent, objects, Vec::new())
    }

    fn request(&self) -> Request {
        let n = self.things.len();
        let id_of = |i: usize| format!("t{}", i % n);
        let arity = |verb: &str| if verb == "put" { 2 } else { 1 };
        let directive = match &self.directive {
            Shaped::Types { verb, kinds } => Directive::Action {
                verb: (*verb).into(),
                arguments: [kinds.0, kinds.1]
                    .iter()
                    .take(arity(verb))
                    .map(|k| ty(KINDS[*k]))
                    .collect(),
                // Now and then `put` by "in", which makes `in(X,Y)` true instead of `on(X,Y)`.
                joiner: (*verb == "put" && kinds.0 == 1).then(|| "in".to_owned()),
            },
            Shaped::Ids { verb, ids } => Directive::Action {
                verb: (*verb).into(),
                arguments: [ids.0, ids.1]
                    .iter()
                    .take(arity(verb))
                    .map(|i| id(&id_of(*i)))
                    .collect(),
                joiner: None,
            },
            Shaped::Attributes {
                verb,
                kind,
                colour,
                fragile,
            } => {
                let properties: &[&str] = if *fragile { &["fragile"] } else { &[] };
                let first = ty_with(KINDS[*kind], properties, &[("color", COLOURS[*colour])]);
                let mut arguments = vec![first];
                if arity(verb) == 2 {
                    arguments.push(ty("box"));
                }
                Directive::Action {
                    verb: (*verb).into(),
                    arguments,
                    joiner: None,
                }
            }
            Shaped::Form { verb, candidates } => {
                let mut seen = Vec::new();
                let mut list = Vec::new();
                for (i, score) in candidates {
                    let id = id_of(*i);
                    if !seen.contains(&id) {
                        seen.push(id.clone());
                        list.push(Candidate {
                            id,
                            score: score.map_or(1.0, |s| f64::from(s) / 10.0),
                        });
                    }
                }
                Directive::Form {
                    action: Term::parse(&format!("{verb}(X)")).unwrap(),
                    bindings: vec![(Sym::from("X"), list)],
                }
            }
            Shaped::Words(text) => Directive::Words { text: text.clone() },
            Shaped::Steps(steps) => Directive::Task(Task {
                steps: (steps.iter().enumerate())
                    .map(|(i, &(verb, kind, back))| {
                        let first = match (back, i) {
                            (true, 1..) => Argument::Earlier {
                                step: i - 1,
                                argument: 0,
                            },
                            _ => Argument::Reference(ty(KINDS[kind])),
                        };
                        let mut arguments = vec![first];
                        if arity(verb) == 2 {
                            arguments.push(Argument::Reference(ty("box")));
                        }
                        Step {
                            verb: verb.into(),
                            arguments,
                            joiner: None,
                        }
                    })
                    .collect(),
                purposes: Vec::new(),
            }),
        };
        // An answer by id names an object of the scene, as the request's checks make sure.
        let answer = match &self.answer {
            Some(Answer::Id(id)) => Some(Answer::Id(id_of(id[1..].parse().unwrap()))),
            other => other.clone(),
        };
        Request {
            speaker_roles: self.roles.iter().map(|r| (*r).to_owned()).collect(),
            context: self.context.into(),
            answer,
            focus: vec![id_of(1)],
            options: Options {
                single_permissible: self.single,
                confirm_above_ratio: self.ratio,
                max_spoken: self.max_spoken,
                ..Options::default()
            },
            ..request(directive)
        }
    }
}

/// The default verbs and one a curator wrote: `tidy` gets a clean object, else points to it,
/// named "tidy up".
fn library() -> Library {
    let mut library = Library::default_library();
    let tidy: ActionInput = serde_json::from_str(
        r#"{"parameters": ["X"], "words": ["tidy up"], "methods": [
            {"steps": ["get(X)"], "preconditions": ["clean(X)"]},
            {"steps": ["pointTo(X)"], "preconditions": ["fragile(X)"]}]}"#,
    )
    .unwrap();
    library.insert(tidy.validate("tidy").unwrap()).unwrap();
    library
}

fn arb_case() -> impl Strategy<Value = Case> {
    (
        prop::collection::vec(arb_thing(), 1..=6),
        (any::<bool>(), any::<bool>(), any::<bool>()),
        arb_shaped(),
        arb_answer(),
        (prop::collection::vec(arb_norm(), 0..=4), prop::bool::weighted(0.25)).prop_map(|(mut norms, outright)| {
            // The paper's own "destroying is forbidden", as often as a purpose could meet it.
            if outright {
                norms.push(NormInput {
                    kind: Some("forbidden_action".into()),
                    action: Some("destroy".into()),
                    ..NormInput::default()
                });
            }
            norms
        }),
        prop::sample::select(vec![vec![], vec!["child"], vec!["owner"], vec!["child", "owner"]]),
        prop::sample::select(vec!["default", "hospital"]),
        prop_oneof![Just(SinglePermissible::Assume), Just(SinglePermissible::Confirm)],
        prop::sample::select(vec![None, Some(0.0), Some(0.5)]),
        2..=5usize,
    )
        .prop_map(
            |(things, geometry, directive, answer, norms, roles, context, single, ratio, max_spoken)| Case {
                things,
                geometry,
                directive,
                answer,
                norms,
                roles,
                context,
                single,
                ratio,
                max_spoken,
            },
        )
}

/// What the answer proposes or acts on is acceptable, with the best norm score among the
/// acceptable readings; a goal only for `comply` and `assume`; nothing acted on past a limit.
pub(super) fn check(d: &Decision) -> Result<(), TestCaseError> {
    let reading = |action: &Term| d.interpretations.iter().find(|i| &i.action == action);
    let best = (d.interpretations.iter())
        .filter(|i| i.acceptable())
        .map(|i| i.norm_score())
        .max();
    for action in &d.offered {
        let Some(i) = reading(action) else {
            return Err(TestCaseError::fail(format!(
                "offered {action}, not a reading: {}",
                d.utterance
            )));
        };
        prop_assert!(
            i.permissible() && i.feasible(),
            "offered {} ({}): {}",
            action,
            d.kind.as_str(),
            d.utterance
        );
        prop_assert_eq!(
            Some(i.norm_score()),
            best,
            "offered a dispreferred {}: {}",
            action,
            &d.utterance
        );
    }
    match d.kind {
        Comply | Assume => {
            let goal = d.goal.as_ref().expect("comply and assume set a goal");
            let i = reading(goal).expect("the goal is a reading");
            prop_assert!(i.acceptable(), "acted on {}: {}", goal, d.utterance);
            prop_assert_eq!(&d.offered, &vec![goal.clone()]);
        }
        Confirm => {
            prop_assert!(d.goal.is_none());
            prop_assert_eq!(d.offered.len(), 1, "{}", &d.utterance);
        }
        _ => prop_assert!(d.goal.is_none(), "{} with a goal", d.kind.as_str()),
    }
    if d.limits.is_some() {
        prop_assert!(d.goal.is_none(), "acted on a partial view: {}", d.utterance);
        prop_assert!(
            !matches!(d.kind, Comply | Assume | Confirm | Explain),
            "{}: {}",
            d.kind.as_str(),
            d.utterance
        );
    }
    for i in &d.interpretations {
        prop_assert_eq!(i.reason_words.len(), i.outcome.reasons.len());
        prop_assert!(
            i.reason_words.iter().all(|w| !w.trim().is_empty()),
            "a reason with no words"
        );
    }
    prop_assert!(
        !d.utterance.chars().any(crate::engine::scene::invisible),
        "{:?}",
        d.utterance
    );
    Ok(())
}

fn every_shape_cases() -> u32 {
    std::env::var("SCRUPLE_PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1000)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(every_shape_cases()))]

    #[test]
    fn no_input_shape_lets_a_bad_reading_through(case in arb_case()) {
        let scene = case.scene();
        let norms = norms(&case.norms);
        let request = case.request();
        let library = library();
        // A choice the question did not offer is the client's error, not a decision.
        let Ok(d) = clarify(&request, &scene, &norms, &library, &|| false) else {
            prop_assert!(matches!(request.answer, Some(Answer::Choice(_) | Answer::Words(_))));
            return Ok(());
        };
        check(&d)?;
        let said = Said {
            words: match &case.directive {
                Shaped::Words(w) => Some(w.as_str()),
                _ => None,
            },
            answer: &case.answer,
            norms: &case.norms,
            roles: &case.roles,
            context: case.context,
        };
        check_tasks(&d, &said, &scene, &norms, &library)?;
        prop_assert_eq!(&clarify(&request, &scene, &norms, &library, &|| false).unwrap(), &d);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases((every_shape_cases() / 100).max(4)))]

    /// More than 2,048 readings (described and worded on rayon's pool), with soft norms and a
    /// deadline somewhere or nowhere: the same invariant.
    #[test]
    fn many_readings_let_no_bad_reading_through(
        fragile_every in 2..9usize,
        red_every in 2..9usize,
        norms_given in prop::collection::vec(arb_norm(), 1..=3),
        after in prop::option::of(0..3000usize),
    ) {
        use std::sync::atomic::{AtomicUsize, Ordering};
        let objects = cups_and_plates(48, |i| {
            let mut properties = vec![];
            if i % fragile_every == 0 { properties.push("fragile"); }
            let colour = if i % red_every == 0 { "red" } else { "green" };
            obj(&format!("cup{i}"), "box", &properties, &[("color", colour)], [0.5, 0.005 * i as f64, 0.8], None)
        });
        let scene = scene(objects, &[]);
        let request = act("put", vec![ty("box"), ty("plate")]);
        let calls = AtomicUsize::new(0);
        let expired = || after.is_some_and(|after| calls.fetch_add(1, Ordering::Relaxed) >= after);
        let d = clarify(&request, &scene, &norms(&norms_given), &library(), &expired).unwrap();
        check(&d)?;
    }
}

/// The generator reaches what it is for: every decision, answers of each kind taken, words read
/// as directives, and the geometric and custom-verb reasons.
#[test]
fn every_shape_reaches_every_decision_and_reason() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    use std::collections::BTreeMap;

    let mut runner = TestRunner::deterministic();
    let strategy = arb_case();
    let (mut decisions, mut reasons): (BTreeMap<&str, usize>, BTreeMap<&str, usize>) = Default::default();
    let library = library();
    let mut tasks = 0usize;
    for _ in 0..4000 {
        let case = strategy.new_tree(&mut runner).expect("a case").current();
        let Ok(d) = clarify(&case.request(), &case.scene(), &norms(&case.norms), &library, &|| false) else {
            continue;
        };
        *decisions.entry(d.kind.as_str()).or_default() += 1;
        tasks += usize::from(
            d.interpretations
                .iter()
                .any(|i| is_task(i.action.args().get(1).unwrap_or(&i.action))),
        );
        for r in d.interpretations.iter().flat_map(|i| &i.outcome.reasons) {
            *reasons.entry(r.kind()).or_default() += 1;
        }
    }
    for kind in [
        "comply",
        "refuse",
        "ask",
        "assume",
        "confirm",
        "explain",
        "unresolved",
        "not_understood",
        "cancelled",
    ] {
        assert!(decisions.get(kind).is_some_and(|&n| n >= 5), "{kind}: {decisions:?}");
    }
    for kind in [
        "forbidden_action",
        "forbidden_state",
        "unknown_action",
        "unreachable",
        "precondition",
        "too_wide",
        "too_heavy",
        "no_room",
        "same_object",
        "preferred_action",
        "discouraged_state",
        "forbidden_purpose",
    ] {
        assert!(reasons.get(kind).is_some_and(|&n| n >= 5), "{kind}: {reasons:?}");
    }
    assert!(tasks >= 50, "tasks decided: {tasks}");
}
