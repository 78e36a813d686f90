//! Several steps in one directive: each construction that makes steps, with a case it takes
//! and one it must not; pronouns bound across steps; task readings simulated as one plan;
//! purposes checked against the forbidden norms; "or" and needs.

use super::fixtures::{fa, fs, mug_shape, norms, obj, paper_norms, request, run, scene, when};
use crate::engine::decision::{BoundTo, Decision, DecisionKind, Unclear};
use crate::engine::norms::CompiledNorms;
use crate::engine::request::Directive;
use crate::engine::resolve::Reference;
use crate::engine::scene::Scene;
use crate::engine::task::{Argument, Step, Task};

/// A kitchen: a red mug and a blue mug, a sink, a plate, a fragile vase and a knife.
fn kitchen() -> Scene {
    scene(
        vec![
            obj("m1", "mug", &[], &[("color", "red")], [0.5, 0.1, 0.8], mug_shape()),
            obj("m2", "mug", &[], &[("color", "blue")], [0.5, 0.3, 0.8], mug_shape()),
            obj("s1", "sink", &[], &[], [0.6, -0.2, 0.8], None),
            obj("p1", "plate", &[], &[], [0.5, -0.3, 0.8], None),
            obj("v1", "vase", &["fragile"], &[], [0.6, 0.4, 0.85], None),
            obj("k1", "knife", &["sweet"], &[], [0.4, 0.0, 0.8], None),
        ],
        &[],
    )
}

fn words(text: &str) -> crate::engine::request::Request {
    request(Directive::Words { text: text.into() })
}

fn decide(text: &str, norms: &CompiledNorms) -> Decision {
    run(&words(text), &kitchen(), norms)
}

fn none() -> CompiledNorms {
    norms(&[])
}

fn goal(d: &Decision) -> Option<String> {
    d.goal.as_ref().map(|g| g.to_string())
}

/// Each construction that makes several steps: the words, the decision, the goal or the
/// readings offered.
#[test]
fn the_constructions_that_make_steps() {
    let cases: &[(&str, DecisionKind, &str)] = &[
        // "and" before a verb; a pronoun for the first step's object.
        (
            "Get the red mug and put it in the sink.",
            DecisionKind::Comply,
            "did(self,and(get(m1),put(m1,s1)))",
        ),
        (
            "Get the red mug, then put it in the sink.",
            DecisionKind::Comply,
            "did(self,and(get(m1),put(m1,s1)))",
        ),
        (
            "Get the red mug and then put it in the sink.",
            DecisionKind::Comply,
            "did(self,and(get(m1),put(m1,s1)))",
        ),
        (
            "Get the red mug. Put it in the sink.",
            DecisionKind::Comply,
            "did(self,and(get(m1),put(m1,s1)))",
        ),
        (
            "First get the red mug, then put it on the plate.",
            DecisionKind::Comply,
            "did(self,and(get(m1),put(m1,p1)))",
        ),
        (
            "Get the red mug. After that put it on the plate.",
            DecisionKind::Comply,
            "did(self,and(get(m1),put(m1,p1)))",
        ),
        // References listed under one verb: one step each.
        (
            "Get the red mug and the plate.",
            DecisionKind::Comply,
            "did(self,and(get(m1),get(p1)))",
        ),
        (
            "Put the red mug and the blue mug in the sink.",
            DecisionKind::Comply,
            "did(self,and(put(m1,s1),put(m2,s1)))",
        ),
        (
            "Get the red mug, the plate and the knife.",
            DecisionKind::Comply,
            "did(self,and(get(m1),get(p1),get(k1)))",
        ),
        // "or" between references: any one will do.
        (
            "Get the red mug or the plate.",
            DecisionKind::Assume,
            "did(self,get(p1))",
        ),
        // Needs are requests to bring it to the speaker.
        ("I need the plate.", DecisionKind::Comply, "did(self,give(p1,human))"),
        (
            "Can I have the plate?",
            DecisionKind::Comply,
            "did(self,give(p1,human))",
        ),
        (
            "I'd like the plate, please.",
            DecisionKind::Comply,
            "did(self,give(p1,human))",
        ),
    ];
    for (text, kind, expected) in cases {
        let d = decide(text, &none());
        assert_eq!(d.kind, *kind, "{text}: {}", d.utterance);
        assert_eq!(goal(&d).as_deref(), Some(*expected), "{text}: {}", d.utterance);
    }
}

