//! What the robot says: a decided plan rendered as an utterance and a speech act, in the paper's
//! own words (`diarc`) or in fluent English whose firmness follows the norm's severity (`natural`).
//!
//! Owns: every sentence and every speech-act term. Must not: decide anything; it only words the
//! plan `clarify` made, and it never names a reading the plan does not name.

use std::borrow::Cow;

use super::decision::{Interpretation, Plan, Style, Unclear, Unfound};
use super::describe::{Describer, is_task, reading_with};
use super::norms::Force;
use super::resolve::plural;
use super::scene::{person_predicate, spoken};
use super::simulate::{Cause, Reason};
use super::term::{Sym, Term};

mod ids;
mod norm;
mod soft;

pub use ids::answer_utterance;
use norm::said_of;
use soft::{
    although, dispreferred_reasons, dispreferred_words, fact_words, natural_rather_not, note_words, soft_words,
};

/// The reason a refusal or an explanation speaks: the first that is not a soft norm's. A reading
/// the plan turns down always has one; the deadline's reason stands in should it not.
fn hard(i: &Interpretation) -> Cow<'_, Reason> {
    match i.outcome.first_hard() {
        Some(reason) => Cow::Borrowed(reason),
        None => Cow::Owned(Reason::unfinished()),
    }
}

fn act(name: &str, what: Term) -> Term {
    Term::compound(name, vec![Term::constant("self"), what])
}

fn mean(speaker: &Term, what: Term) -> Term {
    Term::compound("mean", vec![speaker.clone(), what])
}

/// A phrase as a constant: "the spoon" → `the_spoon`.
fn phrase_term(words: &str) -> Term {
    Term::constant(&words.replace(' ', "_"))
}

fn one_or_and(mut terms: Vec<Term>) -> Term {
    if terms.len() == 1 {
        terms.remove(0)
    } else {
        Term::compound("and", terms)
    }
}

/// `cannot(a,because(r))`, with the first reason.
fn cannot_term(i: &Interpretation) -> Term {
    Term::compound(
        "cannot",
        vec![i.action.clone(), Term::compound("because", vec![hard(i).term()])],
    )
}

/// The speech act of a plan: the logical form of its main act, as in Algorithm 1.
pub fn speech_act(plan: &Plan, all: &[Interpretation], speaker: &Term) -> Term {
    match plan {
        Plan::Comply(i) => act("acknowledge", mean(speaker, all[*i].action.clone())),
        Plan::Refuse(i) => cannot_term(&all[*i]),
        Plan::Ask { offered, more } => {
            let mut options: Vec<Term> = offered.iter().map(|&i| all[i].action.clone()).collect();
            if *more {
                options.push(Term::constant("something_else"));
            }
            act("want_know", mean(speaker, Term::compound("or", options)))
        }
        Plan::AskWhich { nouns } => act(
            "want_know",
            Term::compound(
                "which",
                vec![one_or_and(nouns.iter().map(|n| phrase_term(n)).collect())],
            ),
        ),
        Plan::Assume { chosen, .. } => act("assume", mean(speaker, all[*chosen].action.clone())),
        Plan::Confirm { chosen, .. } => act("want_know", mean(speaker, all[*chosen].action.clone())),
        Plan::Explain(which) => act(
            "believe",
            Term::compound("and", which.iter().map(|&i| cannot_term(&all[i])).collect()),
        ),
        Plan::Unresolved(unfound) => act(
            "want_know",
            one_or_and(
                unfound
                    .iter()
                    .map(|u| Term::compound("referent", vec![phrase_term(&u.words)]))
                    .collect(),
            ),
        ),
        // Nothing is done, and the robot says it heard so: `acknowledge(self,cancel(S))`.
        Plan::Cancelled => act("acknowledge", Term::compound("cancel", vec![speaker.clone()])),
        // What the human meant, and why the words did not say it: `want_know(self,meaning(question))`.
        Plan::NotUnderstood { why, .. } => act(
            "want_know",
            Term::compound("meaning", vec![Term::constant(why.as_str())]),
        ),
    }
}

