//! Number: references to several objects at once ("the cups", "both cups", "two cups"), the
//! groups of objects their slots offer, and the words for counts and plurals.
//!
//! Owns: which groups a plural reference's matches make, what is said when the scene has the
//! wrong count, and the plural and singular forms of nouns. Must not: keep some of the matches
//! where the words said all of them, or make more groups than any request may read.

use std::sync::LazyLock;

use super::ReferenceInput;
use crate::engine::input::Invalid;
use crate::engine::term::{Sym, Term};

/// How many of its matches a plural reference means.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Number {
    /// "the cups", "all cups", "every cup", "each cup": every match, one step each.
    Every,
    /// "both cups", "the two cups": every match, and there must be exactly this many.
    Exactly(usize),
    /// "two cups": any this many of the matches; each choice is a reading.
    Any(usize),
}

/// The most objects one plural reference may act on at once: a reading's plan has a step for
/// each, and a step names at most one plural.
pub const MAX_GROUP: usize = 32;

/// The number `count` and `all` give, checked; taken out of `input`.
pub(super) fn of_input(input: &mut ReferenceInput) -> Result<Option<Number>, Invalid> {
    let (count, all) = (input.count.take(), input.all.take());
    if input.id.is_some() && (count.is_some() || all == Some(true)) {
        let field = if count.is_some() { "/count" } else { "/all" };
        return Err(Invalid::new(
            field,
            "an `id` names one object; `count` and `all` go with a description",
        ));
    }
    let count = match count {
        None => None,
        Some(n) if (1..=MAX_GROUP as u64).contains(&n) => Some(n as usize),
        Some(n) => {
            return Err(Invalid::new(
                "/count",
                format!("`count` is 1 to {MAX_GROUP} objects at once, not {n}"),
            ));
        }
    };
    Ok(match (all == Some(true), count) {
        (true, Some(k)) => Some(Number::Exactly(k)),
        (true, None) => Some(Number::Every),
        (false, Some(k)) => Some(Number::Any(k)),
        (false, None) => None,
    })
}

impl Number {
    /// The words of a description said of several: "the red cup" as "the two red cups"; `rest`
    /// (its relations' words, " on the table") after.
    pub(super) fn words(self, plain: &str, rest: &str) -> String {
        let described = plain.strip_prefix("the ").unwrap_or(plain);
        match self {
            Number::Every => format!("the {}{rest}", plural(described)),
            Number::Exactly(k) => format!("the {} {}{rest}", count_word(k), plural(described)),
            Number::Any(1) => format!("one {described}{rest}"),
            Number::Any(k) => format!("{} {}{rest}", count_word(k), plural(described)),
        }
    }
}

/// The functor of a group's term (`&(c1,c2)`): a name no object or verb can have, so a group
/// is never read as either.
static GROUP: LazyLock<Sym> = LazyLock::new(|| {
    let group = Sym::new("&");
    group.make_lasting();
    group
});

/// The term a slot's reading binds for a group of objects, in scene order.
pub fn group(members: Vec<Term>) -> Term {
    Term::Compound(GROUP.clone(), members.into())
}

/// The objects of a group's term; `None` for any other term.
pub fn members(term: &Term) -> Option<&[Term]> {
    match term {
        Term::Compound(functor, members) if *functor == *GROUP => Some(&members[..]),
        _ => None,
    }
}

/// The objects a value stands for: a group's members, or the value itself.
pub fn objects_of(term: &Term) -> &[Term] {
    members(term).unwrap_or(std::slice::from_ref(term))
}

/// Nouns whose plural is not made by a rule, singular first.
const IRREGULAR: &[(&str, &str)] = &[
    ("child", "children"),
    ("person", "people"),
    ("man", "men"),
    ("woman", "women"),
    ("foot", "feet"),
    ("tooth", "teeth"),
    ("mouse", "mice"),
    ("goose", "geese"),
    ("knife", "knives"),
    ("wife", "wives"),
    ("leaf", "leaves"),
    ("loaf", "loaves"),
    ("shelf", "shelves"),
    ("half", "halves"),
    ("wolf", "wolves"),
    ("scarf", "scarves"),
    ("potato", "potatoes"),
    ("tomato", "tomatoes"),
    ("mango", "mangoes"),
];

