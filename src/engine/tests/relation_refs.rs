//! References by relation, order and number in words: every relation word, superlatives and
//! ordinals (ties, missing measures, no direction), nesting and its union, relative clauses.

use std::f64::consts::FRAC_1_SQRT_2;

use super::relations::{QUARTER, candidates, complied, cuboid, decided, described, holds, ids, roomy, the_box};
use super::words::read;
use super::*;
use crate::engine::decision::Unclear;
use crate::engine::resolve::ReferenceInput;
use crate::engine::scene::relate::Relation;

// Every word of every relation

/// One cup standing in each relation to the box, and in no other.
fn one_cup_each() -> Scene {
    let at = |id: &str, p: [f64; 3]| obj(id, "cup", &[], &[], p, None);
    roomy(
        vec![
            the_box(),
            at("c_on", [0.5, 0.0, 0.01]),
            at("c_in", [0.5, 0.0, -0.25]),
            at("c_under", [0.5, 0.0, -1.0]),
            at("c_near", [0.5, 0.0, 0.1]),
            at("c_left", [0.5, 0.75, -0.25]),
            at("c_right", [0.5, -0.75, -0.25]),
            at("c_behind", [1.25, 0.0, -0.25]),
            at("c_front", [-0.25, 0.0, -0.25]),
        ],
        &[],
        None,
    )
}

#[test]
fn every_word_of_every_relation_selects_its_cup_and_no_other() {
    let scene = one_cup_each();
    let cases: &[(&[&str], &[&str])] = &[
        (&["on", "on top of", "atop", "upon"], &["c_on"]),
        (&["in", "inside", "inside of", "within"], &["c_in"]),
        (&["under", "underneath", "beneath", "below"], &["c_under"]),
        (&["near", "next to", "close to", "near to", "beside", "by"], &["c_near"]),
        (&["left of", "to the left of", "on the left of"], &["c_left"]),
        (&["right of", "to the right of", "on the right of"], &["c_right"]),
        (&["behind", "in back of"], &["c_behind"]),
        (&["in front of"], &["c_front"]),
        (&["from"], &["c_on", "c_in"]),
        // Not relation words here: the reference matches nothing rather than guess.
        (
            &["above", "over", "onto", "beyond", "left", "to the left", "in front"],
            &[],
        ),
    ];
    for (phrases, expected) in cases {
        for phrase in *phrases {
            let text = format!("Get the cup {phrase} the box.");
            assert_eq!(candidates(&text, &scene), ids(expected), "{text}");
            let decision = decided(&text, &scene);
            let want_kind = match expected.len() {
                0 => Unresolved,
                1 => Comply,
                _ => Ask,
            };
            assert_eq!(decision.0, want_kind, "{text}: {decision:?}");
            if let [one] = expected {
                assert_eq!(decision, complied(one), "{text}");
            }
        }
    }
}

// Superlatives

fn boxed(id: &str, p: [f64; 3], shape: Option<Shape>, mass: Option<f64>, colour: &str) -> Object {
    Object {
        mass,
        ..obj(id, "box", &[], &[("color", colour)], p, shape)
    }
}

/// A box of half extents 0.1 × 0.1 × `hz`: its volume and height go with `hz`.
fn slab(hz: f64) -> Option<Shape> {
    cuboid([0.1, 0.1, hz])
}