/// What must not be read as steps, or not as these.
#[test]
fn what_is_not_read_as_steps() {
    for (text, why) in [
        // A step with no object for its verb: the whole is not understood, never half done.
        ("Get the red mug and put.", Unclear::Unplaced),
        ("Get the red mug, then smash.", Unclear::Unplaced),
        // A negated step.
        ("Get the red mug and don't put it in the sink.", Unclear::Negated),
        // A question among the steps.
        ("Get the red mug. What is in the sink?", Unclear::Question),
        // More than eight steps.
        (
            "Get the plate and get the knife and get the vase and get the sink and get the plate and get the \
             knife and get the vase and get the sink and get the plate.",
            Unclear::Several,
        ),
        // "I want to …" is what the speaker will do, not a need.
        ("I want to get the plate.", Unclear::Unplaced),
    ] {
        let d = decide(text, &none());
        assert_eq!(d.kind, DecisionKind::NotUnderstood, "{text}: {}", d.utterance);
        assert_eq!(
            d.parse.as_ref().and_then(|p| p.unclear),
            Some(why),
            "{text}: {}",
            d.utterance
        );
        assert!(d.goal.is_none());
    }
    // Exactly eight steps are read.
    let eight = "Get the plate and get the knife and get the vase and get the sink and get the plate and get the \
                 knife and get the vase and get the sink.";
    assert_eq!(decide(eight, &none()).kind, DecisionKind::Comply);
}

#[test]
fn a_task_that_asks_names_whole_tasks_and_speaks_a_repeated_object_as_it() {
    let d = decide("Get the mug and put it in the sink.", &none());
    assert_eq!(d.kind, DecisionKind::Ask);
    assert_eq!(
        d.utterance,
        "Do you mean that you want me to get the blue mug and put it in the sink or that you want me to get the \
         red mug and put it in the sink?"
    );
    assert_eq!(
        d.offered.iter().map(ToString::to_string).collect::<Vec<_>>(),
        ["did(self,and(get(m2),put(m2,s1)))", "did(self,and(get(m1),put(m1,s1)))"]
    );
    // The same in every reading: "it" is bound, never its own slot.
    assert_eq!(d.interpretations.len(), 2);
}

#[test]
fn a_forbidden_step_makes_the_task_impermissible_and_the_other_reading_is_assumed() {
    let n = norms(&[when(fs("in(X,Y)"), &["color(X,red)", "sink(Y)"])]);
    let d = decide("Get the mug and put it in the sink.", &n);
    assert_eq!(d.kind, DecisionKind::Assume, "{}", d.utterance);
    assert_eq!(goal(&d).as_deref(), Some("did(self,and(get(m2),put(m2,s1)))"));
    assert!(
        d.utterance
            .starts_with("I am assuming you want me to get the blue mug and put it in the sink."),
        "{}",
        d.utterance
    );
}

#[test]
fn effects_carry_over_from_step_to_step() {
    // Destroying the vase and then getting it: the get step runs in the world the destroy made,
    // so a state norm on holding a destroyed thing sees it.
    let n = norms(&[when(fs("holding(self,X)"), &["destroyed(X)"])]);
    let d = decide("Destroy the vase and then get it.", &n);
    assert_eq!(d.kind, DecisionKind::Refuse, "{}", d.utterance);
    let alone = decide("Get the vase.", &n);
    assert_eq!(alone.kind, DecisionKind::Comply, "{}", alone.utterance);
}

#[test]
fn a_forbidden_purpose_is_never_obeyed() {
    let n = paper_norms();
    let d = decide("Grab the plate to smash the vase.", &n);
    assert_eq!(d.kind, DecisionKind::Refuse, "{}", d.utterance);
    assert!(d.goal.is_none());
    assert_eq!(
        d.utterance,
        "I cannot get the plate to destroy the vase because destroy is forbidden action."
    );
    let reason = &d.interpretations[0].outcome.reasons[0];
    assert_eq!(reason.kind(), "forbidden_purpose");
    assert_eq!(reason.detail(), "destroy(v1)");
    // The natural style says it as the norm is.
    let mut natural = words("Grab the plate to smash the vase.");
    natural.options.style = crate::engine::decision::Style::Natural;
    let d = run(&natural, &kitchen(), &n);
    assert_eq!(
        d.utterance,
        "I won't get the plate to destroy the vase: destroying things is not allowed."
    );
    // Every way of saying a purpose.
    for text in [
        "Get the plate in order to smash the vase.",
        "Get the plate so I can smash the vase.",
        "Get the plate so that I can break the vase.",
        "Get the plate for smashing the vase.",
        "Get the vase to smash it.",
    ] {
        let d = decide(text, &n);
        assert_eq!(d.kind, DecisionKind::Refuse, "{text}: {}", d.utterance);
    }
    // A purpose the norms allow changes nothing; one of an unknown verb is shown and ignored.
    let d = decide("Get the plate to put it in the sink.", &n);
    assert_eq!(d.kind, DecisionKind::Comply, "{}", d.utterance);
    assert_eq!(goal(&d).as_deref(), Some("did(self,get(p1))"));
    let d = decide("Get the mug for reheating.", &n);
    assert_eq!(d.kind, DecisionKind::Ask);
    assert_eq!(
        d.parse.as_ref().map(|p| p.ignored.clone()),
        Some(vec!["for reheating".to_owned()])
    );
}

