//! Referring expressions: Dale & Reiter's Incremental Algorithm over the scene, and readings
//! ("get the plastic vase") built from them.
//!
//! Owns: which features describe an object, their order, and how actions are spoken.
//! Must not: depend on hash order; the same scene always yields the same words.

use std::collections::BTreeMap;
use std::sync::{Arc, OnceLock};

use rustc_hash::FxHashMap;

mod relational;

use super::action::Library;
use super::resolve::{members, plural};
use super::scene::{Object, Scene, spoken, spoken_onto};
use super::term::{Sym, Term};

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

/// "the fragile vase", "the green notebook", "the mug on the table", "the left mug", "the mug
/// (object5)": the object's type, preceded by each feature that rules out at least one
/// remaining distractor (another object of its type), properties as listed and then attributes
/// by key, in the order added; when distractors remain (in a scene of at most
/// [`relational::UP_TO`] objects), one relation to a landmark, then a position; the id follows
/// in parentheses only when distractors still remain.
pub fn describe_object(scene: &Scene, object: &Object) -> String {
    describe_told(scene, object).0
}

/// [`describe_object`], and whether a landmark or a position told the object apart.
fn describe_told(scene: &Scene, object: &Object) -> (String, bool) {
    if let Some(words) = scene.person_words(&object.id) {
        return (words, false);
    }
    let others = || scene.same_kind(&object.kind, &object.id);
    let (text, distractors) = describe_among(object, others().count(), || others().collect());
    if distractors && scene.objects.len() <= relational::UP_TO {
        let remaining = remaining_after(object, others().collect());
        if let Some(told) = relational::tell_apart(scene, object, &remaining) {
            let mut words = text;
            if let Some(position) = told.position {
                words.insert_str(3, &format!(" {position}"));
            }
            if let Some(relation) = told.relation {
                words.push(' ');
                words.push_str(&relation);
            }
            return (words, true);
        }
    }
    (with_id(text, distractors, object), false)
}

/// The objects of `others` that have every feature of `object` the Incremental Algorithm says
/// of it: those its words so far still match.
fn remaining_after<'s>(object: &Object, mut others: Vec<&'s Object>) -> Vec<&'s Object> {
    let features = (object.properties.iter().map(|p| Feature::Property(p)))
        .chain(object.attributes.iter().map(|(k, v)| Feature::Attribute(k, v)));
    for feature in features {
        if others.is_empty() {
            break;
        }
        let before = others.len();
        let kept: Vec<&Object> = others.iter().copied().filter(|d| feature.holds_for(d)).collect();
        if kept.len() < before {
            others = kept;
        }
    }
    others
}

/// The description, and the object's id after it when distractors remain.
fn with_id(mut text: String, distractors: bool, object: &Object) -> String {
    if distractors {
        text.push_str(" (");
        text.push_str(&object.id);
        text.push(')');
    }
    text
}

/// [`describe_object`] but the id: the words, and whether distractors remain. Given how many
/// other objects are of its type and how to list them (in scene order): they are listed only
/// once a feature is tried, so that an object with none (most, in a large scene of one type) is
/// described by counting them.
///
/// The result depends only on the object's type and features: the object itself has every
/// feature it lists, so the distractors left after each feature are the objects of its type
/// with the features so far, less itself, whichever object of that type and features it is.
fn describe_among<'s>(object: &Object, others: usize, list: impl Fn() -> Vec<&'s Object>) -> (String, bool) {
    let features = object
        .properties
        .iter()
        .map(|p| Feature::Property(p))
        .chain(object.attributes.iter().map(|(k, v)| Feature::Attribute(k, v)));
    let mut distractors: Option<Vec<&Object>> = None;
    let mut words = vec!["the".to_owned()];
    let mut after = Vec::new();
    for feature in features {
        let remaining = distractors.get_or_insert_with(&list);
        if remaining.is_empty() {
            break;
        }
        let before = remaining.len();
        remaining.retain(|d| feature.holds_for(d));
        if remaining.len() < before {
            let word = feature.word();
            match after_the_noun(&word) {
                true => after.push(word),
                false => words.push(word),
            }
        }
    }
    words.push(spoken(&object.kind));
    words.extend(after);
    (words.join(" "), distractors.map_or(others > 0, |d| !d.is_empty()))
}

