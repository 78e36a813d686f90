//! The action library as data: each verb's parameters and methods (needs, steps, effects).
//!
//! Owns: the definitions, their validation (field-relative errors, no unknown variables, no
//! recursion through the library); the default verbs are in `defaults`, what a directive may
//! leave unsaid in `implied`.
//! Must not: simulate anything (`simulate` interprets these definitions) or read the database.

use std::collections::{BTreeMap, HashSet};

use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

use super::input::Invalid;
use super::term::{Subst, Sym, Term, is_constant_name};

mod defaults;
mod implied;
mod words;

pub use defaults::DEFAULT_VERBS;
pub use implied::Unsaid;
use implied::implied_of;
pub use words::relation_of;
use words::{collide, grammar_free, phrases};

/// One step of a method's plan.
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// The verb's own primitive execution: its effects and needs apply here.
    Itself,
    /// Another action, written over the verb's parameters (`get(X)` inside `put(X,Y)`).
    Do(Term),
}

/// One way of carrying a verb out. A reading is permissible and feasible when any of its verb's
/// methods is.
#[derive(Clone, Debug, PartialEq)]
pub struct Method {
    /// Parameters whose object must be within the agent's reach, with a clear path to it, when
    /// the verb itself runs.
    pub reach: Vec<Sym>,
    /// Parameters whose object the gripper closes around: it must fit the aperture and not
    /// exceed the payload.
    pub grasp: Vec<Sym>,
    /// `(item, support)`: the verb sets the item on the support, which must have room for it.
    pub place: Option<(Sym, Sym)>,
    /// Facts over the parameters that must hold when the verb itself runs.
    pub preconditions: Vec<Term>,
    /// In order; `Itself` appears exactly once.
    pub steps: Vec<Step>,
    /// Made true by the verb itself, besides `did(self,action)`.
    pub adds: Vec<Term>,
    /// Made false by the verb itself.
    pub removes: Vec<Term>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct ActionDef {
    pub name: Sym,
    /// Parameter variables, bound positionally to the action's arguments.
    pub params: Vec<Sym>,
    /// The word that joins the verb's arguments when spoken ("put the cup on the plate").
    pub joiner: Option<String>,
    /// The arguments must be different objects: a reading that names one twice (a cup put on
    /// itself) is infeasible.
    pub distinct: bool,
    /// Tried in order; at least one.
    pub methods: Vec<Method>,
    /// Phrases that name the verb in words ("pick up"), lower case, single-spaced; a phrase names
    /// one verb only.
    pub words: Vec<String>,
    /// For a verb of two parameters: the words understood between its arguments ("into").
    pub joiners: Vec<String>,
    /// Parameters a directive may leave unsaid, in parameter order, each with the facts over it
    /// alone that an object must meet to be its argument (`Y`: `heater(Y)`). They are the verb's
    /// last parameters, never its first.
    pub implied: Vec<(Sym, Vec<Term>)>,
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

    /// Makes every name the verb's plan uses last for the process: every reading of it copies
    /// them (see [`Sym::make_lasting`]).
    fn make_lasting(&self) {
        self.name.make_lasting();
        self.params.iter().for_each(Sym::make_lasting);
        for method in &self.methods {
            let terms = (method.preconditions.iter())
                .chain(&method.adds)
                .chain(&method.removes)
                .chain(method.steps.iter().filter_map(|s| match s {
                    Step::Do(t) => Some(t),
                    Step::Itself => None,
                }));
            terms.for_each(Term::make_lasting);
        }
        self.implied
            .iter()
            .flat_map(|(_, facts)| facts)
            .for_each(Term::make_lasting);
    }

    /// The verbs this one's steps call, by name and arity.
    pub fn callees(&self) -> impl Iterator<Item = (Sym, usize)> + '_ {
        self.methods.iter().flat_map(|m| {
            m.steps.iter().filter_map(|s| match s {
                Step::Do(t) => t.name().map(|n| (n.clone(), t.arity())),
                Step::Itself => None,
            })
        })
    }
}