/// The reason in the paper's words, as the contract's table gives them.
pub fn diarc_reason(reason: &Reason, describer: &mut Describer<'_>) -> String {
    match &reason.cause {
        // The purpose is said with the reading ([`refused`]); the reason is the norm's own.
        Cause::ForbiddenPurpose { .. } => diarc_reason(&reason.behind_purpose(), describer),
        Cause::Soft { .. } => soft_words(reason, describer),
        Cause::ForbiddenAction { .. } | Cause::ForbiddenState { .. }
            if let Some(words) = said_of(reason, Style::Diarc, describer) =>
        {
            words
        }
        Cause::ForbiddenAction { name, .. } => format!("{name} is forbidden action"),
        Cause::ForbiddenState { .. } => "it requires a forbidden state".to_owned(),
        Cause::UnknownAction { verb } => format!("I do not know how to {}", spoken(verb)),
        Cause::Unreachable { object } => {
            format!("{} is out of reach", describer.argument(&Term::Const(object.clone())))
        }
        Cause::UnknownObject { object } => format!("I do not see {}", describer.argument(object)),
        Cause::Precondition { fact } => not_the_case(fact, describer),
        Cause::PlanTooDeep { .. } => "its plan is too deep to simulate".to_owned(),
        Cause::Unfinished => "I could not finish checking it in time".to_owned(),
        other => geometry_words(other, describer, false),
    }
}

/// The geometric reasons, the same in both styles but for a possessive: "my gripper".
fn geometry_words(cause: &Cause, describer: &mut Describer<'_>, natural: bool) -> String {
    let mut name = |id: &Sym| describer.argument(&Term::Const(id.clone()));
    match cause {
        Cause::Blocked { by, .. } => format!("{} is in the way", name(by)),
        Cause::TooWide { object } if natural => format!("{} is too wide for my gripper", name(object)),
        Cause::TooWide { object } => format!("{} is too wide to grasp", name(object)),
        Cause::TooHeavy { object } if natural => format!("{} is too heavy for me to lift", name(object)),
        Cause::TooHeavy { object } => format!("{} is too heavy", name(object)),
        Cause::NoRoom { item, support } => {
            let item = name(item);
            format!("there is no room for {item} on {}", name(support))
        }
        Cause::Person { person } => {
            let person = Term::Const(person.clone());
            let be = describer.copula(&person);
            format!("{}{be}a person, not an object to handle", describer.argument(&person))
        }
        Cause::SameObject { verb, object, joiner } => format!(
            "{} cannot be {} {} itself",
            name(object),
            participle(&spoken(verb)),
            joiner.as_deref().unwrap_or("with")
        ),
        _ => String::new(),
    }
}

/// "put" → "put", "stack" → "stacked", "place" → "placed": the past participle of a verb as
/// spoken (its first word; the rest, a particle, follows). Irregular verbs a curator is likely
/// to define are listed; the rest are taken as regular.
fn participle(verb: &str) -> String {
    let (head, rest) = verb.split_once(' ').map_or((verb, ""), |(h, r)| (h, r));
    let irregular = [
        ("put", "put"),
        ("set", "set"),
        ("get", "got"),
        ("hang", "hung"),
        ("lay", "laid"),
        ("stick", "stuck"),
        ("tie", "tied"),
        ("bind", "bound"),
        ("hold", "held"),
        ("give", "given"),
        ("take", "taken"),
        ("bring", "brought"),
        ("throw", "thrown"),
        ("sit", "sat"),
        ("cut", "cut"),
    ];
    let done = match irregular.iter().find(|(v, _)| *v == head) {
        Some((_, p)) => (*p).to_owned(),
        None if head.ends_with('e') => format!("{head}d"),
        None => format!("{head}ed"),
    };
    if rest.is_empty() {
        done
    } else {
        format!("{done} {rest}")
    }
}

