//! Referring expressions: Dale & Reiter's Incremental Algorithm over the scene, and readings
//! ("get the plastic vase") built from them.
//!
//! Owns: which features describe an object, their order, and how actions are spoken.
//! Must not: depend on hash order; the same scene always yields the same words.

use rustc_hash::FxHashMap;

use super::action::Library;
use super::scene::{Object, Scene, spoken};
use super::term::Term;

/// A distinguishing feature of an object.
#[derive(Clone, Copy)]
enum Feature<'a> {
    Property(&'a str),
    Attribute(&'a str, &'a str),
}

impl Feature<'_> {
    fn holds_for(&self, other: &Object) -> bool {
        match *self {
            Feature::Property(p) => other.properties.iter().any(|q| q == p),
            Feature::Attribute(k, v) => other.attributes.get(k).is_some_and(|w| w == v),
        }
    }

    fn word(&self) -> String {
        match *self {
            Feature::Property(p) => spoken(p),
            Feature::Attribute(_, v) => spoken(v),
        }
    }
}

/// "the fragile vase", "the green notebook", "the mug (object5)": the object's type, preceded by
/// each feature that rules out at least one remaining distractor (another object of its type),
/// properties as listed and then attributes by key, in the order added; the id follows in
/// parentheses when distractors remain.
pub fn describe_object(scene: &Scene, object: &Object) -> String {
    let mut distractors: Vec<&Object> = scene.same_kind(&object.kind, &object.id).collect();
    let features = object
        .properties
        .iter()
        .map(|p| Feature::Property(p))
        .chain(object.attributes.iter().map(|(k, v)| Feature::Attribute(k, v)));
    let mut words = vec!["the".to_owned()];
    for feature in features {
        if distractors.is_empty() {
            break;
        }
        let before = distractors.len();
        distractors.retain(|d| feature.holds_for(d));
        if distractors.len() < before {
            words.push(feature.word());
        }
    }
    words.push(spoken(&object.kind));
    let mut text = words.join(" ");
    if !distractors.is_empty() {
        text.push_str(&format!(" ({})", object.id));
    }
    text
}

/// Describes objects, each at most once per request.
pub struct Describer<'a> {
    scene: &'a Scene,
    library: &'a Library,
    cache: FxHashMap<String, String>,
}

impl<'a> Describer<'a> {
    pub fn new(scene: &'a Scene, library: &'a Library) -> Self {
        Describer {
            scene,
            library,
            cache: FxHashMap::default(),
        }
    }

    /// An argument in words: an object of the scene by its description, another constant as
    /// spoken, anything else as its canonical term.
    pub fn argument(&mut self, arg: &Term) -> String {
        let mut words = String::new();
        self.argument_into(arg, &mut words);
        words
    }

    /// [`Describer::argument`], appended to `out`.
    pub fn argument_into(&mut self, arg: &Term, out: &mut String) {
        let Term::Const(name) = arg else {
            out.push_str(&arg.to_string());
            return;
        };
        let Some(object) = self.scene.object(name) else {
            out.push_str(&spoken(name));
            return;
        };
        if let Some(words) = self.cache.get(object.id.as_str()) {
            out.push_str(words);
            return;
        }
        let words = describe_object(self.scene, object);
        out.push_str(&words);
        self.cache.insert(object.id.clone(), words);
    }

    /// Whether the scene object has an attribute of this key (`color`).
    pub fn has_attribute(&self, id: &str, key: &str) -> bool {
        self.scene.object(id).is_some_and(|o| o.attributes.contains_key(key))
    }

    /// The type of a scene object, spoken ("cash box").
    pub fn kind_of(&self, id: &str) -> Option<String> {
        self.scene.object(id).map(|o| spoken(&o.kind))
    }

    /// The action's arguments in words, joined as its verb joins them ("the cup on the plate").
    pub fn arguments(&mut self, action: &Term) -> String {
        let joiner = self
            .library
            .lookup(action)
            .and_then(|def| def.joiner.clone())
            .unwrap_or_else(|| "and".to_owned());
        let words: Vec<String> = action.args().iter().map(|a| self.argument(a)).collect();
        words.join(&format!(" {joiner} "))
    }

    /// The reading of an action: its verb spoken, then its arguments ("put the blue cup on the plate").
    pub fn reading(&mut self, action: &Term) -> String {
        let verb = action.name().map(|n| spoken(n)).unwrap_or_else(|| action.to_string());
        let args = self.arguments(action);
        if args.is_empty() {
            verb
        } else {
            format!("{verb} {args}")
        }
    }
}
