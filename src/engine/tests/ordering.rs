//! Order of interpretations, descriptions and readings.

use super::*;

// Order of interpretations, descriptions and readings

#[test]
fn ordering_descriptions_and_readings() {
    run_cases(vec![
        case(
            "scores override description order",
            lab(),
            paper_norms(),
            form_scored("get(X)", &[("X", &[("object2", 0.2), ("object1", 0.8)])]),
            expect(
                Ask,
                None,
                "Do you mean that you want me to get the red notebook or that you want me to get the green notebook?",
            )
            .act("want_know(self,mean(human,or(did(self,get(object1)),did(self,get(object2)))))")
            .interps(vec![
                interp("did(self,get(object1))", "the red notebook", vec![], &["get(object1)"]),
                interp(
                    "did(self,get(object2))",
                    "the green notebook",
                    vec![],
                    &["get(object2)"],
                ),
            ]),
        ),
        case(
            "equal scores fall back to description order",
            lab(),
            paper_norms(),
            form_scored("get(X)", &[("X", &[("object1", 0.5), ("object2", 0.5)])]),
            expect(
                Ask,
                None,
                "Do you mean that you want me to get the green notebook or that you want me to get the red notebook?",
            ),
        ),
        case(
            "scores order an explanation",
            lab(),
            paper_norms(),
            form_scored("destroy(X)", &[("X", &[("object3", 0.1), ("object4", 0.9)])]),
            expect(
                Explain,
                None,
                "I believe that I cannot destroy the plastic vase because destroy is forbidden action and that I cannot destroy the fragile vase because destroy is forbidden action.",
            ),
        ),
        case(
            "equal descriptions fall back to the canonical action",
            scene(
                vec![
                    obj("zbox", "cash_box", &[], &[], [0.5, 0.0, 0.8], None),
                    obj("abox", "cashBox", &[], &[], [0.5, 0.2, 0.8], None),
                ],
                &[],
            ),
            norms(&[]),
            form("get(X)", &[("X", &["zbox", "abox"])]),
            expect(
                Ask,
                None,
                "Do you mean that you want me to get the cash box or that you want me to get the cash box?",
            )
            .act("want_know(self,mean(human,or(did(self,get(abox)),did(self,get(zbox)))))"),
        ),
        case(
            "two identical mugs are told apart by a landmark, else a position",
            lab_with(|objects| objects.push(obj("object6", "mug", &[], &[], [0.5, 0.4, 0.8], mug_shape()))),
            paper_norms(),
            act("get", vec![ty("mug")]),
            expect(
                Ask,
                None,
                "Do you mean that you want me to get the left mug or that you want me to get the mug near the fragile vase?",
            )
            .interps(vec![
                interp("did(self,get(object5))", "the left mug", vec![], &["get(object5)"]),
                interp("did(self,get(object6))", "the mug near the fragile vase", vec![], &["get(object6)"]),
            ]),
        ),
        case(
            "two identical mugs at one spot get their ids",
            lab_with(|objects| {
                let at = objects.iter().find(|o| o.id == "object5").expect("the lab's mug").position;
                objects.push(obj("object6", "mug", &[], &[], at, mug_shape()));
            }),
            paper_norms(),
            act("get", vec![ty("mug")]),
            expect(
                Ask,
                None,
                "Do you mean that you want me to get the mug (object5) or that you want me to get the mug (object6)?",
            ),
        ),
        case(
            "a feature that rules nothing out is left out",
            scene(
                vec![
                    obj("v1", "vase", &["fragile", "heavy"], &[], [0.5, 0.0, 0.8], None),
                    obj("v2", "vase", &["fragile"], &[], [0.5, 0.2, 0.8], None),
                ],
                &[],
            ),
            norms(&[]),
            act("get", vec![ty("vase")]),
            expect(
                Ask,
                None,
                "Do you mean that you want me to get the heavy vase or that you want me to get the left vase?",
            ),
        ),
        case(
            "features are added in order: properties as listed, then attributes by key",
            scene(
                vec![
                    obj(
                        "v1",
                        "vase",
                        &["fragile"],
                        &[("size", "big"), ("color", "red")],
                        [0.5, 0.0, 0.8],
                        None,
                    ),
                    obj(
                        "v2",
                        "vase",
                        &["fragile"],
                        &[("color", "blue"), ("size", "big")],
                        [0.5, 0.2, 0.8],
                        None,
                    ),
                    obj(
                        "v3",
                        "vase",
                        &[],
                        &[("color", "red"), ("size", "big")],
                        [0.5, 0.4, 0.8],
                        None,
                    ),
                ],
                &[],
            ),
            norms(&[]),
            act("pointTo", vec![ty("vase")]),
            expect(
                Ask,
                None,
                "Do you mean that you want me to point to the fragile blue vase or that you want me to point to the fragile red vase or that you want me to point to the left red vase?",
            ),
        ),
        case(
            "distractors are only objects of the same type",
            lab_with(|objects| objects.push(obj("object6", "cup", &[], &[("color", "red")], [0.5, 0.3, 0.8], None))),
            paper_norms(),
            act("get", vec![ty_with("notebook", &[], &[("color", "red")])]),
            expect(Comply, Some("did(self,get(object1))"), "Okay.").interps(vec![interp(
                "did(self,get(object1))",
                "the red notebook",
                vec![],
                &["get(object1)"],
            )]),
        ),
        case(
            "spoken forms of types and values",
            scene(
                vec![
                    obj("box1", "cash_box", &[], &[("color", "dark_red")], [0.5, 0.0, 0.8], None),
                    obj(
                        "box2",
                        "cash_box",
                        &[],
                        &[("color", "lightBlue")],
                        [0.5, 0.2, 0.8],
                        None,
                    ),
                ],
                &[],
            ),
            norms(&[]),
            act("pointTo", vec![ty("cash_box")]),
            expect(
                Ask,
                None,
                "Do you mean that you want me to point to the dark red cash box or that you want me to point to the light blue cash box?",
            ),
        ),
        case(
            "put readings join with on",
            lab(),
            paper_norms(),
            act("put", vec![ty_with("notebook", &[], &[("color", "red")]), ty("mug")]),
            expect(Comply, Some("did(self,put(object1,object5))"), "Okay.")
                .act("acknowledge(self,mean(human,did(self,put(object1,object5))))")
                .interps(vec![interp(
                    "did(self,put(object1,object5))",
                    "the red notebook on the mug",
                    vec![],
                    &["get(object1)", "put(object1,object5)"],
                )]),
        ),
        case(
            "put with both arguments ambiguous: every combination, in description order",
            lab(),
            norms(&[]),
            act("put", vec![ty("vase"), ty("notebook")]),
            expect(
                Ask,
                None,
                "Do you mean that you want me to put the fragile vase on the green notebook or that you want me to put the fragile vase on the red notebook or that you want me to put the plastic vase on the green notebook or that you want me to put the plastic vase on the red notebook?",
            ),
        ),
        case(
            "put the vase on the mug: the fragile one needs a forbidden get",
            lab(),
            paper_norms(),
            act("put", vec![ty("vase"), ty("mug")]),
            expect(
                Assume,
                Some("did(self,put(object4,object5))"),
                "I am assuming you want me to put the plastic vase on the mug. I cannot put the fragile vase on the mug because it requires a forbidden state.",
            ),
        ),
        case(
            "form bindings may be listed in any order",
            lab(),
            norms(&[]),
            form("put(X,Y)", &[("Y", &["object5"]), ("X", &["object3", "object4"])]),
            expect(
                Ask,
                None,
                "Do you mean that you want me to put the fragile vase on the mug or that you want me to put the plastic vase on the mug?",
            ),
        ),
    ]);
}