#[test]
fn every_superlative_picks_the_best_and_those_within_five_percent() {
    let at = |x: f64, y: f64, z: f64| [x, y, z];
    // Turned 90° about x: 0.6 long in y, 0.1 tall, 0.006 m³.
    let lying = Some(Shape::Cylinder {
        radius: 0.05,
        half_height: 0.3,
    });
    let sized = roomy(
        vec![
            boxed("b1", at(0.5, 0.0, 0.8), slab(0.1), Some(2.0), "red"),
            boxed("b2", at(0.5, 0.5, 0.8), slab(0.096), Some(1.95), "red"),
            boxed("b3", at(0.5, -0.5, 0.8), slab(0.05), Some(1.0), "red"),
            Object {
                rotation: Some([FRAC_1_SQRT_2, 0.0, 0.0, FRAC_1_SQRT_2]),
                ..boxed("b4", at(1.5, 0.0, 0.8), lying, Some(1.04), "blue")
            },
        ],
        &[],
        None,
    );
    // Distance from the agent at (0, 0, 0.75): 0.5, 0.52, 1.0; left: 0.5, 0.48, −0.5; height:
    // 1.0, 0.96, 0.5.
    let placed = roomy(
        vec![
            boxed("b1", at(0.5, 0.0, 0.75), None, None, "red"),
            boxed("b2", at(0.0, 0.52, 0.75), None, None, "red"),
            boxed("b3", at(1.0, 0.0, 0.75), None, None, "red"),
            boxed("b4", at(0.3, 0.5, 1.0), None, None, "green"),
            boxed("b5", at(0.3, 0.48, 0.96), None, None, "green"),
            boxed("b6", at(0.3, -0.5, 0.5), None, None, "green"),
        ],
        &[],
        None,
    );
    let cases: &[(&str, &Scene, &[&str])] = &[
        ("the biggest red box", &sized, &["b1", "b2"]),
        ("the largest red box", &sized, &["b1", "b2"]),
        ("the smallest red box", &sized, &["b3"]),
        ("the biggest box", &sized, &["b1", "b2"]),
        ("the smallest box", &sized, &["b3"]),
        ("the tallest red box", &sized, &["b1", "b2"]),
        ("the shortest box", &sized, &["b3", "b4"]),
        ("the heaviest box", &sized, &["b1", "b2"]),
        ("the lightest box", &sized, &["b3", "b4"]),
        ("the lightest red box", &sized, &["b3"]),
        ("the nearest red box", &placed, &["b1", "b2"]),
        ("the closest red box", &placed, &["b1", "b2"]),
        ("the farthest red box", &placed, &["b3"]),
        ("the furthest red box", &placed, &["b3"]),
        ("the leftmost green box", &placed, &["b4", "b5"]),
        ("the rightmost green box", &placed, &["b6"]),
        ("the highest green box", &placed, &["b4", "b5"]),
        ("the lowest green box", &placed, &["b6"]),
        ("the lowest red box", &placed, &["b1", "b2", "b3"]),
    ];
    for (reference, scene, expected) in cases {
        let text = format!("Get {reference}.");
        assert_eq!(candidates(&text, scene), ids(expected), "{text}");
    }
    // Just outside the tie: 6% apart.
    let apart = roomy(
        vec![
            boxed("b1", at(0.5, 0.0, 0.75), slab(0.1), Some(2.0), "red"),
            boxed("b2", at(0.0, 0.53, 0.75), slab(0.094), Some(1.88), "red"),
        ],
        &[],
        None,
    );
    for (superlative, expected) in [
        ("biggest", "b1"),
        ("tallest", "b1"),
        ("heaviest", "b1"),
        ("nearest", "b1"),
        ("smallest", "b2"),
        ("lightest", "b2"),
        ("farthest", "b2"),
    ] {
        let text = format!("Get the {superlative} box.");
        assert_eq!(candidates(&text, &apart), ids(&[expected]), "{text}");
        assert_eq!(decided(&text, &apart), complied(expected), "{text}");
    }
    assert_eq!(decided("Get the biggest red box.", &sized).0, Ask);
}

#[test]
fn a_turned_agent_turns_leftmost() {
    let objects = || {
        vec![
            boxed("b1", [0.5, 0.5, 0.75], None, None, "red"),
            boxed("b2", [-0.5, 0.0, 0.75], None, None, "red"),
        ]
    };
    let plain = roomy(objects(), &[], None);
    let turned = roomy(objects(), &[], Some(QUARTER));
    assert_eq!(candidates("Get the leftmost box.", &plain), ids(&["b1"]));
    assert_eq!(candidates("Get the leftmost box.", &turned), ids(&["b2"]));
    assert_eq!(candidates("Get the rightmost box.", &turned), ids(&["b1"]));
}

#[test]
fn a_superlative_the_scene_cannot_measure_selects_nothing_and_says_why() {
    let scene = roomy(
        vec![
            boxed("b1", [0.5, 0.0, 0.8], slab(0.1), Some(1.0), "red"),
            boxed("b2", [0.5, 0.5, 0.8], None, None, "red"),
            boxed("b3", [0.5, -0.5, 0.8], slab(0.05), Some(2.0), "blue"),
        ],
        &[],
        None,
    );
    let cases: &[(&str, Option<&str>)] = &[
        (
            "biggest",
            Some("I cannot tell which box is the biggest: I do not know how big every box is."),
        ),
        (
            "smallest",
            Some("I cannot tell which box is the smallest: I do not know how big every box is."),
        ),
        (
            "tallest",
            Some("I cannot tell which box is the tallest: I do not know how tall every box is."),
        ),
        (
            "shortest",
            Some("I cannot tell which box is the shortest: I do not know how tall every box is."),
        ),
        (
            "heaviest",
            Some("I cannot tell which box is the heaviest: I do not know how heavy every box is."),
        ),
        (
            "lightest",
            Some("I cannot tell which box is the lightest: I do not know how heavy every box is."),
        ),
        // Positions are always known.
        ("nearest", None),
        ("highest", None),
        ("leftmost", None),
    ];
    for (superlative, untold) in cases {
        let text = format!("Get the {superlative} box.");
        let d = decided(&text, &scene);
        match untold {
            Some(utterance) => {
                assert_eq!(candidates(&text, &scene), ids(&[]), "{text}");
                assert_eq!(d, (Unresolved, None, (*utterance).to_owned()), "{text}");
            }
            None => assert_ne!(d.0, Unresolved, "{text}"),
        }
    }
    // The box that cannot be measured is not among those compared: the blue boxes are.
    assert_eq!(candidates("Get the biggest blue box.", &scene), ids(&["b3"]));
    assert_eq!(candidates("Get the heaviest blue box.", &scene), ids(&["b3"]));
}