/// "which cup", then for the same noun again "which other cup", "which third cup": never the
/// same words twice ("which cup and which cup").
fn which(nouns: &[String]) -> Vec<String> {
    const AGAIN: [&str; 7] = ["other", "third", "fourth", "fifth", "sixth", "seventh", "eighth"];
    nouns
        .iter()
        .enumerate()
        .map(|(i, noun)| match nouns[..i].iter().filter(|n| *n == noun).count() {
            0 => format!("which {noun}"),
            seen => match AGAIN.get(seen - 1) {
                Some(word) => format!("which {word} {noun}"),
                None => format!("which {noun} ({})", seen + 1),
            },
        })
        .collect()
}

/// A precondition that does not hold, in words: `open(box1)` → "the box is not open";
/// `color(box1,red)` → "the color of the box is not red"; anything else canonical.
fn not_the_case(fact: &Term, describer: &mut Describer<'_>) -> String {
    if let Some(predicate) = person_predicate(fact) {
        let subject = &fact.args()[0];
        return format!(
            "{}{}not {predicate}",
            describer.argument(subject),
            describer.copula(subject)
        );
    }
    let name = fact.name().map(|n| spoken(n)).unwrap_or_default();
    match fact.args() {
        [subject] => format!("{}{}not {name}", describer.argument(subject), describer.copula(subject)),
        [subject, value] => format!(
            "the {name} of {} is not {}",
            describer.argument(subject),
            describer.argument(value)
        ),
        _ => format!("{fact} does not hold"),
    }
}

/// "destroy" → "destroying", "get" → "getting", "pointTo" → "pointing to".
pub fn gerund(verb: &str) -> String {
    let words = spoken(verb);
    let (head, tail) = match words.split_once(' ') {
        Some((h, t)) => (h.to_owned(), format!(" {t}")),
        None => (words.clone(), String::new()),
    };
    let chars: Vec<char> = head.chars().collect();
    let is_vowel = |c: char| "aeiou".contains(c);
    let n = chars.len();
    let ing = if head.ends_with("ie") {
        format!("{}ying", &head[..head.len() - 2])
    } else if head.ends_with('e') && !head.ends_with("ee") && n > 2 {
        format!("{}ing", &head[..head.len() - 1])
    } else if n == 3 && !is_vowel(chars[0]) && is_vowel(chars[1]) && !is_vowel(chars[2]) && !"wxy".contains(chars[2]) {
        // One short syllable ending consonant-vowel-consonant doubles its last letter: get, put.
        format!("{head}{}ing", chars[2])
    } else {
        format!("{head}ing")
    };
    format!("{ing}{tail}")
}

fn capitalise(text: &str) -> String {
    let mut chars = text.chars();
    match chars.next() {
        Some(first) => first.to_uppercase().chain(chars).collect(),
        None => String::new(),
    }
}

/// The reason in fluent words; a norm's severity picks how strongly it is put.
pub fn natural_reason(reason: &Reason, describer: &mut Describer<'_>) -> String {
    let grave = reason.severity.unwrap_or(3) >= 4;
    match &reason.cause {
        Cause::ForbiddenPurpose { .. } => natural_reason(&reason.behind_purpose(), describer),
        Cause::Soft { .. } => soft_words(reason, describer),
        Cause::ForbiddenAction { .. } | Cause::ForbiddenState { .. }
            if let Some(words) = said_of(reason, Style::Natural, describer) =>
        {
            words
        }
        Cause::ForbiddenAction { name, .. } => {
            let rule = if grave { "is forbidden" } else { "is not allowed" };
            format!("{} things {rule}", gerund(name))
        }
        Cause::ForbiddenState { .. } => {
            if grave {
                "it would lead to a forbidden state".to_owned()
            } else {
                "it would lead to a state I am not allowed to bring about".to_owned()
            }
        }
        Cause::UnknownAction { verb } => format!("I don't know how to {}", spoken(verb)),
        Cause::Unreachable { object } => format!(
            "{} is out of my reach",
            describer.argument(&Term::Const(object.clone()))
        ),
        Cause::UnknownObject { object } => format!("I can't see {}", describer.argument(object)),
        Cause::Precondition { fact } => not_the_case(fact, describer),
        Cause::PlanTooDeep { .. } => "the plan is too complex for me to check".to_owned(),
        Cause::Unfinished => "I ran out of time to check it".to_owned(),
        other => geometry_words(other, describer, true),
    }
}

