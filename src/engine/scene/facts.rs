//! The facts a scene states, as the fact base of a decision starts from them.
//!
//! Owns: which facts each object yields, and their order. Must not: depend on hash order or on
//! how many threads state them.

use std::sync::Arc;

use rayon::prelude::*;
use rustc_hash::FxHashMap;

use super::{Object, Scene};
use crate::engine::term::{Sym, Term};

/// Objects whose facts one thread states at a time.
const OBJECTS_PER_TASK: usize = 2048;

impl Scene {
    /// Every fact the scene states: for each object its type, properties and attributes, then
    /// `facts` as given. A large scene's objects are stated on rayon's pool, in scene order.
    pub fn all_facts(&self) -> Vec<Term> {
        let mut out = Vec::with_capacity(self.objects.len() * 2 + self.facts.len());
        if self.objects.len() <= OBJECTS_PER_TASK {
            object_facts(&self.objects, &mut out);
        } else {
            let parts: Vec<Vec<Term>> = (self.objects.par_chunks(OBJECTS_PER_TASK))
                .map(|objects| {
                    let mut facts = Vec::with_capacity(objects.len() * 2);
                    object_facts(objects, &mut facts);
                    facts
                })
                .collect();
            parts.into_iter().for_each(|facts| out.extend(facts));
        }
        out.extend(self.facts.iter().cloned());
        out
    }
}

/// The facts of `objects`, in their order, appended to `out`.
fn object_facts(objects: &[Object], out: &mut Vec<Term>) {
    // Types, properties and attributes recur across objects: each is interned once here.
    let mut names: FxHashMap<&str, Sym> = FxHashMap::default();
    let mut name = |text| names.entry(text).or_insert_with(|| Sym::new(text)).clone();
    for object in objects {
        let id = Term::Const(Sym::new(&object.id));
        out.push(Term::Compound(name(&object.kind), Arc::from([id.clone()])));
        for property in &object.properties {
            out.push(Term::Compound(name(property), Arc::from([id.clone()])));
        }
        for (key, value) in &object.attributes {
            let value = Term::Const(name(value));
            out.push(Term::Compound(name(key), Arc::from([id.clone(), value])));
        }
    }
}
