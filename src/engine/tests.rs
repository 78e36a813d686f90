//! Table-driven tests of the whole engine (scene, norms, simulation, Algorithm 1, utterances)
//! against CONTRACT.md and `../shared/scenarios/paper-demo.json`, and a property test of the
//! safety invariant: under the moral strategy no reading that violates a norm or cannot be done
//! is ever offered, assumed, confirmed or obeyed.

use std::collections::BTreeMap;

use proptest::prelude::*;

use super::action::Library;
use super::clarify::{
    DEFAULT_MAX_SPOKEN, Directive, FEW, Options, Request, SinglePermissible, Strategy as ClarifyStrategy, clarify,
};
use super::decision::{Decision, DecisionKind, Interpretation};
use super::norms::{CompiledNorms, Norm, NormInput};
use super::resolve::{Candidate, Reference};
use super::scene::{Agent, Object, Scene, Shape};
use super::term::{Sym, Term};

use DecisionKind::{Ask, Assume, Comply, Confirm, Explain, Refuse, Unresolved};

// ---------------------------------------------------------------------------------------------
// Scenes
// ---------------------------------------------------------------------------------------------

fn agent() -> Agent {
    Agent {
        id: "self".into(),
        position: [0.0, 0.0, 0.75],
        reach: 0.9,
        gripper_aperture: None,
        payload: None,
        gripper_size: None,
    }
}

fn obj(
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
    }
}

fn notebook_shape() -> Option<Shape> {
    Some(Shape::Cuboid {
        half_extents: [0.105, 0.148, 0.01],
    })
}

fn vase_shape() -> Option<Shape> {
    Some(Shape::Cylinder {
        radius: 0.06,
        half_height: 0.1,
    })
}

/// The mug is a point here, unlike in paper-demo.json: these tables put notebooks and vases on
/// it to test plans and norms, and a point support has no footprint for the placing check
/// (which needs both shapes; `tests/api/beyond.rs` covers placing). Reach is the same.
fn mug_shape() -> Option<Shape> {
    None
}

