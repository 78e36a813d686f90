//! Norms with conditions and contexts.

use super::*;

// Norms with conditions and contexts

#[test]
fn conditional_and_contextual_norms() {
    let lab_on_table = || scene(lab_objects(), &["on(object3,table1)"]);
    run_cases(vec![
        case(
            "holding a fragile thing is forbidden: the plastic vase is assumed",
            lab(),
            norms(&[when(fs("holding(self,X)"), &["fragile(X)"])]),
            act("get", vec![ty("vase")]),
            expect(
                Assume,
                Some("did(self,get(object4))"),
                "I am assuming you want me to get the plastic vase. I cannot get the fragile vase because holding the fragile vase is forbidden.",
            )
            .interps(vec![
                interp(
                    "did(self,get(object3))",
                    "the fragile vase",
                    vec![(FS, "holding(self,object3)", Some(1))],
                    &["get(object3)"],
                ),
                interp("did(self,get(object4))", "the plastic vase", vec![], &["get(object4)"]),
            ]),
        ),
        case(
            "holding a fragile thing: pointing to it is fine",
            lab(),
            norms(&[when(fs("holding(self,X)"), &["fragile(X)"])]),
            act("pointTo", vec![ty("vase")]),
            expect(
                Ask,
                None,
                "Do you mean that you want me to point to the fragile vase or that you want me to point to the plastic vase?",
            ),
        ),
        case(
            "a when-only variable: getting what is on something is forbidden",
            lab_on_table(),
            norms(&[when(fa("get(X)"), &["on(X,Y)"])]),
            act("get", vec![ty("vase")]),
            expect(
                Assume,
                Some("did(self,get(object4))"),
                "I am assuming you want me to get the plastic vase. I cannot get the fragile vase because getting the fragile vase is forbidden when the fragile vase is on table1.",
            )
            .interps(vec![
                interp("did(self,get(object3))", "the fragile vase", vec![(FA, "get(object3)", Some(1))], &["get(object3)"]),
                interp("did(self,get(object4))", "the plastic vase", vec![], &["get(object4)"]),
            ]),
        ),
        case(
            "a when-only variable on a bare action name: any value will do",
            lab_on_table(),
            norms(&[when(fa("get"), &["on(object3,Y)"])]),
            act("get", vec![ty("vase")]),
            expect(
                Explain,
                None,
                "I believe that I cannot get the fragile vase because getting the fragile vase is forbidden when the fragile vase is on table1 and that I cannot get the plastic vase because getting the plastic vase is forbidden.",
            ),
        ),
        case(
            "a when condition that no fact satisfies never applies",
            lab(),
            norms(&[when(fa("get(X)"), &["on(X,Y)"])]),
            act("get", vec![ty("mug")]),
            expect(Comply, Some("did(self,get(object5))"), "Okay."),
        ),
        case(
            "a when condition the simulation has not made true: destroying what is not held",
            lab(),
            norms(&[when(fs("destroyed(X)"), &["holding(self,X)"])]),
            act("destroy", vec![ty("mug")]),
            expect(Comply, Some("did(self,destroy(object5))"), "Okay."),
        ),
        case(
            "a when condition made true earlier in the plan: put after its own get",
            lab(),
            norms(&[when(fs("did(self,put(X,Y))"), &["did(self,get(X))"])]),
            act("put", vec![ty_with("notebook", &[], &[("color", "red")]), ty("mug")]),
            expect(Refuse, None, "I cannot put the red notebook on the mug because putting the red notebook on the mug is forbidden.")
                .interps(vec![interp(
                    "did(self,put(object1,object5))",
                    "the red notebook on the mug",
                    vec![(FS, "did(self,put(object1,object5))", Some(1))],
                    &["get(object1)", "put(object1,object5)"],
                )]),
        ),
        case(
            "a when condition on the state being entered, with an attribute",
            lab(),
            norms(&[when(fs("holding(self,X)"), &["color(X,red)"])]),
            act("get", vec![ty("notebook")]),
            expect(
                Assume,
                Some("did(self,get(object2))"),
                "I am assuming you want me to get the green notebook. I cannot get the red notebook because holding the red notebook is forbidden.",
            ),
        ),
        case(
            "a state that already held is entered when its condition becomes true",
            lab(),
            norms(&[when(fs("fragile(X)"), &["holding(self,X)"])]),
            act("get", vec![ty("vase")]),
            expect(
                Assume,
                Some("did(self,get(object4))"),
                "I am assuming you want me to get the plastic vase. I cannot get the fragile vase because the fragile vase being fragile is forbidden when I am holding the fragile vase.",
            )
            .interps(vec![
                interp(
                    "did(self,get(object3))",
                    "the fragile vase",
                    vec![(FS, "fragile(object3)", Some(1))],
                    &["get(object3)"],
                ),
                interp("did(self,get(object4))", "the plastic vase", vec![], &["get(object4)"]),
            ]),
        ),
        case(
            "a hospital norm does not apply in the default context",
            lab(),
            norms(&[in_context(fa("get"), "hospital")]),
            act("get", vec![ty("mug")]),
            expect(Comply, Some("did(self,get(object5))"), "Okay."),
        ),
        case(
            "a hospital norm applies in the hospital",
            lab(),
            norms(&[in_context(fa("get"), "hospital")]),
            with_context(act("get", vec![ty("mug")]), "hospital"),
            expect(Refuse, None, "I cannot get the mug because getting the mug is forbidden in the hospital context.")
                .interps(vec![interp("did(self,get(object5))", "the mug", vec![(FA, "get(object5)", Some(1))], &["get(object5)"])]),
        ),
        case(
            "a norm without context applies in the hospital too",
            lab(),
            paper_norms(),
            with_context(act("destroy", vec![ty("mug")]), "hospital"),
            expect(Refuse, None, "I cannot destroy the mug because destroy is forbidden action."),
        ),
        case(
            "a default-context norm does not apply in the hospital",
            lab(),
            norms(&[in_context(fa("destroy"), "default")]),
            with_context(act("destroy", vec![ty("mug")]), "hospital"),
            expect(Comply, Some("did(self,destroy(object5))"), "Okay."),
        ),
        case(
            "a contextual forbidden state",
            lab(),
            norms(&[in_context(fs("did(self,get(object3))"), "hospital")]),
            with_context(act("get", vec![ty("vase")]), "hospital"),
            expect(
                Assume,
                Some("did(self,get(object4))"),
                "I am assuming you want me to get the plastic vase. I cannot get the fragile vase because getting the fragile vase is forbidden in the hospital context.",
            ),
        ),
        case(
            "a contextual forbidden state, out of its context",
            lab(),
            norms(&[in_context(fs("did(self,get(object3))"), "hospital")]),
            act("get", vec![ty("vase")]),
            expect(
                Ask,
                None,
                "Do you mean that you want me to get the fragile vase or that you want me to get the plastic vase?",
            ),
        ),
        case(
            "an action norm with an argument forbids only that argument",
            lab(),
            norms(&[fa("get(object1)")]),
            act("get", vec![ty("notebook")]),
            expect(
                Assume,
                Some("did(self,get(object2))"),
                "I am assuming you want me to get the green notebook. I cannot get the red notebook because get is forbidden action.",
            ),
        ),
        case(
            "a bare action name forbids the verb at every arity",
            lab(),
            norms(&[fa("put")]),
            act("put", vec![ty_with("notebook", &[], &[("color", "red")]), ty("mug")]),
            expect(Refuse, None, "I cannot put the red notebook on the mug because put is forbidden action.").interps(
                vec![interp(
                    "did(self,put(object1,object5))",
                    "the red notebook on the mug",
                    vec![(FA, "put(object1,object5)", Some(1))],
                    &["get(object1)", "put(object1,object5)"],
                )],
            ),
        ),
        case(
            "an action norm written with types and spaces",
            lab(),
            norms(&[fa("destroy( X:physobj )")]),
            act("destroy", vec![ty("mug")]),
            expect(Refuse, None, "I cannot destroy the mug because destroy is forbidden action."),
        ),
    ]);
}

