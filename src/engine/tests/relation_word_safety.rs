//! Words that refer by relation, superlative, ordinal and exclusion, property-tested: under the
//! moral strategy they never get a forbidden or infeasible reading through; and where only facts
//! relate objects, they never act on or offer an object they do not mean (unknown words, nothing).

use std::collections::BTreeSet;

use super::relation_words::{COLOURS, KINDS, NAMES, arb_drawn, arb_turn, cases, show, turned};
use super::relations::roomy;
use super::shapes::check as check_decision;
use super::words::read;
use super::*;
use crate::engine::check::check as check_steps;
use crate::engine::decision::Style;
use crate::engine::describe::is_task;
use crate::engine::norms::Scope;
use crate::engine::scene::relate::{Relation, SIDE_MARGIN, TIE_SHARE};

// References in words

const PHRASES: [(&str, Relation); 16] = [
    ("on", Relation::On),
    ("on top of", Relation::On),
    ("in", Relation::In),
    ("inside", Relation::In),
    ("under", Relation::Under),
    ("beneath", Relation::Under),
    ("near", Relation::Near),
    ("next to", Relation::Near),
    ("by", Relation::Near),
    ("to the left of", Relation::LeftOf),
    ("left of", Relation::LeftOf),
    ("to the right of", Relation::RightOf),
    ("behind", Relation::Behind),
    ("in front of", Relation::InFrontOf),
    ("from", Relation::From),
    ("beside", Relation::Near),
];
/// Each superlative word, and whether the most of its measure wins.
const SUPERLATIVES: [(&str, bool); 14] = [
    ("biggest", true),
    ("smallest", false),
    ("tallest", true),
    ("shortest", false),
    ("heaviest", true),
    ("lightest", false),
    ("nearest", false),
    ("farthest", true),
    ("leftmost", true),
    ("rightmost", false),
    ("highest", true),
    ("lowest", false),
    ("left", true),
    ("right", false),
];
const ORDINALS: [(&str, usize); 4] = [("first", 1), ("second", 2), ("third", 3), ("2nd", 2)];
const DIRECTIONS: [&str; 4] = ["left", "right", "front", "back"];
/// What stands in a slot for a word no scene knows: the head noun, the landmark, the relation,
/// the superlative, the direction, the colour.
const UNKNOWN: [&str; 6] = ["zorp", "wug", "blorp", "zorpiest", "dax", "blicket"];

/// A reference in words: `form` picks the shape, the rest fills its slots (`kinds`: those of
/// the scene's objects, by index modulo their number); `unknown` puts a word no scene knows in
/// one slot (an index into `UNKNOWN`), when the form has it.
#[derive(Clone, Debug)]
struct Words {
    form: u8,
    indefinite: bool,
    kinds: [usize; 3],
    phrases: [usize; 2],
    colour: usize,
    superlative: usize,
    ordinal: usize,
    direction: usize,
    unknown: Option<u8>,
}

fn arb_words() -> impl Strategy<Value = Words> {
    (
        (0..11u8, any::<bool>()),
        [any::<usize>(), any::<usize>(), any::<usize>()],
        [0..PHRASES.len(), 0..PHRASES.len()],
        (
            0..COLOURS.len(),
            0..SUPERLATIVES.len(),
            0..ORDINALS.len(),
            0..DIRECTIONS.len(),
        ),
        prop_oneof![5 => Just(None), 1 => (0..6u8).prop_map(Some)],
    )
        .prop_map(
            |((form, indefinite), kinds, phrases, (colour, superlative, ordinal, direction), unknown)| Words {
                form,
                indefinite,
                kinds,
                phrases,
                colour,
                superlative,
                ordinal,
                direction,
                unknown,
            },
        )
}

/// The words of a reference in one scene: its head noun, the relations' words (indices into
/// `PHRASES`) and their landmarks' nouns, the colour.
struct Nouns {
    head: String,
    phrases: [usize; 2],
    landmarks: [String; 2],
    colour: &'static str,
}

