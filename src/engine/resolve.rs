//! Reference resolution: which objects of the scene each argument (or variable) may mean, and
//! the readings their combinations make.
//!
//! Owns: a reference's constructor (checked against the scene), matching references against objects, the slots of a directive and their candidates,
//! and the readings a follow-up answer keeps. Must not: simulate, decide or word anything.

use std::collections::BTreeMap;

use super::input::{Invalid, constant};
use super::request::{Directive, MOST_READINGS};
use super::scene::relate::{Direction, Relation, Superlative};
use super::scene::{Object, Scene, spoken};
use super::task::Shape;
use super::term::{Subst, Sym, Term};

mod narrowed;
mod number;
mod select;
mod unsaid;
pub(super) use narrowed::Narrowed;
pub use number::{MAX_GROUP, Number, count_of, members, objects_of, plural, singulars};
pub use select::Selected;
pub(in crate::engine) use unsaid::meeting;

/// What an adjective in words may say of an object.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Sense {
    /// The object has this property (`fragile`).
    Property(String),
    /// The object's attribute `key` has this value (`colour` = `red`).
    Attribute { key: String, value: String },
}

/// A reference to objects of the scene: by id, or by type, attributes and properties, or as the
/// human said it in words.
#[derive(Clone, Debug, PartialEq)]
pub enum Reference {
    Id(String),
    Described {
        /// `None` matches any type.
        kind: Option<String>,
        attributes: BTreeMap<String, String>,
        properties: Vec<String>,
    },
    /// In words: an object of one of `kinds` or `named` (any, when both are empty: "the red
    /// one") of which every adjective says something true (one of its senses).
    Spoken {
        kinds: Vec<String>,
        /// Objects called by the noun spoken (one of their `names`), besides those of `kinds`.
        named: Vec<String>,
        adjectives: Vec<Vec<Sense>>,
        words: String,
        /// "a mug": any matching object will do.
        indefinite: bool,
    },
    /// "it", "that one": the object in focus; with none, it matches nothing.
    Pronoun {
        words: String,
    },
    /// Words with one that names nothing here ("the wet mug"): it matches no object, so the
    /// robot says what it did not understand rather than pick another object. `unplaced`: the
    /// words the grammar could not place at all ("pls" in "the mug pls", "second" in "the
    /// second mug"), as against words it understood that describe nothing here.
    Nothing {
        words: String,
        unplaced: Option<String>,
    },
    /// A reference narrowed by words the human added to it: "the cup, the blue one" (`keep`:
    /// `by` must be true of the object too), "the notebook, not the red one" (it must not be).
    /// Words that name nothing never narrow by leaving out nothing: with such a `by`, the
    /// reference matches nothing.
    Narrowed {
        base: Box<Reference>,
        by: Box<Reference>,
        keep: bool,
        words: String,
    },
    /// "the mug or the cup": any one object any of `options` matches will do, as with an
    /// indefinite. An option whose words name nothing here makes the whole match nothing:
    /// the human may have meant just that one.
    Either {
        options: Vec<Reference>,
        words: String,
    },
    /// "the cup on the table": what `base` matches that stands in `relation` to an object `to`
    /// matches (`scene::relate` says when it does).
    Related {
        base: Box<Reference>,
        relation: Relation,
        to: Box<Reference>,
        words: String,
    },
    /// Words that read more than one way ("the cup on the table next to the fork": the table
    /// next to the fork, or the cup next to it): the objects any reading matches.
    Union {
        readings: Vec<Reference>,
        words: String,
    },
    /// "the biggest box": of what `base` matches, the best by the measure and those tied with
    /// it; when one of them lacks the measure, nothing.
    Most {
        base: Box<Reference>,
        superlative: Superlative,
        /// The superlative as said ("biggest").
        said: String,
        words: String,
    },
    /// "the second cup from the left": of what `base` matches, those that may be `nth`
    /// (from 1) counting from `from`.
    Nth {
        base: Box<Reference>,
        nth: usize,
        from: Direction,
        words: String,
    },
    /// "the cups", "both cups", "two cups": several of what `base` matches at once, one step
    /// each; its slot offers groups of objects ([`Number`] says which).
    Plural {
        base: Box<Reference>,
        number: Number,
        words: String,
    },
    /// An argument the directive left unsaid ("Heat up the soup."): any object for which
    /// `facts` hold with `param` bound to it; `untold` says what is missing when none does.
    Implied {
        param: Sym,
        facts: Vec<Term>,
        words: String,
        untold: String,
    },
    /// The speaker ("me", or a recipient left unsaid): their object when the scene holds them,
    /// else the speaker by id alone ([`unsaid`]).
    Speaker(String),
}

