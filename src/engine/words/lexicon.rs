//! The words a request's scene and the action library make known: nouns (each object's type
//! spoken), adjectives (properties and attribute values spoken) and the phrases that name verbs,
//! with the inflections a verb's first word may take.
//!
//! Owns: what a word may mean here, nothing about sentence shape. Must not: know a word the
//! scene and the verbs do not give it: an unknown word is reported, never mapped to a near one.

use std::collections::HashMap;

use crate::engine::action::Library;
use crate::engine::resolve::Sense;
use crate::engine::scene::{Scene, spoken};

/// One phrase that names a verb: its words, the verb, and the verb's arity.
#[derive(Clone, Debug)]
pub struct VerbPhrase {
    pub words: Vec<String>,
    pub verb: String,
    pub arity: usize,
    /// The words understood between the verb's two arguments.
    pub joiners: Vec<String>,
}

/// What a noun names: the types spoken so (`cash box` → `cash_box`), and the objects that
/// have it as one of their `names`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Noun {
    pub kinds: Vec<String>,
    pub named: Vec<String>,
}

/// The known words of one request: built from the scene and the library in the request.
#[derive(Debug, Default)]
pub struct Lexicon {
    /// A spoken type or an object's name, as words, and what it names.
    nouns: HashMap<Vec<String>, Noun>,
    /// A spoken property or attribute value, as words, and what it may mean.
    adjectives: HashMap<Vec<String>, Vec<Sense>>,
    /// Longest phrase of either, in words.
    longest: usize,
    pub verbs: Vec<VerbPhrase>,
}

fn words_of(text: &str) -> Vec<String> {
    text.split_whitespace().map(str::to_lowercase).collect()
}

impl Lexicon {
    pub fn new(scene: &Scene, library: &Library) -> Lexicon {
        let mut lexicon = Lexicon::default();
        for object in &scene.objects {
            lexicon.add_noun(words_of(&spoken(&object.kind)), Some(&object.kind), None);
            for name in &object.names {
                lexicon.add_noun(words_of(name), None, Some(&object.id));
            }
            for property in &object.properties {
                lexicon.add_adjective(words_of(&spoken(property)), Sense::Property(property.clone()));
            }
            for (key, value) in &object.attributes {
                let sense = Sense::Attribute {
                    key: key.clone(),
                    value: value.clone(),
                };
                lexicon.add_adjective(words_of(&spoken(value)), sense);
            }
        }
        for def in library.verbs() {
            for phrase in &def.words {
                lexicon.verbs.push(VerbPhrase {
                    words: words_of(phrase),
                    verb: def.name.to_string(),
                    arity: def.params.len(),
                    joiners: def.joiners.clone(),
                });
            }
        }
        // Longer phrases first, so that "pick up" is tried before a verb named "pick".
        lexicon
            .verbs
            .sort_by(|a, b| b.words.len().cmp(&a.words.len()).then(a.words.cmp(&b.words)));
        lexicon
    }

    fn add_noun(&mut self, words: Vec<String>, kind: Option<&str>, named: Option<&str>) {
        self.longest = self.longest.max(words.len());
        let noun = self.nouns.entry(words).or_default();
        for (list, item) in [(&mut noun.kinds, kind), (&mut noun.named, named)] {
            if let Some(item) = item
                && !list.iter().any(|k| k == item)
            {
                list.push(item.to_owned());
                list.sort();
            }
        }
    }

    fn add_adjective(&mut self, words: Vec<String>, sense: Sense) {
        self.longest = self.longest.max(words.len());
        let senses = self.adjectives.entry(words).or_default();
        if !senses.contains(&sense) {
            senses.push(sense);
            senses.sort();
        }
    }

    /// What `words` names, if it is a noun here.
    pub fn noun(&self, words: &[String]) -> Option<&Noun> {
        self.nouns.get(words)
    }

    /// What `words` may mean as an adjective, if it is one here.
    pub fn adjective(&self, words: &[String]) -> Option<&[Sense]> {
        self.adjectives.get(words).map(Vec::as_slice)
    }

    /// The longest noun or adjective phrase, in words.
    pub fn longest(&self) -> usize {
        self.longest.max(1)
    }
}

/// Whether `token` is `word` or one of its inflected forms: "gets", "got", "getting",
/// "grabbed", "places", "placing", "carries". Only regular endings and the irregular pasts of
/// the common verbs; a form that is none of these is not the word.
pub fn inflects(token: &str, word: &str) -> bool {
    if token == word {
        return true;
    }
    let Some(rest) = token.strip_prefix(word) else {
        return irregular(token, word) || stem_changes(token, word);
    };
    match rest {
        "s" | "es" | "ed" | "ing" => true,
        // grab → grabbed, grabbing; get → getting: the last consonant doubled.
        _ => {
            let last = word.chars().last();
            let doubled = last.map(|c| {
                let c = c.to_string();
                [format!("{c}ed"), format!("{c}ing")].contains(&rest.to_owned())
            });
            doubled.unwrap_or(false) || stem_changes(token, word)
        }
    }
}

/// place → placed, placing; carry → carries, carried.
fn stem_changes(token: &str, word: &str) -> bool {
    if let Some(stem) = word.strip_suffix('e') {
        return token == format!("{stem}ed") || token == format!("{stem}ing") || token == format!("{word}d");
    }
    if let Some(stem) = word.strip_suffix('y') {
        return token == format!("{stem}ies") || token == format!("{stem}ied");
    }
    false
}

fn irregular(token: &str, word: &str) -> bool {
    const PASTS: &[(&str, &[&str])] = &[
        ("get", &["got", "gotten"]),
        ("take", &["took", "taken"]),
        ("bring", &["brought"]),
        ("break", &["broke", "broken"]),
        ("steal", &["stole", "stolen"]),
        ("give", &["gave", "given"]),
        ("hold", &["held"]),
        ("throw", &["threw", "thrown"]),
        ("find", &["found"]),
        ("leave", &["left"]),
        ("put", &["put"]),
        ("set", &["set"]),
    ];
    PASTS.iter().any(|(w, forms)| *w == word && forms.contains(&token))
}
