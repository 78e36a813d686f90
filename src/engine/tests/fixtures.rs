//! Scenes, norms and requests the tables are written in.

use super::*;

// Scenes

pub(super) fn agent() -> Agent {
    Agent {
        id: "self".into(),
        position: [0.0, 0.0, 0.75],
        reach: 0.9,
        gripper_aperture: None,
        payload: None,
        gripper_size: None,
        rotation: None,
    }
}

pub(super) fn obj(
    id: &str,
    kind: &str,
    properties: &[&str],
    attributes: &[(&str, &str)],
    position: [f64; 3],
    shape: Option<Shape>,
) -> Object {
    Object {
        id: id.into(),
        kind: kind.into(),
        properties: properties.iter().map(|p| p.to_string()).collect(),
        attributes: attributes.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect(),
        position,
        shape,
        rotation: None,
        mass: None,
        names: Vec::new(),
    }
}

/// `n` cups and `n` plates, `cup{i}` then `plate{i}` for each `i`: the cups as `cup` makes them,
/// the plates in a row on the table, within reach. Every cup on every plate is `n × n` readings.
pub(super) fn cups_and_plates(n: usize, cup: impl Fn(usize) -> Object) -> Vec<Object> {
    let plate = |i: usize| {
        obj(
            &format!("plate{i}"),
            "plate",
            &[],
            &[],
            [0.5, -0.01 * i as f64, 0.76],
            None,
        )
    };
    (0..n).flat_map(|i| [cup(i), plate(i)]).collect()
}

pub(super) fn notebook_shape() -> Option<Shape> {
    Some(Shape::Cuboid {
        half_extents: [0.105, 0.148, 0.01],
    })
}

pub(super) fn vase_shape() -> Option<Shape> {
    Some(Shape::Cylinder {
        radius: 0.06,
        half_height: 0.1,
    })
}

/// The mug is a point here, unlike in paper-demo.json: these tables put notebooks and vases on
/// it to test plans and norms, and a point support has no footprint for the placing check
/// (which needs both shapes; `tests/api/beyond.rs` covers placing). Reach is the same.
pub(super) fn mug_shape() -> Option<Shape> {
    None
}

/// The objects of paper-demo.json's "lab" scene, in its order.
pub(super) fn lab_objects() -> Vec<Object> {
    vec![
        obj(
            "object1",
            "notebook",
            &[],
            &[("color", "red")],
            [0.55, -0.4, 0.76],
            notebook_shape(),
        ),
        obj(
            "object2",
            "notebook",
            &[],
            &[("color", "green")],
            [0.55, -0.08, 0.76],
            notebook_shape(),
        ),
        obj("object3", "vase", &["fragile"], &[], [0.6, 0.15, 0.85], vase_shape()),
        obj(
            "object4",
            "vase",
            &[],
            &[("material", "plastic")],
            [0.6, 0.35, 0.85],
            vase_shape(),
        ),
        obj("object5", "mug", &[], &[], [0.5, 0.5, 0.8], mug_shape()),
    ]
}

impl Scene {
    /// A scene of a test's fixtures, values already checked.
    pub(crate) fn new(agent: Agent, objects: Vec<Object>, facts: Vec<Term>) -> Scene {
        let by_id = crate::engine::scene::Ids::of(&objects);
        Scene::indexed(agent, objects, facts, by_id)
    }
}

pub(super) fn scene(objects: Vec<Object>, facts: &[&str]) -> Scene {
    Scene::new(agent(), objects, facts.iter().map(|f| t(f)).collect())
}

/// paper-demo.json's "lab".
pub(super) fn lab() -> Scene {
    scene(lab_objects(), &[])
}

/// The lab with its objects changed by `change`.
pub(super) fn lab_with(change: impl FnOnce(&mut Vec<Object>)) -> Scene {
    let mut objects = lab_objects();
    change(&mut objects);
    scene(objects, &[])
}

/// paper-demo.json's "office".
pub(super) fn office() -> Scene {
    let shape = || {
        Some(Shape::Cuboid {
            half_extents: [0.15, 0.1, 0.05],
        })
    };
    scene(
        vec![
            obj("box1", "cash_box", &[], &[("color", "red")], [0.5, -0.2, 0.78], shape()),
            obj(
                "box2",
                "cash_box",
                &[],
                &[("color", "green")],
                [0.5, 0.2, 0.78],
                shape(),
            ),
        ],
        &[],
    )
}

pub(super) fn t(text: &str) -> Term {
    Term::parse(text).unwrap_or_else(|e| panic!("{text}: {e}"))
}

// Norms

pub(super) fn fa(action: &str) -> NormInput {
    NormInput {
        kind: Some("forbidden_action".into()),
        action: Some(action.into()),
        ..NormInput::default()
    }
}

