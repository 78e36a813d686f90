//! Feasibility: unknown verbs, reach, shapes and rotation.

use super::*;

// Feasibility: unknown verbs, reach, shapes and rotation

/// A long thin rod centred 1.5 m in front of the agent; `rotation` turns it about its centre.
fn rod_scene(rotation: Option<[f64; 4]>) -> Scene {
    let mut rod = obj(
        "rod1",
        "rod",
        &[],
        &[],
        [1.5, 0.0, 0.75],
        Some(Shape::Cuboid {
            half_extents: [1.0, 0.05, 0.05],
        }),
    );
    rod.rotation = rotation;
    scene(vec![rod], &[])
}

/// A quarter turn about z as `[x, y, z, w]`: `[0, 0, 0.7071068, 0.7071068]`.
const QUARTER_TURN_ABOUT_Z: [f64; 4] = [
    0.0,
    0.0,
    std::f64::consts::FRAC_1_SQRT_2,
    std::f64::consts::FRAC_1_SQRT_2,
];

#[test]
fn feasibility_cases() {
    run_cases(vec![
        case(
            "an unknown verb",
            lab(),
            paper_norms(),
            act("juggle", vec![ty("mug")]),
            expect(Refuse, None, "I cannot juggle the mug because I do not know how to juggle.")
                .act("cannot(did(self,juggle(object5)),because(unknownAction(juggle)))")
                .interps(vec![interp(
                    "did(self,juggle(object5))",
                    "the mug",
                    vec![("unknown_action", "juggle", None)],
                    &[],
                )]),
        ),
        case(
            "a known verb at the wrong arity is unknown",
            lab(),
            paper_norms(),
            act("get", vec![ty("mug"), ty("mug")]),
            expect(Refuse, None, "I cannot get the mug and the mug because I do not know how to get.")
                .interps(vec![interp(
                    "did(self,get(object5,object5))",
                    "the mug and the mug",
                    vec![("unknown_action", "get", None)],
                    &[],
                )]),
        ),
        case(
            "an unknown camel-case verb is spoken split",
            lab(),
            paper_norms(),
            act("throwAway", vec![ty("mug")]),
            expect(Refuse, None, "I cannot throw away the mug because I do not know how to throw away."),
        ),
        case(
            "an unknown verb under the forbidden-action norm of its name: the norm speaks first",
            lab(),
            norms(&[fa("juggle")]),
            act("juggle", vec![ty("mug")]),
            expect(Refuse, None, "I cannot juggle the mug because juggle is forbidden action.").interps(vec![interp(
                "did(self,juggle(object5))",
                "the mug",
                vec![(FA, "juggle(object5)", Some(1)), ("unknown_action", "juggle", None)],
                &[],
            )]),
        ),
        case(
            "an unknown verb, ambiguous: explain both",
            lab(),
            paper_norms(),
            act("juggle", vec![ty("vase")]),
            expect(
                Explain,
                None,
                "I believe that I cannot juggle the fragile vase because I do not know how to juggle and that I cannot juggle the plastic vase because I do not know how to juggle.",
            ),
        ),
        case(
            "an unreachable object",
            lab_with(|objects| far_mug(objects)),
            paper_norms(),
            act("get", vec![ty("mug")]),
            expect(Refuse, None, "I cannot get the mug because the mug is out of reach.")
                .act("cannot(did(self,get(object5)),because(unreachable(object5)))")
                .interps(vec![interp(
                    "did(self,get(object5))",
                    "the mug",
                    vec![("unreachable", "object5", None)],
                    &["get(object5)"],
                )]),
        ),
        case(
            "an unreachable object under a forbidden action: both reasons, the norm first",
            lab_with(|objects| far_mug(objects)),
            paper_norms(),
            act("destroy", vec![ty("mug")]),
            expect(Refuse, None, "I cannot destroy the mug because destroy is forbidden action.").interps(vec![interp(
                "did(self,destroy(object5))",
                "the mug",
                vec![(FA, "destroy(object5)", Some(1)), ("unreachable", "object5", None)],
                &["destroy(object5)"],
            )]),
        ),
        case(
            "pointing needs no reach",
            lab_with(|objects| far_mug(objects)),
            paper_norms(),
            act("pointTo", vec![ty("mug")]),
            expect(Comply, Some("did(self,pointTo(object5))"), "Okay.")
                .interps(vec![interp("did(self,pointTo(object5))", "the mug", vec![], &["pointTo(object5)"])]),
        ),
        case(
            "putting needs the destination within reach too",
            lab_with(|objects| far_mug(objects)),
            paper_norms(),
            act("put", vec![ty_with("notebook", &[], &[("color", "red")]), ty("mug")]),
            expect(Refuse, None, "I cannot put the red notebook on the mug because the mug is out of reach.").interps(
                vec![interp(
                    "did(self,put(object1,object5))",
                    "the red notebook on the mug",
                    vec![("unreachable", "object5", None)],
                    &["get(object1)", "put(object1,object5)"],
                )],
            ),
        ),
        case(
            "putting an unreachable object: the reason is listed once though get and put both need it",
            lab_with(|objects| far_mug(objects)),
            paper_norms(),
            act("put", vec![ty("mug"), ty_with("notebook", &[], &[("color", "red")])]),
            expect(Refuse, None, "I cannot put the mug on the red notebook because the mug is out of reach.").interps(
                vec![interp(
                    "did(self,put(object5,object1))",
                    "the mug on the red notebook",
                    vec![("unreachable", "object5", None)],
                    &["get(object5)", "put(object5,object1)"],
                )],
            ),
        ),
        case(
            "one of two mugs out of reach: assume the other, each told apart by a landmark or a position",
            lab_with(|objects| {
                objects.push(obj("object6", "mug", &[], &[], [3.0, 0.0, 0.8], mug_shape()));
            }),
            paper_norms(),
            act("get", vec![ty("mug")]),
            expect(
                Assume,
                Some("did(self,get(object5))"),
                "I am assuming you want me to get the mug near the vase. I cannot get the right mug because the right mug is out of reach.",
            )
            .interps(vec![
                interp("did(self,get(object5))", "the mug near the vase", vec![], &["get(object5)"]),
                interp(
                    "did(self,get(object6))",
                    "the right mug",
                    vec![("unreachable", "object6", None)],
                    &["get(object6)"],
                ),
            ]),
        ),
        case(
            "a long rod along x: its near face is 0.5 m away",
            rod_scene(None),
            norms(&[]),
            act("get", vec![ty("rod")]),
            expect(Comply, Some("did(self,get(rod1))"), "Okay."),
        ),
        case(
            "the same rod turned 90 degrees about z: 1.45 m away",
            rod_scene(Some(QUARTER_TURN_ABOUT_Z)),
            norms(&[]),
            act("get", vec![ty("rod")]),
            expect(Refuse, None, "I cannot get the rod because the rod is out of reach.")
                .interps(vec![interp("did(self,get(rod1))", "the rod", vec![("unreachable", "rod1", None)], &["get(rod1)"])]),
        ),
        case(
            "the rotated rod can still be pointed to",
            rod_scene(Some(QUARTER_TURN_ABOUT_Z)),
            norms(&[]),
            act("pointTo", vec![ty("rod")]),
            expect(Comply, Some("did(self,pointTo(rod1))"), "Okay."),
        ),
        case(
            "a point object just within reach is reachable",
            scene(vec![obj("p1", "pebble", &[], &[], [0.89, 0.0, 0.75], None)], &[]),
            norms(&[]),
            act("get", vec![ty("pebble")]),
            expect(Comply, Some("did(self,get(p1))"), "Okay."),
        ),
        case(
            "a point object just beyond reach is not",
            scene(vec![obj("p1", "pebble", &[], &[], [0.91, 0.0, 0.75], None)], &[]),
            norms(&[]),
            act("get", vec![ty("pebble")]),
            expect(Refuse, None, "I cannot get the pebble because the pebble is out of reach."),
        ),
        case(
            "a ball counts from its surface",
            scene(
                vec![obj("b1", "ball", &[], &[], [1.2, 0.0, 0.75], Some(Shape::Ball { radius: 0.35 }))],
                &[],
            ),
            norms(&[]),
            act("get", vec![ty("ball")]),
            expect(Comply, Some("did(self,get(b1))"), "Okay."),
        ),
    ]);
}

