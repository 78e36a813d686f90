//! The words a request's scene and the action library make known: nouns (each object's type
//! spoken, and its names), adjectives (properties and attribute values spoken) and the phrases
//! that name verbs, with the inflections a verb's first word may take.
//!
//! Owns: what a word may mean here, nothing about sentence shape. Must not: know a word the
//! scene and the verbs do not give it: an unknown word is reported, never mapped to a near one.
//! Bounded: the scene's phrases are indexed once, the first time more than one word is asked
//! about, so that a sentence of any length costs one pass over the scene and a lookup per word;
//! a reference of one word ("the vase"), the usual case, is looked up by one pass and no index.

use std::borrow::Cow;
use std::cell::OnceCell;

use rustc_hash::FxHashMap;

use crate::engine::action::{Library, VerbPhrase};
use crate::engine::resolve::Sense;
use crate::engine::scene::{Object, Scene, spoken_into, spoken_is};

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
    /// The speaker's id: what "me" names, whether or not the scene holds them.
    pub speaker: &'a str,
    pub verbs: &'a [VerbPhrase],
    /// Every phrase of the scene, made the first time a lookup needs more than one pass.
    index: OnceCell<Index<'a>>,
    /// Asked between objects while the index is made: past the deadline the index is left
    /// incomplete, and the grammar, which asks it too, reports the deadline rather than what an
    /// incomplete index would have it read.
    expired: &'a dyn Fn() -> bool,
}

/// What one phrase names in the scene, and whether a longer phrase starts with it.
#[derive(Default)]
struct Entry<'a> {
    kinds: Vec<&'a str>,
    /// Ids of the objects with this phrase among their names.
    named: Vec<&'a str>,
    senses: Vec<SenseOf<'a>>,
    /// Some phrase of more words starts with this one: a search for the longest phrase at a
    /// word goes on past it.
    continues: bool,
}

#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum SenseOf<'a> {
    Property(&'a str),
    Attribute(&'a str, &'a str),
}

impl SenseOf<'_> {
    fn owned(self) -> Sense {
        match self {
            SenseOf::Property(p) => Sense::Property(p.to_owned()),
            SenseOf::Attribute(key, value) => Sense::Attribute {
                key: key.to_owned(),
                value: value.to_owned(),
            },
        }
    }
}

/// The scene's phrases as spoken (lower case, words separated by one space).
struct Index<'a> {
    phrases: FxHashMap<Cow<'a, str>, Entry<'a>>,
    /// The most words a phrase has (at least one).
    longest: usize,
}

impl<'a> Index<'a> {
    fn new(scene: &'a Scene, expired: &dyn Fn() -> bool) -> Index<'a> {
        let mut index = Index {
            phrases: FxHashMap::default(),
            longest: 1,
        };
        for (n, o) in scene.objects.iter().enumerate() {
            if n % 256 == 255 && expired() {
                break;
            }
            index.add(&o.kind).kinds.push(&o.kind);
            for name in &o.names {
                index.add(name).named.push(&o.id);
            }
            for property in &o.properties {
                index.add(property).senses.push(SenseOf::Property(property));
            }
            for (key, value) in &o.attributes {
                index.add(value).senses.push(SenseOf::Attribute(key, value));
            }
        }
        // Many objects share a type or a property: each is kept once, in byte order.
        for entry in index.phrases.values_mut() {
            entry.kinds.sort_unstable();
            entry.kinds.dedup();
            entry.named.sort_unstable();
            entry.senses.sort_unstable();
            entry.senses.dedup();
        }
        index
    }

    /// The entry of `name` as spoken, made with the entries of its proper prefixes.
    fn add(&mut self, name: &'a str) -> &mut Entry<'a> {
        let words: Cow<'a, str> = match spoken_as_written(name) {
            true => Cow::Borrowed(name),
            false => {
                let mut buffer = String::with_capacity(name.len() + 4);
                spoken_into(name, &mut buffer);
                Cow::Owned(buffer)
            }
        };
        let mut count = 1;
        for (at, _) in words.match_indices(' ') {
            count += 1;
            let prefix = Cow::Owned(words[..at].to_owned());
            self.phrases.entry(prefix).or_default().continues = true;
        }
        self.longest = self.longest.max(count);
        self.phrases.entry(words).or_default()
    }

    fn get(&self, phrase: &str) -> Option<&Entry<'a>> {
        self.phrases.get(phrase)
    }
}

/// Whether `name` is spoken exactly as written (one word, lower case): most are.
fn spoken_as_written(name: &str) -> bool {
    name.bytes().all(|b| b.is_ascii_lowercase() || b.is_ascii_digit())
}

impl<'a> Lexicon<'a> {
    pub fn new(scene: &'a Scene, library: &'a Library, expired: &'a dyn Fn() -> bool) -> Lexicon<'a> {
        Lexicon {
            scene,
            speaker: crate::engine::scene::DEFAULT_SPEAKER,
            verbs: library.phrases(),
            index: OnceCell::new(),
            expired,
        }
    }

    /// The lexicon, with "me" naming `speaker`.
    pub fn spoken_by(mut self, speaker: &'a str) -> Lexicon<'a> {
        self.speaker = speaker;
        self
    }

    pub fn scene(&self) -> &'a Scene {
        self.scene
    }

    /// Whether the request's deadline has passed (or its client has gone).
    pub fn expired(&self) -> bool {
        (self.expired)()
    }

    fn index(&self) -> &Index<'a> {
        self.index.get_or_init(|| Index::new(self.scene, self.expired))
    }