/// A verb as a curator writes it, as the API carries it and as the store keeps it: terms as
/// text. (Its schema, for the API's document, is `wire::ActionSchema`.)
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ActionInput {
    /// The verb's name; when sent, it must equal the name it is stored as (the request's path).
    #[serde(default)]
    pub name: Option<String>,
    /// Variables such as `X`, bound to the arguments in order.
    #[serde(default)]
    pub parameters: Vec<String>,
    /// The word joining the arguments when spoken: `on` for "put the cup on the plate".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joiner: Option<String>,
    /// The arguments must name different objects (`put` does): a reading that names one object
    /// twice is infeasible (`same_object`) and never offered. Default false.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub distinct: bool,
    /// One or more ways of carrying the verb out; a reading is acceptable when any is.
    #[serde(default)]
    pub methods: Vec<MethodInput>,
    /// Phrases that name the verb when a directive comes in words: `["get", "pick up"]`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub words: Vec<String>,
    /// For a verb of two parameters, the words understood between its arguments in words:
    /// `["on", "onto", "into"]`. `joiner` stays the one word spoken.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joiners: Vec<String>,
    /// Parameters a directive may leave unsaid, each with the facts an object must meet to be
    /// its argument: `{"Y": ["heater(Y)"]}`. Left out, the argument ranges over the scene's
    /// objects that meet them.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub implied: BTreeMap<String, Vec<String>>,
}

/// One way of carrying a verb out. Terms are written over the verb's parameters.
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MethodInput {
    /// Action terms, and the word `itself` for the verb's own execution; default `["itself"]`,
    /// and `itself` is appended when not listed.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub steps: Vec<String>,
    /// Parameters whose object must be within reach, with a clear path, for `itself`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub reach: Vec<String>,
    /// Parameters whose object the gripper closes around (aperture and payload).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub grasp: Vec<String>,
    /// `[item, support]`: the support must have room for the item.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub place: Option<Vec<String>>,
    /// Facts that must hold when `itself` runs: `closed(X)`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub preconditions: Vec<String>,
    /// Facts `itself` makes true (besides `did(self,action)`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub adds: Vec<String>,
    /// Facts `itself` makes false.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub removes: Vec<String>,
}

/// Longest verb name, bytes: the same bound wherever a verb is named (a stored verb, a
/// directive's action, a form, a step), so that any verb a request can name can be defined.
pub const MAX_VERB_LEN: usize = 64;

/// Checks a verb's name; the message says what is wrong.
pub fn verb_name(name: &str) -> Result<(), String> {
    if name.len() > MAX_VERB_LEN {
        return Err(format!(
            "a verb name is at most {MAX_VERB_LEN} bytes; this one is {}",
            name.len()
        ));
    }
    // A letter first: a verb is spoken, and `_` or `3d` would be no word at all.
    if !(is_constant_name(name) && name.starts_with(|c: char| c.is_ascii_lowercase())) {
        return Err(format!(
            "`{name}` is not a verb name (lower-case first, then letters, digits, `_`)"
        ));
    }
    Ok(())
}

pub const MAX_METHODS: usize = 8;
pub const MAX_ITEMS: usize = 32;
/// Most phrases naming one verb, and most words in one phrase.
pub const MAX_WORDS: usize = 16;
pub const MAX_PHRASE_WORDS: usize = 3;
/// Most joiners of one verb.
pub const MAX_JOINERS: usize = 8;

/// Phrases of 1 to `most_words` words of letters, each listed once, normalised; `field` names
/// the list.
impl ActionDef {
    /// The checks a verb's words meet when it is written (not when a stored one is read, so
    /// that a library stored before them still loads): no phrase starts with a word the grammar
    /// reads itself, and no joiner is one.
    pub fn check_written_words(&self) -> Result<(), Invalid> {
        grammar_free(&self.words, &self.joiners)
    }
}

