//! The contract's default library, as a curator would write it: the verbs a fresh store is
//! seeded with (the migrations write the same definitions) and the library of the offline tools.
//!
//! Owns: those definitions. Must not: hold anything the store could not (they pass the same
//! checks as a curator's verb).

use super::{ActionInput, Library};

/// Every default verb, written as `PUT /v1/actions/{name}` takes it. `get` is the paper's;
/// `pointTo`, `destroy`, `steal` and `put` came with the first contract; the rest with people
/// (2026-12-06). A word names one verb: "hand" and "bring" are `give`'s, not `get`'s.
pub const DEFAULT_VERBS: &str = r#"[
{"name":"get","parameters":["X"],"methods":[{"steps":["itself"],"reach":["X"],"grasp":["X"],"adds":["holding(self,X)"]}],
 "words":["get","grab","take","pick up","fetch"]},
{"name":"pointTo","parameters":["X"],"methods":[{"steps":["itself"]}],"words":["point to","point at"]},
{"name":"destroy","parameters":["X"],"methods":[{"steps":["itself"],"reach":["X"],"adds":["destroyed(X)"]}],
 "words":["destroy","break","smash","wreck"]},
{"name":"steal","parameters":["X"],"methods":[{"steps":["itself"],"reach":["X"],"grasp":["X"],"adds":["holding(self,X)"]}],
 "words":["steal"]},
{"name":"put","parameters":["X","Y"],"joiner":"on","distinct":true,
 "methods":[{"steps":["get(X)","itself"],"reach":["X","Y"],"place":["X","Y"],"adds":["on(X,Y)"],"removes":["holding(self,X)"]}],
 "words":["put","place","set","position"],"joiners":["on","onto","in","into","upon","inside"]},
{"name":"give","parameters":["X","P"],"joiner":"to","distinct":true,
 "methods":[{"steps":["get(X)","itself"],"reach":["P"],"preconditions":["person(P)"],"adds":["holding(P,X)"],"removes":["holding(self,X)"]}],
 "words":["give","hand","pass","bring"],"joiners":["to"]},
{"name":"heat","parameters":["X","Y"],"joiner":"with","distinct":true,"implied":{"Y":["heater(Y)"]},
 "methods":[{"steps":["get(X)","itself"],"reach":["Y"],"preconditions":["heater(Y)"],"adds":["hot(X)"],"removes":["holding(self,X)"]}],
 "words":["heat","heat up","warm","warm up"],"joiners":["in","on","with"]},
{"name":"open","parameters":["X"],"methods":[{"steps":["itself"],"reach":["X"],"preconditions":["closed(X)"],"adds":["open(X)"],"removes":["closed(X)"]}],
 "words":["open"]},
{"name":"close","parameters":["X"],"methods":[{"steps":["itself"],"reach":["X"],"preconditions":["open(X)"],"adds":["closed(X)"],"removes":["open(X)"]}],
 "words":["close","shut"]},
{"name":"discard","parameters":["X"],"methods":[{"steps":["get(X)","itself"],"adds":["discarded(X)"],"removes":["holding(self,X)"]}],
 "words":["throw away","throw out","discard","dispose of","get rid of"]},
{"name":"clean","parameters":["X"],"methods":[{"steps":["itself"],"reach":["X"],"adds":["clean(X)"],"removes":["dirty(X)"]}],
 "words":["wash","clean","rinse","wipe"]},
{"name":"pour","parameters":["X","Y"],"joiner":"into","distinct":true,
 "methods":[{"steps":["get(X)","itself"],"reach":["Y"],"adds":["in(X,Y)"]}],
 "words":["pour"],"joiners":["into","in"]},
{"name":"cut","parameters":["X","Y"],"joiner":"with","distinct":true,"implied":{"Y":["knife(Y)"]},
 "methods":[{"steps":["get(Y)","itself"],"reach":["X"],"preconditions":["knife(Y)"],"adds":["cut(X)"]}],
 "words":["cut","chop","slice","dice"],"joiners":["with"]},
{"name":"switchOn","parameters":["X"],"methods":[{"steps":["itself"],"reach":["X"],"adds":["powered(X)"]}],
 "words":["turn on","switch on"]},
{"name":"switchOff","parameters":["X"],"methods":[{"steps":["itself"],"reach":["X"],"removes":["powered(X)"]}],
 "words":["turn off","switch off"]}
]"#;

impl Library {
    /// The contract's default library: [`DEFAULT_VERBS`], each checked as a curator's verb is.
    pub fn default_library() -> Library {
        let verbs: Vec<ActionInput> =
            serde_json::from_str(DEFAULT_VERBS).expect("the default verbs are written as the API takes them");
        let mut library = Library::default();
        for verb in verbs {
            let name = verb.name.clone().expect("each default verb is named");
            let def = verb.validate(&name).expect("the default verbs are valid");
            def.check_written_words()
                .expect("the default verbs' words are free of the grammar's");
            library.insert(def).expect("the default library has no cycles");
        }
        library.check_words("").expect("a word names one default verb");
        library
    }
}