/// Whether a feature's words follow the noun in English: a phrase that opens with a
/// preposition or a participle ("on floor", "filled with water": "the book on floor", never
/// "the on floor book"). A single word, or a phrase of adjectives ("dark red"), goes before it.
pub(crate) fn after_the_noun(words: &str) -> bool {
    const PREPOSITIONS: &[&str] = &[
        "on", "in", "at", "under", "over", "near", "by", "with", "without", "from", "of", "for", "inside", "behind",
        "beside", "above", "below", "beneath", "next", "left", "right", "outside", "into", "onto", "to",
    ];
    let Some((first, _)) = words.split_once(' ') else {
        return false;
    };
    PREPOSITIONS.contains(&first) || first.len() > 4 && (first.ends_with("ed") || first.ends_with("ing"))
}

/// Up to this many objects, the objects of a type are found by scanning the scene: listing
/// them by type costs more than the scans a small scene's descriptions make.
const SCAN_KINDS: usize = 64;

type Kinds<'a> = FxHashMap<&'a str, Kind<'a>>;

/// The objects of one type in a large scene, and which of them has each feature: a description
/// then intersects short lists of holders rather than passing over every object of its type,
/// so describing all of them is not quadratic in their number.
#[derive(Default)]
struct Kind<'a> {
    /// In scene order.
    objects: Vec<&'a Object>,
    /// Each object's position in `objects`, by id.
    at: FxHashMap<&'a str, u32>,
    /// For each feature, the positions of the objects that have it, ascending.
    holders: FxHashMap<(&'a str, Option<&'a str>), Vec<u32>>,
}

impl<'a> Kind<'a> {
    fn add(&mut self, object: &'a Object) {
        let n = self.objects.len() as u32;
        self.objects.push(object);
        self.at.insert(&object.id, n);
        let mut hold = |key| {
            let list: &mut Vec<u32> = self.holders.entry(key).or_default();
            // A property listed twice is held once.
            if list.last() != Some(&n) {
                list.push(n);
            }
        };
        for p in &object.properties {
            hold((p.as_str(), None));
        }
        for (k, v) in &object.attributes {
            hold((k.as_str(), Some(v.as_str())));
        }
    }

    /// What [`describe_among`] says of `object` (one of this type's), by the lists of holders.
    fn describe(&self, object: &Object) -> (String, bool) {
        let me = self.at.get(&*object.id).copied();
        let features = (object.properties.iter().map(|p| (p.as_str(), None)))
            .chain(object.attributes.iter().map(|(k, v)| (k.as_str(), Some(v.as_str()))));
        let mut remaining: Option<Vec<u32>> = None;
        let mut words = vec!["the".to_owned()];
        let mut after = Vec::new();
        for key in features {
            if remaining.as_ref().is_some_and(Vec::is_empty) {
                break;
            }
            let holders = self.holders.get(&key).map_or(&[][..], Vec::as_slice);
            let (before, kept): (usize, Vec<u32>) = match &remaining {
                None => (
                    self.objects.len() - 1,
                    holders.iter().copied().filter(|&i| Some(i) != me).collect(),
                ),
                Some(left) => (
                    left.len(),
                    left.iter()
                        .copied()
                        .filter(|i| holders.binary_search(i).is_ok())
                        .collect(),
                ),
            };
            if kept.len() < before {
                let word = match key {
                    (p, None) => spoken(p),
                    (_, Some(v)) => spoken(v),
                };
                match after_the_noun(&word) {
                    true => after.push(word),
                    false => words.push(word),
                }
            }
            remaining = Some(kept);
        }
        words.push(spoken(&object.kind));
        words.extend(after);
        let others = self.objects.len() > 1;
        (words.join(" "), remaining.map_or(others, |d| !d.is_empty()))
    }
}

