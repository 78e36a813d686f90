//! The people a scene holds: who they are called, their roles and where they stand. A person is
//! a referent like an object (of type `person`: reach, relations and words apply), but not an
//! object to handle.
//!
//! Owns: a person's checks (fields named relative to the person), the facts a person yields
//! beyond its type (`role(p,r)`), the speaker's facts, and the name a person is spoken by.
//! Must not: decide what a verb may do to a person (the simulation does, by the verb's
//! preconditions).

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::sync::Arc;

use rustc_hash::FxHashMap;

use super::spoken::names_of;
use super::{Object, Scene, spoken};
use crate::engine::input::{Invalid, constant, finite};
use crate::engine::norms::validate_roles;
use crate::engine::term::{Sym, Term};

/// Who speaks when a request does not say: the contract's default.
pub const DEFAULT_SPEAKER: &str = "human";

/// The type every person has: a person yields `person(p)` as an object yields its type.
pub const PERSON: &str = "person";

/// A person as a request describes them, before they are checked.
#[derive(Clone, Debug)]
pub struct PersonInput {
    pub id: String,
    /// Proper names, as written ("Bob"): heard in any case, spoken as written.
    pub names: Vec<String>,
    pub roles: Vec<String>,
    /// Where the person stands, metres, world frame: a hand-over needs them within reach.
    pub position: [f64; 3],
}

/// What a scene knows of one person beyond the object it is as a referent.
#[derive(Clone, Debug, PartialEq)]
pub struct Person {
    /// Index of the person's object in the scene's list.
    pub index: usize,
    /// Normalised role names, each once, in the order given.
    pub roles: Vec<String>,
    /// The first name as written, spoken as the person's name when no one else has it.
    pub name: Option<String>,
    /// What tells the person apart by their own words ([`Scene::person_words`]), set once the
    /// scene's people are all known.
    pub words: Option<String>,
}

impl PersonInput {
    /// The person as a referent: an object of type `person`, a point at `position`, called by
    /// their names and by each role ("the child"); and what the scene keeps of them. Fields
    /// named relative to the person; the id's uniqueness is the scene's to check.
    pub(super) fn checked(self, id: Sym, index: usize) -> Result<(Object, Person), Invalid> {
        finite("/position", &self.position)?;
        // Spoken as written, but one space between words.
        let name = (self.names.first()).map(|n| n.split_whitespace().collect::<Vec<_>>().join(" "));
        let mut names = names_of(self.names)?;
        let roles = validate_roles("/roles", Some(self.roles))?;
        for role in &roles {
            constant("", role, "a role").map_err(|e| e.within("/roles"))?;
            let noun = spoken(role);
            if !names.contains(&noun) {
                names.push(noun);
            }
        }
        let object = Object {
            id,
            kind: PERSON.to_owned(),
            properties: Vec::new(),
            attributes: BTreeMap::new(),
            position: self.position,
            shape: None,
            rotation: None,
            mass: None,
            names,
        };
        Ok((
            object,
            Person {
                index,
                roles,
                name,
                words: None,
            },
        ))
    }
}

impl Scene {
    /// Whether the object `id` is a person: one of `people`, or an object of type `person`.
    pub fn is_person(&self, id: &str) -> bool {
        self.object(id).is_some_and(|o| o.kind == PERSON)
    }

    /// The person behind the object at `index`, if it came from `people` (they follow the
    /// scene's own objects, in order).
    pub fn person_at(&self, index: usize) -> Option<&Person> {
        let first = self.people.first()?.index;
        self.people.get(index.checked_sub(first)?)
    }

    /// How a person of `people` is spoken when their words alone tell them apart: their name as
    /// written when no other person is called so, else "the {role}" for a role no other person
    /// has.
    pub fn person_words(&self, id: &str) -> Option<String> {
        if self.people.is_empty() {
            return None;
        }
        self.person_at(self.index_of(id)?)?.words.clone()
    }

    /// `role(p,r)` for each role of each person, in the order the people and roles were given.
    pub(super) fn role_facts(&self, out: &mut Vec<Term>) {
        let role = Sym::from("role");
        for person in &self.people {
            let id = Term::Const(self.objects[person.index].id.clone());
            for r in &person.roles {
                out.push(Term::Compound(role.clone(), Arc::from([id.clone(), Term::constant(r)])));
            }
        }
    }
}

/// What a person fact says, as the predicate of a sentence about its subject: `person(p)` →
/// "a person", `role(p,child)` → "a child"; `None` for any other fact.
pub fn person_predicate(fact: &Term) -> Option<String> {
    let noun = match (fact.name().map(|n| &**n), fact.args()) {
        (Some(PERSON), [_]) => PERSON.to_owned(),
        (Some("role"), [_, Term::Const(role)]) => spoken(role),
        _ => return None,
    };
    let article = match noun.starts_with(['a', 'e', 'i', 'o', 'u']) {
        true => "an",
        false => "a",
    };
    Some(format!("{article} {noun}"))
}

/// Sets each person's words: the name no other person is called by, else a role no other
/// person has. Counted once, so that describing ten thousand people is not a product.
pub(super) fn settle(people: &mut [Person], objects: &[Object]) {
    if people.is_empty() {
        return;
    }
    // What each noun may be said of: any object's names, and the other types spoken (each
    // type spoken once, however many objects have it).
    let mut called: FxHashMap<Cow<'_, str>, usize> = FxHashMap::default();
    let mut kinds: FxHashMap<&str, usize> = FxHashMap::default();
    for o in objects {
        for name in &o.names {
            *called.entry(Cow::Borrowed(name)).or_default() += 1;
        }
        if o.kind != PERSON {
            *kinds.entry(&o.kind).or_default() += 1;
        }
    }
    for (kind, n) in kinds {
        *called.entry(Cow::Owned(spoken(kind))).or_default() += n;
    }
    let mut roles: FxHashMap<&str, usize> = FxHashMap::default();
    for role in people.iter().flat_map(|p| &p.roles) {
        *roles.entry(role).or_default() += 1;
    }
    let words: Vec<Option<String>> = (people.iter())
        .map(
            // The first name as heard is the first of the object's names (normalised as words
            // are); it is spoken as written.
            |p| match (p.name.as_ref()).filter(|_| {
                let heard = objects[p.index].names.first().map(String::as_str);
                heard.is_some_and(|n| called.get(n) == Some(&1))
            }) {
                Some(name) => Some(name.clone()),
                None => (p.roles.iter())
                    .find(|r| roles.get(r.as_str()) == Some(&1) && called.get(spoken(r).as_str()) == Some(&1))
                    .map(|r| format!("the {}", spoken(r))),
            },
        )
        .collect();
    for (p, words) in people.iter_mut().zip(words) {
        p.words = words;
    }
}

/// The speaker is a person with the request's roles: `person(s)` and `role(s,r)` for each.
pub fn speaker_facts(speaker: &str, roles: &[String]) -> Vec<Term> {
    let id = Term::constant(speaker);
    let mut out = vec![Term::compound(PERSON, vec![id.clone()])];
    out.extend(
        roles
            .iter()
            .map(|r| Term::compound("role", vec![id.clone(), Term::constant(r)])),
    );
    out
}