/// The words of `items`, each once, in the order first said: two norms that say the same thing
/// are said once.
fn unique(items: Vec<String>) -> Vec<String> {
    let mut kept: Vec<String> = Vec::with_capacity(items.len());
    for item in items {
        if !kept.contains(&item) {
            kept.push(item);
        }
    }
    kept
}

/// The words for one reason in the given style: what `reasons[].words` carries.
pub fn reason_words(reason: &Reason, style: Style, describer: &mut Describer<'_>) -> String {
    match style {
        Style::Diarc => diarc_reason(reason, describer),
        Style::Natural => natural_reason(reason, describer),
    }
}

/// `I cannot {reading} because {reason}` (diarc).
fn diarc_cannot(i: &Interpretation, describer: &mut Describer<'_>) -> String {
    let reason = hard(i);
    format!(
        "I cannot {} because {}",
        refused(i, &reason, describer),
        diarc_reason(&reason, describer)
    )
}

/// A reading turned down for `reason`, in words: with the purpose the human gave when it is
/// the purpose that is forbidden ("get the mug to destroy the vase").
fn refused(i: &Interpretation, reason: &Reason, describer: &mut Describer<'_>) -> String {
    match &reason.cause {
        Cause::ForbiddenPurpose { purpose, said, .. } => {
            // The purpose's objects as the human said them, or "it" for one the reading acts on.
            let objects: Vec<&Term> = match is_task(action_of(i)) {
                true => action_of(i).args().iter().flat_map(Term::args).collect(),
                false => action_of(i).args().iter().collect(),
            };
            let mut words = Vec::with_capacity(purpose.arity());
            for (j, argument) in purpose.args().iter().enumerate() {
                words.push(match (said.get(j).cloned().flatten(), objects.contains(&argument)) {
                    (Some(said), _) => said,
                    (None, true) => "it".to_owned(),
                    (None, false) => describer.argument(argument),
                });
            }
            let joiner = describer.joiner_of(purpose);
            format!(
                "{} to {}",
                reading(i),
                reading_with(purpose, &words.join(&format!(" {joiner} ")))
            )
        }
        _ => reading(i),
    }
}

/// How firmly a reading is turned down in the natural style, by its first reason: a norm's
/// severity sets the tone (1–2 gentle, 3 plain, 4–5 firm); an inability is a plain "can't".
fn natural_refusal(i: &Interpretation, describer: &mut Describer<'_>) -> String {
    let reason = hard(i);
    let why = natural_reason(&reason, describer);
    let what = refused(i, &reason, describer);
    if !reason.is_norm_violation() {
        return format!("I can't {what}: {why}.");
    }
    match reason.severity.unwrap_or(3) {
        1 | 2 => format!("Sorry, I'd rather not {what}: {why}."),
        3 => format!("I won't {what}: {why}."),
        _ => format!("I will not {what}. {}.", capitalise(&why)),
    }
}