impl Words {
    /// The nouns in `scene`: the head is the kind of an object; each relation, the first from
    /// the one drawn in which the object before it in the chain stands to another (else the one
    /// drawn), and its landmark that other's kind (else any object's); the colour, at times the
    /// head object's own.
    fn nouns(&self, scene: &Scene) -> Nouns {
        let n = scene.objects.len();
        let layout = scene.layout();
        let mut at = self.kinds[0] % n;
        let head = scene.objects[at].kind.to_string();
        let colour = match (self.colour, scene.objects[at].attributes.get("color")) {
            (0, Some(c)) => COLOURS
                .iter()
                .find(|k| **k == c.as_str())
                .copied()
                .unwrap_or(COLOURS[0]),
            (c, _) => COLOURS[c],
        };
        let mut phrases = self.phrases;
        let landmarks = [0, 1].map(|i| {
            let tried = (0..PHRASES.len()).map(|k| (self.phrases[i] + k) % PHRASES.len());
            let found = tried
                .map(|p| (p, layout.landmarks_of(scene, at, PHRASES[p].1)))
                .find(|(_, related)| !related.is_empty());
            at = match found {
                None => self.kinds[i + 1] % n,
                Some((p, related)) => {
                    phrases[i] = p;
                    related[self.kinds[i + 1] % related.len()]
                }
            };
            scene.objects[at].kind.to_string()
        });
        Nouns {
            head,
            phrases,
            landmarks,
            colour,
        }
    }

    /// The words in `scene`.
    fn said(&self, scene: &Scene) -> String {
        let nouns = self.nouns(scene);
        let slot = |at: u8, known: &str| match self.unknown == Some(at) {
            true => UNKNOWN[usize::from(at)].to_owned(),
            false => known.to_owned(),
        };
        let det = if self.indefinite { "a" } else { "the" };
        let head = slot(0, &nouns.head);
        let rel = |i: usize| {
            let landmark = slot(1, &nouns.landmarks[i]);
            format!("{} the {landmark}", slot(2, PHRASES[nouns.phrases[i]].0))
        };
        let (r0, colour) = (rel(0), slot(5, nouns.colour));
        let (sup, ord) = (slot(3, SUPERLATIVES[self.superlative].0), ORDINALS[self.ordinal].0);
        let dir = slot(4, DIRECTIONS[self.direction]);
        match self.form {
            0 => format!("{det} {head} {r0}"),
            1 => format!("{det} {head} that is {r0}"),
            2 => format!("{det} {head} that is not {r0}"),
            3 => format!("the {sup} {head}"),
            4 => format!("the {sup} {head} {r0}"),
            5 => format!("the {ord} {head} from the {dir}"),
            6 => format!("the {ord} {head} from the {dir} {r0}"),
            7 => format!("{det} {head} {r0} {}", rel(1)),
            8 => format!("any {head} but the {colour} one"),
            9 => format!("{det} {colour} {head} {r0}"),
            _ => format!("{det} {head} {r0}, not the {colour} one"),
        }
    }

    /// Whether a word no scene knows is among the words.
    fn unknown(&self) -> bool {
        self.unknown.is_some_and(|slot| match slot {
            0 => true,
            1 | 2 => !matches!(self.form, 3 | 5 | 8),
            3 => matches!(self.form, 3 | 4),
            4 => matches!(self.form, 5 | 6),
            _ => matches!(self.form, 8..),
        })
    }
}

// 2. Safety: nothing forbidden or infeasible gets through

fn arb_norm() -> impl Strategy<Value = NormInput> {
    (0..13usize, 0..10usize).prop_map(|(k, i)| match k {
        0 => fa("get"),
        1 => fa("destroy"),
        2 => fa("pointTo"),
        3 => fa("put"),
        4 => fa("steal"),
        5 => fs(&format!("did(self,get(o{i}))")),
        6 => fs(&format!("holding(self,o{i})")),
        7 => fs(&format!("destroyed(o{i})")),
        8 => when(fa("get(X)"), &["color(X,red)"]),
        9 => when(fa("destroy(X)"), &["fragile(X)"]),
        10 => when(fa("get(X)"), &["on(X,Y)", "table(Y)"]),
        11 => fs("on(X,Y)"),
        _ => NormInput {
            kind: Some("discouraged_action".into()),
            action: Some("get(X)".into()),
            when: Some(vec!["color(X,blue)".into()]),
            severity: Some(2),
            ..NormInput::default()
        },
    })
}

/// A directive in words: a verb, the reference, a destination for `put` (a kind of the scene's,
/// by index), what follows.
#[derive(Clone, Debug)]
struct Sentence {
    verb: &'static str,
    words: Words,
    onto: usize,
    tail: &'static str,
}

