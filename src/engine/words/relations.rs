//! A reference with relations to others ("the cup on the table next to the fork"), a
//! superlative ("the biggest box") or an ordinal with its direction ("the second cup from the
//! left"), as the contract's "References by relation, order and number" reads them.
//!
//! ```text
//! related := node (relation node)*            at most MAX_RELATIONS relations
//! node    := determiner? (superlative | ordinal)? adjective* (noun | "one") direction?
//! direction := "from the" ("left" | "right" | "front" | "back")
//! ```
//!
//! Owns: the closed lists of relation, superlative, ordinal and direction words, and where a
//! relation attaches. Must not: pick one attachment where the words allow several (the objects
//! are those of any), or read a word it does not know as anything but unknown.

use super::Phrase;
use super::lexicon::Lexicon;
use super::number::{described_plural, quantifier};
use super::reference::{described, unplaced};
use super::vocabulary::{DETERMINERS, PLURAL_DETERMINERS, PRONOUNS};
use crate::engine::resolve::{Number, Reference};
use crate::engine::scene::relate::{Direction, Relation, Superlative};

/// The most relations one reference chains: four give at most 14 attachments.
const MAX_RELATIONS: usize = 4;

/// The words of each relation, as the contract lists them; the longest that fits is taken.
const RELATION_WORDS: &[(&[&str], Relation)] = &[
    (&["on", "the", "left", "of"], Relation::LeftOf),
    (&["on", "the", "right", "of"], Relation::RightOf),
    (&["to", "the", "left", "of"], Relation::LeftOf),
    (&["to", "the", "right", "of"], Relation::RightOf),
    (&["on", "top", "of"], Relation::On),
    (&["in", "front", "of"], Relation::InFrontOf),
    (&["in", "back", "of"], Relation::Behind),
    (&["inside", "of"], Relation::In),
    (&["left", "of"], Relation::LeftOf),
    (&["right", "of"], Relation::RightOf),
    (&["next", "to"], Relation::Near),
    (&["close", "to"], Relation::Near),
    (&["near", "to"], Relation::Near),
    (&["on"], Relation::On),
    (&["atop"], Relation::On),
    (&["upon"], Relation::On),
    (&["in"], Relation::In),
    (&["inside"], Relation::In),
    (&["within"], Relation::In),
    (&["under"], Relation::Under),
    (&["underneath"], Relation::Under),
    (&["beneath"], Relation::Under),
    (&["below"], Relation::Under),
    (&["near"], Relation::Near),
    (&["beside"], Relation::Near),
    (&["by"], Relation::Near),
    (&["behind"], Relation::Behind),
    (&["from"], Relation::From),
];

const SUPERLATIVES: &[(&str, Superlative)] = &[
    ("biggest", Superlative::Volume { most: true }),
    ("largest", Superlative::Volume { most: true }),
    ("smallest", Superlative::Volume { most: false }),
    ("tallest", Superlative::Height { most: true }),
    ("shortest", Superlative::Height { most: false }),
    ("heaviest", Superlative::Mass { most: true }),
    ("lightest", Superlative::Mass { most: false }),
    ("nearest", Superlative::Distance { most: false }),
    ("closest", Superlative::Distance { most: false }),
    ("farthest", Superlative::Distance { most: true }),
    ("furthest", Superlative::Distance { most: true }),
    ("leftmost", Superlative::Left { most: true }),
    ("rightmost", Superlative::Left { most: false }),
    ("highest", Superlative::Elevation { most: true }),
    ("lowest", Superlative::Elevation { most: false }),
    // A position, as the robot's own descriptions say it: "the left cup" is the leftmost.
    ("left", Superlative::Left { most: true }),
    ("right", Superlative::Left { most: false }),
];

const ORDINALS: &[&str] = &[
    "first", "second", "third", "fourth", "fifth", "sixth", "seventh", "eighth", "ninth", "tenth",
];

const DIRECTIONS: &[(&str, Direction)] = &[
    ("left", Direction::Left),
    ("right", Direction::Right),
    ("front", Direction::Front),
    ("back", Direction::Back),
];

/// The relation whose words start at `at`, and how many words they take.
pub(super) fn relation_at(words: &[String], at: usize) -> Option<(Relation, usize)> {
    RELATION_WORDS
        .iter()
        .find(|(said, _)| super::grammar::is(words, at, said))
        .map(|(said, relation)| (*relation, said.len()))
}

