//! Number words, property-tested over random rooms and norms: under the moral strategy no act
//! of a plural's reading that is forbidden or infeasible is offered, assumed, confirmed or
//! obeyed; and the acts are on exactly the objects the words mean, as CONTRACT.md counts them
//! (every match; exactly two or nothing; any k distinct matches), never on another.

use std::collections::BTreeSet;

use super::relation_words::cases;
use super::shapes::check as check_decision;
use super::*;
use crate::engine::check::check as check_steps;
use crate::engine::decision::Style;
use crate::engine::describe::is_task;
use crate::engine::norms::Scope;

const KINDS: [&str; 3] = ["cup", "vase", "box"];
const COLOURS: [&str; 2] = ["red", "blue"];

/// One object: its kind and colour (indices), whether fragile, whether within reach.
type Drawn = (usize, usize, bool, bool);

fn room(drawn: &[Drawn]) -> Scene {
    let objects = (drawn.iter().enumerate())
        .map(|(i, &(kind, colour, fragile, near))| {
            let properties: &[&str] = if fragile { &["fragile"] } else { &[] };
            let x = if near { 0.5 } else { 3.0 };
            let position = [x, 0.1 * i as f64 - 0.4, 0.8];
            obj(
                &format!("o{i}"),
                KINDS[kind],
                properties,
                &[("color", COLOURS[colour])],
                position,
                None,
            )
        })
        .collect();
    scene(objects, &[])
}

fn arb_norm() -> impl Strategy<Value = NormInput> {
    (0..8usize, 0..8usize).prop_map(|(k, i)| match k {
        0 => fa("get"),
        1 => fa("destroy"),
        2 => fs(&format!("did(self,get(o{i}))")),
        3 => fs(&format!("destroyed(o{i})")),
        4 => when(fa("get(X)"), &["color(X,red)"]),
        5 => when(fa("destroy(X)"), &["fragile(X)"]),
        6 => when(fa("pointTo(X)"), &["color(X,blue)"]),
        _ => fs(&format!("holding(self,o{i})")),
    })
}

/// How many of its matches a form means.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Count {
    Every,
    Exactly(usize),
    Any(usize),
}

/// Each form of words: how it is said (`{k}` the kind, `{ks}` its plural, `{c}` a colour), how
/// many it means, and whether it says a colour (true of the matches) or excludes one.
const FORMS: [(&str, Count, Option<bool>); 11] = [
    ("the {ks}", Count::Every, None),
    ("all the {c} {ks}", Count::Every, Some(true)),
    ("every {k}", Count::Every, None),
    ("each of the {c} {ks}", Count::Every, Some(true)),
    ("the {ks} except the {c} one", Count::Every, Some(false)),
    ("both {ks}", Count::Exactly(2), None),
    ("the two {c} {ks}", Count::Exactly(2), Some(true)),
    ("two {ks}", Count::Any(2), None),
    ("three {c} {ks}", Count::Any(3), Some(true)),
    ("one of the {ks}", Count::Any(1), None),
    ("the {ks} that are not {c}", Count::Every, Some(false)),
];

fn plural(kind: &str) -> String {
    crate::engine::resolve::plural(kind)
}

/// The words of form `form` for kind `k` and colour `c`; with `unknown`, a word no scene knows
/// as an adjective.
fn said(form: usize, k: &str, c: &str, unknown: bool) -> String {
    let words = FORMS[form]
        .0
        .replace("{ks}", &plural(k))
        .replace("{k}", k)
        .replace("{c}", c);
    if !unknown {
        return words;
    }
    let noun = if words.contains(&plural(k)) {
        plural(k)
    } else {
        k.to_owned()
    };
    words.replacen(&noun, &format!("zorpy {noun}"), 1)
}

/// The objects the words match, by the contract: of the kind, with the colour said (or without
/// the colour excluded).
fn matches(scene: &Scene, form: usize, k: &str, c: &str) -> BTreeSet<String> {
    (scene.objects.iter())
        .filter(|o| o.kind == k)
        .filter(|o| match FORMS[form].2 {
            None => true,
            Some(keep) => (o.attributes.get("color").map(String::as_str) == Some(c)) == keep,
        })
        .map(|o| o.id.to_string())
        .collect()
}