/// The plural of a spoken noun: its last word made plural ("cash boxes", "knives", "berries").
pub fn plural(noun: &str) -> String {
    let (head, last) = match noun.rsplit_once(' ') {
        Some((head, last)) => (Some(head), last),
        None => (None, noun),
    };
    let last = if let Some((_, many)) = IRREGULAR.iter().find(|(one, _)| *one == last) {
        (*many).to_owned()
    } else if let Some(stem) = last.strip_suffix('y')
        && stem.chars().last().is_some_and(|c| !"aeiou".contains(c))
    {
        format!("{stem}ies")
    } else if ["s", "x", "z", "ch", "sh"].iter().any(|e| last.ends_with(e)) {
        format!("{last}es")
    } else {
        format!("{last}s")
    };
    match head {
        Some(head) => format!("{head} {last}"),
        None => last,
    }
}

/// The singulars a word may be the plural of, likeliest first: the caller keeps the first that
/// names something. Only a plural [`plural`] would say is one: "boxs" and "vasees" are not.
pub fn singulars(word: &str) -> Vec<String> {
    if let Some((one, _)) = IRREGULAR.iter().find(|(_, many)| *many == word) {
        return vec![(*one).to_owned()];
    }
    let mut stems = Vec::new();
    if let Some(stem) = word.strip_suffix('s') {
        stems.push(stem.to_owned());
    }
    if let Some(stem) = word.strip_suffix("es") {
        stems.push(stem.to_owned());
    }
    if let Some(stem) = word.strip_suffix("ies") {
        stems.push(format!("{stem}y"));
    }
    stems.retain(|stem| !stem.is_empty() && plural(stem) == word);
    stems
}

/// A count in words: "one" to "ten", then digits.
pub fn count_word(n: usize) -> String {
    const WORDS: [&str; 11] = [
        "no", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten",
    ];
    WORDS.get(n).map_or_else(|| n.to_string(), |w| (*w).to_owned())
}

/// The number a word says, 1 to [`MAX_GROUP`]: "two", "3".
pub fn count_of(word: &str) -> Option<usize> {
    const WORDS: [&str; 10] = [
        "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten",
    ];
    let n = match WORDS.iter().position(|w| *w == word) {
        Some(i) => i + 1,
        None => word
            .parse::<usize>()
            .ok()
            .filter(|_| word.bytes().all(|b| b.is_ascii_digit()))?,
    };
    (1..=MAX_GROUP).contains(&n).then_some(n)
}

/// `n` of the noun, as said: "one cup", "three cups".
fn counted(n: usize, noun: &str) -> String {
    match n {
        1 => format!("one {noun}"),
        _ => format!("{} {}", count_word(n), plural(noun)),
    }
}

/// The groups a plural reference's `matches` (in scene order) make for `number`, in
/// lexicographic order of their members' places; at most `most` of them (the caller makes one
/// more than it may read, to know there are too many). With none, what the scene has instead.
pub(super) fn groups(number: Number, matches: &[Term], noun: &str, most: usize) -> Result<Vec<Term>, String> {
    let n = matches.len();
    let wanted = match number {
        Number::Every => n,
        Number::Exactly(k) | Number::Any(k) => k,
    };
    let too_many = |n: usize| {
        format!(
            "There are {} here: I can act on at most {MAX_GROUP} at once.",
            counted(n, noun)
        )
    };
    match number {
        _ if n == 0 => Err(format!("I see no {} here.", plural(noun))),
        Number::Every if n > MAX_GROUP => Err(too_many(n)),
        Number::Exactly(k) if n > k => Err(format!(
            "I cannot tell which {} you mean: I see {}.",
            counted(k, noun),
            count_word(n)
        )),
        Number::Exactly(k) | Number::Any(k) if n < k => {
            Err(format!("I see only {} here, not {}.", counted(n, noun), count_word(k)))
        }
        // More choices than may be read: only their count is looked at (the readings are too
        // many to simulate), so they are one group's term, shared, not each made.
        _ if choices(n, wanted) > most as u128 => Ok(vec![group(matches[..wanted].to_vec()); most]),
        _ => Ok(choose(matches, wanted, most)),
    }
}