impl Reference {
    /// The objects the words rule out anywhere in this reference: what each exclusion's `by`
    /// matches ("the stove" in "the microwave, not the stove"), landmarks' too. Nothing offered
    /// in place of what was said may be one of them.
    pub fn excluded(&self, scene: &Scene, expired: &dyn Fn() -> bool, into: &mut Vec<usize>) {
        match self {
            Reference::Narrowed { base, by, keep, .. } => {
                if !keep && let Some(selected) = by.select(scene, expired) {
                    into.extend(selected.objects);
                }
                base.excluded(scene, expired, into);
            }
            Reference::Either { options: all, .. } | Reference::Union { readings: all, .. } => {
                all.iter().for_each(|r| r.excluded(scene, expired, into));
            }
            Reference::Related { base, to, .. } => {
                base.excluded(scene, expired, into);
                to.excluded(scene, expired, into);
            }
            Reference::Most { base, .. } | Reference::Nth { base, .. } | Reference::Plural { base, .. } => {
                base.excluded(scene, expired, into);
            }
            Reference::Id(_)
            | Reference::Described { .. }
            | Reference::Spoken { .. }
            | Reference::Pronoun { .. }
            | Reference::Nothing { .. }
            | Reference::Implied { .. }
            | Reference::Speaker(_) => {}
        }
    }
}

/// A reference as a request gives it, before it is checked: `id`, or a description; attribute
/// values already as text.
#[derive(Clone, Debug, Default)]
pub struct ReferenceInput {
    pub id: Option<String>,
    pub kind: Option<String>,
    pub attributes: Option<BTreeMap<String, String>>,
    pub properties: Option<Vec<String>>,
    /// `(relation name, landmark)`: the object must stand in each to an object the landmark
    /// matches.
    pub relations: Vec<(String, ReferenceInput)>,
    /// `count`: that many objects, any of the matches ("two cups"); with `all`, exactly that
    /// many must match ("both cups").
    pub count: Option<u64>,
    /// Every match, one step each ("the cups").
    pub all: Option<bool>,
}

/// The most relations a structured reference carries, counting those of its landmarks: as
/// many as words may chain, and a bound on the work they ask.
pub const MAX_RELATIONS: usize = 8;

impl Reference {
    /// A reference by id must name an object of the scene; a description needs at least one of
    /// its parts. Fields named relative to the reference.
    /// `count` and `all` make it plural.
    pub fn from_input(mut input: ReferenceInput, scene: &Scene) -> Result<Reference, Invalid> {
        let number = number::of_input(&mut input)?;
        let mut budget = MAX_RELATIONS;
        let reference = Reference::from_input_within(input, scene, &mut budget)?;
        let Some(number) = number else {
            return Ok(reference);
        };
        // "the red cup on the table" said of several: "the two red cups on the table".
        let plain = match &reference {
            Reference::Related { .. } => {
                let mut base = &reference;
                while let Reference::Related { base: inner, .. } = base {
                    base = inner;
                }
                base.words(scene)
            }
            other => other.words(scene),
        };
        let all = reference.words(scene);
        let rest = all.strip_prefix(plain.as_str()).unwrap_or_default();
        Ok(Reference::Plural {
            words: number.words(&plain, rest),
            base: Box::new(reference),
            number,
        })
    }

