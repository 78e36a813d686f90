//! The words a request's scene and the action library make known: nouns (each object's type
//! spoken, and its names), adjectives (properties and attribute values spoken) and the phrases
//! that name verbs, with the inflections a verb's first word may take.
//!
//! Owns: what a word may mean here, nothing about sentence shape. Must not: know a word the
//! scene and the verbs do not give it: an unknown word is reported, never mapped to a near one.
//! Looks words up in the scene as asked, rather than indexing every object first: a sentence
//! asks about a handful of phrases, a scene may hold thousands of objects.

use std::borrow::Cow;
use std::cell::OnceCell;

use crate::engine::action::{Library, VerbPhrase};
use crate::engine::resolve::Sense;
use crate::engine::scene::{Scene, spoken_into, spoken_is};

/// What a noun names: the types spoken so (`cash box` → `cash_box`), and the objects that
/// have it as one of their `names`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Noun {
    pub kinds: Vec<String>,
    pub named: Vec<String>,
}

/// The known words of one request: the scene's and the library's.
pub struct Lexicon<'a> {
    scene: &'a Scene,
    pub verbs: &'a [VerbPhrase],
    /// Longest noun or adjective phrase, in words: counted from the scene's names the first
    /// time a phrase of more than one word is in question, which most sentences never ask.
    longest: OnceCell<usize>,
}

/// How many words `name` is spoken as: `cash_box` is two, `pointTo` two.
fn spoken_words(name: &str) -> usize {
    let mut buffer = String::new();
    spoken_into(name, &mut buffer);
    buffer.split(' ').count()
}

impl<'a> Lexicon<'a> {
    pub fn new(scene: &'a Scene, library: &'a Library) -> Lexicon<'a> {
        Lexicon {
            scene,
            verbs: library.phrases(),
            longest: OnceCell::new(),
        }
    }

    /// The most words, of `n` at hand, one noun or adjective phrase may take: `n` itself when
    /// it is one or none, without looking at the scene.
    pub fn longest_within(&self, n: usize) -> usize {
        if n <= 1 {
            return n;
        }
        n.min(*self.longest.get_or_init(|| longest_phrase(self.scene)))
    }

    /// What `words` names, if it is a noun here.
    pub fn noun(&self, words: &[String]) -> Option<Noun> {
        let wanted = phrase(words);
        let mut buffer = String::new();
        let mut noun = Noun::default();
        for o in &self.scene.objects {
            if spoken_is(&o.kind, &wanted, &mut buffer) && !noun.kinds.contains(&o.kind) {
                noun.kinds.push(o.kind.clone());
            }
            if o.names.iter().any(|n| *n == wanted) && !noun.named.iter().any(|n| o.id == n.as_str()) {
                noun.named.push(o.id.to_string());
            }
        }
        noun.kinds.sort();
        noun.named.sort();
        (noun != Noun::default()).then_some(noun)
    }

    /// What `words` may mean as an adjective, if it is one here.
    pub fn adjective(&self, words: &[String]) -> Option<Vec<Sense>> {
        let wanted = phrase(words);
        let mut buffer = String::new();
        let mut senses: Vec<Sense> = Vec::new();
        let mut add = |sense: Sense| {
            if !senses.contains(&sense) {
                senses.push(sense);
            }
        };
        for o in &self.scene.objects {
            for property in &o.properties {
                if spoken_is(property, &wanted, &mut buffer) {
                    add(Sense::Property(property.clone()));
                }
            }
            for (key, value) in &o.attributes {
                if spoken_is(value, &wanted, &mut buffer) {
                    add(Sense::Attribute {
                        key: key.clone(),
                        value: value.clone(),
                    });
                }
            }
        }
        senses.sort();
        (!senses.is_empty()).then_some(senses)
    }
}

/// The longest noun or adjective phrase `scene`'s names make, in words (at least one).
fn longest_phrase(scene: &Scene) -> usize {
    let mut longest = 1;
    for o in &scene.objects {
        // Most names are one word; only those that may have a separator are counted out.
        // One pass over the bytes: any non-ASCII byte may be part of an upper-case letter
        // (a word boundary), so such a name is counted out too.
        let separated = |n: &str| {
            n.bytes()
                .any(|b| b == b'_' || b == b' ' || b.is_ascii_uppercase() || !b.is_ascii())
        };
        for name in std::iter::once(&o.kind)
            .chain(&o.properties)
            .chain(o.attributes.values())
            .chain(&o.names)
        {
            if separated(name) {
                longest = longest.max(spoken_words(name));
            }
        }
    }
    longest
}

/// `words` as one phrase: a lone word as it is, several joined by spaces.
fn phrase(words: &[String]) -> Cow<'_, str> {
    match words {
        [one] => Cow::Borrowed(one),
        _ => Cow::Owned(words.join(" ")),
    }
}

/// Whether `token` is `word` or one of its inflected forms: "gets", "got", "getting",
/// "grabbed", "places", "placing", "carries". Only regular endings and the irregular pasts of
/// the common verbs; a form that is none of these is not the word. Allocates nothing: it is
/// asked for every verb phrase a sentence might start with.
pub fn inflects(token: &str, word: &str) -> bool {
    if token == word {
        return true;
    }
    // Every form below, the irregular ones included, starts with the word's first letter.
    if token.as_bytes().first() != word.as_bytes().first() {
        return false;
    }
    if let Some(rest) = token.strip_prefix(word) {
        if matches!(rest, "s" | "es" | "ed" | "ing") {
            return true;
        }
        // grab → grabbed, grabbing; get → getting: the last consonant doubled.
        if let Some(last) = word.chars().last()
            && let Some(after) = rest.strip_prefix(last)
            && matches!(after, "ed" | "ing")
        {
            return true;
        }
        // place → placed.
        if rest == "d" && word.ends_with('e') {
            return true;
        }
    }
    // place → placing; carry → carries, carried.
    if let Some(stem) = word.strip_suffix('e')
        && token.strip_prefix(stem) == Some("ing")
    {
        return true;
    }
    if let Some(stem) = word.strip_suffix('y')
        && matches!(token.strip_prefix(stem), Some("ies" | "ied"))
    {
        return true;
    }
    irregular(token, word)
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