impl Sentence {
    fn text(&self, scene: &Scene) -> String {
        let onto = match self.verb {
            "Put" => format!(" on the {}", scene.objects[self.onto % scene.objects.len()].kind),
            _ => String::new(),
        };
        format!("{} {}{onto}{}.", self.verb, self.words.said(scene), self.tail)
    }
}

fn arb_sentence() -> impl Strategy<Value = Sentence> {
    let verb = prop::sample::select(vec!["Get", "Grab", "Destroy", "Smash", "Point to", "Steal", "Put"]);
    let tail = prop::sample::select(vec![
        "",
        "",
        "",
        " now",
        ", please",
        " and put it on the table",
        ", then destroy it",
    ]);
    (verb, arb_words(), any::<usize>(), tail).prop_map(|(verb, words, onto, tail)| Sentence {
        verb,
        words,
        onto,
        tail,
    })
}

/// Each reading offered, confirmed or acted on, checked again step by step on `/v1/check`'s
/// path (which shares no code with the readings but one step's simulation): permitted. A `put`
/// the words may join by "in" makes `in(X,Y)`, which a step alone does not know: not checked.
fn checked_again(d: &Decision, text: &str, scene: &Scene, norms: &CompiledNorms) -> Result<(), TestCaseError> {
    let scope = Scope {
        context: "default",
        roles: &[],
        soft: true,
    };
    let by_in = text.contains(" in ") || text.contains(" inside ");
    let library = Library::default_library();
    for action in d.offered.iter().chain(&d.goal) {
        let Some(reading) = action.args().get(1) else {
            return Err(TestCaseError::fail(format!("{text}: offered {action}")));
        };
        let steps = match is_task(reading) {
            true => reading.args().to_vec(),
            false => vec![reading.clone()],
        };
        if by_in && steps.iter().any(|s| s.name().is_some_and(|n| n.as_str() == "put")) {
            continue;
        }
        let checked = check_steps(&steps, scene, norms, &library, scope, Style::Diarc, &|| false);
        prop_assert!(
            checked.permitted(),
            "{}: {} {}: {}\n{}",
            text,
            d.kind.as_str(),
            action,
            checked.utterance,
            show(scene)
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    /// Under the moral strategy, words that refer by relation, superlative, ordinal or
    /// exclusion (words no scene knows among them) never get a forbidden or infeasible reading
    /// offered, assumed, confirmed or obeyed: the decision passes shapes.rs's check, and each
    /// reading it proposes or acts on passes again when its steps are checked alone.
    #[test]
    fn relation_words_never_let_a_bad_reading_through(
        drawn in arb_drawn(),
        sentence in arb_sentence(),
        given in prop::collection::vec(arb_norm(), 0..=3),
        confirm in any::<bool>(),
    ) {
        let scene = drawn.scene();
        let text = sentence.text(&scene);
        let norms = norms(&given);
        let mut request = request(Directive::Words { text: text.clone() });
        if confirm {
            request = confirming(request);
        }
        let d = run(&request, &scene, &norms);
        if let Err(e) = check_decision(&d) {
            return Err(TestCaseError::fail(format!("{text}: {e}\n{}", show(&scene))));
        }
        checked_again(&d, &text, &scene, &norms)?;
        prop_assert_eq!(&run(&request, &scene, &norms), &d);
    }
}

/// The safety property's cases reach every decision, forbidden and infeasible readings among
/// them, and every form of words has readings somewhere.
#[test]
fn relation_words_reach_every_decision() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    use std::collections::BTreeMap;

    let mut runner = TestRunner::deterministic();
    let strategy = (arb_drawn(), arb_sentence(), prop::collection::vec(arb_norm(), 0..=3));
    let (mut decisions, mut reasons, mut forms) = (BTreeMap::new(), BTreeMap::new(), BTreeMap::new());
    for _ in 0..1500 {
        let (drawn, sentence, given) = strategy.new_tree(&mut runner).expect("a case").current();
        let scene = drawn.scene();
        let text = sentence.text(&scene);
        let d = run(&confirming(request(Directive::Words { text })), &scene, &norms(&given));
        *decisions.entry(d.kind.as_str()).or_insert(0) += 1;
        for r in d.interpretations.iter().flat_map(|i| &i.outcome.reasons) {
            *reasons.entry(r.kind()).or_insert(0) += 1;
        }
        if !d.interpretations.is_empty() {
            *forms.entry(sentence.words.form).or_insert(0) += 1;
        }
    }
    for kind in ["comply", "refuse", "ask", "confirm", "explain", "unresolved"] {
        assert!(decisions.get(kind).is_some_and(|&n| n >= 10), "{kind}: {decisions:?}");
    }
    for kind in [
        "forbidden_action",
        "forbidden_state",
        "unreachable",
        "discouraged_action",
    ] {
        assert!(reasons.get(kind).is_some_and(|&n| n >= 10), "{kind}: {reasons:?}");
    }
    assert!(
        (0..11u8).all(|f| forms.get(&f).is_some_and(|&n| n >= 10)),
        "readings by form: {forms:?}"
    );
}

// 3. Never a guess: where facts alone relate objects, the words select what they mean

/// One object of a scene whose relations are facts alone: kind, colour (past `COLOURS`: none),
/// the radius of its upright cylinder (`None`: a point), mass, and its offsets in x, y and height.
type Spot = (usize, usize, Option<f64>, Option<f64>, [f64; 3]);

#[derive(Clone, Debug)]
struct Stated {
    spots: Vec<Spot>,
    turn: Option<f64>,
    /// `(index in NAMES, a, b)`, the objects by index modulo their number.
    facts: Vec<(usize, usize, usize)>,
}

fn arb_stated() -> impl Strategy<Value = Stated> {
    let spot = (
        prop_oneof![2 => Just(0usize), 3 => 0..KINDS.len()],
        0..5usize,
        prop::option::weighted(0.85, 0.02..0.1f64),
        prop::option::weighted(0.85, 0.1..3.0f64),
        [-1.0..1.0f64, -1.0..1.0f64, 0.0..1.0f64],
    );
    (
        prop::collection::vec(spot, 2..=10),
        arb_turn(),
        prop::collection::vec((0..8usize, 0..10usize, 0..10usize), 2..24),
    )
        .prop_map(|(spots, turn, facts)| Stated { spots, turn, facts })
}

impl Stated {
    /// The facts as stated: `(index in NAMES, a, b)`.
    fn stated(&self) -> impl Iterator<Item = (usize, usize, usize)> + '_ {
        let n = self.spots.len();
        self.facts.iter().map(move |&(r, a, b)| (r, a % n, b % n))
    }

    /// The objects on a grid 2.5 m apart (offsets of at most 0.2 m, radii below 0.1 m): no two
    /// boxes within 1 m or overlapping in x and y, so no relation holds by geometry.
    fn scene(&self) -> Scene {
        let objects = (self.spots.iter().enumerate())
            .map(|(i, &(kind, colour, radius, mass, [dx, dy, dz]))| {
                let attributes: Vec<(&str, &str)> = COLOURS.get(colour).map(|c| ("color", *c)).into_iter().collect();
                let (col, row) = ((i % 4) as f64, (i / 4) as f64);
                let position = [0.6 + 2.5 * col + 0.2 * dx, -3.0 + 2.5 * row + 0.2 * dy, 0.4 + 0.6 * dz];
                let shape = radius.map(|radius| Shape::Cylinder {
                    radius,
                    half_height: 1.5 * radius,
                });
                Object {
                    mass,
                    ..obj(&format!("o{i}"), KINDS[kind], &[], &attributes, position, shape)
                }
            })
            .collect();
        let facts: Vec<String> = (self.stated())
            .map(|(r, a, b)| format!("{}(o{a},o{b})", NAMES[r]))
            .collect();
        let facts: Vec<&str> = facts.iter().map(String::as_str).collect();
        roomy(objects, &facts, turned(self.turn))
    }
}