impl ActionInput {
    /// Validates every field; the verb is named by the caller (the path of the request).
    pub fn validate(&self, name: &str) -> Result<ActionDef, Invalid> {
        if let Some(given) = &self.name
            && given != name
        {
            return Err(Invalid::new(
                "/name",
                format!("`{given}` differs from the verb `{name}` it is stored as"),
            ));
        }
        verb_name(name).map_err(|m| Invalid::new("/name", m))?;
        if self.parameters.len() > 8 {
            return Err(Invalid::new("/parameters", "at most 8 parameters"));
        }
        let mut params: Vec<Sym> = Vec::new();
        for (i, p) in self.parameters.iter().enumerate() {
            let field = format!("/parameters/{i}");
            let term = Term::parse(p).map_err(|e| Invalid::new(&field, format!("not a variable: {e}")))?;
            let Term::Var(v) = term else {
                return Err(Invalid::new(
                    field,
                    format!("`{p}` is not a variable (upper-case first, or `?`)"),
                ));
            };
            if params.contains(&v) {
                return Err(Invalid::new(field, format!("`{v}` is listed twice")));
            }
            params.push(v);
        }
        if let Some(joiner) = &self.joiner
            && (joiner.is_empty() || joiner.len() > 32 || !joiner.chars().all(|c| c.is_ascii_lowercase() || c == ' '))
        {
            return Err(Invalid::new("/joiner", "a short lower-case word, like `on` or `to`"));
        }
        if self.methods.is_empty() || self.methods.len() > MAX_METHODS {
            return Err(Invalid::new("/methods", format!("give 1 to {MAX_METHODS} methods")));
        }
        let methods = self
            .methods
            .iter()
            .enumerate()
            .map(|(i, m)| m.validate(&format!("/methods/{i}"), name, &params))
            .collect::<Result<_, _>>()?;
        if self.distinct && params.len() < 2 {
            return Err(Invalid::new("/distinct", "`distinct` needs two or more parameters"));
        }
        let words = phrases("/words", &self.words, MAX_WORDS, MAX_PHRASE_WORDS)?;
        let joiners = phrases("/joiners", &self.joiners, MAX_JOINERS, 1)?;
        if !joiners.is_empty() && params.len() != 2 {
            return Err(Invalid::new("/joiners", "joiners go with a verb of two parameters"));
        }
        let implied = implied_of(&self.implied, &params)?;
        Ok(ActionDef {
            name: Sym::from(name),
            params,
            joiner: self.joiner.clone(),
            distinct: self.distinct,
            methods,
            words,
            joiners,
            implied,
        })
    }
}

impl MethodInput {
    fn validate(&self, at: &str, verb: &str, params: &[Sym]) -> Result<Method, Invalid> {
        let known = |field: &str, term: &Term| -> Result<(), Invalid> {
            match term.variables().into_iter().find(|v| !params.contains(v)) {
                Some(v) => Err(Invalid::new(field, format!("`{v}` is not a parameter of the verb"))),
                None => Ok(()),
            }
        };
        let terms = |name: &str, list: &[String]| -> Result<Vec<Term>, Invalid> {
            if list.len() > MAX_ITEMS {
                return Err(Invalid::new(format!("{at}/{name}"), format!("at most {MAX_ITEMS}")));
            }
            list.iter()
                .enumerate()
                .map(|(i, text)| {
                    let field = format!("{at}/{name}/{i}");
                    let term = Term::parse(text).map_err(|e| Invalid::new(&field, format!("not a term: {e}")))?;
                    if term.is_var() {
                        return Err(Invalid::new(field, "must start with a name, not a variable"));
                    }
                    known(&field, &term)?;
                    Ok(term)
                })
                .collect()
        };
        let parameter_list = |name: &str, list: &[String]| -> Result<Vec<Sym>, Invalid> {
            list.iter()
                .enumerate()
                .map(|(i, text)| {
                    let field = format!("{at}/{name}/{i}");
                    params
                        .iter()
                        .find(|p| &***p == text.trim())
                        .cloned()
                        .ok_or_else(|| Invalid::new(field, format!("`{text}` is not a parameter of the verb")))
                })
                .collect()
        };
        let mut steps = Vec::new();
        let mut itself = false;
        for (i, text) in self.steps.iter().enumerate() {
            let field = format!("{at}/steps/{i}");
            if text.trim() == "itself" {
                if itself {
                    return Err(Invalid::new(field, "`itself` may appear once"));
                }
                itself = true;
                steps.push(Step::Itself);
                continue;
            }
            let term = Term::parse(text).map_err(|e| Invalid::new(&field, format!("not a term: {e}")))?;
            if term.is_var() {
                return Err(Invalid::new(field, "a step names an action, not a variable"));
            }
            known(&field, &term)?;
            if term.name().is_some_and(|n| &**n == verb) && term.arity() == params.len() {
                return Err(Invalid::new(field, format!("`{verb}` cannot be a step of itself")));
            }
            steps.push(Step::Do(term));
        }
        if !itself {
            steps.push(Step::Itself);
        }
        let place = match &self.place {
            None => None,
            Some(pair) if pair.len() == 2 => {
                let both = parameter_list("place", pair)?;
                Some((both[0].clone(), both[1].clone()))
            }
            Some(_) => return Err(Invalid::new(format!("{at}/place"), "give [item, support]")),
        };
        Ok(Method {
            reach: parameter_list("reach", &self.reach)?,
            grasp: parameter_list("grasp", &self.grasp)?,
            place,
            preconditions: terms("preconditions", &self.preconditions)?,
            steps,
            adds: terms("adds", &self.adds)?,
            removes: terms("removes", &self.removes)?,
        })
    }
}