/// Each act of an action offered or acted on: `did(self,X)`'s X, or its steps.
fn acts(action: &Term) -> Vec<Term> {
    match action.args().get(1) {
        Some(reading) if is_task(reading) => reading.args().to_vec(),
        Some(reading) => vec![reading.clone()],
        None => Vec::new(),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    /// Whatever a plural's decision offers, confirms or acts on passes shapes.rs's check, and
    /// each of its acts is permitted when checked again alone; its objects are exactly those
    /// the words mean (all of them, or k distinct ones), and words with one the scene does not
    /// know act on nothing.
    #[test]
    fn number_words_act_on_what_they_mean_and_nothing_forbidden(
        drawn in prop::collection::vec((0..3usize, 0..2usize, any::<bool>(), prop::bool::weighted(0.8)), 2..10),
        form in 0..FORMS.len(),
        (kind, colour) in (0..3usize, 0..2usize),
        verb in prop::sample::select(vec!["Get", "Destroy", "Point to"]),
        given in prop::collection::vec(arb_norm(), 0..=3),
        unknown in prop::bool::weighted(0.15),
        confirm in any::<bool>(),
    ) {
        let scene = room(&drawn);
        let (k, c) = (KINDS[kind], COLOURS[colour]);
        let words = said(form, k, c, unknown);
        let text = format!("{verb} {words}.");
        let norms = norms(&given);
        let mut request = request(Directive::Words { text: text.clone() });
        if confirm {
            request = confirming(request);
        }
        let d = run(&request, &scene, &norms);
        let shown = || format!("{text} in {:?}: {} ({})", drawn, d.utterance, d.kind.as_str());
        if let Err(e) = check_decision(&d) {
            return Err(TestCaseError::fail(format!("{}: {e}", shown())));
        }
        let scope = Scope { context: "default", roles: &[], soft: true };
        let library = Library::default_library();
        let meant = matches(&scene, form, k, c);
        for action in d.offered.iter().chain(&d.goal) {
            let steps = acts(action);
            let checked = check_steps(&steps, &scene, &norms, &library, scope, Style::Diarc, &|| false);
            prop_assert!(checked.permitted(), "{}: {} {}", shown(), action, checked.utterance);
            let objects: Vec<String> = steps.iter().filter_map(|s| s.args().first()).map(Term::to_string).collect();
            let distinct: BTreeSet<String> = objects.iter().cloned().collect();
            prop_assert_eq!(distinct.len(), objects.len(), "{}: an object twice in {}", shown(), action);
            prop_assert!(!unknown, "{}: acted on unknown words", shown());
            match FORMS[form].1 {
                Count::Every => prop_assert_eq!(&distinct, &meant, "{}", shown()),
                Count::Exactly(n) => {
                    prop_assert_eq!(meant.len(), n, "{}", shown());
                    prop_assert_eq!(&distinct, &meant, "{}", shown());
                }
                Count::Any(n) => {
                    prop_assert_eq!(distinct.len(), n, "{}", shown());
                    prop_assert!(distinct.is_subset(&meant), "{}", shown());
                }
            }
        }
        let wrong_count = match FORMS[form].1 {
            Count::Every => meant.is_empty(),
            Count::Exactly(n) => meant.len() != n,
            Count::Any(n) => meant.len() < n,
        };
        if unknown || wrong_count {
            prop_assert!(matches!(d.kind, Unresolved | NotUnderstood), "{}", shown());
        }
    }
}

/// The property's cases reach every form with its objects acted on, and refusals among them.
#[test]
fn number_words_reach_every_form_and_decision() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;

    let mut runner = TestRunner::deterministic();
    let mut acted = vec![0usize; FORMS.len()];
    let mut kinds = BTreeSet::new();
    let arb = (
        prop::collection::vec((0..3usize, 0..2usize, any::<bool>(), prop::bool::weighted(0.8)), 2..10),
        0..FORMS.len(),
        (0..3usize, 0..2usize),
        prop::collection::vec(arb_norm(), 0..=2),
    );
    for _ in 0..1500 {
        let (drawn, form, (kind, colour), given) = arb.new_tree(&mut runner).expect("a case").current();
        let scene = room(&drawn);
        let text = format!("Get {}.", said(form, KINDS[kind], COLOURS[colour], false));
        let d = run(&request(Directive::Words { text }), &scene, &norms(&given));
        kinds.insert(d.kind.as_str());
        if d.goal.is_some() || !d.offered.is_empty() {
            acted[form] += 1;
        }
    }
    assert!(acted.iter().all(|&n| n >= 5), "acted on by form: {acted:?}");
    for kind in ["comply", "assume", "refuse", "unresolved"] {
        assert!(kinds.contains(kind), "{kind} never reached: {kinds:?}");
    }
}