    /// [`Reference::from_input`] without a number: a landmark's, or the one a number applies to;
    /// with `budget` relations left to the whole reference.
    fn from_input_within(mut input: ReferenceInput, scene: &Scene, budget: &mut usize) -> Result<Reference, Invalid> {
        for (field, given) in [("/count", input.count.is_some()), ("/all", input.all.is_some())] {
            if given {
                return Err(Invalid::new(
                    field,
                    "`count` and `all` go with an argument, not with a landmark: a landmark is any object it matches",
                ));
            }
        }
        let relations = std::mem::take(&mut input.relations);
        let mut reference = Reference::plain_input(input, scene)?;
        for (i, (name, to)) in relations.into_iter().enumerate() {
            let at = format!("/relations/{i}");
            let Some(relation) = Relation::from_name(&name) else {
                let names: Vec<&str> = Relation::ALL.iter().map(|r| r.name()).collect();
                return Err(Invalid::new(
                    format!("{at}/relation"),
                    format!("unknown relation `{name}`; expected one of {}", names.join(", ")),
                ));
            };
            if *budget == 0 {
                return Err(Invalid::new(
                    at,
                    format!("at most {MAX_RELATIONS} relations in one reference, its landmarks' included"),
                ));
            }
            *budget -= 1;
            let to = Reference::from_input_within(to, scene, budget).map_err(|e| e.within(&format!("{at}/to")))?;
            let words = format!("{} {} {}", reference.words(scene), relation.spoken(), to.words(scene));
            reference = Reference::Related {
                base: Box::new(reference),
                relation,
                to: Box::new(to),
                words,
            };
        }
        Ok(reference)
    }

    /// A reference by id or by description, without relations.
    fn plain_input(input: ReferenceInput, scene: &Scene) -> Result<Reference, Invalid> {
        if let Some(id) = input.id {
            if input.kind.is_some() || input.attributes.is_some() || input.properties.is_some() {
                return Err(Invalid::new(
                    "",
                    "a reference gives either `id` or `type` (with attributes and properties), not both",
                ));
            }
            if scene.object(&id).is_none() {
                return Err(Invalid::new("/id", format!("no object `{id}` in the scene")));
            }
            return Ok(Reference::Id(id));
        }
        // An empty list or map says nothing about the object: `{"properties": []}` is as empty as
        // `{}` (and as gRPC's default message, which cannot tell them apart).
        let says_nothing = input.kind.is_none()
            && input.attributes.as_ref().is_none_or(|a| a.is_empty())
            && input.properties.as_ref().is_none_or(|p| p.is_empty());
        if says_nothing {
            return Err(Invalid::new(
                "",
                "a reference needs `id`, `type`, or at least one property or attribute",
            ));
        }
        if let Some(kind) = &input.kind {
            constant("/type", kind, "a type")?;
        }
        Ok(Reference::Described {
            kind: input.kind,
            attributes: input.attributes.unwrap_or_default(),
            properties: input.properties.unwrap_or_default(),
        })
    }

    /// Whether the object is one the reference may mean, judged by the object alone: exact for
    /// a reference by id, description or adjectives; for one with relations, a superlative or
    /// an ordinal, what its head matches (a superset of [`Reference::select`]).
    pub fn head_matches(&self, object: &Object) -> bool {
        match self {
            Reference::Id(id) => object.id == id.as_str(),
            Reference::Described {
                kind,
                attributes,
                properties,
            } => {
                kind.as_ref().is_none_or(|k| k == &object.kind)
                    && attributes.iter().all(|(k, v)| object.attributes.get(k) == Some(v))
                    && properties.iter().all(|p| object.properties.contains(p))
            }
            Reference::Spoken {
                kinds,
                named,
                adjectives,
                ..
            } => {
                (kinds.is_empty() && named.is_empty()
                    || kinds.contains(&object.kind)
                    || named.iter().any(|n| object.id == n.as_str()))
                    && adjectives.iter().all(|senses| {
                        senses.iter().any(|sense| match sense {
                            Sense::Property(p) => object.properties.contains(p),
                            Sense::Attribute { key, value } => object.attributes.get(key) == Some(value),
                        })
                    })
            }
            Reference::Narrowed { base, .. } => base.head_matches(object),
            Reference::Either { options, .. } => options.iter().any(|o| o.head_matches(object)),
            Reference::Union { readings, .. } => readings.iter().any(|o| o.head_matches(object)),
            Reference::Related { base, .. }
            | Reference::Most { base, .. }
            | Reference::Nth { base, .. }
            | Reference::Plural { base, .. } => base.head_matches(object),
            Reference::Speaker(id) => object.id == id.as_str(),
            Reference::Pronoun { .. } | Reference::Nothing { .. } | Reference::Implied { .. } => false,
        }
    }