impl ActionDef {
    /// The verb as a curator would write it: the inverse of [`ActionInput::validate`].
    pub fn to_input(&self) -> ActionInput {
        let names = |list: &[Sym]| list.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let texts = |list: &[Term]| list.iter().map(Term::to_string).collect::<Vec<_>>();
        ActionInput {
            name: Some(self.name.to_string()),
            parameters: names(&self.params),
            joiner: self.joiner.clone(),
            distinct: self.distinct,
            words: self.words.clone(),
            joiners: self.joiners.clone(),
            implied: (self.implied.iter())
                .map(|(p, facts)| (p.to_string(), texts(facts)))
                .collect(),
            methods: self
                .methods
                .iter()
                .map(|m| MethodInput {
                    steps: m
                        .steps
                        .iter()
                        .map(|s| match s {
                            Step::Itself => "itself".to_owned(),
                            Step::Do(t) => t.to_string(),
                        })
                        .collect(),
                    reach: names(&m.reach),
                    grasp: names(&m.grasp),
                    place: m.place.as_ref().map(|(a, b)| vec![a.to_string(), b.to_string()]),
                    preconditions: texts(&m.preconditions),
                    adds: texts(&m.adds),
                    removes: texts(&m.removes),
                })
                .collect(),
        }
    }
}

/// Most steps one reading of a verb may cost to simulate, counted as the simulation tries them:
/// every step of every method (a reading whose first method fails tries the next), each call
/// of another verb at that verb's own cost. Checked when a verb is stored, so that no directive
/// can expand into millions of steps (five verbs of 8 methods × 4 steps over each other did).
pub const MAX_EXPANSION: u64 = 10_000;

/// Verbs by name and arity.
#[derive(Clone, Debug, Default)]
pub struct Library {
    /// FxHash: a verb is looked up at every step of every reading, and its key's symbol
    /// hashes as one precomputed word. Never iterated where order reaches the output.
    defs: FxHashMap<(Sym, usize), ActionDef>,
    /// The stored version this library was loaded from (0 for the built-in one).
    pub version: i64,
    /// Each verb's expansion cost, worked out once on first use (a request asks it for its
    /// verb); emptied by every insert.
    costs: std::sync::OnceLock<FxHashMap<(Sym, usize), u64>>,
    /// Every phrase naming a verb, longest first, worked out once on first use.
    phrases: std::sync::OnceLock<Vec<VerbPhrase>>,
    /// The name and arity of every fact some method makes true, each once, and whether an
    /// effect is a bare variable; worked out once, as every request's simulation asks.
    effects: std::sync::OnceLock<(Vec<(Sym, usize)>, bool)>,
}

/// One phrase that names a verb, in words, with the verb it names.
#[derive(Clone, Debug)]
pub struct VerbPhrase {
    pub words: Vec<String>,
    pub verb: String,
    pub arity: usize,
    /// The words understood between the verb's two arguments.
    pub joiners: Vec<String>,
    /// Whether the verb's arguments after its first may be left unsaid ("Heat up the soup.").
    pub leaves_unsaid: bool,
    /// Whether the verb's second argument is a person it hands something to, who may be said
    /// first ("Hand Bob the knife."): a verb of two parameters whose every method takes the
    /// second as a person.
    pub recipient: bool,
}

impl Library {
    /// Adds or replaces a verb, refusing one whose steps would call it again through the
    /// library (a plan that never ends).
    pub fn insert(&mut self, def: ActionDef) -> Result<(), Invalid> {
        def.make_lasting();
        let key = (def.name.clone(), def.params.len());
        self.costs = std::sync::OnceLock::new();
        self.phrases = std::sync::OnceLock::new();
        self.effects = std::sync::OnceLock::new();
        let previous = self.defs.insert(key.clone(), def);
        if let Some(cycle) = self.cycle_through(&key) {
            match previous {
                Some(p) => self.defs.insert(key, p),
                None => self.defs.remove(&key),
            };
            return Err(Invalid::new(
                "/methods",
                format!("the steps call back into the verb: {cycle}"),
            ));
        }
        Ok(())
    }