#[test]
fn a_conditional_purpose_is_forbidden_only_where_it_applies() {
    // Destroying fragile things is forbidden: smashing the plate is not.
    let n = norms(&[when(fa("destroy(X)"), &["fragile(X)"])]);
    assert_eq!(decide("Get the mug to smash the plate.", &n).kind, DecisionKind::Ask);
    let d = decide("Get the red mug to smash the vase.", &n);
    assert_eq!(d.kind, DecisionKind::Refuse, "{}", d.utterance);
    // Said as the norm says it: conditional, never "destroy is forbidden action".
    assert!(!d.utterance.contains("destroy is forbidden action"), "{}", d.utterance);
}

#[test]
fn pronouns_bind_to_the_nearest_earlier_step_and_the_focus_serves_only_the_first() {
    let d = decide("Get the red mug and put it in the sink.", &none());
    let parse = d.parse.clone().expect("parse");
    assert_eq!(
        parse.form.map(|f| f.to_string()).as_deref(),
        Some("want(human,did(self,and(get(X),put(X,Y))))")
    );
    assert_eq!(parse.steps.len(), 2);
    assert_eq!(parse.steps[1].pronouns[0].to, BoundTo::Step { step: 0, argument: 0 });
    assert_eq!(parse.steps[1].references[0].candidates, ["m1"]);
    // With no antecedent, the focus; with neither, nothing.
    let mut focused = words("Put it in the sink and get the plate.");
    focused.focus = vec!["m2".into()];
    let d = run(&focused, &kitchen(), &none());
    assert_eq!(
        goal(&d).as_deref(),
        Some("did(self,and(put(m2,s1),get(p1)))"),
        "{}",
        d.utterance
    );
    let d = decide("Put it in the sink and get the plate.", &none());
    assert_eq!(d.kind, DecisionKind::Unresolved, "{}", d.utterance);
}

#[test]
fn a_first_sentence_that_says_what_something_is_narrows_a_later_pronoun() {
    let d = decide("It is too sweet. Can you get it?", &none());
    assert_eq!(goal(&d).as_deref(), Some("did(self,get(k1))"), "{}", d.utterance);
    let d = decide("The red mug is dirty. Put it in the sink.", &none());
    // "dirty" is said of no mug here: nothing matches, never another mug.
    assert_eq!(d.kind, DecisionKind::Unresolved, "{}", d.utterance);
}

#[test]
fn readings_are_the_consistent_combinations_never_the_product_over_pronouns() {
    // Three two-way references and two pronouns: 2 × 2 × 2 = 8 readings.
    let objects = vec![
        obj("m1", "mug", &[], &[("color", "red")], [0.5, 0.1, 0.8], mug_shape()),
        obj("m2", "mug", &[], &[("color", "blue")], [0.5, 0.3, 0.8], mug_shape()),
        obj("s1", "sink", &[], &[("color", "red")], [0.6, -0.2, 0.8], None),
        obj("s2", "sink", &[], &[("color", "blue")], [0.6, -0.4, 0.8], None),
        obj("p1", "plate", &[], &[("color", "red")], [0.5, -0.3, 0.8], None),
        obj("p2", "plate", &[], &[("color", "blue")], [0.4, -0.3, 0.8], None),
    ];
    let d = run(
        &words("Get the mug and put it in the sink and get the plate and destroy it."),
        &scene(objects, &[]),
        &none(),
    );
    assert_eq!(d.interpretations.len(), 8, "{}", d.utterance);
}

#[test]
fn a_structured_task_is_decided_as_its_words_are() {
    let task = Directive::Task(Task {
        steps: vec![
            Step {
                verb: "get".into(),
                arguments: vec![Argument::Reference(Reference::Described {
                    kind: Some("mug".into()),
                    attributes: [("color".to_owned(), "red".to_owned())].into(),
                    properties: Vec::new(),
                })],
                joiner: None,
            },
            Step {
                verb: "put".into(),
                arguments: vec![
                    Argument::Earlier { step: 0, argument: 0 },
                    Argument::Reference(Reference::Id("s1".into())),
                ],
                joiner: Some("in".into()),
            },
        ],
        purposes: Vec::new(),
    });
    let structured = run(&request(task), &kitchen(), &none());
    let said = decide("Get the red mug and put it in the sink.", &none());
    assert_eq!(structured.kind, said.kind);
    assert_eq!(structured.goal, said.goal);
    assert_eq!(structured.utterance, said.utterance);
}