/// A norm is passed over when a condition names a functor no fact of the world has (the world
/// being the scene's facts and what the reading has made true so far): facts made true by an
/// earlier step must still count, or a forbidden reading would pass.
#[test]
fn conditions_on_facts_only_the_simulation_makes_true() {
    let red_on_mug = || act("put", vec![ty_with("notebook", &[], &[("color", "red")]), ty("mug")]);
    run_cases(vec![
        case(
            "an action's condition made true by the step before it",
            lab(),
            norms(&[when(fa("put(X,Y)"), &["holding(self,X)"])]),
            red_on_mug(),
            expect(
                Refuse,
                None,
                "I cannot put the red notebook on the mug because putting the red notebook on the mug is forbidden when I am holding the red notebook.",
            ),
        ),
        case(
            "a state's condition made true by an earlier step",
            lab(),
            norms(&[when(fs("on(X,Y)"), &["did(self,get(X))"])]),
            red_on_mug(),
            expect(
                Refuse,
                None,
                "I cannot put the red notebook on the mug because the red notebook being on the mug is forbidden.",
            ),
        ),
        case(
            "a condition no fact can meet",
            lab(),
            norms(&[when(fs("holding(self,X)"), &["cursed(X)"])]),
            act("get", vec![ty("mug")]),
            expect(Comply, Some("did(self,get(object5))"), "Okay."),
        ),
    ]);
}

