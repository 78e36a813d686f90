//! Plans: steps, states entered mid-plan, and the order and uniqueness of reasons.

use super::*;

// Plans: steps, states entered mid-plan, and the order and uniqueness of reasons

#[test]
fn plans_and_reasons() {
    let red_notebook = || ty_with("notebook", &[], &[("color", "red")]);
    run_cases(vec![
        case(
            "a forbidden state entered by put's get step",
            lab(),
            norms(&[fs("did(self,get(object3))")]),
            form("put(X,Y)", &[("X", &["object3"]), ("Y", &["object5"])]),
            expect(
                Refuse,
                None,
                "I cannot put the fragile vase on the mug because it requires a forbidden state.",
            )
            .act("cannot(did(self,put(object3,object5)),because(forbiddenState(did(self,get(object3)))))")
            .interps(vec![interp(
                "did(self,put(object3,object5))",
                "the fragile vase on the mug",
                vec![(FS, "did(self,get(object3))", Some(1))],
                &["get(object3)", "put(object3,object5)"],
            )]),
        ),
        case(
            "holding entered mid-plan though put lets go at the end",
            lab(),
            norms(&[fs("holding(self,object1)")]),
            act("put", vec![red_notebook(), ty("mug")]),
            expect(
                Refuse,
                None,
                "I cannot put the red notebook on the mug because it requires a forbidden state.",
            )
            .interps(vec![interp(
                "did(self,put(object1,object5))",
                "the red notebook on the mug",
                vec![(FS, "holding(self,object1)", Some(1))],
                &["get(object1)", "put(object1,object5)"],
            )]),
        ),
        case(
            "a forbidden action as a step of the directive",
            lab(),
            norms(&[fa("get")]),
            act("put", vec![red_notebook(), ty("mug")]),
            expect(
                Refuse,
                None,
                "I cannot put the red notebook on the mug because get is forbidden action.",
            )
            .interps(vec![interp(
                "did(self,put(object1,object5))",
                "the red notebook on the mug",
                vec![(FA, "get(object1)", Some(1))],
                &["get(object1)", "put(object1,object5)"],
            )]),
        ),
        case(
            "the final state of put: on(X,Y) forbidden",
            lab(),
            norms(&[fs("on(X,object5)")]),
            act("put", vec![red_notebook(), ty("mug")]),
            expect(
                Refuse,
                None,
                "I cannot put the red notebook on the mug because it requires a forbidden state.",
            )
            .interps(vec![interp(
                "did(self,put(object1,object5))",
                "the red notebook on the mug",
                vec![(FS, "on(object1,object5)", Some(1))],
                &["get(object1)", "put(object1,object5)"],
            )]),
        ),
        case(
            "DIARC order: the directive's forbidden action before the forbidden state it enters",
            lab(),
            norms(&[fa("destroy"), fs("destroyed(X)")]),
            act("destroy", vec![ty("mug")]),
            expect(
                Refuse,
                None,
                "I cannot destroy the mug because destroy is forbidden action.",
            )
            .interps(vec![interp(
                "did(self,destroy(object5))",
                "the mug",
                vec![(FA, "destroy(object5)", Some(1)), (FS, "destroyed(object5)", Some(2))],
                &["destroy(object5)"],
            )]),
        ),
        case(
            "DIARC order, not norm id order",
            lab(),
            norms(&[fs("destroyed(X)"), fa("destroy")]),
            act("destroy", vec![ty("mug")]),
            expect(
                Refuse,
                None,
                "I cannot destroy the mug because destroy is forbidden action.",
            )
            .interps(vec![interp(
                "did(self,destroy(object5))",
                "the mug",
                vec![(FA, "destroy(object5)", Some(2)), (FS, "destroyed(object5)", Some(1))],
                &["destroy(object5)"],
            )]),
        ),
        case(
            "did(self,a) is checked before the steps and listed once",
            lab(),
            norms(&[fs("holding(self,X)"), fs("did(self,get(X))"), fa("get")]),
            act("get", vec![ty("mug")]),
            expect(Refuse, None, "I cannot get the mug because get is forbidden action.").interps(vec![interp(
                "did(self,get(object5))",
                "the mug",
                vec![
                    (FA, "get(object5)", Some(3)),
                    (FS, "did(self,get(object5))", Some(2)),
                    (FS, "holding(self,object5)", Some(1)),
                ],
                &["get(object5)"],
            )]),
        ),
        case(
            "two norms with the same state are two reasons",
            lab(),
            norms(&[fs("holding(self,X)"), fs("holding(self,object5)")]),
            act("get", vec![ty("mug")]),
            expect(
                Refuse,
                None,
                "I cannot get the mug because it requires a forbidden state.",
            )
            .interps(vec![interp(
                "did(self,get(object5))",
                "the mug",
                vec![
                    (FS, "holding(self,object5)", Some(1)),
                    (FS, "holding(self,object5)", Some(2)),
                ],
                &["get(object5)"],
            )]),
        ),
        case(
            "steps in order: get's reasons before put's",
            lab_with(|objects| far_mug(objects)),
            norms(&[fs("did(self,put(X,Y))"), fs("holding(self,X)")]),
            act("put", vec![red_notebook(), ty("mug")]),
            expect(
                Refuse,
                None,
                "I cannot put the red notebook on the mug because it requires a forbidden state.",
            )
            .interps(vec![interp(
                "did(self,put(object1,object5))",
                "the red notebook on the mug",
                vec![
                    (FS, "did(self,put(object1,object5))", Some(1)),
                    (FS, "holding(self,object1)", Some(2)),
                    ("unreachable", "object5", None),
                ],
                &["get(object1)", "put(object1,object5)"],
            )]),
        ),
        case(
            // `put` is distinct: a mug is not put on itself. The simulation still runs its
            // plan, so that every other reason is found too.
            "putting an object on itself is infeasible, and still simulated",
            lab(),
            norms(&[]),
            act("put", vec![ty("mug"), ty("mug")]),
            expect(
                Refuse,
                None,
                "I cannot put the mug on the mug because the mug cannot be put on itself.",
            )
            .interps(vec![interp(
                "did(self,put(object5,object5))",
                "the mug on the mug",
                vec![("same_object", "object5", None)],
                &["get(object5)", "put(object5,object5)"],
            )]),
        ),
    ]);
}

/// "(4) each step in order: the step against the forbidden actions ... (for an action, the world
/// before it)". `put(X,Y)`'s steps are `get(X)`, then itself; before itself runs, the robot holds X.
#[test]
fn the_directive_itself_is_checked_as_a_step_in_the_world_before_it() {
    run_cases(vec![case(
        "forbidden_action put(X,Y) when holding(self,X)",
        lab(),
        norms(&[when(fa("put(X,Y)"), &["holding(self,X)"])]),
        act("put", vec![ty_with("notebook", &[], &[("color", "red")]), ty("mug")]),
        expect(
            Refuse,
            None,
            "I cannot put the red notebook on the mug because putting the red notebook on the mug is forbidden when I am holding the red notebook.",
        )
        .interps(vec![interp(
            "did(self,put(object1,object5))",
            "the red notebook on the mug",
            vec![(FA, "put(object1,object5)", Some(1))],
            &["get(object1)", "put(object1,object5)"],
        )]),
    )]);
}