mod never_guess {
    use proptest::prelude::*;

    use super::{kitchen, none, words};
    use crate::engine::decision::DecisionKind;
    use crate::engine::describe::is_task;
    use crate::engine::term::Term;

    const ADJECTIVES: &[&str] = &["", "red", "blue", "fragile", "wet", "★", "second"];
    const NOUNS: &[&str] = &["mug", "plate", "vase", "knife", "cup", "mugz", "one"];
    const JOINS: &[&str] = &[" and ", ", then ", ". ", " and then ", " and after that "];

    /// The object an adjective and a noun may name: every word true of it.
    fn named(object: &crate::engine::scene::Object, adjective: &str, noun: &str) -> bool {
        (noun == "one" || object.kind == noun)
            && (adjective.is_empty()
                || object.properties.iter().any(|p| p == adjective)
                || object.attributes.values().any(|v| v == adjective))
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(
            std::env::var("SCRUPLE_PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(1000)
        ))]

        /// In a task of two steps, "get the A N and get (the B M | it)", whatever is offered or
        /// acted on gets, at each step, an object that step's words name (the first step's
        /// object for "it"); words the scene does not know act on nothing.
        #[test]
        fn no_step_acts_on_an_object_its_words_do_not_match(
            a in prop::sample::select(ADJECTIVES),
            n in prop::sample::select(NOUNS),
            join in prop::sample::select(JOINS),
            pronoun in any::<bool>(),
            b in prop::sample::select(ADJECTIVES),
            m in prop::sample::select(NOUNS),
        ) {
            let first = [a, n].iter().filter(|w| !w.is_empty()).copied().collect::<Vec<_>>().join(" ");
            let second = if pronoun {
                "it".to_owned()
            } else {
                ["the", b, m].iter().filter(|w| !w.is_empty()).copied().collect::<Vec<_>>().join(" ")
            };
            let text = format!("Get the {first}{join}get {second}.");
            let scene = kitchen();
            let d = crate::engine::tests::fixtures::run(&words(&text), &scene, &none());
            let known = |w: &str| w.is_empty() || w == "one" || scene.objects.iter().any(|o| {
                o.kind == w || o.properties.iter().any(|p| p == w) || o.attributes.values().any(|v| v == w)
            });
            if !(known(a) && known(n) && (pronoun || known(b) && known(m))) {
                prop_assert!(
                    matches!(d.kind, DecisionKind::Unresolved | DecisionKind::NotUnderstood),
                    "{text}: {} ({})", d.utterance, d.kind.as_str()
                );
            }
            for action in d.offered.iter().chain(&d.goal) {
                let Some(task) = action.args().get(1).filter(|t| is_task(t)) else {
                    return Err(TestCaseError::fail(format!("{text}: offered {action}, not a task")));
                };
                let object = |step: usize| match task.args()[step].args().first() {
                    Some(Term::Const(id)) => scene.object(id).cloned(),
                    _ => None,
                };
                let (Some(one), Some(two)) = (object(0), object(1)) else {
                    return Err(TestCaseError::fail(format!("{text}: offered {action}")));
                };
                prop_assert!(named(&one, a, n), "{text}: step 1 got {}", one.id);
                if pronoun {
                    prop_assert_eq!(&two.id, &one.id, "{}: \"it\" is not the first step's object", text);
                } else {
                    prop_assert!(named(&two, b, m), "{text}: step 2 got {}", two.id);
                }
            }
        }
    }
}