    /// A path of verbs from `start` back to itself, if any.
    fn cycle_through(&self, start: &(Sym, usize)) -> Option<String> {
        let mut stack = vec![(start.clone(), vec![start.0.to_string()])];
        let mut seen = HashSet::new();
        while let Some((key, path)) = stack.pop() {
            let Some(def) = self.defs.get(&key) else { continue };
            for callee in def.callees() {
                let mut next = path.clone();
                next.push(callee.0.to_string());
                if &callee == start {
                    return Some(next.join(" → "));
                }
                if seen.insert(callee.clone()) {
                    stack.push((callee, next));
                }
            }
        }
        None
    }

    /// A library from verbs as written (the store's rows), each validated under its own name,
    /// and refused whole if any is invalid or the steps loop.
    pub fn from_written(version: i64, verbs: &[(String, ActionInput)]) -> Result<Library, (String, Invalid)> {
        let mut library = Library {
            version,
            ..Library::default()
        };
        for (name, input) in verbs {
            let def = input.validate(name).map_err(|e| (name.clone(), e))?;
            library.insert(def).map_err(|e| (name.clone(), e))?;
        }
        Ok(library)
    }

    /// The steps one reading of `name/arity` may cost (see [`MAX_EXPANSION`]), saturating; an
    /// unknown verb costs one step (it is found unknown).
    pub fn expansion(&self, name: &str, arity: usize) -> u64 {
        self.costs().get(&(Sym::from(name), arity)).copied().unwrap_or(1)
    }

    /// Every phrase that names a verb, longest first (so that "pick up" is tried before a verb
    /// whose word is "pick"), then in byte order.
    pub fn phrases(&self) -> &[VerbPhrase] {
        self.phrases.get_or_init(|| {
            let mut phrases: Vec<VerbPhrase> = (self.defs.values())
                .flat_map(|def| {
                    def.words.iter().map(|phrase| VerbPhrase {
                        words: phrase.split(' ').map(str::to_owned).collect(),
                        verb: def.name.to_string(),
                        arity: def.params.len(),
                        joiners: def.joiners.clone(),
                        leaves_unsaid: def.unsaid(1).is_some(),
                        recipient: def.params.len() == 2 && def.methods.iter().all(|m| m.takes_person(&def.params[1])),
                    })
                })
                .collect();
            phrases.sort_by(|a, b| {
                (b.words.len().cmp(&a.words.len()))
                    .then_with(|| a.words.cmp(&b.words))
                    .then_with(|| a.verb.cmp(&b.verb))
                    .then_with(|| a.arity.cmp(&b.arity))
            });
            phrases
        })
    }

    /// The costliest verb's steps per reading.
    pub fn most_expansion(&self) -> u64 {
        self.costs().values().copied().max().unwrap_or(1)
    }

    /// Every verb's cost. The library has no cycles, so each is the sum over its methods' steps
    /// of the costs of the verbs they call, worked out callees first.
    fn costs(&self) -> &FxHashMap<(Sym, usize), u64> {
        self.costs.get_or_init(|| {
            let mut costs = FxHashMap::with_capacity_and_hasher(self.defs.len(), Default::default());
            for key in self.defs.keys() {
                self.cost_into(key, &mut costs);
            }
            costs
        })
    }

    fn cost_into(&self, key: &(Sym, usize), costs: &mut FxHashMap<(Sym, usize), u64>) -> u64 {
        if let Some(&cost) = costs.get(key) {
            return cost;
        }
        let Some(def) = self.defs.get(key) else { return 1 };
        let cost = (def.methods.iter())
            .map(|m| self.method_cost(m, &mut |callee| self.cost_into(callee, costs)))
            .fold(0u64, u64::saturating_add);
        costs.insert(key.clone(), cost);
        cost
    }

    /// A method's cost: one step for `itself`, each called verb at its own cost.
    fn method_cost(&self, method: &Method, callee: &mut dyn FnMut(&(Sym, usize)) -> u64) -> u64 {
        (method.steps.iter())
            .map(|step| match step {
                Step::Itself => 1,
                Step::Do(t) => t.name().map_or(1, |n| callee(&(n.clone(), t.arity()))),
            })
            .fold(0u64, u64::saturating_add)
    }