/// "from the left" at `at`: the direction an ordinal counts from.
fn direction_at(words: &[String], at: usize) -> Option<Direction> {
    if !super::grammar::is(words, at, &["from", "the"]) {
        return None;
    }
    let word = words.get(at + 2)?;
    DIRECTIONS.iter().find(|(w, _)| w == word).map(|(_, d)| *d)
}

/// The ordinal a word says, from 1: "second", "2nd".
fn ordinal(word: &str) -> Option<usize> {
    if let Some(n) = ORDINALS.iter().position(|w| *w == word) {
        return Some(n + 1);
    }
    let digits = word
        .strip_suffix("st")
        .or_else(|| word.strip_suffix("nd"))
        .or_else(|| word.strip_suffix("rd"))
        .or_else(|| word.strip_suffix("th"))?;
    digits.parse::<usize>().ok().filter(|n| (1..=1000).contains(n))
}

/// One noun phrase of the chain: where its words are in the span, and what was said of its
/// direction.
struct Node {
    start: usize,
    end: usize,
    direction: Option<(Direction, usize)>,
}

/// The reference `span` says, when it has a relation, a superlative or an ordinal the
/// contract reads; `None` when it has none of them (the caller reads it as a plain reference).
pub(super) fn related(span: &[String], lexicon: &Lexicon) -> Option<Phrase> {
    if span.is_empty() {
        return None;
    }
    let words = span.join(" ");
    let nothing = |unplaced: Option<String>| {
        Some(Phrase {
            reference: Reference::Nothing {
                words: words.clone(),
                unplaced,
            },
            words: words.clone(),
        })
    };
    let mut nodes = vec![Node {
        start: 0,
        end: span.len(),
        direction: None,
    }];
    let mut relations: Vec<Relation> = Vec::new();
    let mut i = 1;
    while i < span.len() {
        let last = nodes.last_mut().expect("one node at least");
        if let Some(direction) = direction_at(span, i) {
            if last.direction.is_some() || i == last.start {
                return nothing(Some(span[i..].join(" ")));
            }
            last.end = i;
            last.direction = Some((direction, i + 3));
            i += 3;
            continue;
        }
        // "the table on floor": a feature of the scene's said after the noun, opening with a
        // relation's word, is the feature (as the robot's own descriptions say it).
        if i > last.start
            && let Some((_, n)) = lexicon.adjective_at(&span[i..]).filter(|(_, n)| *n > 1)
            && relation_at(span, i).is_some()
        {
            i += n;
            continue;
        }
        if i > last.start
            && let Some((relation, n)) = relation_at(span, i)
        {
            if last.direction.is_none() {
                last.end = i;
            }
            if i + n >= span.len() {
                return nothing(Some(span[i..].join(" ")));
            }
            relations.push(relation);
            nodes.push(Node {
                start: i + n,
                end: span.len(),
                direction: None,
            });
            i += n;
            continue;
        }
        if last.direction.is_some() {
            // Words after "from the left" that are not another relation.
            return nothing(Some(span[i..].join(" ")));
        }
        i += 1;
    }
    let head_word = |node: &Node| {
        let first = node.start + usize::from(DETERMINERS.contains(&span[node.start].as_str()));
        span.get(first).map(String::as_str)
    };
    let picked = nodes
        .iter()
        .any(|n| head_word(n).is_some_and(|w| ordinal(w).is_some() || SUPERLATIVES.iter().any(|(s, _)| *s == w)));
    if relations.len() > MAX_RELATIONS {
        return nothing(Some(words.clone()));
    }
    let mut heads: Vec<Head> = nodes.iter().map(|n| head(span, n, lexicon)).collect();
    // A count said, read or not ("40 cups" is one past what may be read).
    let counted = heads.iter().any(|h| h.number.is_some())
        || quantifier(&span[nodes[0].start..nodes[0].end]).is_some()
        || span[nodes[0].start].bytes().all(|b| b.is_ascii_digit());
    // "every one", "the ones": a plural of anything at all is not a reference to act on.
    if relations.is_empty()
        && heads[0].number.is_some()
        && heads[0].pick.is_none()
        && let Reference::Spoken {
            kinds,
            named,
            adjectives,
            ..
        } = &heads[0].reference
        && kinds.is_empty()
        && named.is_empty()
        && adjectives.is_empty()
    {
        return nothing(Some(words.clone()));
    }
    if relations.is_empty() && !picked && !counted && nodes[0].direction.is_none() {
        return None;
    }
    // A landmark is any object it matches: "the cup near the plates" is near any plate, but
    // "near both plates" or "near two plates" would ask more of each, which is not read.
    for (node, head) in nodes.iter().zip(&mut heads).skip(1) {
        if matches!(head.number, Some(Number::Exactly(_) | Number::Any(_))) {
            head.reference = Reference::Nothing {
                words: span[node.start..node.end].join(" "),
                unplaced: Some(span[node.start].clone()),
            };
        }
        head.number = None;
    }
    let mut readings = Vec::new();
    for parents in attachments(nodes.len()) {
        readings.push(tree(0, &parents, &nodes, &relations, &heads, span));
    }
    let reference = match readings.len() {
        1 => readings.pop().expect("one reading"),
        _ => Reference::Union {
            readings,
            words: words.clone(),
        },
    };
    Some(Phrase { reference, words })
}