    /// Words that can match no object whatever the scene: unknown words, or a pronoun with no
    /// object in focus.
    fn names_nothing(&self) -> bool {
        match self {
            Reference::Nothing { .. } | Reference::Pronoun { .. } => true,
            Reference::Narrowed { base, by, .. } => base.names_nothing() || by.names_nothing(),
            Reference::Either { options, .. } => options.iter().any(Reference::names_nothing),
            Reference::Union { readings, .. } => readings.iter().any(Reference::names_nothing),
            Reference::Related { base, to, .. } => base.names_nothing() || to.names_nothing(),
            Reference::Most { base, .. } | Reference::Nth { base, .. } | Reference::Plural { base, .. } => {
                base.names_nothing()
            }
            Reference::Id(_)
            | Reference::Described { .. }
            | Reference::Spoken { .. }
            | Reference::Implied { .. }
            | Reference::Speaker(_) => false,
        }
    }

    /// "a mug": any matching object will do.
    pub(super) fn indefinite(&self) -> bool {
        match self {
            Reference::Spoken { indefinite, .. } => *indefinite,
            // "two cups": any two will do; "the cups" or "both cups" leave no choice.
            Reference::Plural { number, .. } => matches!(number, Number::Any(_)),
            Reference::Narrowed { base, .. }
            | Reference::Related { base, .. }
            | Reference::Most { base, .. }
            | Reference::Nth { base, .. } => base.indefinite(),
            Reference::Union { readings, .. } => readings.first().is_some_and(Reference::indefinite),
            Reference::Either { .. } => true,
            _ => false,
        }
    }

    /// The words of the reference that could not be placed at all, if any.
    pub(super) fn unplaced(&self) -> Option<String> {
        match self {
            Reference::Nothing { unplaced, .. } => unplaced.clone(),
            Reference::Narrowed { base, by, .. } => base.unplaced().or_else(|| by.unplaced()),
            Reference::Either { options, .. } => options.iter().find_map(Reference::unplaced),
            Reference::Union { readings, .. } => readings.iter().find_map(Reference::unplaced),
            Reference::Related { base, to, .. } => base.unplaced().or_else(|| to.unplaced()),
            Reference::Most { base, .. } | Reference::Nth { base, .. } | Reference::Plural { base, .. } => {
                base.unplaced()
            }
            _ => None,
        }
    }

    /// The reference in words: "the spoon", "the blue notebook", "the red one".
    pub(super) fn words(&self, scene: &Scene) -> String {
        match self {
            Reference::Id(id) => match scene.object(id) {
                Some(object) => super::describe::describe_object(scene, object),
                None => id.clone(),
            },
            Reference::Described {
                attributes, properties, ..
            } => {
                let mut words = vec!["the".to_owned()];
                words.extend(properties.iter().map(|p| spoken(p)));
                words.extend(attributes.values().map(|v| spoken(v)));
                words.push(self.noun().unwrap_or_else(|| "one".to_owned()));
                words.join(" ")
            }
            Reference::Spoken { words, .. }
            | Reference::Pronoun { words }
            | Reference::Nothing { words, .. }
            | Reference::Either { words, .. }
            | Reference::Union { words, .. }
            | Reference::Related { words, .. }
            | Reference::Most { words, .. }
            | Reference::Nth { words, .. }
            | Reference::Plural { words, .. }
            | Reference::Implied { words, .. }
            | Reference::Narrowed { words, .. } => words.clone(),
            Reference::Speaker(_) => "me".to_owned(),
        }
    }