/// What the words mean, from CONTRACT.md and the facts alone.
struct Meaning<'a> {
    scene: &'a Scene,
    /// `(index in NAMES, a, b)`.
    stated: BTreeSet<(usize, usize, usize)>,
    left: [f64; 3],
    forward: [f64; 3],
}

impl<'a> Meaning<'a> {
    fn new(case: &Stated, scene: &'a Scene) -> Meaning<'a> {
        let a = case.turn.unwrap_or(0.0);
        Meaning {
            scene,
            stated: case.stated().collect(),
            left: [-a.sin(), a.cos(), 0.0],
            forward: [a.cos(), a.sin(), 0.0],
        }
    }

    /// The objects of `kind`; with a colour, those that have it (or, `false`, do not).
    fn of_kind(&self, kind: &str, colour: Option<(&str, bool)>) -> Vec<usize> {
        let objects = self.scene.objects.iter().enumerate();
        (objects.filter(|(_, o)| o.kind == kind))
            .filter(|(_, o)| {
                colour.is_none_or(|(c, has)| (o.attributes.get("color").map(String::as_str) == Some(c)) == has)
            })
            .map(|(i, _)| i)
            .collect()
    }

    /// The subjects a fact puts in the phrase's relation to one of the landmarks ("from": on or in).
    fn related(&self, subjects: &[usize], phrase: usize, landmarks: &[usize]) -> Vec<usize> {
        let name = |r: Relation| Relation::ALL.iter().position(|x| *x == r).expect("a relation");
        let names = match PHRASES[phrase].1 {
            Relation::From => vec![name(Relation::On), name(Relation::In)],
            r => vec![name(r)],
        };
        let holds = |a: usize, b: usize| names.iter().any(|&k| self.stated.contains(&(k, a, b)));
        (subjects.iter().copied())
            .filter(|&a| landmarks.iter().any(|&b| a != b && holds(a, b)))
            .collect()
    }

    fn along(&self, i: usize, axis: [f64; 3]) -> f64 {
        let (p, agent) = (self.scene.objects[i].position, self.scene.agent.position);
        (0..3).map(|k| (p[k] - agent[k]) * axis[k]).sum()
    }

    /// A superlative's measure of object `i`; `None` when it lacks what is compared.
    fn measure(&self, i: usize, word: &str) -> Option<f64> {
        let o = &self.scene.objects[i];
        let radius = match o.shape {
            Some(Shape::Cylinder { radius, .. }) => Some(radius),
            _ => None,
        };
        let (p, agent) = (o.position, self.scene.agent.position);
        match word {
            "biggest" | "smallest" => radius.map(|r| 2.0 * r * 2.0 * r * 3.0 * r),
            "tallest" | "shortest" => radius.map(|r| 3.0 * r),
            "heaviest" | "lightest" => o.mass,
            "nearest" | "farthest" => Some((0..3).map(|k| (p[k] - agent[k]).powi(2)).sum::<f64>().sqrt()),
            "highest" | "lowest" => Some(p[2]),
            _ => Some(self.along(i, self.left)),
        }
    }

    /// The best by the superlative and those within 5% of it; nothing when one lacks the measure.
    fn most(&self, among: &[usize], superlative: usize) -> Vec<usize> {
        let (word, most) = SUPERLATIVES[superlative];
        let Some(values) = among
            .iter()
            .map(|&i| self.measure(i, word))
            .collect::<Option<Vec<f64>>>()
        else {
            return Vec::new();
        };
        let pick = |a: f64, b: f64| if most { a.max(b) } else { a.min(b) };
        let Some(best) = values.iter().copied().reduce(pick) else {
            return Vec::new();
        };
        (among.iter().zip(&values))
            .filter(|(_, v)| (*v - best).abs() <= TIE_SHARE * best.abs())
            .map(|(&i, _)| i)
            .collect()
    }

    /// The objects that may be the nth counting from the direction: fewer than n lie clearly
    /// (by more than the side margin) before it, and fewer than its count less n clearly after.
    fn nth(&self, among: &[usize], ordinal: usize, direction: usize) -> Vec<usize> {
        let n = ORDINALS[ordinal].1;
        let value = |i: usize| match DIRECTIONS[direction] {
            "left" => self.along(i, self.left),
            "right" => -self.along(i, self.left),
            "front" => -self.along(i, self.forward),
            _ => self.along(i, self.forward),
        };
        let count = |keep: &dyn Fn(f64) -> bool| among.iter().filter(|&&j| keep(value(j))).count();
        (among.iter().copied())
            .filter(|&i| {
                let v = value(i);
                count(&|w| w > v + SIDE_MARGIN) < n && n <= among.len() - count(&|w| w < v - SIDE_MARGIN)
            })
            .collect()
    }

    /// The objects the words mean; none when a word is one the scene does not know (a colour
    /// no object has is such a word).
    fn of(&self, words: &Words, nouns: &Nouns) -> Vec<usize> {
        let known = |c: &str| (self.scene.objects.iter()).any(|o| o.attributes.get("color").is_some_and(|v| v == c));
        if words.unknown() || words.form >= 8 && !known(nouns.colour) {
            return Vec::new();
        }
        let [p0, p1] = nouns.phrases;
        let t0 = self.of_kind(&nouns.head, None);
        let t1 = self.of_kind(&nouns.landmarks[0], None);
        let r0 = || self.related(&t0, p0, &t1);
        let without = |set: Vec<usize>| {
            let coloured = self.of_kind(&nouns.head, Some((nouns.colour, true)));
            set.into_iter().filter(|i| !coloured.contains(i)).collect()
        };
        match words.form {
            0 | 1 => r0(),
            2 => {
                let related = r0();
                t0.into_iter().filter(|i| !related.contains(i)).collect()
            }
            3 => self.most(&t0, words.superlative),
            4 => self.most(&r0(), words.superlative),
            5 => self.nth(&t0, words.ordinal, words.direction),
            6 => self.nth(&r0(), words.ordinal, words.direction),
            7 => {
                let t2 = self.of_kind(&nouns.landmarks[1], None);
                let mut union = self.related(&t0, p0, &self.related(&t1, p1, &t2));
                union.extend(self.related(&r0(), p1, &t2));
                union.sort_unstable();
                union.dedup();
                union
            }
            8 => without(t0.clone()),
            9 => self.related(&self.of_kind(&nouns.head, Some((nouns.colour, true))), p0, &t1),
            _ => without(r0()),
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    /// Where facts alone relate objects, "Get <words>." selects exactly the objects CONTRACT.md
    /// says the words mean, and the decision (any verb, any norms) acts on or offers none
    /// other; with a word no scene knows in any slot, it acts on and offers nothing.
    #[test]
    fn relation_words_never_act_on_what_they_do_not_mean(
        stated in arb_stated(),
        words in arb_words(),
        verb in prop::sample::select(vec!["Get", "Point to", "Destroy"]),
        given in prop::collection::vec(arb_norm(), 0..=2),
    ) {
        let scene = stated.scene();
        let said = words.said(&scene);
        let meant = Meaning::new(&stated, &scene).of(&words, &words.nouns(&scene));
        let meant: Vec<String> = meant.iter().map(|&i| scene.objects[i].id.to_string()).collect();
        let shown = || format!("{said}: {meant:?}\n{}", show(&scene));
        match read(&format!("Get {said}."), &scene) {
            Ok((_, candidates)) => prop_assert_eq!(candidates, vec![meant.clone()], "{}", shown()),
            Err((why, _)) => prop_assert!(words.unknown(), "{:?}: {}", why, shown()),
        }
        let d = run(&request(Directive::Words { text: format!("{verb} {said}.") }), &scene, &norms(&given));
        for action in d.offered.iter().chain(&d.goal) {
            let object = action.args().get(1).and_then(|a| a.args().first()).map(Term::to_string);
            prop_assert!(object.is_some_and(|o| meant.contains(&o)), "{} {}: {}", verb, action, shown());
        }
        if words.unknown() {
            prop_assert!(matches!(d.kind, Unresolved | NotUnderstood), "{}: {}", d.kind.as_str(), shown());
            prop_assert!(d.offered.is_empty() && d.goal.is_none());
        }
    }
}

/// The never-guess property's cases mean something in every form, and act on or offer it.
#[test]
fn relation_words_mean_something_in_every_form() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    use std::collections::BTreeMap;

    let mut runner = TestRunner::deterministic();
    let (mut meaning, mut acted) = (BTreeMap::new(), 0);
    for _ in 0..1500 {
        let (stated, words) = (arb_stated(), arb_words())
            .new_tree(&mut runner)
            .expect("a case")
            .current();
        let scene = stated.scene();
        if !Meaning::new(&stated, &scene)
            .of(&words, &words.nouns(&scene))
            .is_empty()
        {
            *meaning.entry(words.form).or_insert(0) += 1;
        }
        let text = format!("Get {}.", words.said(&scene));
        acted += usize::from(
            !run(&request(Directive::Words { text }), &scene, &norms(&[]))
                .offered
                .is_empty(),
        );
    }
    assert!(
        (0..11u8).all(|f| meaning.get(&f).is_some_and(|&n| n >= 20)),
        "meaning by form: {meaning:?}"
    );
    assert!(acted >= 500, "acted on or offered: {acted}");
}