/// A node's own words read: the reference of its determiner, adjectives and noun, and the
/// superlative or ordinal that picks among what the whole node matches.
struct Head {
    reference: Reference,
    pick: Option<Pick>,
    /// How many the node means, when it is plural.
    number: Option<Number>,
}

enum Pick {
    Most(Superlative, String),
    Nth(usize, Direction),
}

fn head(span: &[String], node: &Node, lexicon: &Lexicon) -> Head {
    let said = &span[node.start..node.end];
    let words = said.join(" ");
    let nothing = |unplaced: Option<String>| Head {
        reference: Reference::Nothing {
            words: words.clone(),
            unplaced,
        },
        pick: None,
        number: None,
    };
    // "next to it": a pronoun landmark, bound as any pronoun is.
    if said.len() == 1 && PRONOUNS.contains(&said[0].as_str()) && node.direction.is_none() {
        return Head {
            reference: Reference::Pronoun { words },
            pick: None,
            number: None,
        };
    }
    let determiner = usize::from(DETERMINERS.contains(&said[0].as_str()));
    let (mut number, mut body, plural) = match quantifier(said) {
        Some((number, n, plural)) => (Some(number), &said[n..], plural),
        None => (None, &said[determiner..], false),
    };
    // The quantifier as said ("the two", "both of the"), to say back where it is not read.
    let quantified = said[..said.len() - body.len()].join(" ");
    let mut pick = None;
    if let Some(first) = body.first() {
        if let Some((word, superlative)) = SUPERLATIVES.iter().find(|(w, _)| w == first) {
            pick = Some(Pick::Most(*superlative, (*word).to_owned()));
            body = &body[1..];
        } else if let Some(n) = ordinal(first) {
            let Some((direction, _)) = node.direction else {
                // "the second cup": the direction is not guessed.
                return nothing(Some(first.clone()));
            };
            pick = Some(Pick::Nth(n, direction));
            body = &body[1..];
        }
    }
    if let Some((_, end)) = node.direction
        && !matches!(pick, Some(Pick::Nth(..)))
    {
        return nothing(Some(span[node.end..end].join(" ")));
    }
    // "the two biggest boxes", "the first two cups": a count with a pick is not read.
    if matches!(number, Some(Number::Exactly(_) | Number::Any(_))) && pick.is_some() {
        return nothing(Some(quantified));
    }
    let indefinite = number.is_none() && determiner == 1 && ["a", "an", "any"].contains(&said[0].as_str());
    // A noun in the plural is every match, after a determiner that may say so ("the cups").
    let plural_said = number.is_none() && (determiner == 0 || PLURAL_DETERMINERS.contains(&said[0].as_str()));
    let any_one = |words: &String| Reference::Spoken {
        kinds: Vec::new(),
        named: Vec::new(),
        adjectives: Vec::new(),
        words: words.clone(),
        indefinite,
    };
    if body == ["ones"] && (plural || plural_said) {
        // "the ones on the table"
        number = number.or(Some(Number::Every));
        return Head {
            reference: any_one(&words),
            pick,
            number,
        };
    }
    let mut found = match plural {
        true => described_plural(body, lexicon),
        false => described(body, lexicon).or_else(|| {
            let found = plural_said.then(|| described_plural(body, lexicon)).flatten()?;
            number = Some(Number::Every);
            Some(found)
        }),
    };
    // "the 2 box": a number that is an attribute's value, where no count agrees with the noun.
    if found.is_none()
        && number.is_some()
        && pick.is_none()
        && let Some(plain) = described(&said[determiner..], lexicon)
    {
        (number, found, body) = (None, Some(plain), &said[determiner..]);
    }
    let reference = if body == ["one"] && !plural {
        // "the one on the table": any object the rest says.
        any_one(&words)
    } else {
        match found {
            Some((noun, adjectives)) => Reference::Spoken {
                kinds: noun.kinds,
                named: noun.named,
                adjectives,
                words: words.clone(),
                indefinite,
            },
            None if body.is_empty() => return nothing(None),
            // "both cup", "every cups": the number said back, as what did not agree.
            None if number.is_some() && described(body, lexicon).or(described_plural(body, lexicon)).is_some() => {
                return nothing(Some(quantified));
            }
            // "40 cups": a count past what a plural may act on at once is not read.
            None if body[0].bytes().all(|b| b.is_ascii_digit()) => return nothing(Some(body[0].clone())),
            None => return nothing(unplaced(body, lexicon)),
        }
    };
    Head {
        reference,
        pick,
        number,
    }
}