/// When every reading is the same verb on one object of one type, turned down for the same
/// first reason: "I won't destroy either notebook: destroying things is not allowed."
fn natural_grouped(which: &[usize], all: &[Interpretation], describer: &mut Describer<'_>) -> Option<String> {
    let first = &all[which[0]];
    let verb = first.action.args().get(1)?.name()?.clone();
    // Grouped only when the refusal would be worded the same for each: same verb on one object,
    // same reason in the same words, under the same severity.
    let words: Vec<String> = which
        .iter()
        .map(|&i| natural_reason(&hard(&all[i]), describer))
        .collect();
    let same = which.iter().zip(&words).all(|(&i, w)| {
        let a = &all[i];
        let (r, r0) = (hard(a), hard(first));
        // A purpose is said with each reading: never grouped away.
        if matches!(r.cause, Cause::ForbiddenPurpose { .. }) {
            return false;
        }
        a.action.args().get(1).and_then(Term::name) == Some(&verb)
            && a.action.args().get(1).map(Term::arity) == Some(1)
            && r.is_norm_violation() == r0.is_norm_violation()
            && r.severity == r0.severity
            && w == &words[0]
    });
    if !same {
        return None;
    }
    let kinds: Vec<Option<String>> = which
        .iter()
        .map(|&i| {
            let target = all[i].action.args().get(1)?.args().first()?.name()?.clone();
            describer.kind_of(&target)
        })
        .collect();
    let noun = kinds.first()?.clone()?;
    if kinds.iter().any(|k| k.as_ref() != Some(&noun)) {
        return None;
    }
    let reason = hard(first);
    let why = &words[0];
    let quantity = if which.len() == 2 {
        format!("either {noun}")
    } else {
        format!("any of the {}", plural(&noun))
    };
    let verb = spoken(&verb);
    Some(if reason.is_norm_violation() {
        match reason.severity.unwrap_or(3) {
            1 | 2 => format!("Sorry, I'd rather not {verb} {quantity}: {why}."),
            3 => format!("I won't {verb} {quantity}: {why}."),
            _ => format!("I will not {verb} {quantity}. {}.", capitalise(why)),
        }
    } else {
        format!("I can't {verb} {quantity}: {why}.")
    })
}

/// A reading in words: "get the plastic vase", its verb spoken and then its description.
pub(crate) fn reading(i: &Interpretation) -> String {
    reading_with(action_of(i), &i.description)
}

/// The action a simulated reading is of: `X` in its `did(self,X)`.
pub(crate) fn action_of(i: &Interpretation) -> &Term {
    i.action.args().get(1).unwrap_or(&i.action)
}

/// A reading as a gerund: "getting the plastic vase"; a task of several steps as "to" and
/// its reading ("to get the mug and put it in the sink").
fn doing(i: &Interpretation) -> String {
    if is_task(action_of(i)) {
        return format!("to {}", reading(i));
    }
    let verb = action_of(i).name().map(|n| gerund(n));
    match (verb, i.description.is_empty()) {
        (Some(verb), true) => verb,
        (Some(verb), false) => format!("{verb} {}", i.description),
        (None, _) => reading(i),
    }
}

/// Joins phrases as a list: "a", "a or b", "a, b, or c".
fn listed(items: &[String], conjunction: &str) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [a, b] => format!("{a} {conjunction} {b}"),
        [rest @ .., last] => format!("{}, {conjunction} {last}", rest.join(", ")),
    }
}

/// The utterance of a plan in the given style.
pub fn utterance(plan: &Plan, all: &[Interpretation], style: Style, describer: &mut Describer<'_>) -> String {
    match style {
        Style::Diarc => diarc(plan, all, describer),
        Style::Natural => natural(plan, all, describer),
    }
}

