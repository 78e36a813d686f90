//! Two objects in each relation, from facts and from the boxes at and either side of each
//! threshold, seen by a turned agent, as points: `holds`, words, decision and structured form.

use std::f64::consts::FRAC_1_SQRT_2;

use super::words::read;
use super::*;
use crate::engine::resolve::ReferenceInput;
use crate::engine::scene::relate::Relation;

use Relation::{Behind, From, In, InFrontOf, LeftOf, Near, On, RightOf, Under};

// Scenes and requests, shared with `relation_refs`

/// The fixtures' agent, reaching every object of these tables: reach is not what they test.
pub(super) fn roomy(objects: Vec<Object>, facts: &[&str], rotation: Option<[f64; 4]>) -> Scene {
    let agent = Agent {
        reach: 50.0,
        rotation,
        ..agent()
    };
    Scene::new(agent, objects, facts.iter().map(|f| t(f)).collect())
}

pub(super) fn words(text: &str) -> Request {
    request(Directive::Words { text: text.into() })
}

pub(super) fn cuboid(h: [f64; 3]) -> Option<Shape> {
    Some(Shape::Cuboid { half_extents: h })
}

/// The landmark: a box spanning x 0.25..0.75, y −0.25..0.25, z −0.5..0 (every bound exact).
pub(super) fn the_box() -> Object {
    obj("box", "box", &[], &[], [0.5, 0.0, -0.25], cuboid([0.25; 3]))
}

/// The candidates of the only reference of the words.
pub(super) fn candidates(text: &str, scene: &Scene) -> Vec<String> {
    match read(text, scene) {
        Ok((_, mut references)) if references.len() == 1 => references.remove(0),
        other => panic!("{text}: read as {other:?}"),
    }
}

/// What a decision shows: kind, goal and utterance.
pub(super) fn shown(d: &Decision) -> (DecisionKind, Option<String>, String) {
    (d.kind, d.goal.as_ref().map(Term::to_string), d.utterance.clone())
}

/// What "Get ..." decides in the scene, as shown.
pub(super) fn decided(text: &str, scene: &Scene) -> (DecisionKind, Option<String>, String) {
    shown(&run(&words(text), scene, &norms(&[])))
}

pub(super) fn complied(id: &str) -> (DecisionKind, Option<String>, String) {
    (Comply, Some(format!("did(self,get({id}))")), "Okay.".to_owned())
}

/// A structured description of a type with relations to others.
pub(super) fn described(kind: &str, relations: Vec<(&str, ReferenceInput)>) -> ReferenceInput {
    ReferenceInput {
        kind: Some(kind.into()),
        relations: relations.into_iter().map(|(r, to)| (r.to_owned(), to)).collect(),
        ..ReferenceInput::default()
    }
}

pub(super) fn ids(list: &[&str]) -> Vec<String> {
    list.iter().map(|s| (*s).to_owned()).collect()
}

pub(super) fn holds(scene: &Scene, relation: Relation, a: &str, b: &str) -> bool {
    let index = |id: &str| scene.index_of(id).unwrap_or_else(|| panic!("no {id}"));
    scene.layout().holds(scene, relation, index(a), index(b))
}

/// Turned 90° about z: the agent faces +y, and −x is its left.
pub(super) const QUARTER: [f64; 4] = [0.0, 0.0, FRAC_1_SQRT_2, FRAC_1_SQRT_2];
/// Turned 180° about z: +y is its right.
const HALF: [f64; 4] = [0.0, 0.0, 1.0, 0.0];

// Two objects, every relation

/// One row: a cup and a landmark box (the agent turned by `rotation`; `facts`), and the
/// relations `relation(cup, box)` that hold; every other must not.
struct Pair {
    name: &'static str,
    cup: Object,
    landmark: Object,
    rotation: Option<[f64; 4]>,
    facts: &'static [&'static str],
    holding: &'static [Relation],
}

/// A row with [`the_box`], the agent unturned and no facts.
fn row(name: &'static str, cup: Object, holding: &'static [Relation]) -> Pair {
    Pair {
        name,
        cup,
        landmark: the_box(),
        rotation: None,
        facts: &[],
        holding,
    }
}

impl Pair {
    fn turned(self, rotation: [f64; 4]) -> Pair {
        Pair {
            rotation: Some(rotation),
            ..self
        }
    }