    /// How many objects the reference means at once, when it is plural: its own number, or that
    /// of the reference its relations, pick or narrowing apply to.
    pub fn number(&self) -> Option<Number> {
        match self {
            Reference::Plural { number, .. } => Some(*number),
            Reference::Narrowed { base, .. }
            | Reference::Related { base, .. }
            | Reference::Most { base, .. }
            | Reference::Nth { base, .. } => base.number(),
            Reference::Union { readings, .. } => readings.first().and_then(Reference::number),
            _ => None,
        }
    }

    /// The head noun: the type spoken, if the reference names one.
    pub(super) fn noun(&self) -> Option<String> {
        match self {
            Reference::Described { kind: Some(k), .. } => Some(spoken(k)),
            Reference::Spoken { kinds, .. } => kinds.first().map(|k| spoken(k)),
            Reference::Narrowed { base, .. }
            | Reference::Related { base, .. }
            | Reference::Most { base, .. }
            | Reference::Nth { base, .. }
            | Reference::Plural { base, .. } => base.noun(),
            Reference::Union { readings, .. } => readings.first().and_then(Reference::noun),
            Reference::Either { options, .. } => {
                let nouns: Vec<Option<String>> = options.iter().map(Reference::noun).collect();
                nouns
                    .windows(2)
                    .all(|w| w[0] == w[1])
                    .then(|| nouns[0].clone())
                    .flatten()
            }
            _ => None,
        }
    }
}

/// A candidate binding from an upstream resolver; higher scores are likelier.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    pub id: String,
    pub score: f64,
}

/// One argument (or variable) of the directive and its candidates.
pub(super) struct Slot {
    pub(super) candidates: Vec<(Term, f64)>,
    /// The slot in words when nothing matches it ("the spoon").
    pub(super) words: String,
    /// The slot's head noun when asking which one is meant ("spoon").
    pub(super) noun: String,
    /// Words of the slot's reference that could not be placed at all ("pls").
    pub(super) unplaced: Option<String>,
    /// What the scene could not tell, when that is why nothing matches ("I cannot tell which
    /// box is the biggest: …").
    pub(super) untold: Option<String>,
    /// Whether the candidates are groups of objects (a plural reference's).
    pub(super) group: bool,
}

/// How one choice of candidates, one per slot, becomes an action.
pub(super) enum Template<'a> {
    /// The verb applied to the chosen objects, in argument order.
    Verb(Sym),
    /// The form with each variable (in first-appearance order) bound to its choice.
    Form(&'a Term, Vec<Sym>),
    /// A task's steps, each argument bound to its slot's choice.
    Task(Box<Shape>),
}

impl Template<'_> {
    pub(super) fn action(&self, values: &[Term]) -> Term {
        match self {
            Template::Verb(verb) => Term::compound(verb, values.to_vec()),
            Template::Form(form, variables) => {
                let mut subst = Subst::new();
                for (variable, value) in variables.iter().zip(values) {
                    subst.bind(variable.clone(), value.clone());
                }
                form.substitute(&subst)
            }
            Template::Task(shape) => shape.action(values),
        }
    }
}

/// The common type of a slot's candidate objects, spoken; "one" when they differ.
fn common_noun(scene: &Scene, candidates: &[(Term, f64)]) -> String {
    let mut kinds = candidates
        .iter()
        .filter_map(|(t, _)| t.name().and_then(|id| scene.object(id)))
        .map(|o| o.kind.as_str());
    match kinds.next() {
        Some(first) if kinds.all(|k| k == first) => spoken(first),
        _ => "one".to_owned(),
    }
}