    /// The head noun that ends `body`: the most words at its end that name a type or an
    /// object's name, and how many they are.
    pub fn head_noun(&self, body: &[String]) -> Option<(Noun, usize)> {
        if let [word] = body
            && self.index.get().is_none()
        {
            return self.scan_noun(word).map(|noun| (noun, 1));
        }
        let index = self.index();
        let mut phrase = String::new();
        for from in body.len().saturating_sub(index.longest)..body.len() {
            phrase.clear();
            for (n, word) in body[from..].iter().enumerate() {
                if n > 0 {
                    phrase.push(' ');
                }
                phrase.push_str(word);
            }
            if let Some(entry) = index.get(&phrase)
                && (!entry.kinds.is_empty() || !entry.named.is_empty())
            {
                let noun = Noun {
                    kinds: entry.kinds.iter().map(|k| (*k).to_owned()).collect(),
                    named: entry.named.iter().map(|n| (*n).to_owned()).collect(),
                };
                return Some((noun, body.len() - from));
            }
        }
        None
    }

    /// The longest adjective at the start of `words` (a property or an attribute value
    /// spoken), with every sense it may have, and how many words it takes.
    pub fn adjective_at(&self, words: &[String]) -> Option<(Vec<Sense>, usize)> {
        let index = self.index();
        let mut phrase = String::new();
        let mut best = None;
        for (n, word) in words.iter().enumerate() {
            if n > 0 {
                phrase.push(' ');
            }
            phrase.push_str(word);
            let Some(entry) = index.get(&phrase) else {
                break;
            };
            if !entry.senses.is_empty() {
                best = Some((n + 1, entry));
            }
            if !entry.continues {
                break;
            }
        }
        best.map(|(n, entry)| (entry.senses.iter().map(|s| s.owned()).collect(), n))
    }

    /// Whether `word` alone is a noun or an adjective here.
    pub fn knows(&self, word: &str) -> bool {
        self.index()
            .get(word)
            .is_some_and(|e| !e.kinds.is_empty() || !e.named.is_empty() || !e.senses.is_empty())
    }

    /// What one word names as a noun, found by one pass over the scene and no index.
    fn scan_noun(&self, word: &str) -> Option<Noun> {
        let mut buffer = String::new();
        let mut noun = Noun::default();
        let mut add = |o: &Object| {
            if spoken_is(&o.kind, word, &mut buffer) && !noun.kinds.contains(&o.kind) {
                noun.kinds.push(o.kind.clone());
            }
            if o.names.iter().any(|n| n == word) {
                noun.named.push(o.id.to_string());
            }
        };
        self.scene.objects.iter().for_each(&mut add);
        noun.kinds.sort();
        noun.named.sort();
        (noun != Noun::default()).then_some(noun)
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

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::Lexicon;
    use crate::engine::action::Library;
    use crate::engine::input::RequestLimits;
    use crate::engine::scene::{AgentInput, ObjectInput, Scene, SceneInput};

    fn scene(objects: Vec<(String, Vec<String>, Vec<String>)>) -> Scene {
        let input = SceneInput {
            agent: AgentInput {
                id: None,
                position: [0.0, 0.0, 0.0],
                reach: 1.0,
                gripper_aperture: None,
                payload: None,
                gripper_size: None,
                rotation: None,
            },
            objects: (objects.into_iter().enumerate())
                .map(|(i, (kind, properties, names))| ObjectInput {
                    id: format!("o{i}"),
                    kind,
                    properties,
                    attributes: Default::default(),
                    position: [0.0, 0.0, 0.0],
                    shape: None,
                    rotation: None,
                    mass: None,
                    names,
                })
                .collect(),
            facts: Vec::new(),
            people: Vec::new(),
        };
        Scene::from_input(input, &RequestLimits::default()).expect("a valid scene")
    }

    const NAMES: &[&str] = &["cup", "cash_box", "cashBox", "red", "dark_red", "tea_cup", "box"];

    proptest! {
        /// A one-word reference found by one pass over the scene names what the index says it
        /// names: the two lookups never disagree.
        #[test]
        fn one_pass_and_the_index_agree(
            objects in prop::collection::vec(
                (prop::sample::select(NAMES), prop::collection::vec(prop::sample::select(NAMES), 0..3),
                 prop::collection::vec(prop::sample::select(&["cup", "box", "tea cup", "drink"][..]), 0..2)),
                0..8),
            word in prop::sample::select(&["cup", "box", "red", "drink", "tea", "cashbox", "mug"][..]),
        ) {
            let objects = objects.into_iter()
                .map(|(k, ps, ns)| {
                    let mut names: Vec<String> = ns.into_iter().map(str::to_owned).collect();
                    names.dedup();
                    (k.to_owned(), ps.into_iter().map(str::to_owned).collect(), names)
                })
                .collect();
            let scene = scene(objects);
            let library = Library::default_library();
            let never = || false;
            let scanned = Lexicon::new(&scene, &library, &never).head_noun(&[word.to_owned()]);
            let lexicon = Lexicon::new(&scene, &library, &never);
            lexicon.index();
            prop_assert_eq!(scanned, lexicon.head_noun(&[word.to_owned()]));
        }
    }
}