/// "an `assume` or `confirm` names the chosen reading first and then explains the others in this
/// order": the chosen reading has the lowest score, the others follow by score.
#[test]
fn assume_names_the_chosen_reading_first_then_the_others_by_score() {
    let d = run(
        &form_scored(
            "get(X)",
            &[("X", &[("object3", 0.9), ("object4", 0.1), ("object5", 0.5)])],
        ),
        &lab(),
        &norms(&[fs("did(self,get(object3))"), fs("did(self,get(object5))")]),
    );
    let failures = mismatches(
        "assume by score",
        &d,
        &expect(
            Assume,
            Some("did(self,get(object4))"),
            "I am assuming you want me to get the plastic vase. I cannot get the fragile vase because it requires a forbidden state. I cannot get the mug because it requires a forbidden state.",
        )
        .interps(vec![
            interp(
                "did(self,get(object3))",
                "the fragile vase",
                vec![(FS, "did(self,get(object3))", Some(1))],
                &["get(object3)"],
            ),
            interp("did(self,get(object5))", "the mug", vec![(FS, "did(self,get(object5))", Some(2))], &["get(object5)"]),
            interp("did(self,get(object4))", "the plastic vase", vec![], &["get(object4)"]),
        ]),
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    let scores: Vec<f64> = d.interpretations.iter().map(|i| i.score).collect();
    assert_eq!(scores, vec![0.9, 0.5, 0.1]);
}

/// Readings enough to be described batch by batch on rayon's pool (2,048 or more, in several
/// batches): each keeps the words of its own action, and they stand in the contract's order.
#[test]
fn many_readings_keep_their_own_words_in_the_contracts_order() {
    let objects = cups_and_plates(46, |i| {
        let color = ["red", "green", "blue"][i % 3];
        obj(
            &format!("cup{i}"),
            "cup",
            &[],
            &[("color", color)],
            [0.5, 0.01 * i as f64, 0.8],
            None,
        )
    });
    let scene = scene(objects, &[]);
    let library = Library::default_library();
    let request = act("put", vec![ty("cup"), ty("plate")]);
    let decision = clarify(&request, &scene, &norms(&[]), &library, &|| false).unwrap();
    assert_eq!(decision.interpretations.len(), 46 * 46);
    let mut describer = super::super::describe::Describer::new(&scene, &library);
    for i in &decision.interpretations {
        let action = &i.action.args()[1];
        assert_eq!(i.description, describer.arguments(action), "{}", i.action);
        assert_eq!(speech::reading(i), describer.reading(action), "{}", i.action);
    }
    let key = |i: &Interpretation| (i.description.clone(), i.action.to_string());
    assert!(
        decision.interpretations.windows(2).all(|w| key(&w[0]) <= key(&w[1])),
        "not in the contract's order"
    );
}

proptest! {
    /// In a scene large enough to list objects by type, objects that look alike are described
    /// once for all of them: every object still gets the words a scan of the scene gives it,
    /// its own id included.
    #[test]
    fn objects_that_look_alike_are_described_as_a_scan_describes_each(
        looks in proptest::collection::vec((0..2usize, proptest::collection::vec(0..3usize, 0..3), 0..3usize), 65..140)
    ) {
        let objects = (looks.iter().enumerate())
            .map(|(i, (kind, properties, color))| {
                let properties: Vec<&str> = properties.iter().map(|p| ["fragile", "heavy", "red"][*p]).collect();
                let attributes: &[(&str, &str)] = match color {
                    0 => &[],
                    1 => &[("color", "green")],
                    _ => &[("color", "blue")],
                };
                obj(&format!("o{i}"), ["cup", "plate"][*kind], &properties, attributes, [0.5, 0.0, 0.8], None)
            })
            .collect();
        let scene = scene(objects, &[]);
        let library = Library::default_library();
        let mut describer = super::super::describe::Describer::new(&scene, &library);
        for object in &scene.objects {
            let scanned = super::super::describe::describe_object(&scene, object);
            prop_assert_eq!(describer.argument(&Term::constant(&object.id)), scanned);
        }
    }
}

proptest! {
    /// Many more readings than candidates, so each slot's candidates are put in order before the
    /// readings are made: whatever the candidates' scores and the order the form takes its
    /// variables in, every reading is there once and they stand in the contract's order.
    #[test]
    fn many_scored_readings_stand_in_the_contracts_order(
        scores in prop::collection::vec(0..3usize, 32),
        variables in prop::sample::select(vec!["did(self,put(X,Y))", "did(self,put(Y,X))", "put(X,Y)"]),
    ) {
        let objects = cups_and_plates(16, |i| {
            let fragile: &[&str] = if i % 5 == 0 { &["fragile"] } else { &[] };
            obj(&format!("cup{i}"), "cup", fragile, &[], [0.5, 0.01 * i as f64, 0.8], None)
        });
        let scene = scene(objects, &[]);
        let score = |k: usize| [0.25, 0.5, 1.0][scores[k]];
        let cups: Vec<(String, f64)> = (0..16).map(|i| (format!("cup{i}"), score(i))).collect();
        let plates: Vec<(String, f64)> = (0..16).rev().map(|i| (format!("plate{i}"), score(16 + i))).collect();
        fn listed(candidates: &[(String, f64)]) -> Vec<(&str, f64)> {
            candidates.iter().map(|(id, score)| (id.as_str(), *score)).collect()
        }
        let request = form_scored(variables, &[("X", &listed(&cups)), ("Y", &listed(&plates))]);
        let decision = clarify(&request, &scene, &norms(&[]), &Library::default_library(), &|| false).unwrap();
        let actions: std::collections::BTreeSet<String> = decision.interpretations.iter().map(|i| i.action.to_string()).collect();
        prop_assert_eq!((decision.interpretations.len(), actions.len()), (256, 256));
        let key = |i: &Interpretation| (std::cmp::Reverse(i.score.to_bits()), i.description.clone(), i.action.to_string());
        prop_assert!(
            decision.interpretations.windows(2).all(|w| key(&w[0]) <= key(&w[1])),
            "not in the contract's order"
        );
    }
}
