//! The facts a scene states, as the fact base of a decision starts from them.
//!
//! Owns: which facts each object yields, and their order. Must not: depend on hash order.

use std::sync::Arc;

use rustc_hash::FxHashMap;

use super::Scene;
use crate::engine::term::{Sym, Term};

/// How many distinct names a scene's map of them has room for from the start, at most.
const NAMES_RESERVED: usize = 64;

impl Scene {
    /// Every fact the scene states: for each object its type, properties and attributes, each
    /// person's roles, then `facts` as given. On one thread: the facts of one type share its name's count, which
    /// threads stating them side by side would take turns at (the bench's 10,000-object case
    /// took about a tenth longer with the facts stated on two threads).
    pub fn all_facts(&self) -> Vec<Term> {
        // An object states its type, each property and each attribute; an attribute names two.
        let (stated, named) = (self.objects.iter()).fold((0, 0), |(stated, named), o| {
            let (properties, attributes) = (o.properties.len(), o.attributes.len());
            (
                stated + 1 + properties + attributes,
                named + 1 + properties + 2 * attributes,
            )
        });
        let roles: usize = self.people.iter().map(|p| p.roles.len()).sum();
        let mut out = Vec::with_capacity(stated + roles + self.facts.len());
        // Types, properties and attributes recur across objects: each is interned once here.
        // Room for every name a small scene can have, so that its map never grows; a large
        // scene repeats its names.
        let mut names: FxHashMap<&str, Sym> =
            FxHashMap::with_capacity_and_hasher(named.min(NAMES_RESERVED), Default::default());
        let mut name = |text| names.entry(text).or_insert_with(|| Sym::new(text)).clone();
        for object in &self.objects {
            let id = Term::Const(object.id.clone());
            out.push(Term::Compound(name(&object.kind), Arc::from([id.clone()])));
            for property in &object.properties {
                out.push(Term::Compound(name(property), Arc::from([id.clone()])));
            }
            for (key, value) in &object.attributes {
                let value = Term::Const(name(value));
                out.push(Term::Compound(name(key), Arc::from([id.clone(), value])));
            }
        }
        self.role_facts(&mut out);
        out.extend(self.facts.iter().cloned());
        out
    }

    /// [`Scene::all_facts`], and the speaker's: a person with the request's roles.
    pub fn facts_with_speaker(&self, speaker: &str, roles: &[String]) -> Vec<Term> {
        let mut out = self.all_facts();
        out.extend(super::speaker_facts(speaker, roles));
        out
    }
}