fn diarc(plan: &Plan, all: &[Interpretation], describer: &mut Describer<'_>) -> String {
    // After the reading chosen, each other: a dispreferred one (acceptable, but with a lower
    // norm score) is one the robot would rather not do; any other one it cannot.
    let others = |chosen: usize, others: &[usize], describer: &mut Describer<'_>| -> String {
        others
            .iter()
            .map(|&i| match all[i].acceptable() {
                true => format!(
                    " I would rather not {} because {}.",
                    reading(&all[i]),
                    dispreferred_words(&dispreferred_reasons(&all[i], &all[chosen]), &all[chosen], describer)
                ),
                false => format!(" {}.", diarc_cannot(&all[i], describer)),
            })
            .collect()
    };
    match plan {
        Plan::Comply(i) => match although(&all[*i], describer) {
            Some((why, _)) => format!("Okay, although {why}."),
            None => "Okay.".to_owned(),
        },
        Plan::Refuse(i) => format!("{}.", diarc_cannot(&all[*i], describer)),
        Plan::Ask { offered, more } => {
            let readings: Vec<String> = offered.iter().map(|&i| reading(&all[i])).collect();
            let tail = if *more { " or something else" } else { "" };
            format!(
                "Do you mean that you want me to {}{tail}?",
                readings.join(" or that you want me to ")
            )
        }
        Plan::AskWhich { nouns } => format!("I do not know {} you mean.", which(nouns).join(" and ")),
        Plan::Assume { chosen, others: rest } => format!(
            "I am assuming you want me to {}.{}",
            reading(&all[*chosen]),
            others(*chosen, rest, describer)
        ),
        Plan::Confirm { chosen, others: rest } => format!(
            "Do you want me to {}?{}",
            reading(&all[*chosen]),
            others(*chosen, rest, describer)
        ),
        Plan::Explain(which) => {
            let clauses: Vec<String> = which
                .iter()
                .map(|&i| diarc_cannot(&all[i], describer).trim_start_matches("I ").to_owned())
                .collect();
            format!("I believe that I {}.", clauses.join(" and that I "))
        }
        Plan::Unresolved(unfound) => unplaced_words(unfound).unwrap_or_else(|| {
            let words: Vec<&str> = unfound.iter().map(|u| u.words.as_str()).collect();
            format!("I do not know what you mean by {}.", words.join(" and "))
        }),
        Plan::NotUnderstood { why, words } => not_understood(*why, words),
        Plan::Cancelled => CANCELLED.to_owned(),
    }
}

/// What the robot says when the human takes back what was asked; the same in both styles.
const CANCELLED: &str = "Okay, I will not.";

/// When words of a reference could not be placed at all, the robot says which, in both styles
/// (else what the scene could not tell, if that is why):
/// "I can't find the mug pls" would claim it looked for a "mug pls".
fn unplaced_words(unfound: &[Unfound]) -> Option<String> {
    let Some(u) = unfound.iter().find(|u| u.unplaced.is_some()) else {
        return unfound.iter().find_map(|u| u.untold.clone());
    };
    let unplaced = u.unplaced.as_deref()?;
    Some(match unplaced == u.words {
        true => format!("I do not understand \"{unplaced}\"."),
        false => format!("I do not understand \"{unplaced}\" in \"{}\".", u.words),
    })
}

/// What the robot says to words that are not a directive; the same in both styles, since
/// nothing was refused. Names the words it could not place where there are some.
fn not_understood(why: Unclear, words: &str) -> String {
    match why {
        Unclear::Empty => "I did not hear anything to do.".to_owned(),
        Unclear::Question => format!("I can act on requests, but I did not understand \"{words}\" as one."),
        Unclear::Negated => {
            "I understood what you do not want me to do; tell me what you would like me to do.".to_owned()
        }
        Unclear::Several => format!("Please ask me for at most {} things at a time.", super::task::MAX_STEPS),
        Unclear::Unplaced => format!("I did not understand \"{words}\"."),
        Unclear::Unasked => format!("I did not ask anything that \"{words}\" answers."),
        Unclear::Deadline => "I ran out of time before I understood that.".to_owned(),
        Unclear::Ambiguous => format!("I can read \"{words}\" in more than one way here; please say it another way."),
    }
}