    /// Refuses a library in which a phrase names two verbs: the error names the verb at fault,
    /// the phrase and the verb that has it. `first` (the verb being stored) is looked at before
    /// the others, so that a clash it makes is reported on it.
    pub fn check_words(&self, first: &str) -> Result<(), (String, Invalid)> {
        let mut order: Vec<&ActionDef> = self.defs.values().collect();
        order.sort_by_key(|d| (&*d.name != first, d.name.clone()));
        for def in &order {
            for (i, word) in def.words.iter().enumerate() {
                // Forms of one word clash only for the verb being written: a library stored
                // before the rule still loads (its exact clashes never did).
                let clash = (order.iter()).filter(|o| o.name != def.name).find_map(|o| {
                    let written = !first.is_empty() && (*def.name == *first || *o.name == *first);
                    let clashes = |w: &&String| *w == word || written && collide(w, word);
                    o.words.iter().find(clashes).map(|w| (o, w))
                });
                if let Some((other, theirs)) = clash {
                    let message = match theirs == word {
                        true => format!("`{word}` already names the verb `{}`", other.name),
                        false => format!(
                            "`{word}` and `{theirs}` are forms of one word, and `{theirs}` names the verb `{}`",
                            other.name
                        ),
                    };
                    return Err((def.name.to_string(), Invalid::new(format!("/words/{i}"), message)));
                }
            }
        }
        Ok(())
    }

    /// Refuses a library in which some verb expands past [`MAX_EXPANSION`] steps: the error names
    /// the verb and the costliest of its methods. `first` (the verb being stored) is looked at
    /// before the verbs that call it, which then cost more still.
    pub fn check_expansion(&self, first: &str) -> Result<(), (String, Invalid)> {
        let costs = self.costs();
        let known = |key: &(Sym, usize)| costs.get(key).copied().unwrap_or(1);
        let mut verbs = self.verbs();
        verbs.sort_by_key(|d| &*d.name != first);
        for def in verbs {
            let cost = known(&(def.name.clone(), def.params.len()));
            if cost > MAX_EXPANSION {
                let (worst, worst_cost) = (def.methods.iter().enumerate())
                    .map(|(i, m)| (i, self.method_cost(m, &mut |k| known(k))))
                    .fold((0, 0), |best, (i, c)| if c > best.1 { (i, c) } else { best });
                return Err((
                    def.name.to_string(),
                    Invalid::new(
                        format!("/methods/{worst}"),
                        format!(
                            "a reading of `{}` would expand to {cost} steps (this method {worst_cost}); at most {MAX_EXPANSION} are allowed",
                            def.name
                        ),
                    ),
                ));
            }
        }
        Ok(())
    }

    pub fn get(&self, name: &str, arity: usize) -> Option<&ActionDef> {
        self.defs.get(&(Sym::from(name), arity))
    }

    /// The verb definition for an action term, if the library knows that name at that arity.
    pub fn lookup(&self, action: &Term) -> Option<&ActionDef> {
        self.defs.get(&(action.name()?.clone(), action.arity()))
    }

    /// The name and arity of every fact some method makes true, each once, in no order; and
    /// whether some effect is a bare variable (which could be any fact).
    pub fn effects(&self) -> (&[(Sym, usize)], bool) {
        let (made, any) = self.effects.get_or_init(|| {
            let mut made: Vec<(Sym, usize)> = Vec::new();
            let mut any = false;
            for fact in self.defs.values().flat_map(|def| &def.methods).flat_map(|m| &m.adds) {
                match fact.name() {
                    Some(name) if !fact.is_var() => {
                        if !made.iter().any(|(n, a)| n == name && *a == fact.arity()) {
                            made.push((name.clone(), fact.arity()));
                        }
                    }
                    _ => any = true,
                }
            }
            (made, any)
        });
        (made, *any)
    }

    /// Every verb, by name then arity.
    pub fn verbs(&self) -> Vec<&ActionDef> {
        let mut all: Vec<&ActionDef> = self.defs.values().collect();
        all.sort_by(|a, b| a.name.cmp(&b.name).then(a.params.len().cmp(&b.params.len())));
        all
    }
}
