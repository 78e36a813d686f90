//! Relation words, property-tested: every description the service speaks reads back through the
//! words path as its object alone (an id only where no landmark and no position would do); words
//! by relation, superlative, ordinal and exclusion never let a bad reading through; and, where
//! facts alone relate objects, they never act on or offer an object they do not mean.

use std::collections::BTreeSet;
use std::f64::consts::{FRAC_PI_2, TAU};

use super::relations::cuboid;
use super::shape_tasks::{Said, check_tasks};
use super::shapes::check as check_decision;
use super::words::read;
use super::*;
use crate::engine::check::check as check_steps;
use crate::engine::decision::Style;
use crate::engine::describe::{describe_object, is_task};
use crate::engine::norms::Scope;
use crate::engine::scene::relate::Relation;

const KINDS: [&str; 5] = ["cup", "plate", "fork", "table", "box"];
const TABLE: usize = 3;
const COLOURS: [&str; 3] = ["red", "green", "blue"];
/// The contract's eight fact names, in `Relation::ALL`'s order.
const NAMES: [&str; 8] = [
    "on",
    "in",
    "under",
    "near",
    "left_of",
    "right_of",
    "behind",
    "in_front_of",
];

/// 256 cases on every `cargo test`; the long run sets `SCRUPLE_PROPTEST_CASES`.
fn cases() -> u32 {
    std::env::var("SCRUPLE_PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(256)
}

// Random small scenes of look-alikes

/// One object as drawn: kind; colour (past `COLOURS`: none); fragile; shape (0 point, 1 cuboid,
/// 2 cylinder) and size; placement (0, 1 free, 2 on an earlier table, 3 at an earlier object's
/// spot) and which; fractions of the free area in x and y.
type Thing = (usize, usize, bool, (u8, f64), (u8, usize), (f64, f64));

fn arb_thing() -> impl Strategy<Value = Thing> {
    (
        0..KINDS.len(),
        0..5usize,
        prop::bool::weighted(0.3),
        (0..3u8, 0.02..0.1f64),
        (prop_oneof![6 => 0..3u8, 1 => Just(3u8)], any::<usize>()),
        (0.0..1.0f64, 0.0..1.0f64),
    )
}

#[derive(Clone, Debug)]
struct Drawn {
    things: Vec<Thing>,
    /// The agent's turn about z, radians; `None`: no rotation given.
    turn: Option<f64>,
    /// `(index in NAMES, a, b)` stated as facts; an index past the objects names none.
    facts: Vec<(usize, usize, usize)>,
}

fn arb_turn() -> impl Strategy<Value = Option<f64>> {
    prop_oneof![
        2 => Just(None),
        1 => (0..4u8).prop_map(|k| Some(f64::from(k) * FRAC_PI_2)),
        1 => (0.0..TAU).prop_map(Some),
    ]
}

fn arb_drawn() -> impl Strategy<Value = Drawn> {
    (
        prop::collection::vec(arb_thing(), 2..=10),
        arb_turn(),
        prop::collection::vec((0..8usize, 0..10usize, 0..10usize), 0..3),
    )
        .prop_map(|(things, turn, facts)| Drawn { things, turn, facts })
}

/// A table's top, and its half extents (its centre is 0.02 below the top).
const TABLE_TOP: f64 = 0.72;
const TABLE_HALF: [f64; 3] = [0.3, 0.2, 0.02];

fn features(colour: usize, fragile: bool) -> (Vec<&'static str>, Vec<(&'static str, &'static str)>) {
    let properties = if fragile { vec!["fragile"] } else { vec![] };
    (
        properties,
        COLOURS.get(colour).map(|c| ("color", *c)).into_iter().collect(),
    )
}

fn turned(turn: Option<f64>) -> Option<[f64; 4]> {
    turn.map(|a| [0.0, 0.0, (a / 2.0).sin(), (a / 2.0).cos()])
}

impl Drawn {
    fn objects(&self) -> Vec<Object> {
        let mut out: Vec<Object> = Vec::with_capacity(self.things.len());
        for (i, &(kind, colour, fragile, (shape, size), (place, which), (fx, fy))) in self.things.iter().enumerate() {
            let (shape, half_height) = match (kind, shape) {
                (TABLE, _) => (cuboid(TABLE_HALF), TABLE_HALF[2]),
                (_, 0) => (None, 0.0),
                (_, 1) => (cuboid([size, 0.8 * size, 1.2 * size]), 1.2 * size),
                _ => (
                    Some(Shape::Cylinder {
                        radius: size,
                        half_height: 1.5 * size,
                    }),
                    1.5 * size,
                ),
            };
            let tables: Vec<usize> = (0..i).filter(|&j| out[j].kind == KINDS[TABLE]).collect();
            let free = [0.3 + 1.2 * fx, -0.8 + 1.6 * fy];
            let position = match place {
                3 if i > 0 => out[which % i].position,
                2 if kind != TABLE && !tables.is_empty() => {
                    let t = out[tables[which % tables.len()]].position;
                    let (dx, dy) = ((fx - 0.5) * 1.8 * TABLE_HALF[0], (fy - 0.5) * 1.8 * TABLE_HALF[1]);
                    [t[0] + dx, t[1] + dy, TABLE_TOP + half_height]
                }
                _ if kind == TABLE => [free[0], free[1], TABLE_TOP - TABLE_HALF[2]],
                _ => [free[0], free[1], 0.75 + half_height],
            };
            let (properties, attributes) = features(colour, fragile);
            out.push(obj(
                &format!("o{i}"),
                KINDS[kind],
                &properties,
                &attributes,
                position,
                shape,
            ));
        }
        out
    }

    fn scene(&self) -> Scene {
        let agent = Agent {
            rotation: turned(self.turn),
            ..agent()
        };
        let n = self.things.len();
        let facts = (self.facts.iter())
            .filter(|(_, a, b)| *a < n && *b < n)
            .map(|(r, a, b)| t(&format!("{}(o{a},o{b})", NAMES[*r])))
            .collect();
        Scene::new(agent, self.objects(), facts)
    }
}

/// The scene as a failure shows it.
fn show(scene: &Scene) -> String {
    let mut lines = vec![format!("agent rotation {:?}", scene.agent.rotation)];
    for o in &scene.objects {
        lines.push(format!(
            "  {} {} {:?} {:?} at {:?} {:?}",
            o.id, o.kind, o.properties, o.attributes, o.position, o.shape
        ));
    }
    let facts: Vec<String> = scene.facts.iter().map(Term::to_string).collect();
    lines.push(format!("  facts {facts:?}"));
    lines.join("\n")
}

// 1. Round trip: what the service says of an object, its words read back as that object

fn alone(scene: &Scene, words: &str, object: &Object) -> bool {
    read(&format!("Get {words}."), scene) == Ok(("get".to_owned(), vec![vec![object.id.to_string()]]))
}

/// Each way to say a landmark of another type than `kind`: its type, alone or with any of its
/// features.
fn landmark_words(scene: &Scene, kind: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for l in scene.objects.iter().filter(|l| l.kind != kind) {
        let colour = l.attributes.get("color").map(String::as_str);
        let fragile = l.properties.iter().any(|p| p == "fragile").then_some("fragile");
        for (f, c) in [(None, None), (fragile, None), (None, colour), (fragile, colour)] {
            let words: Vec<&str> = (["the"].into_iter().chain(f).chain(c).chain([l.kind.as_str()])).collect();
            out.insert(words.join(" "));
        }
    }
    out
}

/// The description `words` (its id left off) leaves look-alikes, and neither a relation to any
/// landmark of another type, said by its type and features, nor a position leaves the object
/// alone; with `both`, nor a position and a relation together.
fn nothing_tells_apart(scene: &Scene, object: &Object, words: &str, both: bool) -> Result<(), String> {
    match read(&format!("Get {words}."), scene) {
        Ok((_, c)) if c.len() == 1 && c[0].len() > 1 && c[0].contains(&object.id.to_string()) => {}
        other => return Err(format!("\"{words}\" without its id reads as {other:?}")),
    }
    let rest = words.strip_prefix("the ").ok_or("a description opens with \"the\"")?;
    let landmarks = landmark_words(scene, &object.kind);
    let positions: &[&str] = if both { &["", "left ", "right "] } else { &[""] };
    for position in ["left ", "right "] {
        let said = format!("the {position}{rest}");
        if alone(scene, &said, object) {
            return Err(format!("\"{said}\" tells it apart"));
        }
    }
    for position in positions {
        for relation in &Relation::ALL[..8] {
            for landmark in &landmarks {
                let said = format!("the {position}{rest} {} {landmark}", relation.spoken());
                if alone(scene, &said, object) {
                    return Err(format!("\"{said}\" tells it apart"));
                }
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    /// Every object's description, read as "Get <description>.", selects that object alone;
    /// one that ends with the object's id is spoken so only when its words leave look-alikes
    /// and no landmark relation, position, or both, would have left it alone.
    #[test]
    fn every_description_reads_back_as_its_object(drawn in arb_drawn()) {
        let scene = drawn.scene();
        for object in &scene.objects {
            let said = describe_object(&scene, object);
            let id = format!(" ({})", object.id);
            match said.strip_suffix(&id) {
                Some(words) => {
                    prop_assert!(!words.contains('('), "{said}\n{}", show(&scene));
                    if let Err(why) = nothing_tells_apart(&scene, object, words, false) {
                        return Err(TestCaseError::fail(format!("{}: \"{said}\": {why}\n{}", object.id, show(&scene))));
                    }
                }
                None => {
                    prop_assert!(!said.contains('('), "{said}\n{}", show(&scene));
                    let got = read(&format!("Get {said}."), &scene);
                    prop_assert_eq!(
                        got,
                        Ok(("get".to_owned(), vec![vec![object.id.to_string()]])),
                        "{}: \"{}\"\n{}", object.id, said, show(&scene)
                    );
                }
            }
        }
    }
}