/// The objects of paper-demo.json's "lab" scene, in its order.
fn lab_objects() -> Vec<Object> {
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

fn scene(objects: Vec<Object>, facts: &[&str]) -> Scene {
    Scene::new(agent(), objects, facts.iter().map(|f| t(f)).collect())
}

/// paper-demo.json's "lab".
fn lab() -> Scene {
    scene(lab_objects(), &[])
}

/// The lab with its objects changed by `change`.
fn lab_with(change: impl FnOnce(&mut Vec<Object>)) -> Scene {
    let mut objects = lab_objects();
    change(&mut objects);
    scene(objects, &[])
}

/// paper-demo.json's "office".
fn office() -> Scene {
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

fn t(text: &str) -> Term {
    Term::parse(text).unwrap_or_else(|e| panic!("{text}: {e}"))
}

// ---------------------------------------------------------------------------------------------
// Norms
// ---------------------------------------------------------------------------------------------

fn fa(action: &str) -> NormInput {
    NormInput {
        kind: Some("forbidden_action".into()),
        action: Some(action.into()),
        ..NormInput::default()
    }
}

fn fs(state: &str) -> NormInput {
    NormInput {
        kind: Some("forbidden_state".into()),
        state: Some(state.into()),
        ..NormInput::default()
    }
}

fn when(norm: NormInput, conditions: &[&str]) -> NormInput {
    NormInput {
        when: Some(conditions.iter().map(|c| c.to_string()).collect()),
        ..norm
    }
}

fn in_context(norm: NormInput, context: &str) -> NormInput {
    NormInput {
        context: Some(context.into()),
        ..norm
    }
}

/// A compiled norm set; ids are 1..=n in the order given.
fn norms(inputs: &[NormInput]) -> CompiledNorms {
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
fn paper_norms() -> CompiledNorms {
    norms(&[fa("destroy"), fs("did(self,get(object3))"), fa("steal")])
}

// ---------------------------------------------------------------------------------------------
// Requests
// ---------------------------------------------------------------------------------------------

fn ty(kind: &str) -> Reference {
    Reference::Described {
        kind: Some(kind.into()),
        attributes: BTreeMap::new(),
        properties: Vec::new(),
    }
}

fn ty_with(kind: &str, properties: &[&str], attributes: &[(&str, &str)]) -> Reference {
    Reference::Described {
        kind: Some(kind.into()),
        attributes: attributes.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect(),
        properties: properties.iter().map(|p| p.to_string()).collect(),
    }
}

fn id(id: &str) -> Reference {
    Reference::Id(id.into())
}

fn request(directive: Directive) -> Request {
    Request {
        speaker: Sym::from("human"),
        speaker_roles: Vec::new(),
        directive,
        context: "default".into(),
        options: Options::default(),
        answer: None,
    }
}

/// `{"action": verb, "arguments": [...]}`.
fn act(verb: &str, arguments: Vec<Reference>) -> Request {
    request(Directive::Action {
        verb: verb.into(),
        arguments,
    })
}

/// `{"form": ..., "bindings": {...}}` with every candidate scored 1.
fn form(text: &str, bindings: &[(&str, &[&str])]) -> Request {
    let scored: Vec<(&str, Vec<(&str, f64)>)> = bindings
        .iter()
        .map(|(v, ids)| (*v, ids.iter().map(|i| (*i, 1.0)).collect()))
        .collect();
    let scored: Vec<(&str, &[(&str, f64)])> = scored.iter().map(|(v, c)| (*v, c.as_slice())).collect();
    form_scored(text, &scored)
}

/// `{"form": ..., "bindings": {"X": [{"id": ..., "score": ...}]}}`.
fn form_scored(text: &str, bindings: &[(&str, &[(&str, f64)])]) -> Request {
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

fn with_context(request: Request, context: &str) -> Request {
    Request {
        context: context.into(),
        ..request
    }
}

fn confirming(request: Request) -> Request {
    Request {
        options: Options {
            single_permissible: SinglePermissible::Confirm,
            ..request.options
        },
        ..request
    }
}

fn reflexive(request: Request) -> Request {
    Request {
        options: Options {
            strategy: ClarifyStrategy::Reflexive,
            ..request.options
        },
        ..request
    }
}

fn run(request: &Request, scene: &Scene, norms: &CompiledNorms) -> Decision {
    clarify(request, scene, norms, &Library::default_library(), &|| false).expect("clarify")
}

// ---------------------------------------------------------------------------------------------
// Expectations and the table runner
// ---------------------------------------------------------------------------------------------

/// A reason as the contract shows it: kind, detail, norm id.
type R = (&'static str, &'static str, Option<i64>);

struct Interp {
    action: &'static str,
    description: &'static str,
    reasons: Vec<R>,
    plan: Vec<&'static str>,
}

/// An expected interpretation; `permissible` and `feasible` follow from the reasons' kinds, as the
/// contract defines them.
fn interp(action: &'static str, description: &'static str, reasons: Vec<R>, plan: &[&'static str]) -> Interp {
    Interp {
        action,
        description,
        reasons,
        plan: plan.to_vec(),
    }
}

struct Expect {
    kind: DecisionKind,
    goal: Option<&'static str>,
    utterance: &'static str,
    speech_act: Option<&'static str>,
    /// `None`: not checked.
    interpretations: Option<Vec<Interp>>,
}

fn expect(kind: DecisionKind, goal: Option<&'static str>, utterance: &'static str) -> Expect {
    Expect {
        kind,
        goal,
        utterance,
        speech_act: None,
        interpretations: None,
    }
}

impl Expect {
    fn act(self, speech_act: &'static str) -> Expect {
        Expect {
            speech_act: Some(speech_act),
            ..self
        }
    }

    fn interps(self, interpretations: Vec<Interp>) -> Expect {
        Expect {
            interpretations: Some(interpretations),
            ..self
        }
    }
}

struct Case {
    name: &'static str,
    scene: Scene,
    norms: CompiledNorms,
    request: Request,
    expect: Expect,
}

fn case(name: &'static str, scene: Scene, norms: CompiledNorms, request: Request, expect: Expect) -> Case {
    Case {
        name,
        scene,
        norms,
        request,
        expect,
    }
}

fn is_forbidden(kind: &str) -> bool {
    kind.starts_with("forbidden_")
}

/// Every difference between the decision and the expectation, each naming the case.
fn mismatches(name: &str, d: &Decision, e: &Expect) -> Vec<String> {
    let mut out = Vec::new();
    let mut differ = |what: &str, got: String, want: String| {
        if got != want {
            out.push(format!("[{name}] {what}:\n     got: {got}\n    want: {want}"));
        }
    };
    differ("decision", d.kind.as_str().into(), e.kind.as_str().into());
    differ(
        "goal",
        format!("{:?}", d.goal.as_ref().map(Term::to_string)),
        format!("{:?}", e.goal),
    );
    differ("utterance", d.utterance.clone(), e.utterance.into());
    if let Some(speech_act) = e.speech_act {
        differ("speech_act", d.speech_act.to_string(), speech_act.into());
    }
    if let Some(want) = &e.interpretations {
        let got_actions: Vec<String> = d.interpretations.iter().map(|i| i.action.to_string()).collect();
        let want_actions: Vec<String> = want.iter().map(|i| i.action.to_string()).collect();
        differ(
            "interpretations' order",
            format!("{got_actions:?}"),
            format!("{want_actions:?}"),
        );
        for (got, want) in d.interpretations.iter().zip(want) {
            let at = format!("interpretation {}", want.action);
            differ(
                &format!("{at} description"),
                got.description.clone(),
                want.description.into(),
            );
            let got_reasons: Vec<(String, String, Option<i64>)> = got
                .outcome
                .reasons
                .iter()
                .map(|r| (r.kind().to_owned(), r.detail(), r.norm_id))
                .collect();
            let want_reasons: Vec<(String, String, Option<i64>)> = want
                .reasons
                .iter()
                .map(|(k, d, n)| (k.to_string(), d.to_string(), *n))
                .collect();
            differ(
                &format!("{at} reasons"),
                format!("{got_reasons:?}"),
                format!("{want_reasons:?}"),
            );
            let got_plan: Vec<String> = got.outcome.plan.iter().map(Term::to_string).collect();
            differ(
                &format!("{at} plan"),
                format!("{got_plan:?}"),
                format!("{:?}", want.plan),
            );
            let permissible = !want.reasons.iter().any(|(k, _, _)| is_forbidden(k));
            let feasible = want.reasons.iter().all(|(k, _, _)| is_forbidden(k));
            differ(
                &format!("{at} permissible"),
                got.permissible().to_string(),
                permissible.to_string(),
            );
            differ(
                &format!("{at} feasible"),
                got.feasible().to_string(),
                feasible.to_string(),
            );
        }
    }
    out
}

fn run_cases(cases: Vec<Case>) {
    let mut failures = Vec::new();
    for c in &cases {
        match clarify(&c.request, &c.scene, &c.norms, &Library::default_library(), &|| false) {
            Ok(d) => failures.extend(mismatches(c.name, &d, &c.expect)),
            Err(e) => failures.push(format!("[{}] clarify failed: {e}", c.name)),
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases differ:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

const FA: &str = "forbidden_action";
const FS: &str = "forbidden_state";

// ---------------------------------------------------------------------------------------------
// paper-demo.json
// ---------------------------------------------------------------------------------------------

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

// ---------------------------------------------------------------------------------------------
// Each decision outside the paper's cases: single candidates, unresolved references, strategies
// ---------------------------------------------------------------------------------------------

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

// ---------------------------------------------------------------------------------------------
// Feasibility: unknown verbs, reach, shapes and rotation
// ---------------------------------------------------------------------------------------------

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

/// Moves the lab's mug (object5) 3 m away, out of reach.
fn far_mug(objects: &mut [Object]) {
    objects[4].position = [3.0, 0.0, 0.8];
}

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
            "one of two mugs out of reach: assume the other, explain with its id",
            lab_with(|objects| {
                objects.push(obj("object6", "mug", &[], &[], [3.0, 0.0, 0.8], mug_shape()));
            }),
            paper_norms(),
            act("get", vec![ty("mug")]),
            expect(
                Assume,
                Some("did(self,get(object5))"),
                "I am assuming you want me to get the mug (object5). I cannot get the mug (object6) because the mug (object6) is out of reach.",
            )
            .interps(vec![
                interp("did(self,get(object5))", "the mug (object5)", vec![], &["get(object5)"]),
                interp(
                    "did(self,get(object6))",
                    "the mug (object6)",
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

// ---------------------------------------------------------------------------------------------
// Norms with conditions and contexts
// ---------------------------------------------------------------------------------------------

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
                "I am assuming you want me to get the plastic vase. I cannot get the fragile vase because it requires a forbidden state.",
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
                "I am assuming you want me to get the plastic vase. I cannot get the fragile vase because get is forbidden action.",
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
                "I believe that I cannot get the fragile vase because get is forbidden action and that I cannot get the plastic vase because get is forbidden action.",
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
            expect(Refuse, None, "I cannot put the red notebook on the mug because it requires a forbidden state.")
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
                "I am assuming you want me to get the green notebook. I cannot get the red notebook because it requires a forbidden state.",
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
                "I am assuming you want me to get the plastic vase. I cannot get the fragile vase because it requires a forbidden state.",
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
            expect(Refuse, None, "I cannot get the mug because get is forbidden action.")
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
                "I am assuming you want me to get the plastic vase. I cannot get the fragile vase because it requires a forbidden state.",
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

// ---------------------------------------------------------------------------------------------
// Plans: steps, states entered mid-plan, and the order and uniqueness of reasons
// ---------------------------------------------------------------------------------------------

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
            "I cannot put the red notebook on the mug because put is forbidden action.",
        )
        .interps(vec![interp(
            "did(self,put(object1,object5))",
            "the red notebook on the mug",
            vec![(FA, "put(object1,object5)", Some(1))],
            &["get(object1)", "put(object1,object5)"],
        )]),
    )]);
}

// ---------------------------------------------------------------------------------------------
// Order of interpretations, descriptions and readings
// ---------------------------------------------------------------------------------------------

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
            "two identical mugs get their ids",
            lab_with(|objects| objects.push(obj("object6", "mug", &[], &[], [0.5, 0.4, 0.8], mug_shape()))),
            paper_norms(),
            act("get", vec![ty("mug")]),
            expect(
                Ask,
                None,
                "Do you mean that you want me to get the mug (object5) or that you want me to get the mug (object6)?",
            )
            .interps(vec![
                interp("did(self,get(object5))", "the mug (object5)", vec![], &["get(object5)"]),
                interp("did(self,get(object6))", "the mug (object6)", vec![], &["get(object6)"]),
            ]),
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
                "Do you mean that you want me to get the heavy vase or that you want me to get the vase (v2)?",
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
                "Do you mean that you want me to point to the fragile blue vase or that you want me to point to the fragile red vase or that you want me to point to the red vase (v3)?",
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

// ---------------------------------------------------------------------------------------------
// The safety invariant, property-tested
// ---------------------------------------------------------------------------------------------

const TYPES: [&str; 3] = ["vase", "mug", "cash_box"];
const VERBS: [&str; 6] = ["get", "destroy", "steal", "pointTo", "juggle", "put"];

/// One random object: type index, fragile, heavy, colour, out of reach, y offset, has a shape.
type ObjGen = (usize, bool, bool, Option<&'static str>, bool, f64, bool);

fn arb_object() -> impl Strategy<Value = ObjGen> {
    (
        0..3usize,
        any::<bool>(),
        any::<bool>(),
        prop_oneof![Just(None), Just(Some("red")), Just(Some("green"))],
        prop::bool::weighted(0.3),
        -0.4..0.4f64,
        any::<bool>(),
    )
}

fn arb_context() -> impl Strategy<Value = Option<&'static str>> {
    prop_oneof![Just(None), Just(Some("default")), Just(Some("hospital"))]
}

fn arb_when() -> impl Strategy<Value = Option<&'static str>> {
    prop_oneof![
        2 => Just(None),
        1 => Just(Some("fragile(X)")),
        1 => Just(Some("heavy(X)")),
        1 => Just(Some("color(X,red)")),
        1 => Just(Some("holding(self,X)")),
        1 => Just(Some("on(X,Y)")),
    ]
}

fn arb_norm() -> impl Strategy<Value = NormInput> {
    let action =
        (0..5usize, any::<bool>(), arb_when(), arb_context()).prop_map(|(verb, with_variable, cond, context)| {
            let name = ["get", "destroy", "steal", "put", "pointTo"][verb];
            let text = match (with_variable, name) {
                (false, _) => name.to_owned(),
                (true, "put") => "put(X,Y)".to_owned(),
                (true, _) => format!("{name}(X)"),
            };
            finish(fa(&text), cond, context)
        });
    let state = (0..3usize, 1..=6usize, arb_when(), arb_context()).prop_map(|(which, n, cond, context)| {
        let text = match which {
            0 => "holding(self,X)".to_owned(),
            1 => "destroyed(X)".to_owned(),
            _ => format!("did(self,get(object{n}))"),
        };
        finish(fs(&text), cond, context)
    });
    prop_oneof![action, state]
}

fn finish(norm: NormInput, cond: Option<&str>, context: Option<&str>) -> NormInput {
    let norm = match cond {
        Some(c) => when(norm, &[c]),
        None => norm,
    };
    match context {
        Some(c) => in_context(norm, c),
        None => norm,
    }
}

fn random_scene(objects: &[ObjGen], type_count: usize, on_table: &[bool]) -> Scene {
    let objects: Vec<Object> = objects
        .iter()
        .enumerate()
        .map(|(i, &(kind, fragile, heavy, color, far, y, shaped))| {
            let mut properties = Vec::new();
            if fragile {
                properties.push("fragile");
            }
            if heavy {
                properties.push("heavy");
            }
            let attributes: Vec<(&str, &str)> = color.map(|c| ("color", c)).into_iter().collect();
            let x = if far { 2.5 } else { 0.5 };
            let shape = shaped.then_some(Shape::Ball { radius: 0.05 });
            obj(
                &format!("object{}", i + 1),
                TYPES[kind % type_count],
                &properties,
                &attributes,
                [x, y, 0.8],
                shape,
            )
        })
        .collect();
    let facts: Vec<String> = (0..objects.len())
        .filter(|i| on_table.get(*i).copied().unwrap_or(false))
        .map(|i| format!("on(object{},table1)", i + 1))
        .collect();
    let facts: Vec<&str> = facts.iter().map(String::as_str).collect();
    scene(objects, &facts)
}

/// Algorithm 1 by counts, and the words it must (and must not) say.
fn check_invariant(d: &Decision, single: SinglePermissible) -> Result<(), TestCaseError> {
    let all = &d.interpretations;
    let good: Vec<_> = all.iter().filter(|i| i.permissible() && i.feasible()).collect();
    let bad: Vec<_> = all.iter().filter(|i| !(i.permissible() && i.feasible())).collect();
    for i in all {
        let forbidden = i.outcome.reasons.iter().any(|r| r.kind().starts_with("forbidden_"));
        let other = i.outcome.reasons.iter().any(|r| !r.kind().starts_with("forbidden_"));
        prop_assert_eq!(i.permissible(), !forbidden, "permissible of {}", i.action);
        prop_assert_eq!(i.feasible(), !other, "feasible of {}", i.action);
        for (n, r) in i.outcome.reasons.iter().enumerate() {
            prop_assert!(
                !i.outcome.reasons[..n].contains(r),
                "{}: reason {:?} listed twice",
                i.action,
                r
            );
            prop_assert_eq!(
                r.norm_id.is_some(),
                r.kind().starts_with("forbidden_"),
                "norm id of {:?}",
                r
            );
        }
    }
    let expected = match (all.len(), good.len()) {
        (0, _) => Unresolved,
        (1, 1) => Comply,
        (1, _) => Refuse,
        (_, 0) => Explain,
        (_, 1) => match single {
            SinglePermissible::Assume => Assume,
            SinglePermissible::Confirm => Confirm,
        },
        _ => Ask,
    };
    prop_assert_eq!(d.kind, expected, "utterance: {}", d.utterance);
    match d.kind {
        Comply | Assume => {
            let goal = d.goal.as_ref().expect("comply and assume set a goal");
            prop_assert!(
                good.iter().any(|i| &i.action == goal),
                "goal {} is not acceptable",
                goal
            );
        }
        _ => prop_assert!(d.goal.is_none(), "{} with goal {:?}", d.kind.as_str(), d.goal),
    }
    match d.kind {
        Comply => prop_assert_eq!(d.utterance.as_str(), "Okay."),
        Refuse => {
            let prefix = format!("I cannot {} because ", all[0].reading);
            prop_assert!(d.utterance.starts_with(&prefix), "{}", d.utterance);
        }
        Ask => {
            // Only acceptable readings are ever named, in order: all of them when they fit in
            // `max_spoken`; else the first few and "or something else", or no reading at all
            // but the ambiguous words.
            let offered: Vec<&Interpretation> = d
                .offered
                .iter()
                .map(|a| {
                    all.iter()
                        .find(|i| &i.action == a)
                        .expect("an offered reading is a reading")
                })
                .collect();
            prop_assert!(
                offered.iter().all(|i| i.permissible() && i.feasible()),
                "{}",
                d.utterance
            );
            prop_assert!(
                good.iter()
                    .map(|i| &i.action)
                    .take(offered.len())
                    .eq(offered.iter().map(|i| &i.action))
            );
            let readings: Vec<&str> = offered.iter().map(|i| i.reading.as_str()).collect();
            if good.len() <= DEFAULT_MAX_SPOKEN {
                prop_assert_eq!(offered.len(), good.len());
                let question = format!(
                    "Do you mean that you want me to {}?",
                    readings.join(" or that you want me to ")
                );
                prop_assert_eq!(&d.utterance, &question);
                let or = Term::compound("or", good.iter().map(|i| i.action.clone()).collect());
                prop_assert_eq!(d.speech_act.to_string(), format!("want_know(self,mean(human,{or}))"));
            } else if offered.is_empty() {
                prop_assert!(d.utterance.starts_with("I do not know which "), "{}", d.utterance);
                prop_assert!(d.utterance.ends_with(" you mean."), "{}", d.utterance);
            } else {
                prop_assert!(offered.len() <= FEW);
                let question = format!(
                    "Do you mean that you want me to {} or something else?",
                    readings.join(" or that you want me to ")
                );
                prop_assert_eq!(&d.utterance, &question);
            }
        }
        Assume | Confirm => {
            let first = match d.kind {
                Assume => format!("I am assuming you want me to {}.", good[0].reading),
                _ => format!("Do you want me to {}?", good[0].reading),
            };
            prop_assert!(d.utterance.starts_with(&first), "{}", d.utterance);
            let mut at = first.len();
            for other in &bad {
                let sentence = format!(" I cannot {} because ", other.reading);
                prop_assert!(
                    d.utterance[at..].starts_with(&sentence),
                    "{} at {}: {}",
                    sentence,
                    at,
                    d.utterance
                );
                at += sentence.len();
                at += d.utterance[at..].find('.').map_or(0, |p| p + 1);
            }
            prop_assert_eq!(at, d.utterance.len(), "{}", d.utterance);
        }
        Explain => {
            let mut at = 0;
            for (n, i) in all.iter().enumerate() {
                let clause = if n == 0 {
                    format!("I believe that I cannot {} because ", i.reading)
                } else {
                    format!(" and that I cannot {} because ", i.reading)
                };
                match d.utterance[at..].find(&clause) {
                    Some(p) => at += p + clause.len(),
                    None => {
                        return Err(TestCaseError::fail(format!("{clause:?} missing in {}", d.utterance)));
                    }
                }
            }
            prop_assert!(d.utterance.ends_with('.'));
        }
        Unresolved => prop_assert!(d.utterance.starts_with("I do not know what you mean by the ")),
    }
    Ok(())
}

/// Everything one random request needs; the scene is rebuilt from it on demand.
#[derive(Clone, Debug)]
struct RandomCase {
    objects: Vec<ObjGen>,
    type_count: usize,
    on_table: Vec<bool>,
    norms: Vec<NormInput>,
    verb: &'static str,
    /// Indices into TYPES; `put` uses both, the others the first.
    references: (usize, usize),
    context: &'static str,
    single: SinglePermissible,
}

impl RandomCase {
    fn scene(&self) -> Scene {
        random_scene(&self.objects, self.type_count, &self.on_table)
    }

    fn request(&self) -> Request {
        let (first, second) = self.references;
        let arguments = if self.verb == "put" {
            vec![ty(TYPES[first]), ty(TYPES[second])]
        } else {
            vec![ty(TYPES[first])]
        };
        Request {
            context: self.context.into(),
            options: Options {
                strategy: ClarifyStrategy::Moral,
                single_permissible: self.single,
                ..Options::default()
            },
            ..act(self.verb, arguments)
        }
    }
}

fn arb_case() -> impl Strategy<Value = RandomCase> {
    (
        prop::collection::vec(arb_object(), 1..=6),
        1..=3usize,
        prop::collection::vec(any::<bool>(), 6),
        prop::collection::vec(arb_norm(), 0..=4),
        prop::sample::select(VERBS.to_vec()),
        (0..3usize, 0..3usize),
        prop::sample::select(vec!["default", "hospital"]),
        prop_oneof![Just(SinglePermissible::Assume), Just(SinglePermissible::Confirm)],
    )
        .prop_map(
            |(objects, type_count, on_table, norms, verb, references, context, single)| RandomCase {
                objects,
                type_count,
                on_table,
                norms,
                verb,
                references,
                context,
                single,
            },
        )
}

/// 1,000 cases on every `cargo test`; the long run sets `SCRUPLE_PROPTEST_CASES` (e.g. 10000,
/// see README "Hostile input").
fn safety_cases() -> u32 {
    std::env::var("SCRUPLE_PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1000)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(safety_cases()))]

    #[test]
    fn moral_strategy_never_offers_assumes_confirms_or_obeys_a_bad_reading(case in arb_case()) {
        let scene = case.scene();
        let norms = norms(&case.norms);
        let request = case.request();
        let library = Library::default_library();
        let d = clarify(&request, &scene, &norms, &library, &|| false).expect("clarify");
        check_invariant(&d, case.single)?;
        // The same inputs, again and on a freshly built scene: the same decision.
        prop_assert_eq!(&clarify(&request, &scene, &norms, &library, &|| false).expect("clarify"), &d);
        prop_assert_eq!(&clarify(&request, &case.scene(), &norms, &library, &|| false).expect("clarify"), &d);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(safety_cases() / 4))]

    /// The deadline may fall anywhere, even inside a reading's plan: whatever was cut short is
    /// never offered, assumed, confirmed or obeyed, and the answer says a limit was hit.
    #[test]
    fn a_deadline_anywhere_never_lets_an_unchecked_reading_through(case in arb_case(), after in 0..40usize) {
        use std::sync::atomic::{AtomicUsize, Ordering};
        let scene = case.scene();
        let norms = norms(&case.norms);
        let request = case.request();
        let library = Library::default_library();
        let calls = AtomicUsize::new(0);
        let expired = || calls.fetch_add(1, Ordering::Relaxed) >= after;
        let d = clarify(&request, &scene, &norms, &library, &expired).expect("clarify");
        let unfinished = d.interpretations.iter().any(|i| i.outcome.unfinished());
        if unfinished {
            prop_assert!(d.limits.is_some(), "a reading was cut short and the answer does not say so");
        }
        if d.limits.is_some() {
            prop_assert!(d.goal.is_none(), "{}: acted on a partial view", d.utterance);
            prop_assert!(matches!(d.kind, Ask | Refuse), "{:?}: {}", d.kind, d.utterance);
        }
        let offered: Vec<_> = d.interpretations.iter().filter(|i| d.offered.contains(&i.action)).collect();
        for i in offered {
            prop_assert!(i.permissible() && i.feasible(), "offered {} ({})", i.action, d.utterance);
        }
        for words in d.interpretations.iter().flat_map(|i| &i.reason_words) {
            prop_assert!(!words.trim().is_empty(), "a reason with no words: {}", d.utterance);
        }
    }
}

/// The property above is only as strong as its inputs: they must reach every decision, and every
/// reason kind the default library can produce.
#[test]
fn random_cases_reach_every_decision_and_reason_kind() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    use std::collections::BTreeMap;

    let mut runner = TestRunner::deterministic();
    let strategy = arb_case();
    let mut decisions: BTreeMap<&str, usize> = BTreeMap::new();
    let mut reasons: BTreeMap<&str, usize> = BTreeMap::new();
    for _ in 0..1000 {
        let case = strategy.new_tree(&mut runner).expect("a case").current();
        let d = run(&case.request(), &case.scene(), &norms(&case.norms));
        *decisions.entry(d.kind.as_str()).or_default() += 1;
        for i in &d.interpretations {
            for r in &i.outcome.reasons {
                *reasons.entry(r.kind()).or_default() += 1;
            }
        }
    }
    for kind in ["comply", "refuse", "ask", "assume", "confirm", "explain", "unresolved"] {
        assert!(decisions.get(kind).is_some_and(|&n| n >= 10), "{kind}: {decisions:?}");
    }
    for kind in ["forbidden_action", "forbidden_state", "unknown_action", "unreachable"] {
        assert!(reasons.get(kind).is_some_and(|&n| n >= 10), "{kind}: {reasons:?}");
    }
}

/// Enough readings to run on rayon's pool: one thread or four, the same decision, byte for byte.
#[test]
fn the_decision_is_the_same_whatever_the_thread_count() {
    let mut objects = Vec::new();
    for i in 0..40 {
        let far = if i % 7 == 0 { 3.0 } else { 0.5 };
        objects.push(obj(
            &format!("cup{i}"),
            "cup",
            &[],
            &[],
            [far, 0.01 * i as f64, 0.8],
            None,
        ));
        objects.push(obj(
            &format!("plate{i}"),
            "plate",
            &[],
            &[],
            [0.5, -0.01 * i as f64, 0.76],
            None,
        ));
    }
    let scene = scene(objects, &["fragile(cup3)", "fragile(cup5)"]);
    let norms = norms(&[when(fa("put(X,Y)"), &["fragile(X)"]), fs("on(cup8,plate9)")]);
    let request = act("put", vec![ty("cup"), ty("plate")]);
    let run_on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| clarify(&request, &scene, &norms, &Library::default_library(), &|| false).unwrap())
    };
    let one = run_on(1);
    assert_eq!(one.interpretations.len(), 1600);
    assert!(one.interpretations.len() >= super::clarify::PARALLEL_FROM);
    assert_eq!(one, run_on(4));
    assert_eq!(one, run_on(2));
}
