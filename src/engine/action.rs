//! The action library as data: each verb's parameters, needs, steps and effects.
//!
//! Owns: the definitions and the default library (get, pointTo, destroy, steal, put).
//! Must not: simulate anything; `simulate` interprets these definitions.

use std::collections::HashMap;

use super::term::{Subst, Sym, Term};

/// One step of a verb's plan.
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// The verb's own primitive execution: its effects and needs apply here.
    Itself,
    /// Another action, written over the verb's parameters (`get(X)` inside `put(X,Y)`).
    Do(Term),
}

#[derive(Clone, Debug, PartialEq)]
pub struct ActionDef {
    pub name: Sym,
    /// Parameter variables, bound positionally to the action's arguments.
    pub params: Vec<Sym>,
    /// Parameters whose object must be within the agent's reach, with a clear path to it, when
    /// the verb itself runs.
    pub reach: Vec<Sym>,
    /// Parameters whose object the gripper closes around: it must fit the aperture and not
    /// exceed the payload.
    pub grasp: Vec<Sym>,
    /// `(item, support)`: the verb sets the item on the support, which must have room for it.
    pub place: Option<(Sym, Sym)>,
    /// Facts (over the parameters; other variables are existential) that must hold when the verb
    /// itself runs.
    pub preconditions: Vec<Term>,
    pub steps: Vec<Step>,
    /// Made true by the verb itself, besides `did(self,action)`.
    pub adds: Vec<Term>,
    /// Made false by the verb itself.
    pub removes: Vec<Term>,
    /// The word that joins the verb's arguments when spoken ("put the cup on the plate").
    pub joiner: Option<String>,
}

impl ActionDef {
    /// Binds the parameters to an action's arguments; `None` when the arity differs.
    pub fn bind(&self, action: &Term) -> Option<Subst> {
        if action.arity() != self.params.len() {
            return None;
        }
        let mut subst = Subst::new();
        for (param, arg) in self.params.iter().zip(action.args()) {
            subst.bind(param.clone(), arg.clone());
        }
        Some(subst)
    }
}

/// Verbs by name and arity.
#[derive(Clone, Debug, Default)]
pub struct Library {
    defs: HashMap<(Sym, usize), ActionDef>,
}

fn term(text: &str) -> Term {
    Term::parse(text).expect("the default library is written in valid terms")
}

impl Library {
    pub fn insert(&mut self, def: ActionDef) {
        self.defs.insert((def.name.clone(), def.params.len()), def);
    }

    pub fn get(&self, name: &str, arity: usize) -> Option<&ActionDef> {
        self.defs.get(&(Sym::from(name), arity))
    }

    /// The verb definition for an action term, if the library knows that name at that arity.
    pub fn lookup(&self, action: &Term) -> Option<&ActionDef> {
        self.get(action.name()?, action.arity())
    }

    /// The contract's default library.
    pub fn default_library() -> Library {
        let handle = |name: &str, adds: &[&str]| ActionDef {
            name: Sym::from(name),
            params: vec![Sym::from("X")],
            reach: vec![Sym::from("X")],
            grasp: vec![],
            place: None,
            preconditions: vec![],
            steps: vec![Step::Itself],
            adds: adds.iter().map(|t| term(t)).collect(),
            removes: vec![],
            joiner: None,
        };
        let mut library = Library::default();
        let grasping = |def: ActionDef| ActionDef {
            grasp: vec![Sym::from("X")],
            ..def
        };
        library.insert(grasping(handle("get", &["holding(self,X)"])));
        library.insert(handle("destroy", &["destroyed(X)"]));
        library.insert(grasping(handle("steal", &["holding(self,X)"])));
        library.insert(ActionDef {
            reach: vec![],
            ..handle("pointTo", &[])
        });
        library.insert(ActionDef {
            name: Sym::from("put"),
            params: vec![Sym::from("X"), Sym::from("Y")],
            reach: vec![Sym::from("X"), Sym::from("Y")],
            // X was grasped by the get step.
            grasp: vec![],
            place: Some((Sym::from("X"), Sym::from("Y"))),
            preconditions: vec![],
            steps: vec![Step::Do(term("get(X)")), Step::Itself],
            adds: vec![term("on(X,Y)")],
            removes: vec![term("holding(self,X)")],
            joiner: Some("on".into()),
        });
        library
    }
}