    fn facts(self, facts: &'static [&'static str]) -> Pair {
        Pair { facts, ..self }
    }

    /// The landmark a point at (0.5, 0, 0).
    fn landmark_a_point(self) -> Pair {
        Pair {
            landmark: obj("box", "box", &[], &[], [0.5, 0.0, 0.0], None),
            ..self
        }
    }
}

/// A point cup.
fn p(x: f64, y: f64, z: f64) -> Object {
    obj("cup", "cup", &[], &[], [x, y, z], None)
}

/// A cube cup of half side `h`.
fn c(h: f64, x: f64, y: f64, z: f64) -> Object {
    obj("cup", "cup", &[], &[], [x, y, z], cuboid([h; 3]))
}

/// The words each relation is said with here: as the robot speaks it, so that the structured
/// reference's words (which the robot makes) are the same.
fn said(relation: Relation) -> &'static str {
    match relation {
        LeftOf => "to the left of",
        RightOf => "to the right of",
        InFrontOf => "in front of",
        other => other.name(),
    }
}

/// Every difference from the row, for each of the nine relations: `holds`, the candidates of
/// "Get the cup REL the box.", its decision, and the decision of the structured reference.
fn pair_mismatches(row: &Pair) -> Vec<String> {
    let scene = roomy(vec![row.cup.clone(), row.landmark.clone()], row.facts, row.rotation);
    let mut out = Vec::new();
    for relation in Relation::ALL {
        let want = row.holding.contains(&relation);
        let at = format!("[{}] {}(cup,box)", row.name, relation.name());
        if scene.layout().holds(&scene, relation, 0, 1) != want {
            out.push(format!("{at}: holds is {}", !want));
        }
        let text = format!("Get the cup {} the box.", said(relation));
        let got = candidates(&text, &scene);
        if got != ids(if want { &["cup"] } else { &[] }) {
            out.push(format!("{at}: {text} selects {got:?}"));
        }
        let by_words = decided(&text, &scene);
        let want_decision = match want {
            true => complied("cup"),
            false => (
                Unresolved,
                None,
                format!("I do not know what you mean by the cup {} the box.", said(relation)),
            ),
        };
        if by_words != want_decision {
            out.push(format!("{at}: {text} is decided {by_words:?}"));
        }
        let input = described("cup", vec![(relation.name(), described("box", vec![]))]);
        let structured = Reference::from_input(input, &scene).expect("a known relation");
        let by_structure = shown(&run(&act("get", vec![structured]), &scene, &norms(&[])));
        if by_structure != by_words {
            out.push(format!(
                "{at}: structured is decided {by_structure:?}, words {by_words:?}"
            ));
        }
    }
    out
}

