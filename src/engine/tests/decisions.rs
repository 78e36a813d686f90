//! Each decision outside the paper's cases: single candidates, unresolved references, strategies.

use super::*;

// Each decision outside the paper's cases: single candidates, unresolved references, strategies

#[test]
fn single_candidates_unresolved_references_and_strategies() {
    run_cases(vec![
        case(
            "an unknown type is unresolved",
            lab(),
            paper_norms(),
            act("get", vec![ty("spoon")]),
            expect(Unresolved, None, "I do not know what you mean by the spoon.").interps(vec![]),
        ),
        case(
            "attributes that match nothing are unresolved, spoken with them",
            lab(),
            paper_norms(),
            act("get", vec![ty_with("notebook", &[], &[("color", "blue")])]),
            expect(Unresolved, None, "I do not know what you mean by the blue notebook.").interps(vec![]),
        ),
        case(
            "properties that match nothing are unresolved",
            lab(),
            paper_norms(),
            act("get", vec![ty_with("mug", &["fragile"], &[])]),
            expect(Unresolved, None, "I do not know what you mean by the fragile mug.").interps(vec![]),
        ),
        case(
            "an empty scene is unresolved",
            scene(vec![], &[]),
            paper_norms(),
            act("get", vec![ty("mug")]),
            expect(Unresolved, None, "I do not know what you mean by the mug.").interps(vec![]),
        ),
        case(
            "one unresolved argument of two is enough",
            lab(),
            paper_norms(),
            act("put", vec![ty("notebook"), ty("spoon")]),
            expect(Unresolved, None, "I do not know what you mean by the spoon.").interps(vec![]),
        ),
        case(
            "a reference with properties narrows to one: comply",
            lab(),
            paper_norms(),
            act("get", vec![ty_with("vase", &[], &[("material", "plastic")])]),
            expect(Comply, Some("did(self,get(object4))"), "Okay."),
        ),
        case(
            "a reference by id to the forbidden vase: refuse with the forbidden state",
            lab(),
            paper_norms(),
            act("get", vec![id("object3")]),
            expect(
                Refuse,
                None,
                "I cannot get the fragile vase because it requires a forbidden state.",
            )
            .act("cannot(did(self,get(object3)),because(forbiddenState(did(self,get(object3)))))")
            .interps(vec![interp(
                "did(self,get(object3))",
                "the fragile vase",
                vec![(FS, "did(self,get(object3))", Some(2))],
                &["get(object3)"],
            )]),
        ),
        case(
            "no norms at all: two vases are asked about",
            lab(),
            norms(&[]),
            act("get", vec![ty("vase")]),
            expect(
                Ask,
                None,
                "Do you mean that you want me to get the fragile vase or that you want me to get the plastic vase?",
            ),
        ),
        case(
            "reflexive, one candidate, permissible: comply like moral",
            lab(),
            paper_norms(),
            reflexive(act("get", vec![ty("mug")])),
            expect(Comply, Some("did(self,get(object5))"), "Okay."),
        ),
        case(
            "reflexive, one candidate, forbidden: refuse like moral",
            lab(),
            paper_norms(),
            reflexive(act("destroy", vec![ty("mug")])),
            expect(
                Refuse,
                None,
                "I cannot destroy the mug because destroy is forbidden action.",
            ),
        ),
        case(
            "reflexive, several: asks about all, the forbidden one too",
            lab(),
            paper_norms(),
            reflexive(act("get", vec![ty("vase")])),
            expect(
                Ask,
                None,
                "Do you mean that you want me to get the fragile vase or that you want me to get the plastic vase?",
            )
            .act("want_know(self,mean(human,or(did(self,get(object3)),did(self,get(object4)))))"),
        ),
        case(
            "reflexive, several, all forbidden: still asks",
            lab(),
            paper_norms(),
            reflexive(act("destroy", vec![ty("notebook")])),
            expect(
                Ask,
                None,
                "Do you mean that you want me to destroy the green notebook or that you want me to destroy the red notebook?",
            ),
        ),
        case(
            "reflexive ignores single_permissible too: it asks",
            lab(),
            paper_norms(),
            confirming(reflexive(act("get", vec![ty("vase")]))),
            expect(
                Ask,
                None,
                "Do you mean that you want me to get the fragile vase or that you want me to get the plastic vase?",
            ),
        ),
        case(
            "confirm with one candidate still complies",
            lab(),
            paper_norms(),
            confirming(act("get", vec![ty("mug")])),
            expect(Comply, Some("did(self,get(object5))"), "Okay."),
        ),
    ]);
}

/// Issue 50, §2: "I'll get the cup (cup1)." An id is spoken only where nothing else in the
/// answer tells its object apart: not when the reading's object is the only one of its type the
/// answer names. The readings' descriptions keep it, as the contract describes them. The twins
/// stand at one spot, so that no landmark or position tells them apart either.
#[test]
fn an_id_is_spoken_only_where_the_answer_needs_it() {
    let twins = || {
        scene(
            vec![
                obj("cup1", "cup", &[], &[], [0.5, 0.0, 0.8], None),
                obj("cup2", "cup", &[], &[], [0.5, 0.0, 0.8], None),
                obj("cup3", "cup", &[], &[], [3.5, 0.1, 0.8], None),
            ],
            &[],
        )
    };
    let d = run(&natural(act("get", vec![id("cup1")])), &twins(), &norms(&[]));
    assert_eq!(d.utterance, "Okay, I will get the cup.");
    assert_eq!(d.interpretations[0].description, "the cup (cup1)");
    let d = run(&act("destroy", vec![id("cup1")]), &twins(), &norms(&[fa("destroy")]));
    assert_eq!(
        d.utterance,
        "I cannot destroy the cup because destroy is forbidden action."
    );
    // Two cups in the answer: the ids tell them apart.
    let d = run(&act("get", vec![ty("cup")]), &twins(), &norms(&[]));
    assert_eq!(d.kind, Ask);
    assert!(
        d.utterance.contains("(cup1)") && d.utterance.contains("(cup2)"),
        "{}",
        d.utterance
    );
}

/// Issue 50, §2: a property that is a phrase was spoken raw before the noun ("the on floor
/// book"). A phrase that opens with a preposition or a participle follows it.
#[test]
fn a_phrase_of_a_property_reads_as_english() {
    let shelf = scene(
        vec![
            obj("book1", "book", &["on_floor"], &[], [0.5, 0.0, 0.8], None),
            obj("book2", "book", &["dark_red"], &[], [0.5, 0.1, 0.8], None),
            obj("cup1", "cup", &["filled_with_water"], &[], [0.5, 0.2, 0.8], None),
            obj("cup2", "cup", &[], &[], [0.5, 0.3, 0.8], None),
        ],
        &[],
    );
    let d = run(&act("get", vec![ty("book")]), &shelf, &norms(&[]));
    assert_eq!(
        d.utterance,
        "Do you mean that you want me to get the book on floor or that you want me to get the dark red book?"
    );
    let d = run(&act("get", vec![ty("cup")]), &shelf, &norms(&[]));
    assert!(d.utterance.contains("the cup filled with water"), "{}", d.utterance);
    // Said back as the robot speaks it, it is understood.
    let d = run(
        &request(Directive::Words {
            text: "Get the book on floor.".into(),
        }),
        &shelf,
        &norms(&[]),
    );
    assert_eq!(
        d.goal.as_ref().map(ToString::to_string).as_deref(),
        Some("did(self,get(book1))"),
        "{}",
        d.utterance
    );
}