pub(super) fn fs(state: &str) -> NormInput {
    NormInput {
        kind: Some("forbidden_state".into()),
        state: Some(state.into()),
        ..NormInput::default()
    }
}

pub(super) fn when(norm: NormInput, conditions: &[&str]) -> NormInput {
    NormInput {
        when: Some(conditions.iter().map(|c| c.to_string()).collect()),
        ..norm
    }
}

pub(super) fn in_context(norm: NormInput, context: &str) -> NormInput {
    NormInput {
        context: Some(context.into()),
        ..norm
    }
}

/// A compiled norm set; ids are 1..=n in the order given.
pub(super) fn norms(inputs: &[NormInput]) -> CompiledNorms {
    let norms = inputs
        .iter()
        .enumerate()
        .map(|(i, input)| Norm {
            id: i as i64 + 1,
            revision: 0,
            spec: input
                .clone()
                .validate()
                .unwrap_or_else(|e| panic!("norm {}: {e}", i + 1)),
        })
        .collect();
    CompiledNorms::compile(1, norms)
}

/// paper-demo.json's three norms: destroy (1), did(self,get(object3)) (2), steal (3).
pub(super) fn paper_norms() -> CompiledNorms {
    norms(&[fa("destroy"), fs("did(self,get(object3))"), fa("steal")])
}

// Requests

pub(super) fn ty(kind: &str) -> Reference {
    Reference::Described {
        kind: Some(kind.into()),
        attributes: BTreeMap::new(),
        properties: Vec::new(),
    }
}

pub(super) fn ty_with(kind: &str, properties: &[&str], attributes: &[(&str, &str)]) -> Reference {
    Reference::Described {
        kind: Some(kind.into()),
        attributes: attributes.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect(),
        properties: properties.iter().map(|p| p.to_string()).collect(),
    }
}

pub(super) fn id(id: &str) -> Reference {
    Reference::Id(id.into())
}

pub(super) fn request(directive: Directive) -> Request {
    Request {
        speaker: Sym::from("human"),
        speaker_roles: Vec::new(),
        directive,
        context: "default".into(),
        options: Options::default(),
        answer: None,
        focus: Vec::new(),
    }
}

/// `{"action": verb, "arguments": [...]}`.
pub(super) fn act(verb: &str, arguments: Vec<Reference>) -> Request {
    request(Directive::Action {
        verb: verb.into(),
        arguments,
        joiner: None,
    })
}

/// `{"form": ..., "bindings": {...}}` with every candidate scored 1.
pub(super) fn form(text: &str, bindings: &[(&str, &[&str])]) -> Request {
    let scored: Vec<(&str, Vec<(&str, f64)>)> = bindings
        .iter()
        .map(|(v, ids)| (*v, ids.iter().map(|i| (*i, 1.0)).collect()))
        .collect();
    let scored: Vec<(&str, &[(&str, f64)])> = scored.iter().map(|(v, c)| (*v, c.as_slice())).collect();
    form_scored(text, &scored)
}

/// `{"form": ..., "bindings": {"X": [{"id": ..., "score": ...}]}}`.
pub(super) fn form_scored(text: &str, bindings: &[(&str, &[(&str, f64)])]) -> Request {
    request(Directive::Form {
        action: t(text),
        bindings: bindings
            .iter()
            .map(|(var, candidates)| {
                (
                    Sym::from(*var),
                    candidates
                        .iter()
                        .map(|(id, score)| Candidate {
                            id: id.to_string(),
                            score: *score,
                        })
                        .collect(),
                )
            })
            .collect(),
    })
}

pub(super) fn with_context(request: Request, context: &str) -> Request {
    Request {
        context: context.into(),
        ..request
    }
}

pub(super) fn confirming(request: Request) -> Request {
    Request {
        options: Options {
            single_permissible: SinglePermissible::Confirm,
            ..request.options
        },
        ..request
    }
}

/// The request, answered in the natural style.
pub(super) fn natural(request: Request) -> Request {
    Request {
        options: Options {
            style: crate::engine::decision::Style::Natural,
            ..request.options
        },
        ..request
    }
}

pub(super) fn reflexive(request: Request) -> Request {
    Request {
        options: Options {
            strategy: ClarifyStrategy::Reflexive,
            ..request.options
        },
        ..request
    }
}

pub(super) fn run(request: &Request, scene: &Scene, norms: &CompiledNorms) -> Decision {
    clarify(request, scene, norms, &Library::default_library(), &|| false).expect("clarify")
}

/// Moves the lab's mug (object5) 3 m away, out of reach.
pub(super) fn far_mug(objects: &mut [Object]) {
    objects[4].position = [3.0, 0.0, 0.8];
}
