//! Fuzzes the reading of a directive in words: arbitrary text against the paper's lab and the
//! default verbs.
//!
//! Owns: the grammar's promises: it never panics, reads the same text the same way every
//! time, and never lets a reference match an object that one of its words is not true of (a
//! reference with a word the scene does not know matches nothing). Must not: simulate.
#![no_main]

use std::collections::BTreeMap;
use std::sync::LazyLock;

use libfuzzer_sys::fuzz_target;
use scruple::engine::Library;
use scruple::engine::input::RequestLimits;
use scruple::engine::request::Directive;
use scruple::engine::scene::{AgentInput, ObjectInput, Scene, SceneInput};
use scruple::engine::words::{Understanding, heard, understand};

fn object(id: &str, kind: &str, properties: &[&str], attributes: &[(&str, &str)]) -> ObjectInput {
    ObjectInput {
        id: id.into(),
        kind: kind.into(),
        properties: properties.iter().map(|p| (*p).to_owned()).collect(),
        attributes: attributes
            .iter()
            .map(|(k, v)| ((*k).to_owned(), (*v).to_owned()))
            .collect::<BTreeMap<_, _>>(),
        position: [0.5, 0.0, 0.8],
        shape: None,
        rotation: None,
        mass: None,
        names: Vec::new(),
    }
}

static SCENE: LazyLock<Scene> = LazyLock::new(|| {
    let input = SceneInput {
        agent: AgentInput {
            id: None,
            position: [0.0, 0.0, 0.75],
            reach: 0.9,
            gripper_aperture: None,
            payload: None,
            gripper_size: None,
            rotation: None,
        },
        objects: vec![
            object("object1", "notebook", &[], &[("color", "red")]),
            object("object2", "notebook", &[], &[("color", "green")]),
            object("object3", "vase", &["fragile"], &[]),
            object("object4", "vase", &[], &[("material", "plastic")]),
            object("object5", "mug", &[], &[]),
            object("box1", "cash_box", &[], &[("color", "red")]),
        ],
        facts: vec![],
        people: vec![],
    };
    Scene::from_input(input, &RequestLimits::default()).expect("the fuzzer's scene is valid")
});

static LIBRARY: LazyLock<Library> = LazyLock::new(Library::default_library);

/// The words of the scene: a reference may match an object only when each of its words (past
/// the determiner) is one of these. "me" names the speaker (a list may join it: "the cash box or
/// me" matches the box).
const KNOWN: &[&str] = &[
    "the", "a", "an", "this", "that", "my", "your", "one", "me", "notebook", "vase", "mug", "cash", "box", "red", "green",
    "fragile", "plastic", "not", "or", "it", "them", "is", "it's", "too", "very", "really", "so", "quite",
    "rather", "extremely", "bit", "little", "which", "but", "except", "other", "than", "any",
    // Relations, superlatives, ordinals and their directions: words that narrow by place.
    "on", "top", "of", "atop", "upon", "in", "inside", "within", "under", "underneath", "beneath", "below",
    "near", "next", "to", "close", "beside", "by", "left", "right", "behind", "back", "front", "from",
    "biggest", "largest", "smallest", "tallest", "shortest", "heaviest", "lightest", "nearest", "closest",
    "farthest", "furthest", "leftmost", "rightmost", "highest", "lowest", "first", "second", "third",
    // Number: plurals of the scene's nouns, quantifiers and counts (digits are counts too).
    "notebooks", "vases", "mugs", "boxes", "ones", "all", "every", "each", "both", "these", "those", "are",
    "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten",
];

fuzz_target!(|text: &str| {
    let first = understand(text, &SCENE, &LIBRARY, heard(&[]), &|| false);
    assert_eq!(first, understand(text, &SCENE, &LIBRARY, heard(&[]), &|| false), "{text:?} read two ways");
    let Understanding::Directive { directive, parse } = first else {
        return;
    };
    match directive {
        Directive::Action { arguments, .. } => {
            assert!(arguments.len() <= 2, "{text:?}: {} references", arguments.len())
        }
        Directive::Task(task) => {
            assert!(
                (1..=scruple::engine::task::MAX_STEPS).contains(&task.steps.len()),
                "{text:?}: {} steps",
                task.steps.len()
            );
            assert!(task.steps.iter().all(|s| s.arguments.len() <= 2), "{text:?}: {task:?}");
        }
        other => panic!("{text:?} read as {other:?}"),
    }
    for phrase in &parse.references {
        let matches = (phrase.reference.select(&SCENE, &|| false))
            .map_or(0, |selected| selected.objects.len());
        // A narrowing is set off by a comma: "the notebook, not the red one".
        // "the mug or the vase", and a pronoun narrowed by a first sentence: "it (it is fragile)".
        let unknown = (phrase.words.split([' ', ',', '(', ')'])).any(|w| !w.is_empty() && !KNOWN.contains(&w) && !w.bytes().all(|b| b.is_ascii_digit()));
        assert!(
            !(unknown && matches > 0),
            "{text:?}: `{}` has an unknown word and matches {matches}",
            phrase.words
        );
    }
});