/// Issue 50, §3.5: "no room" compared boxes rounded where the objects stand, so the red
/// notebook fitted on the green one and the green one not on the red. Twins fit both ways.
#[test]
fn twin_supports_make_room_for_each_other_wherever_they_stand() {
    let library = Library::default_library();
    for (a, b) in [("object1", "object2"), ("object2", "object1")] {
        let d = clarify(&act("put", vec![id(a), id(b)]), &lab(), &norms(&[]), &library, &|| {
            false
        })
        .unwrap();
        assert!(
            d.interpretations[0]
                .outcome
                .reasons
                .iter()
                .all(|r| r.kind() != "no_room"),
            "{a} on {b}: {}",
            d.utterance
        );
    }
    for y in [-0.4, -0.08, 0.013, 0.37, 1.0e-3, 0.3333] {
        let twin = |id: &str, y: f64| obj(id, "notebook", &[], &[], [0.55, y, 0.76], notebook_shape());
        let objects = vec![twin("n1", y), twin("n2", y + 0.29)];
        let scene = scene(objects, &[]);
        for (a, b) in [("n1", "n2"), ("n2", "n1")] {
            let d = clarify(&act("put", vec![id(a), id(b)]), &scene, &norms(&[]), &library, &|| {
                false
            })
            .unwrap();
            assert!(
                d.interpretations[0]
                    .outcome
                    .reasons
                    .iter()
                    .all(|r| r.kind() != "no_room"),
                "{a} on {b} at {y}: {}",
                d.utterance
            );
        }
    }
}