fn run_pairs(rows: Vec<Pair>) {
    let failures: Vec<String> = rows.iter().flat_map(pair_mismatches).collect();
    assert!(
        failures.is_empty(),
        "{} differences:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

const E: f64 = 1e-6;

#[test]
fn on_in_and_under_from_the_boxes_at_each_threshold() {
    run_pairs(vec![
        row("on: bottom 0.03 above the top", p(0.5, 0.0, 0.03), &[On, From]),
        row("on: 1e-6 higher is only near", p(0.5, 0.0, 0.03 + E), &[Near]),
        row("on: bottom sunk 0.03 into the top", p(0.5, 0.0, -0.03), &[On, From]),
        row("on: sunk 1e-6 more is in", p(0.5, 0.0, -0.03 - E), &[In, From]),
        row("on: a cube resting on it", c(0.0625, 0.5, 0.0, 0.0625), &[On, From]),
        // The sides hold beside `on`: the centre is 0.25 further left and farther.
        row(
            "on: centre over the corner",
            p(0.75, 0.25, 0.0),
            &[On, From, LeftOf, Behind],
        ),
        row("on: centre 1e-6 past the edge", p(0.75 + E, 0.0, 0.0), &[Near, Behind]),
        row(
            "on: overhanging, centre over",
            c(0.0625, 0.74, 0.0, 0.0625),
            &[On, From, Behind],
        ),
        row("in: at the centre", p(0.5, 0.0, -0.25), &[In, From]),
        row(
            "in: the bottom corner counts",
            p(0.25, -0.25, -0.5),
            &[In, From, RightOf, InFrontOf],
        ),
        row("in: 1e-6 outside is near", p(0.25 - E, 0.0, -0.25), &[Near, InFrontOf]),
        row(
            "in: larger than the box, centre inside",
            c(0.5, 0.5, 0.0, -0.25),
            &[In, From],
        ),
        // The box's centre is over the point and its bottom 1e-6 above it: the box is on
        // the cup, so neither is near the other.
        row("under: 1e-6 below, the box on it", p(0.5, 0.0, -0.5 - E), &[Under]),
        row(
            "under: 1e-6 below, aside",
            p(0.6, 0.0, -0.5 - E),
            &[Under, Near, Behind],
        ),
        row("under: at the bottom is in", p(0.5, 0.0, -0.5), &[In, From]),
        row("under: far below the corner", p(0.75, 0.25, -2.0), &[Under]),
        row("under: 1e-6 past the corner", p(0.75 + E, 0.25, -2.0), &[]),
        row(
            "under: sides touching in x",
            c(0.0625, 0.8125, 0.0, -1.0),
            &[Under, Behind],
        ),
        row("under: 1e-6 apart in x", c(0.0625, 0.8125 + E, 0.0, -1.0), &[Behind]),
    ]);
}

#[test]
fn near_and_the_sides_from_the_boxes_at_each_threshold() {
    run_pairs(vec![
        row("near: 0.25 apart", c(0.0625, 1.0625, 0.0, -0.25), &[Near, Behind]),
        row("near: 0.25 + 1e-6 apart", c(0.0625, 1.0625 + E, 0.0, -0.25), &[Behind]),
        // 0.15 and 0.1999 apart along x and y: 0.24992 apart.
        row("near: diagonal inside", p(0.9, 0.4499, -0.25), &[Near, LeftOf, Behind]),
        // 0.15 and 0.2001: 0.25008 apart, though each axis alone is within 0.25.
        row("near: diagonal outside", p(0.9, 0.4501, -0.25), &[LeftOf, Behind]),
        row("left_of: exactly 0.05 further left", p(0.5, 0.05, -0.25), &[In, From]),
        row("left_of: 0.05 + 1e-6", p(0.5, 0.05 + E, -0.25), &[In, From, LeftOf]),
        row("left_of: exactly 1 m apart", p(0.5, 1.25, -0.25), &[LeftOf]),
        row("left_of: 1 m + 1e-6 apart", p(0.5, 1.25 + E, -0.25), &[]),
        row(
            "right_of: exactly 0.05 further right",
            p(0.5, -0.05, -0.25),
            &[In, From],
        ),
        row("right_of: 0.05 + 1e-6", p(0.5, -0.05 - E, -0.25), &[In, From, RightOf]),
        row("right_of: exactly 1 m apart", p(0.5, -1.25, -0.25), &[RightOf]),
        row("right_of: 1 m + 1e-6 apart", p(0.5, -1.25 - E, -0.25), &[]),
        row("behind: 0.05 − 1e-6 farther", p(0.55 - E, 0.0, -0.25), &[In, From]),
        row(
            "behind: 0.05 + 1e-6 farther",
            p(0.55 + E, 0.0, -0.25),
            &[In, From, Behind],
        ),
        row("behind: exactly 1 m apart", p(1.75, 0.0, -0.25), &[Behind]),
        row("behind: 1 m + 1e-6 apart", p(1.75 + E, 0.0, -0.25), &[]),
        row("in_front_of: 0.05 − 1e-6 nearer", p(0.45 + E, 0.0, -0.25), &[In, From]),
        row(
            "in_front_of: 0.05 + 1e-6 nearer",
            p(0.45 - E, 0.0, -0.25),
            &[In, From, InFrontOf],
        ),
        row("in_front_of: exactly 1 m apart", p(-0.75, 0.0, -0.25), &[InFrontOf]),
        row("in_front_of: 1 m + 1e-6 apart", p(-0.75 - E, 0.0, -0.25), &[]),
    ]);
}

#[test]
fn the_sides_are_seen_from_the_agent_and_points_have_no_extent() {
    run_pairs(vec![
        row("unturned: −x is in front", p(-0.25, 0.0, -0.25), &[InFrontOf]),
        row("turned 90°: −x is left", p(-0.25, 0.0, -0.25), &[LeftOf]).turned(QUARTER),
        row("turned 90°: +x is right", p(1.25, 0.0, -0.25), &[RightOf]).turned(QUARTER),
        row("turned 90°: +y is behind", p(0.5, 0.75, -0.25), &[Behind]).turned(QUARTER),
        row("unturned: +y is left", p(0.5, 0.75, -0.25), &[LeftOf]),
        row("turned 180°: +y is right", p(0.5, 0.75, -0.25), &[RightOf]).turned(HALF),
        row("points: 0.02 above a point", p(0.5, 0.0, 0.02), &[On, From]).landmark_a_point(),
        row("points: 1 mm aside is only near", p(0.5, 0.001, 0.02), &[Near]).landmark_a_point(),
        // Its centre is the point's box: on it, so not in it.
        row("points: at the same place is on", p(0.5, 0.0, 0.0), &[On, From]).landmark_a_point(),
        row("points: right below is under", p(0.5, 0.0, -0.5), &[Under]).landmark_a_point(),
        row("points: 1e-6 aside is not under", p(0.5, E, -0.5), &[]).landmark_a_point(),
    ]);
}

#[test]
fn every_relation_a_fact_states_holds_and_no_other_fact_does() {
    // 4.75 m apart: no relation from the boxes.
    let far = || p(0.5, 5.0, -0.25);
    run_pairs(vec![
        row("no facts", far(), &[]),
        row("fact on", far(), &[On, From]).facts(&["on(cup,box)"]),
        row("fact in", far(), &[In, From]).facts(&["in(cup,box)"]),
        row("fact under", far(), &[Under]).facts(&["under(cup,box)"]),
        row("fact near", far(), &[Near]).facts(&["near(cup,box)"]),
        row("fact left_of", far(), &[LeftOf]).facts(&["left_of(cup,box)"]),
        row("fact right_of", far(), &[RightOf]).facts(&["right_of(cup,box)"]),
        row("fact behind", far(), &[Behind]).facts(&["behind(cup,box)"]),
        row("fact in_front_of", far(), &[InFrontOf]).facts(&["in_front_of(cup,box)"]),
        // A fact holds as stated, one way round: left_of(box,cup) says nothing of cup to box.
        row("facts the other way round", far(), &[]).facts(&["left_of(box,cup)", "on(box,cup)"]),
        // Facts state the eight relations; "from" is on or in.
        row("a from fact is none", far(), &[]).facts(&["from(cup,box)"]),
        row("facts naming no object, or not two", far(), &[]).facts(&[
            "on(cup,ghost)",
            "on(ghost,box)",
            "on(cup)",
            "on(cup,box,box)",
            "on(cup,f(box))",
            "near(X,box)",
        ]),
        // The boxes say under, and near; the fact says on: all three hold but near, which
        // `on` (stated) rules out.
        row("the boxes alone", p(0.5, 0.0, -0.6), &[Under, Near]),
        row("a fact against the boxes", p(0.5, 0.0, -0.6), &[On, From, Under]).facts(&["on(cup,box)"]),
        row("a cycle of facts", far(), &[On, From]).facts(&["on(cup,box)", "on(box,cup)"]),
        row("a fact of an object to itself", far(), &[]).facts(&["on(cup,cup)", "near(box,box)"]),
    ]);
}

#[test]
fn cycles_in_facts_and_an_object_to_itself_end_and_say_nothing_more() {
    let facts = ["on(cup,box)", "on(box,cup)", "in(cup,cup)"];
    let scene = roomy(vec![p(0.5, 5.0, 0.0), the_box()], &facts, None);
    assert!(holds(&scene, On, "cup", "box") && holds(&scene, On, "box", "cup"));
    assert!(!holds(&scene, Near, "cup", "box") && !holds(&scene, Near, "box", "cup"));
    for relation in Relation::ALL {
        assert!(!holds(&scene, relation, "cup", "cup"), "{relation:?}(cup,cup)");
    }
    // The cup on (the box on the cup), or the cup on the box and on the cup: the first holds.
    assert_eq!(candidates("Get the cup on the box on the cup.", &scene), ids(&["cup"]));
    assert_eq!(candidates("Get the cup in the cup.", &scene), ids(&[]));
}