/// What an object's description depends on besides its id: its type and features.
type Look<'a> = (&'a str, &'a [String], &'a BTreeMap<String, String>);

/// Describes objects, each at most once per request (per thread, when many readings are
/// described at once).
pub struct Describer<'a> {
    scene: &'a Scene,
    library: &'a Library,
    /// By the object's id, as a symbol: looking one up hashes a precomputed word.
    cache: FxHashMap<Sym, String>,
    /// In a large scene, the objects of each type, in scene order, listed at the first
    /// description, and shared with the describers made from this one ([`Describer::fresh`]).
    kinds: Arc<OnceLock<Kinds<'a>>>,
    /// In a large scene, the words for each type and features described so far, and whether
    /// distractors remain: objects that look alike are described by one pass over their type.
    looks: FxHashMap<Look<'a>, (String, bool)>,
    /// Objects whose id is left out of what is spoken: each is the only one of its type among
    /// the readings an answer speaks of, so its description serves without it.
    alone: Vec<Sym>,
    /// The joiner the human said between this verb's arguments ("put the fork in the
    /// microwave"), spoken instead of the verb's own.
    said: Option<(Sym, String)>,
    /// Whether a landmark or a position told an object described so far apart.
    told: bool,
    /// Who the robot speaks to: spoken "you" when a person or not in the scene at all.
    listener: Option<Sym>,
}

impl<'a> Describer<'a> {
    pub fn new(scene: &'a Scene, library: &'a Library) -> Self {
        Describer {
            scene,
            library,
            cache: FxHashMap::default(),
            kinds: Arc::default(),
            looks: FxHashMap::default(),
            alone: Vec::new(),
            said: None,
            told: false,
            listener: None,
        }
    }