/// The slot of one reference: every object of the scene it matches, in scene order. Past the
/// deadline it is left empty; the caller asks the deadline before reading an empty slot.
/// A plural reference's slot offers groups of its matches ([`number::groups`]).
pub(super) fn slot(reference: &Reference, scene: &Scene, expired: &dyn Fn() -> bool) -> Slot {
    // A speaker the scene does not hold is named by id: they come for what they are given.
    if let Reference::Speaker(id) = reference
        && scene.index_of(id).is_none()
    {
        return Slot {
            candidates: vec![(Term::constant(id), 1.0)],
            words: reference.words(scene),
            noun: "you".to_owned(),
            unplaced: None,
            untold: None,
            group: false,
        };
    }
    let selected = reference.select_once(scene, expired).unwrap_or_default();
    let objects: Vec<(Term, f64)> = (selected.objects.iter())
        .map(|&i| (Term::Const(scene.objects[i].id.clone()), 1.0))
        .collect();
    let noun = reference.noun().unwrap_or_else(|| common_noun(scene, &objects));
    let mut untold = selected.untold;
    let number = reference.number();
    let (candidates, noun) = match number {
        None => (objects, noun),
        // Nothing found says why as a singular would, unless the count is what is wrong.
        Some(_) if objects.is_empty() && (untold.is_some() || reference.names_nothing() || expired()) => {
            (objects, plural(&noun))
        }
        Some(number) => {
            let matches: Vec<Term> = objects.into_iter().map(|(t, _)| t).collect();
            // One group more than any request may read says there are too many.
            match number::groups(number, &matches, &noun, MOST_READINGS + 1) {
                Ok(groups) => (groups.into_iter().map(|g| (g, 1.0)).collect(), plural(&noun)),
                Err(why) => {
                    untold = Some(why);
                    (Vec::new(), plural(&noun))
                }
            }
        }
    };
    Slot {
        untold: untold.filter(|_| candidates.is_empty()),
        candidates,
        words: reference.words(scene),
        noun,
        unplaced: reference.unplaced(),
        group: number.is_some(),
    }
}

pub(super) fn slots<'a>(
    directive: &'a Directive,
    scene: &Scene,
    expired: &dyn Fn() -> bool,
) -> (Template<'a>, Vec<Slot>) {
    match directive {
        Directive::Action { verb, arguments, .. } => {
            let slots = arguments
                .iter()
                .map(|reference| slot(reference, scene, expired))
                .collect();
            (Template::Verb(Sym::from(verb.as_str())), slots)
        }
        // A task's slots are made with its shape (`Task::shape`), which its readings need too.
        Directive::Task(task) => {
            let (shape, slots, _) = task.shape(scene, expired);
            (Template::Task(Box::new(shape)), slots)
        }
        // Words are read into an action before anything is resolved; unread, they name nothing.
        Directive::Words { text } => (
            Template::Verb(Sym::from("")),
            vec![Slot {
                candidates: Vec::new(),
                words: text.clone(),
                noun: "one".to_owned(),
                unplaced: None,
                untold: None,
                group: false,
            }],
        ),
        Directive::Form { action, bindings } => {
            let variables = action.variables();
            let slots = variables
                .iter()
                .map(|variable| {
                    let given = bindings
                        .iter()
                        .find(|(v, _)| v == variable)
                        .map(|(_, cs)| cs.as_slice());
                    let candidates: Vec<(Term, f64)> = given
                        .unwrap_or_default()
                        .iter()
                        .filter_map(|c| scene.object(&c.id).map(|o| (Term::Const(o.id.clone()), c.score)))
                        .collect();
                    let noun = common_noun(scene, &candidates);
                    Slot {
                        candidates,
                        words: variable.to_string(),
                        noun,
                        unplaced: None,
                        untold: None,
                        group: false,
                    }
                })
                .collect();
            (Template::Form(action, variables), slots)
        }
    }
}

/// Every combination of one candidate from each list (last list fastest): the values and the
/// score.
pub(super) fn combinations(lists: &[&[(Term, f64)]]) -> Vec<(Vec<Term>, f64)> {
    let mut out = Vec::new();
    if lists.iter().any(|l| l.is_empty()) {
        return out;
    }
    let mut choice = vec![0usize; lists.len()];
    loop {
        let values = choice.iter().zip(lists).map(|(&i, l)| l[i].0.clone()).collect();
        let score = choice.iter().zip(lists).map(|(&i, l)| l[i].1).product();
        out.push((values, score));
        let mut slot = lists.len();
        loop {
            if slot == 0 {
                return out;
            }
            slot -= 1;
            choice[slot] += 1;
            if choice[slot] < lists[slot].len() {
                break;
            }
            choice[slot] = 0;
        }
    }
}
