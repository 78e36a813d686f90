//! The paper's cases, word for word (`../shared/scenarios/paper-demo.json`).

use super::*;

// paper-demo.json

#[test]
fn paper_demo_cases_are_exact() {
    let vases_get = || {
        vec![
            interp(
                "did(self,get(object3))",
                "the fragile vase",
                vec![(FS, "did(self,get(object3))", Some(2))],
                &["get(object3)"],
            ),
            interp("did(self,get(object4))", "the plastic vase", vec![], &["get(object4)"]),
        ]
    };
    let assume_plastic = || {
        expect(
            Assume,
            Some("did(self,get(object4))"),
            "I am assuming you want me to get the plastic vase. I cannot get the fragile vase because it requires a forbidden state.",
        )
        .act("assume(self,mean(human,did(self,get(object4))))")
        .interps(vases_get())
    };
    let steal_boxes = || {
        vec![
            interp(
                "did(self,steal(box2))",
                "the green cash box",
                vec![(FA, "steal(box2)", Some(3))],
                &["steal(box2)"],
            ),
            interp(
                "did(self,steal(box1))",
                "the red cash box",
                vec![(FA, "steal(box1)", Some(3))],
                &["steal(box1)"],
            ),
        ]
    };
    run_cases(vec![
        case(
            "unambiguous permissible",
            lab(),
            paper_norms(),
            act("get", vec![ty("mug")]),
            expect(Comply, Some("did(self,get(object5))"), "Okay.")
                .act("acknowledge(self,mean(human,did(self,get(object5))))")
                .interps(vec![interp("did(self,get(object5))", "the mug", vec![], &["get(object5)"])]),
        ),
        case(
            "unambiguous forbidden action",
            lab(),
            paper_norms(),
            act("destroy", vec![ty("mug")]),
            expect(Refuse, None, "I cannot destroy the mug because destroy is forbidden action.")
                .act("cannot(did(self,destroy(object5)),because(forbiddenAction(destroy)))")
                .interps(vec![interp(
                    "did(self,destroy(object5))",
                    "the mug",
                    vec![(FA, "destroy(object5)", Some(1))],
                    &["destroy(object5)"],
                )]),
        ),
        case(
            "ambiguous, both permissible",
            lab(),
            paper_norms(),
            act("get", vec![ty("notebook")]),
            expect(
                Ask,
                None,
                "Do you mean that you want me to get the green notebook or that you want me to get the red notebook?",
            )
            .act("want_know(self,mean(human,or(did(self,get(object2)),did(self,get(object1)))))")
            .interps(vec![
                interp("did(self,get(object2))", "the green notebook", vec![], &["get(object2)"]),
                interp("did(self,get(object1))", "the red notebook", vec![], &["get(object1)"]),
            ]),
        ),
        case(
            "ambiguous, forbidden action",
            lab(),
            paper_norms(),
            act("destroy", vec![ty("notebook")]),
            expect(
                Explain,
                None,
                "I believe that I cannot destroy the green notebook because destroy is forbidden action and that I cannot destroy the red notebook because destroy is forbidden action.",
            )
            .act(
                "believe(self,and(cannot(did(self,destroy(object2)),because(forbiddenAction(destroy))),cannot(did(self,destroy(object1)),because(forbiddenAction(destroy)))))",
            )
            .interps(vec![
                interp(
                    "did(self,destroy(object2))",
                    "the green notebook",
                    vec![(FA, "destroy(object2)", Some(1))],
                    &["destroy(object2)"],
                ),
                interp(
                    "did(self,destroy(object1))",
                    "the red notebook",
                    vec![(FA, "destroy(object1)", Some(1))],
                    &["destroy(object1)"],
                ),
            ]),
        ),
        case(
            "ambiguous, forbidden action, vases",
            lab(),
            paper_norms(),
            act("destroy", vec![ty("vase")]),
            expect(
                Explain,
                None,
                "I believe that I cannot destroy the fragile vase because destroy is forbidden action and that I cannot destroy the plastic vase because destroy is forbidden action.",
            )
            .act(
                "believe(self,and(cannot(did(self,destroy(object3)),because(forbiddenAction(destroy))),cannot(did(self,destroy(object4)),because(forbiddenAction(destroy)))))",
            )
            .interps(vec![
                interp(
                    "did(self,destroy(object3))",
                    "the fragile vase",
                    vec![(FA, "destroy(object3)", Some(1))],
                    &["destroy(object3)"],
                ),
                interp(
                    "did(self,destroy(object4))",
                    "the plastic vase",
                    vec![(FA, "destroy(object4)", Some(1))],
                    &["destroy(object4)"],
                ),
            ]),
        ),
        case("ambiguous, one forbidden state", lab(), paper_norms(), act("get", vec![ty("vase")]), assume_plastic()),
        case(
            "same, as a logical form with bindings from an upstream resolver",
            lab(),
            paper_norms(),
            form("get(X)", &[("X", &["object3", "object4"])]),
            assume_plastic(),
        ),
        case(
            "same, confirming instead of assuming",
            lab(),
            paper_norms(),
            confirming(act("get", vec![ty("vase")])),
            expect(
                Confirm,
                None,
                "Do you want me to get the plastic vase? I cannot get the fragile vase because it requires a forbidden state.",
            )
            .act("want_know(self,mean(human,did(self,get(object4))))")
            .interps(vases_get()),
        ),
        case(
            "experiment, morally sensitive condition",
            office(),
            paper_norms(),
            act("steal", vec![ty("cash_box")]),
            expect(
                Explain,
                None,
                "I believe that I cannot steal the green cash box because steal is forbidden action and that I cannot steal the red cash box because steal is forbidden action.",
            )
            .act(
                "believe(self,and(cannot(did(self,steal(box2)),because(forbiddenAction(steal))),cannot(did(self,steal(box1)),because(forbiddenAction(steal)))))",
            )
            .interps(steal_boxes()),
        ),
        case(
            "experiment, control condition (the reflexive status quo)",
            office(),
            paper_norms(),
            reflexive(act("steal", vec![ty("cash_box")])),
            expect(
                Ask,
                None,
                "Do you mean that you want me to steal the green cash box or that you want me to steal the red cash box?",
            )
            .act("want_know(self,mean(human,or(did(self,steal(box2)),did(self,steal(box1)))))")
            .interps(steal_boxes()),
        ),
    ]);
}
