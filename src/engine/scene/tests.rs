//! Reach, clearance and the scene's checks, on scenes built by hand.

use super::*;

fn object(position: [f64; 3], shape: Option<Shape>, rotation: Option<[f64; 4]>) -> Object {
    Object {
        id: "o".into(),
        kind: "thing".into(),
        properties: vec![],
        attributes: BTreeMap::new(),
        position,
        shape,
        rotation,
        mass: None,
        names: Vec::new(),
    }
}

#[test]
fn distances_follow_each_shape_and_rotation() {
    let origin = [0.0, 0.0, 0.0];
    let cases: Vec<(Object, f64)> = vec![
        (object([1.0, 0.0, 0.0], None, None), 1.0),
        (object([1.0, 0.0, 0.0], Some(Shape::Ball { radius: 0.25 }), None), 0.75),
        (
            object(
                [1.0, 0.0, 0.0],
                Some(Shape::Cuboid {
                    half_extents: [0.1, 0.5, 0.5],
                }),
                None,
            ),
            0.9,
        ),
        // Cylinder axis along z: its radius faces the agent along x.
        (
            object(
                [1.0, 0.0, 0.0],
                Some(Shape::Cylinder {
                    radius: 0.2,
                    half_height: 0.5,
                }),
                None,
            ),
            0.8,
        ),
        // Straight above: the cap (half height) faces the agent.
        (
            object(
                [0.0, 0.0, 1.0],
                Some(Shape::Cylinder {
                    radius: 0.2,
                    half_height: 0.5,
                }),
                None,
            ),
            0.5,
        ),
        // The same cylinder turned a quarter about y lies along x: the radius faces up.
        (
            object(
                [0.0, 0.0, 1.0],
                Some(Shape::Cylinder {
                    radius: 0.2,
                    half_height: 0.5,
                }),
                Some([
                    0.0,
                    std::f64::consts::FRAC_1_SQRT_2,
                    0.0,
                    std::f64::consts::FRAC_1_SQRT_2,
                ]),
            ),
            0.8,
        ),
        // Inside the shape: zero.
        (object([0.0, 0.0, 0.0], Some(Shape::Ball { radius: 1.0 }), None), 0.0),
    ];
    for (object, expected) in cases {
        let d = distance_to_shape(&object, &origin);
        assert!((d - expected).abs() < 1e-5, "{object:?}: {d} != {expected}");
    }
}

/// Found by `fuzz/fuzz_targets/clarify_request.rs`: with one or two shaped objects not first
/// in the scene, building the BVH panicked inside parry.
#[test]
fn clearance_is_found_when_point_objects_come_before_the_shaped_ones() {
    let agent = Agent {
        id: "self".into(),
        position: [0.0, 0.0, 0.0],
        reach: 2.0,
        gripper_aperture: None,
        payload: None,
        gripper_size: Some(0.05),
        rotation: None,
    };
    let named = |id: &str, position: [f64; 3], shape: Option<Shape>| Object {
        id: id.into(),
        ..object(position, shape, None)
    };
    let ball = || Some(Shape::Ball { radius: 0.1 });
    let cases: Vec<(Vec<Object>, &str, Option<&str>)> = vec![
        (
            vec![named("p", [0.0, 1.0, 0.0], None), named("b", [1.0, 0.0, 0.0], ball())],
            "b",
            None,
        ),
        (
            vec![named("p", [0.0, 1.0, 0.0], None), named("b", [1.0, 0.0, 0.0], ball())],
            "p",
            None,
        ),
        (
            vec![
                named("p", [0.0, 1.0, 0.0], None),
                named("wall", [0.5, 0.0, 0.0], ball()),
                named("b", [1.0, 0.0, 0.0], ball()),
            ],
            "b",
            Some("wall"),
        ),
        (
            vec![
                named("p", [0.0, 1.0, 0.0], None),
                named("q", [0.0, -1.0, 0.0], None),
                named("wall", [0.5, 0.0, 0.0], ball()),
                named("b", [1.0, 0.0, 0.0], None),
            ],
            "b",
            Some("wall"),
        ),
    ];
    for (objects, target, expected) in cases {
        let scene = Scene::new(agent.clone(), objects, vec![]);
        let blocker = scene.blocked_by(target).map(|o| o.id.as_str());
        assert_eq!(blocker, expected, "reaching for {target}");
    }
}