fn natural(plan: &Plan, all: &[Interpretation], describer: &mut Describer<'_>) -> String {
    let others = |chosen: usize, others: &[usize], describer: &mut Describer<'_>| -> String {
        others
            .iter()
            .map(|&i| match all[i].acceptable() {
                true => format!(" {}", natural_rather_not(&all[i], &all[chosen], describer)),
                false => format!(" {}", natural_refusal(&all[i], describer)),
            })
            .collect()
    };
    match plan {
        Plan::Comply(i) => match although(&all[*i], describer) {
            // A strong "should not" is put plainly; a mild one as an aside.
            Some((why, 4..)) => format!("Okay, I will {}, but you should know that {why}.", reading(&all[*i])),
            Some((why, _)) => format!("Okay, I will {}, although {why}.", reading(&all[*i])),
            None => format!("Okay, I will {}.", reading(&all[*i])),
        },
        Plan::Refuse(i) => natural_refusal(&all[*i], describer),
        Plan::Ask { offered, more } => {
            // One verb throughout: say it once and list what it applies to.
            let verbs: Vec<Option<&Term>> = offered.iter().map(|&i| all[i].action.args().get(1)).collect();
            let one_verb = verbs
                .windows(2)
                .all(|w| w[0].and_then(Term::name) == w[1].and_then(Term::name))
                && !verbs.iter().flatten().any(|a| is_task(a));
            let (lead, mut items): (String, Vec<String>) = match verbs.first().copied().flatten() {
                Some(action) if one_verb && action.arity() > 0 => (
                    format!("{} ", spoken(action.name().map(|n| &**n).unwrap_or_default())),
                    offered.iter().map(|&i| all[i].description.clone()).collect(),
                ),
                _ => (String::new(), offered.iter().map(|&i| reading(&all[i])).collect()),
            };
            if *more {
                items.push("something else".to_owned());
            }
            format!("Do you want me to {lead}{}?", listed(&items, "or"))
        }
        Plan::AskWhich { nouns } => format!("{} do you mean?", capitalise(&listed(&which(nouns), "and"))),
        Plan::Assume { chosen, others: rest } => {
            format!("I'll {}.{}", reading(&all[*chosen]), others(*chosen, rest, describer))
        }
        Plan::Confirm { chosen, others: rest } => {
            format!(
                "Should I {}?{}",
                reading(&all[*chosen]),
                others(*chosen, rest, describer)
            )
        }
        Plan::Explain(which) => natural_grouped(which, all, describer).unwrap_or_else(|| {
            which
                .iter()
                .map(|&i| natural_refusal(&all[i], describer))
                .collect::<Vec<_>>()
                .join(" ")
        }),
        Plan::Unresolved(unfound) => unplaced_words(unfound).unwrap_or_else(|| {
            let words: Vec<String> = unfound.iter().map(|u| u.words.clone()).collect();
            format!("I can't find {} here.", listed(&words, "or"))
        }),
        Plan::NotUnderstood { why, words } => not_understood(*why, words),
        Plan::Cancelled => CANCELLED.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_note_is_spoken_without_what_a_listener_cannot_see() {
        for (note, words) in [
            ("that mug is reserved", Some("that mug is reserved")),
            ("  that mug\tis\n\nreserved.  ", Some("that mug is reserved")),
            ("\u{202e}evil\u{0}", Some("evil")),
            ("a\u{0}b", Some("a b")),
            ("zero\u{200b}width\u{feff}", Some("zerowidth")),
            ("\u{2066}isolated\u{2069} text", Some("isolated text")),
            ("\u{1b}[31mred", Some("[31mred")),
            ("Ünïcödé stays, 雨 too", Some("Ünïcödé stays, 雨 too")),
            ("\u{0}\u{202e} . ", None),
            ("", None),
        ] {
            assert_eq!(note_words(note).as_deref(), words, "{note:?}");
        }
    }

    #[test]
    fn gerunds_and_plurals() {
        for (verb, ing) in [
            ("destroy", "destroying"),
            ("get", "getting"),
            ("put", "putting"),
            ("steal", "stealing"),
            ("pointTo", "pointing to"),
            ("take", "taking"),
            ("see", "seeing"),
            ("tie", "tying"),
            ("fix", "fixing"),
        ] {
            assert_eq!(gerund(verb), ing);
        }
        assert_eq!(plural("notebook"), "notebooks");
        assert_eq!(plural("cash box"), "cash boxes");
        // One plural for what is read and what is said: "any of the knives", not "knifes".
        assert_eq!(plural("kitchen knife"), "kitchen knives");
        assert_eq!(plural("battery"), "batteries");
        assert_eq!(listed(&["a".into(), "b".into(), "c".into()], "or"), "a, b, or c");
    }
}