// Ordinals

/// Four cups; from the left (+y first) c2 c3 c1 c4, from the front (nearest x first) c1 c2 c3 c4.
fn four_cups(rotation: Option<[f64; 4]>) -> Scene {
    let at = |id: &str, x: f64, y: f64| obj(id, "cup", &[], &[], [x, y, 0.8], None);
    roomy(
        vec![
            at("c1", 0.3, -0.1),
            at("c2", 0.5, 0.3),
            at("c3", 0.7, 0.1),
            at("c4", 0.9, -0.3),
        ],
        &[],
        rotation,
    )
}

#[test]
fn an_ordinal_counts_from_the_direction_said() {
    let scene = four_cups(None);
    let turned = four_cups(Some(QUARTER));
    let cases: &[(&str, &Scene, &[&str])] = &[
        ("the first cup from the left", &scene, &["c2"]),
        ("the second cup from the left", &scene, &["c3"]),
        ("the 2nd cup from the left", &scene, &["c3"]),
        ("the fourth cup from the left", &scene, &["c4"]),
        ("the first cup from the right", &scene, &["c4"]),
        ("the second cup from the right", &scene, &["c1"]),
        ("the first cup from the front", &scene, &["c1"]),
        ("the third cup from the front", &scene, &["c3"]),
        ("the first cup from the back", &scene, &["c4"]),
        ("the second cup from the back", &scene, &["c3"]),
        // Turned 90°: −x is left, so the nearest in x is the leftmost.
        ("the first cup from the left", &turned, &["c1"]),
        ("the first cup from the front", &turned, &["c4"]),
        // Beyond the count.
        ("the fifth cup from the left", &scene, &[]),
        ("the tenth cup from the back", &scene, &[]),
    ];
    for (reference, scene, expected) in cases {
        let text = format!("Get {reference}.");
        assert_eq!(candidates(&text, scene), ids(expected), "{text}");
    }
    assert_eq!(decided("Get the second cup from the left.", &scene), complied("c3"));
    let beyond = "I do not know what you mean by the fifth cup from the left.".to_owned();
    assert_eq!(
        decided("Get the fifth cup from the left.", &scene),
        (Unresolved, None, beyond)
    );
    // No direction: not guessed.
    for (text, ordinal, reference) in [
        ("Get the second cup.", "second", "the second cup"),
        ("Get the 2nd cup.", "2nd", "the 2nd cup"),
    ] {
        assert_eq!(candidates(text, &scene), ids(&[]), "{text}");
        let utterance = format!("I do not understand \"{ordinal}\" in \"{reference}\".");
        assert_eq!(decided(text, &scene), (Unresolved, None, utterance), "{text}");
    }
}

#[test]
fn cups_within_five_centimetres_may_each_be_either_place() {
    let row = |gap: f64| {
        let at = |id: &str, y: f64| obj(id, "cup", &[], &[], [0.5, y, 0.8], None);
        roomy(vec![at("a", 0.3), at("b", 0.3 - gap), at("c", -0.1)], &[], None)
    };
    let (close, apart) = (row(0.04), row(0.06));
    let cases: &[(&str, &Scene, &[&str])] = &[
        ("first", &close, &["a", "b"]),
        ("second", &close, &["a", "b"]),
        ("third", &close, &["c"]),
        ("first", &apart, &["a"]),
        ("second", &apart, &["b"]),
        ("third", &apart, &["c"]),
    ];
    for (nth, scene, expected) in cases {
        let text = format!("Get the {nth} cup from the left.");
        assert_eq!(candidates(&text, scene), ids(expected), "{text}");
    }
    assert_eq!(decided("Get the first cup from the left.", &close).0, Ask);
}

// Nesting, attachment and relative clauses