/// Every way the relations may attach: `parents[i]` is the node the i-th node hangs from (by
/// the relation before it). A relation attaches to the noun just before it or to one that
/// noun hangs from, so no two attachments cross.
fn attachments(nodes: usize) -> Vec<Vec<usize>> {
    let mut out = Vec::new();
    let mut parents = vec![0usize; nodes];
    grow(1, &mut parents, &mut out);
    out
}

fn grow(next: usize, parents: &mut Vec<usize>, out: &mut Vec<Vec<usize>>) {
    if next >= parents.len() {
        out.push(parents.clone());
        return;
    }
    // The nearest first: node next-1, then each node it hangs from, up to the head.
    let mut at = next - 1;
    loop {
        parents[next] = at;
        grow(next + 1, parents, out);
        if at == 0 {
            break;
        }
        at = parents[at];
    }
}

/// The reference node `j` makes with what hangs from it; its words are those from its first
/// to its last descendant's.
fn tree(
    j: usize,
    parents: &[usize],
    nodes: &[Node],
    relations: &[Relation],
    heads: &[Head],
    span: &[String],
) -> Reference {
    let children: Vec<usize> = (j + 1..nodes.len()).filter(|&k| parents[k] == j).collect();
    let last = last_descendant(j, parents);
    let end = nodes[last].direction.map_or(nodes[last].end, |(_, end)| end);
    let words = span[nodes[j].start..end].join(" ");
    let mut reference = heads[j].reference.clone();
    for &child in &children {
        reference = Reference::Related {
            base: Box::new(reference),
            relation: relations[child - 1],
            to: Box::new(tree(child, parents, nodes, relations, heads, span)),
            words: words.clone(),
        };
    }
    let reference = match &heads[j].pick {
        None => reference,
        Some(Pick::Most(superlative, said)) => Reference::Most {
            base: Box::new(reference),
            superlative: *superlative,
            said: said.clone(),
            words: words.clone(),
        },
        Some(Pick::Nth(nth, from)) => Reference::Nth {
            base: Box::new(reference),
            nth: *nth,
            from: *from,
            words: words.clone(),
        },
    };
    // The number counts what the whole node selects: "both cups on the table" are the cups on
    // the table, and there must be two of those.
    match heads[j].number {
        Some(number) => Reference::Plural {
            base: Box::new(reference),
            number,
            words,
        },
        None => reference,
    }
}

fn last_descendant(j: usize, parents: &[usize]) -> usize {
    // Descendants of j are contiguous after it.
    let mut last = j;
    for k in j + 1..parents.len() {
        let mut a = parents[k];
        let mut under = a == j;
        while !under && a > j {
            a = parents[a];
            under = a == j;
        }
        if under {
            last = k;
        } else {
            break;
        }
    }
    last
}