/// Found by a hostile pass of this feature's own: commas between imperatives, a connective with
/// nothing after it, an unknown verb before "me", words after a pronoun.
#[test]
fn what_a_hostile_pass_found() {
    let n = none();
    for (text, expected) in [
        (
            "Get the plate, get the knife, get the vase.",
            "did(self,and(get(p1),get(k1),get(v1)))",
        ),
        (
            "Get the red mug, put it in the sink, then get the plate.",
            "did(self,and(get(m1),put(m1,s1),get(p1)))",
        ),
        (
            "Get the red mug, and, put it in the sink.",
            "did(self,and(get(m1),put(m1,s1)))",
        ),
        ("Pepper, get the plate.", "did(self,get(p1))"),
        ("Please, get the plate.", "did(self,get(p1))"),
        (
            "Get the red mug and put it in the sink and get it and put it on the plate and get it and put it in the \
             sink and get it and put it on the plate.",
            "did(self,and(get(m1),put(m1,s1),get(m1),put(m1,p1),get(m1),put(m1,s1),get(m1),put(m1,p1)))",
        ),
    ] {
        let d = decide(text, &n);
        assert_eq!(goal(&d).as_deref(), Some(expected), "{text}: {}", d.utterance);
    }
    // Cut short, or a step that is no directive: said back, nothing done.
    for (text, said) in [
        ("Get the mug and then.", "I did not understand \"then\"."),
        ("Get the mug and.", "I did not understand \"and\"."),
        (
            "Get the red mug and tell me a joke.",
            "I did not understand \"tell me a joke\".",
        ),
        (
            "Get the red mug and get it back.",
            "I do not understand \"back\" in \"it back\".",
        ),
    ] {
        let d = decide(text, &n);
        assert!(d.goal.is_none(), "{text}");
        assert_eq!(d.utterance, said, "{text}");
    }
}

#[test]
fn the_deadline_and_the_cap_apply_to_the_task_as_a_whole() {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let library = crate::engine::action::Library::default_library();
    let request = words("Get the mug and put it in the sink and get the plate.");
    // The deadline may fall anywhere, while the words are read or any step is simulated: what
    // was cut short is never acted on, and a task is never done in part.
    let mut cut = 0;
    for after in 0..60 {
        let calls = AtomicUsize::new(0);
        let expired = || calls.fetch_add(1, Ordering::Relaxed) >= after;
        let d = crate::engine::clarify::clarify(&request, &kitchen(), &none(), &library, &expired).unwrap();
        if d.limits.is_some() || d.kind == DecisionKind::NotUnderstood {
            cut += 1;
            assert!(d.goal.is_none(), "after {after}: {}", d.utterance);
            assert!(
                !matches!(
                    d.kind,
                    DecisionKind::Comply | DecisionKind::Assume | DecisionKind::Confirm
                ),
                "after {after}: {}",
                d.utterance
            );
            // A question may name the whole tasks simulated to the end, and only those.
            for offered in &d.offered {
                let reading = d
                    .interpretations
                    .iter()
                    .find(|i| &i.action == offered)
                    .expect("a reading");
                assert!(
                    reading.acceptable() && !reading.outcome.unfinished(),
                    "after {after}: {offered}"
                );
            }
        }
    }
    assert!(cut > 0, "the deadline never fell");
    // More readings than the cap: nothing simulated, the ambiguous words named.
    let mut capped = words("Get the mug and put it in the sink and get the mug.");
    capped.options.max_readings = 3;
    let d = run(&capped, &kitchen(), &none());
    assert!(d.goal.is_none() && d.interpretations.is_empty());
    assert_eq!(d.limits.map(|l| l.readings), Some(4));
    assert_eq!(d.utterance, "I do not know which mug and which other mug you mean.");
}

/// Each construction's negative case: words that look like it and are not it, or that it must
/// not take as it.
#[test]
fn each_construction_takes_only_what_it_is() {
    let n = none();
    for (text, kind) in [
        // "and" between two references of one verb is a list, never two verbs.
        ("Get the red mug and the sink.", DecisionKind::Comply),
        // "then" with nothing after it: cut short.
        ("Get the red mug, then.", DecisionKind::NotUnderstood),
        // "after that" alone is no step.
        ("After that.", DecisionKind::NotUnderstood),
        // "first" is the order said, never a word of the reference.
        ("First get the first mug.", DecisionKind::Unresolved),
        // "or" with a reference that names nothing: the human may have meant just that one.
        ("Get the red mug or the spoon.", DecisionKind::Unresolved),
        // A need of nothing, or of an act: no request.
        ("I need.", DecisionKind::NotUnderstood),
        ("I need to get the plate.", DecisionKind::NotUnderstood),
        // A purpose whose verb is known but whose object cannot be placed: not understood.
        ("Get the plate to put it.", DecisionKind::NotUnderstood),
        // A first sentence that is not "it is …": a clause like any other.
        ("It fell. Get it.", DecisionKind::NotUnderstood),
    ] {
        let d = decide(text, &n);
        assert_eq!(d.kind, kind, "{text}: {}", d.utterance);
        if kind != DecisionKind::Comply {
            assert!(d.goal.is_none(), "{text}");
        }
    }
    assert_eq!(
        goal(&decide("Get the red mug and the sink.", &n)).as_deref(),
        Some("did(self,and(get(m1),get(s1)))")
    );
}