/// Two tables, one 0.16 m from the window (the cup on it 0.37 m from it); a cup on each, and
/// a third on the far table that a fact puts by the window; a fourth on the floor.
fn kitchen() -> Scene {
    let table = |id: &str, x: f64| obj(id, "table", &[], &[], [x, 0.0, 0.375], cuboid([0.25, 0.25, 0.375]));
    let mug = |id: &str, x: f64, z: f64| obj(id, "cup", &[], &[], [x, 0.0, z], cuboid([0.03, 0.03, 0.05]));
    roomy(
        vec![
            table("t1", 0.5),
            table("t2", 2.5),
            obj("w", "window", &[], &[], [0.5, 0.4, 0.8], None),
            mug("cup1", 0.5, 0.8),
            mug("cup2", 2.4, 0.8),
            mug("cup3", 2.6, 0.8),
            mug("cup4", 4.0, 0.05),
        ],
        &["near(cup2,w)"],
        None,
    )
}

#[test]
fn a_relation_after_two_nouns_attaches_to_either_and_the_candidates_are_the_union() {
    let scene = kitchen();
    assert!(holds(&scene, Relation::Near, "t1", "w") && !holds(&scene, Relation::Near, "t2", "w"));
    let cases: &[(&str, &[&str])] = &[
        ("the cup on the table", &["cup1", "cup2", "cup3"]),
        ("the table by the window", &["t1"]),
        // The cup on (the table by the window), or the cup on a table and by the window.
        ("the cup on the table by the window", &["cup1", "cup2"]),
        ("the cup on the table next to the window", &["cup1", "cup2"]),
        ("the cup that is on the table by the window", &["cup1", "cup2"]),
        ("the cup that is on the table", &["cup1", "cup2", "cup3"]),
        ("the cup that is not on the table", &["cup4"]),
        ("the cup that is not by the window", &["cup1", "cup3", "cup4"]),
        ("the cup on the table to the left of the window", &[]),
        ("the cup on the table by the door", &[]),
        ("the cup on the zorp by the window", &[]),
    ];
    for (reference, expected) in cases {
        let text = format!("Get {reference}.");
        assert_eq!(candidates(&text, &scene), ids(expected), "{text}");
    }
    assert_eq!(
        decided("Get the cup that is not on the table.", &scene),
        complied("cup4")
    );
    // Structured, each attachment is its own reference; together they are the words' union.
    let window = || described("window", vec![]);
    let nested = described("cup", vec![("on", described("table", vec![("near", window())]))]);
    let both = described("cup", vec![("on", described("table", vec![])), ("near", window())]);
    let select = |input: ReferenceInput| {
        let reference = Reference::from_input(input, &scene).expect("known relations");
        let selected = reference.select(&scene, &|| false).expect("no deadline").objects;
        selected
            .iter()
            .map(|&i| scene.objects[i].id.to_string())
            .collect::<Vec<_>>()
    };
    assert_eq!(select(nested), ids(&["cup1"]));
    assert_eq!(select(both), ids(&["cup2"]));
}

#[test]
fn a_structured_relation_of_an_unknown_name_is_refused_at_its_field() {
    let scene = kitchen();
    let at = |input: ReferenceInput| Reference::from_input(input, &scene).map(|_| ()).map_err(|e| e.field);
    assert_eq!(
        at(described("cup", vec![("onto", described("table", vec![]))])),
        Err("/relations/0/relation".into())
    );
    assert_eq!(
        at(described("cup", vec![("On", described("table", vec![]))])),
        Err("/relations/0/relation".into())
    );
    let deep = described(
        "cup",
        vec![
            ("on", described("table", vec![])),
            (
                "near",
                described("window", vec![("next_to", described("table", vec![]))]),
            ),
        ],
    );
    assert_eq!(at(deep), Err("/relations/1/to/relations/0/relation".into()));
    for relation in Relation::ALL {
        assert_eq!(
            at(described("cup", vec![(relation.name(), described("table", vec![]))])),
            Ok(())
        );
    }
    let refused = Reference::from_input(described("cup", vec![("atop", described("table", vec![]))]), &scene);
    let message = refused.expect_err("unknown").message;
    assert!(message.contains("unknown relation `atop`"), "{message}");
}

/// A typo inside "to the left of" was read as a purpose of an unknown verb ("to teh ...") and
/// left out as ignored, so the relation was dropped and the one cup, which is to the right of
/// the box, was got: never a guess, the words are not understood.
#[test]
fn a_typo_inside_to_the_left_of_matches_nothing() {
    let scene = roomy(
        vec![the_box(), obj("cup", "cup", &[], &[], [0.5, -0.75, -0.25], None)],
        &[],
        None,
    );
    assert_eq!(candidates("Get the cup to the left of the box.", &scene), ids(&[]));
    assert!(
        matches!(
            read("Get the cup to teh left of the box.", &scene),
            Err((Unclear::Unplaced, _))
        ),
        "not understood, never read without its relation"
    );
    assert_ne!(decided("Get the cup to teh left of the box.", &scene).0, Comply);
}