/// Issue 50, §2: a norm about knives and children refused a child's "Hand me the knife." with
/// "get is forbidden action" / "Getting things is forbidden.", telling a child that getting
/// anything is forbidden. A conditional norm is spoken by its note, else by what made it apply;
/// the paper's unconditional norms keep their words in the diarc style.
#[test]
fn a_conditional_norm_is_never_spoken_as_absolute() {
    use crate::engine::decision::Style;
    let kitchen = || {
        scene(
            vec![
                obj("knife1", "knife", &[], &[], [0.5, 0.0, 0.8], None),
                obj("spoon1", "spoon", &[], &[], [0.5, 0.2, 0.8], None),
            ],
            &[],
        )
    };
    let knives_for_children = |note: Option<&str>| NormInput {
        note: note.map(str::to_owned),
        roles: Some(vec!["child".into()]),
        ..when(fa("get(X)"), &["knife(X)"])
    };
    let child = |text: &str, style: Style| Request {
        speaker_roles: vec!["child".into()],
        options: Options {
            style,
            ..Options::default()
        },
        ..request(Directive::Words { text: text.into() })
    };
    for (note, style, utterance) in [
        (
            Some("never hand knives to children"),
            Style::Diarc,
            "I cannot give the knife to you because never hand knives to children.",
        ),
        (
            Some("never hand knives to children!"),
            Style::Natural,
            "I won't give the knife to you: never hand knives to children.",
        ),
        (
            None,
            Style::Diarc,
            "I cannot give the knife to you because getting the knife is forbidden for a child.",
        ),
        (
            None,
            Style::Natural,
            "I won't give the knife to you: getting the knife is not allowed for a child.",
        ),
    ] {
        let d = run(
            &child("Hand me the knife.", style),
            &kitchen(),
            &norms(&[knives_for_children(note)]),
        );
        assert_eq!(d.kind, Refuse, "{note:?}");
        assert_eq!(d.utterance, utterance, "{note:?} {style:?}");
        // The norm forbids nothing else: the spoon is got.
        let d = run(
            &child("Hand me the spoon.", style),
            &kitchen(),
            &norms(&[knives_for_children(note)]),
        );
        assert_eq!(d.kind, Comply);
    }
    // In the natural style an unconditional norm with a note is spoken by its note; in the
    // diarc style by the paper's words.
    let destroy = || NormInput {
        note: Some("destroying any object is forbidden.".into()),
        ..fa("destroy")
    };
    let d = run(&natural(act("destroy", vec![ty("mug")])), &lab(), &norms(&[destroy()]));
    assert_eq!(
        d.utterance,
        "I won't destroy the mug: destroying any object is forbidden."
    );
    let d = run(&act("destroy", vec![ty("mug")]), &lab(), &norms(&[destroy()]));
    assert_eq!(
        d.utterance,
        "I cannot destroy the mug because destroy is forbidden action."
    );
}

/// Two norms that give the same reason in the same words are said once.
#[test]
fn a_reason_two_norms_give_is_said_once() {
    let dirty = || NormInput {
        severity: Some(2),
        ..when(
            NormInput {
                kind: Some("discouraged_action".into()),
                action: Some("get(X)".into()),
                ..NormInput::default()
            },
            &["dirty(X)"],
        )
    };
    let scene = scene(vec![obj("mug1", "mug", &["dirty"], &[], [0.5, 0.0, 0.8], None)], &[]);
    let d = run(&act("get", vec![ty("mug")]), &scene, &norms(&[dirty(), dirty()]));
    assert_eq!(d.utterance, "Okay, although the mug is dirty.");
}