    /// The verb "to be" after `subject` spoken, spaced: " are " after "you", else " is ".
    pub fn copula(&self, subject: &Term) -> &'static str {
        match (self.listener.as_ref(), subject) {
            (Some(listener), Term::Const(id)) if listener == id => " are ",
            _ => " is ",
        }
    }

    /// The same describer, speaking to `speaker`: they are "you".
    pub fn to(mut self, speaker: &Sym) -> Self {
        let person = self
            .scene
            .object(speaker)
            .is_none_or(|o| o.kind == crate::engine::scene::PERSON);
        self.listener = person.then(|| speaker.clone());
        self
    }

    /// Another describer of the same scene, for another thread: its own cache of descriptions,
    /// the objects by type shared.
    pub fn fresh(&self) -> Describer<'a> {
        Describer {
            scene: self.scene,
            library: self.library,
            cache: FxHashMap::default(),
            kinds: self.kinds.clone(),
            looks: FxHashMap::default(),
            alone: self.alone.clone(),
            said: self.said.clone(),
            told: false,
            listener: self.listener.clone(),
        }
    }

    pub fn scene(&self) -> &'a Scene {
        self.scene
    }

    /// Whether a landmark or a position told apart an object this describer described.
    pub fn told_apart(&self) -> bool {
        self.told
    }

    /// Speaks `joiner` between `verb`'s arguments from now on, as the human said it.
    pub fn say_joiner(&mut self, verb: Sym, joiner: String) {
        self.said = Some((verb, joiner));
    }

    /// Leaves the ids of `objects` out of what is spoken from now on ("the cup", not "the cup
    /// (cup1)"): for an answer in which each is the only object of its type.
    pub fn without_ids(&mut self, objects: Vec<Sym>) {
        self.alone = objects;
    }

    /// `words` (an object's description) as spoken: when the object is alone, by its type and
    /// features only (without the id, landmark or position that told it from the others).
    fn push_spoken(&self, name: &Sym, words: &str, out: &mut String) {
        if !self.alone.contains(name) {
            out.push_str(words);
            return;
        }
        match words.strip_suffix(&format!(" ({name})")) {
            Some(plain) => out.push_str(plain),
            None => out.push_str(self.plain(name).as_deref().unwrap_or(words)),
        }
    }

    /// The object's description by its type and features only, as the Incremental Algorithm
    /// gives it: no id, landmark or position.
    pub fn plain(&self, id: &str) -> Option<String> {
        let object = self.scene.object(id)?;
        if let Some(words) = self.scene.person_words(id) {
            return Some(words);
        }
        let others = || self.scene.same_kind(&object.kind, &object.id);
        Some(describe_among(object, others().count(), || others().collect()).0)
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
        // A group of objects: every object of a type as the type ("the cups", "both cups"),
        // else listed ("the red cup, the blue cup and the green cup").
        if let Some(members) = members(arg) {
            if let Some(all) = self.all_of_a_kind(members) {
                out.push_str(&all);
                return;
            }
            for (i, member) in members.iter().enumerate() {
                match i {
                    0 => {}
                    _ if i + 1 == members.len() => out.push_str(" and "),
                    _ => out.push_str(", "),
                }
                self.argument_into(member, out);
            }
            return;
        }
        let Term::Const(name) = arg else {
            out.push_str(&arg.to_string());
            return;
        };
        if self.listener.as_ref() == Some(name) {
            out.push_str("you");
            return;
        }
        if let Some(words) = self.cache.get(name) {
            self.push_spoken(name, words, out);
            return;
        }
        let Some(object) = self.scene.object(name) else {
            out.push_str(&spoken(name));
            return;
        };
        let words = if self.scene.objects.len() <= SCAN_KINDS {
            let (words, told) = describe_told(self.scene, object);
            self.told |= told;
            words
        } else {
            let scene = self.scene;
            let kinds = self.kinds.get_or_init(|| {
                let mut kinds: Kinds<'_> = FxHashMap::default();
                for o in &scene.objects {
                    kinds.entry(o.kind.as_str()).or_default().add(o);
                }
                kinds
            });
            let look = (object.kind.as_str(), &object.properties[..], &object.attributes);
            let (text, distractors) = self
                .looks
                .entry(look)
                .or_insert_with(|| match kinds.get(object.kind.as_str()) {
                    Some(kind) => kind.describe(object),
                    None => describe_among(object, 0, Vec::new),
                });
            with_id(text.clone(), *distractors, object)
        };
        self.push_spoken(name, &words, out);
        self.cache.insert(name.clone(), words);
    }

    /// "both cups" or "the cups", when `members` are two or more objects of one type and the
    /// scene has no other of it (looked for in scenes of up to [`SCAN_KINDS`] objects).
    fn all_of_a_kind(&self, members: &[Term]) -> Option<String> {
        if members.len() < 2 || self.scene.objects.len() > SCAN_KINDS {
            return None;
        }
        let kind = &self.scene.object(members[0].name()?)?.kind;
        for member in members {
            if self.scene.object(member.name()?)?.kind != *kind {
                return None;
            }
        }
        let of_kind = self.scene.objects.iter().filter(|o| o.kind == *kind).count();
        let many = plural(&spoken(kind));
        (of_kind == members.len()).then(|| match of_kind {
            2 => format!("both {many}"),
            _ => format!("the {many}"),
        })
    }

    /// Whether `id` names the robot itself (the scene's agent): spoken "I" or "me".
    pub fn is_agent(&self, id: &str) -> bool {
        self.scene.agent.id == id
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
        // Room for the words of a few short descriptions, so that they are not copied as they grow.
        let mut words = String::with_capacity(64);
        self.arguments_onto(action, &mut words);
        words
    }

    /// [`Describer::arguments`], appended to `out`.
    fn arguments_onto(&mut self, action: &Term, out: &mut String) {
        let library = self.library;
        let said = (self.said.as_ref()).filter(|(verb, _)| action.name() == Some(verb));
        let joiner: std::borrow::Cow<'_, str> = match said {
            Some((_, joiner)) => joiner.clone().into(),
            None => (library.lookup(action))
                .and_then(|def| def.joiner.as_deref())
                .unwrap_or("and")
                .into(),
        };
        for (i, arg) in action.args().iter().enumerate() {
            if i > 0 {
                out.push(' ');
                out.push_str(&joiner);
                out.push(' ');
            }
            self.argument_into(arg, out);
        }
    }

    /// The word said between `action`'s arguments: its verb's joiner, else "and".
    pub fn joiner_of(&self, action: &Term) -> String {
        (self.library.lookup(action))
            .and_then(|def| def.joiner.clone())
            .unwrap_or_else(|| "and".to_owned())
    }

    /// One step of a task in words, appended to `out`: its verb spoken, its arguments joined by
    /// `joiner` (the verb's own when `None`), an object already in `named` spoken "it".
    pub fn step_in_task_onto(&mut self, step: &Term, joiner: Option<&str>, named: &[Term], out: &mut String) {
        let Some(name) = step.name() else {
            out.push_str(&step.to_string());
            return;
        };
        spoken_onto(name, out);
        if step.arity() > 0 {
            out.push(' ');
        }
        self.arguments_in_task_onto(step, joiner, named, out);
    }

    /// The arguments of [`Describer::step_in_task_onto`], without the verb.
    pub fn arguments_in_task(&mut self, step: &Term, joiner: Option<&str>, named: &[Term]) -> String {
        let mut out = String::new();
        self.arguments_in_task_onto(step, joiner, named, &mut out);
        out
    }

    fn arguments_in_task_onto(&mut self, step: &Term, joiner: Option<&str>, named: &[Term], out: &mut String) {
        let library = self.library;
        let joiner = joiner
            .or_else(|| library.lookup(step).and_then(|def| def.joiner.as_deref()))
            .unwrap_or("and");
        for (i, arg) in step.args().iter().enumerate() {
            if i > 0 {
                out.push(' ');
                out.push_str(joiner);
                out.push(' ');
            }
            // A person is never "it": named again, by name, role or "you".
            let person = arg
                .name()
                .is_some_and(|id| self.listener.as_ref() == Some(id) || self.scene.is_person(id));
            if !person && (named.contains(arg) || step.args()[..i].contains(arg)) {
                out.push_str(if members(arg).is_some() { "them" } else { "it" });
            } else {
                self.argument_into(arg, out);
            }
        }
    }

    /// The reading of an action: its verb spoken, then its arguments ("put the blue cup on the plate").
    pub fn reading(&mut self, action: &Term) -> String {
        reading_with(action, &self.arguments(action))
    }
}

/// Whether `action` is a task of several steps, `and(A1,A2,…)`, rather than one verb's action.
pub fn is_task(action: &Term) -> bool {
    action.name().is_some_and(|n| &**n == "and")
        && action.arity() >= 2
        && action.args().iter().all(|a| a.name().is_some())
}

/// The reading of an action whose arguments are already in words (its
/// [`arguments`](Describer::arguments)): the same words as [`Describer::reading`], without
/// describing its objects again.
pub fn reading_with(action: &Term, arguments: &str) -> String {
    let Some(name) = action.name() else {
        return action.to_string();
    };
    // A task's words are its steps' readings already ([`Describer::step_in_task_onto`]).
    if is_task(action) {
        return arguments.to_owned();
    }
    let mut reading = String::with_capacity(name.len() + 1 + arguments.len());
    spoken_onto(name, &mut reading);
    if !arguments.is_empty() {
        reading.push(' ');
        reading.push_str(arguments);
    }
    reading
}