/// How many ways there are to choose `k` of `n`, saturating.
fn choices(n: usize, k: usize) -> u128 {
    let k = k.min(n - k.min(n));
    (0..k).fold(1u128, |c, i| {
        // c · (n − i) / (i + 1) is whole at each step; past u128 it saturates.
        c.checked_mul((n - i) as u128)
            .map_or(u128::MAX, |c| c / (i as u128 + 1))
    })
}

/// Every choice of `k` of `items`, in lexicographic order of positions; at most `most`.
fn choose(items: &[Term], k: usize, most: usize) -> Vec<Term> {
    let mut out = Vec::new();
    if k == 0 || k > items.len() {
        return out;
    }
    let mut at: Vec<usize> = (0..k).collect();
    loop {
        if out.len() >= most {
            return out;
        }
        out.push(group(at.iter().map(|&i| items[i].clone()).collect()));
        // The rightmost position that can still move on, and those after it just behind it.
        let Some(i) = (0..k).rev().find(|&i| at[i] < items.len() - k + i) else {
            return out;
        };
        at[i] += 1;
        for j in i + 1..k {
            at[j] = at[j - 1] + 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plurals_and_singulars_agree() {
        for noun in [
            "cup", "box", "dish", "glass", "knife", "berry", "child", "cash box", "toy", "shelf", "base",
        ] {
            let many = plural(noun);
            let last = many.rsplit(' ').next().unwrap();
            let one = noun.rsplit(' ').next().unwrap();
            assert!(singulars(last).contains(&one.to_owned()), "{noun} → {many}");
        }
        assert_eq!(plural("cash box"), "cash boxes");
        assert_eq!(plural("berry"), "berries");
        assert_eq!(plural("toy"), "toys");
        assert!(singulars("glass").is_empty());
        for not_a_plural in ["boxs", "vasees", "berrys", "knifes", "s", "es"] {
            assert!(
                !singulars(not_a_plural)
                    .iter()
                    .any(|one| ["box", "vase", "berry", "knife"].contains(&one.as_str())),
                "{not_a_plural}: {:?}",
                singulars(not_a_plural)
            );
        }
        assert_eq!(singulars("potatoes"), ["potato"]);
    }

    #[test]
    fn choices_are_every_combination_once_in_order() {
        let items: Vec<Term> = ["a", "b", "c", "d"].iter().map(|s| Term::constant(s)).collect();
        let two = choose(&items, 2, usize::MAX);
        let shown: Vec<String> = two
            .iter()
            .map(|t| objects_of(t).iter().map(|m| m.to_string()).collect())
            .collect();
        assert_eq!(shown, ["ab", "ac", "ad", "bc", "bd", "cd"]);
        assert_eq!(choose(&items, 4, usize::MAX).len(), 1);
        assert_eq!(choose(&items, 2, 3).len(), 3);
        assert_eq!(choices(4, 2), 6);
        assert_eq!(choices(10_000, 2), 49_995_000);
        assert_eq!(choices(10_000, 32), u128::MAX);
        assert_eq!(choices(5, 5), 1);
        assert!(choose(&items, 5, usize::MAX).is_empty());
    }

    #[test]
    fn a_wrong_count_says_how_many_there_are() {
        let cups: Vec<Term> = ["c1", "c2", "c3"].iter().map(|s| Term::constant(s)).collect();
        assert_eq!(
            groups(Number::Exactly(2), &cups, "cup", 10).unwrap_err(),
            "I cannot tell which two cups you mean: I see three."
        );
        assert_eq!(
            groups(Number::Exactly(2), &cups[..1], "cup", 10).unwrap_err(),
            "I see only one cup here, not two."
        );
        assert_eq!(
            groups(Number::Any(2), &[], "cup", 10).unwrap_err(),
            "I see no cups here."
        );
        assert_eq!(groups(Number::Every, &cups, "cup", 10).unwrap().len(), 1);
        assert_eq!(groups(Number::Any(2), &cups, "cup", 10).unwrap().len(), 3);
        assert_eq!(count_of("3"), Some(3));
        assert_eq!(count_of("33"), None);
        assert_eq!(count_of("+3"), None);
    }
}
