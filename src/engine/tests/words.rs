//! The words table: each construction of the grammar, with a case it takes and one it must not;
//! every kind of words that are not a directive; and that a word the scene does not know
//! inside a reference makes it match nothing (never another object).

use super::fixtures::{lab, office, paper_norms, request, run};
use crate::engine::action::Library;
use crate::engine::decision::{DecisionKind, Unclear};
use crate::engine::request::Directive;
use crate::engine::resolve::Reference;
use crate::engine::scene::Scene;
use crate::engine::words::{Understanding, heard, inflects, understand};

/// A verb and each reference's candidates in the scene.
type Read = (String, Vec<Vec<String>>);

/// The directive the words are read as, in the structured form's terms: the verb and each
/// reference's candidates in the scene.
pub(super) fn read(text: &str, scene: &Scene) -> Result<Read, (Unclear, String)> {
    match understand(text, scene, &Library::default_library(), heard(&[]), &|| false) {
        Understanding::Directive {
            directive: Directive::Action { verb, arguments, .. },
            ..
        } => {
            let candidates = arguments
                .iter()
                .map(|r| {
                    (r.select(scene, &|| false).expect("no deadline").objects.iter())
                        .map(|&i| scene.objects[i].id.to_string())
                        .collect()
                })
                .collect();
            Ok((verb, candidates))
        }
        Understanding::Directive { directive, .. } => panic!("{text}: read as {directive:?}"),
        Understanding::NotUnderstood { why, words } => Err((why, words)),
        Understanding::Expired => panic!("{text}: no deadline was set"),
    }
}

pub(super) fn ids(list: &[&str]) -> Vec<String> {
    list.iter().map(|s| (*s).to_owned()).collect()
}

#[test]
fn the_constructions_the_grammar_takes() {
    let lab = lab();
    let office = office();
    let cases: &[(&str, &Scene, &str, &[&[&str]])] = &[
        ("Get the vase.", &lab, "get", &[&["object3", "object4"]]),
        ("get the vase", &lab, "get", &[&["object3", "object4"]]),
        ("GET THE VASE!", &lab, "get", &[&["object3", "object4"]]),
        (
            "Pepper, can you go steal the cash box for me?",
            &office,
            "steal",
            &[&["box1", "box2"]],
        ),
        ("Get the vase, robot.", &lab, "get", &[&["object3", "object4"]]),
        (
            "Could you please destroy the red notebook?",
            &lab,
            "destroy",
            &[&["object1"]],
        ),
        ("Would you mind getting the mug?", &lab, "get", &[&["object5"]]),
        ("I want you to get the plastic vase.", &lab, "get", &[&["object4"]]),
        ("I'd like you to grab the fragile vase.", &lab, "get", &[&["object3"]]),
        ("Go and fetch the mug.", &lab, "get", &[&["object5"]]),
        ("Get the mug, please.", &lab, "get", &[&["object5"]]),
        ("Please pick up the mug.", &lab, "get", &[&["object5"]]),
        ("Pick the mug up.", &lab, "get", &[&["object5"]]),
        ("Hand me the mug.", &lab, "give", &[&["object5"]]),
        ("Get the green one.", &lab, "get", &[&["object2"]]),
        ("Get a notebook.", &lab, "get", &[&["object1", "object2"]]),
        ("Get the mug for reheating.", &lab, "get", &[&["object5"]]),
        ("Get the mug now", &lab, "get", &[&["object5"]]),
        (
            "Put the mug on the red notebook.",
            &lab,
            "put",
            &[&["object5"], &["object1"]],
        ),
        (
            "Place the mug onto the green notebook",
            &lab,
            "put",
            &[&["object5"], &["object2"]],
        ),
        ("Point to the mug.", &lab, "pointTo", &[&["object5"]]),
        ("Juggle the mug.", &lab, "juggle", &[&["object5"]]),
        ("Smash the plastic vase", &lab, "destroy", &[&["object4"]]),
    ];
    for (text, scene, verb, candidates) in cases {
        let expected: Vec<Vec<String>> = candidates.iter().map(|c| ids(c)).collect();
        assert_eq!(read(text, scene), Ok(((*verb).to_owned(), expected)), "{text}");
    }
}

#[test]
fn a_word_the_scene_does_not_know_inside_a_reference_matches_nothing() {
    let lab = lab();
    for text in [
        "Get the wet mug.",
        "Get the gizmo.",
        "Get the blue notebook.",
        "Get the mug on the notebook.",
        "Get the second mug.",
        "Get some mugs.",
        "Get the one.",
        "Get it.",
    ] {
        let (_, candidates) = read(text, &lab).unwrap_or_else(|e| panic!("{text}: {e:?}"));
        assert_eq!(candidates, vec![Vec::<String>::new()], "{text} must match nothing");
    }
}

#[test]
fn words_that_are_not_a_directive_are_said_to_be_so() {
    let lab = lab();
    let cases = [
        ("What color is the mug?", Unclear::Question),
        ("Is the vase fragile?", Unclear::Question),
        ("Can I tell the mug?", Unclear::Question),
        ("Don't destroy the notebook.", Unclear::Negated),
        ("Do not destroy the notebook.", Unclear::Negated),
        (
            "Get the mug and get the mug and get the mug and get the mug and get the mug and get the mug and get \
             the mug and get the mug and get the mug.",
            Unclear::Several,
        ),
        ("mug vase notebook", Unclear::Unplaced),
        ("Put the mug.", Unclear::Unplaced),
        ("", Unclear::Empty),
        ("Please.", Unclear::Empty),
        ("Pepper, please.", Unclear::Empty),
    ];
    for (text, why) in cases {
        assert_eq!(read(text, &lab).map_err(|e| e.0), Err(why), "{text}");
    }
}

#[test]
fn a_verbs_first_word_is_understood_inflected_and_nothing_else_is() {
    for (token, word) in [
        ("gets", "get"),
        ("got", "get"),
        ("getting", "get"),
        ("grabbed", "grab"),
        ("placing", "place"),
        ("placed", "place"),
        ("fetches", "fetch"),
        ("stole", "steal"),
        ("putting", "put"),
    ] {
        assert!(inflects(token, word), "{token} is {word}");
    }
    for (token, word) in [("gate", "get"), ("getaway", "get"), ("plac", "place"), ("set", "get")] {
        assert!(!inflects(token, word), "{token} is not {word}");
    }
}

#[test]
fn a_pronoun_is_the_first_object_in_focus() {
    let lab = lab();
    let focus = ids(&["object4", "object3"]);
    match understand("Get it.", &lab, &Library::default_library(), heard(&focus), &|| false) {
        Understanding::Directive {
            directive: Directive::Action { arguments, .. },
            ..
        } => assert_eq!(arguments, vec![Reference::Id("object4".into())]),
        other => panic!("{other:?}"),
    }
}

/// The paper's cases, sent as words, decide as their structured directives do.
#[test]
fn the_paper_in_words_decides_as_the_structured_directive() {
    let norms = paper_norms();
    let lab = lab();
    for (text, scene, kind) in [
        ("Get the mug.", &lab, DecisionKind::Comply),
        ("Destroy the mug.", &lab, DecisionKind::Refuse),
        ("Get the notebook.", &lab, DecisionKind::Ask),
        ("Destroy the notebook.", &lab, DecisionKind::Explain),
        ("Get the vase.", &lab, DecisionKind::Assume),
    ] {
        let words = run(&request(Directive::Words { text: text.into() }), scene, &norms);
        assert_eq!(words.kind, kind, "{text}");
        let Ok((verb, _)) = read(text, scene) else {
            panic!("{text}")
        };
        let noun = text.trim_end_matches('.').rsplit(' ').next().unwrap();
        let structured = run(
            &request(Directive::Action {
                verb,
                arguments: vec![super::fixtures::ty(noun)],
                joiner: None,
            }),
            scene,
            &norms,
        );
        assert_eq!(words.utterance, structured.utterance, "{text}");
        assert_eq!(words.speech_act, structured.speech_act, "{text}");
        assert_eq!(words.goal, structured.goal, "{text}");
        assert_eq!(words.interpretations, structured.interpretations, "{text}");
        let parse = words.parse.as_ref().expect("a parse");
        assert_eq!(
            parse.form.as_ref().unwrap().to_string(),
            format!(
                "want(human,did(self,{}(X)))",
                if text.starts_with("Get") { "get" } else { "destroy" }
            )
        );
    }
}

mod never_guess {
    use proptest::prelude::*;

    use super::super::fixtures::{lab, paper_norms, request, run};
    use crate::engine::decision::DecisionKind;
    use crate::engine::request::Directive;
    use crate::engine::term::Term;

    const VERBS: &[&str] = &[
        "get",
        "grab",
        "take",
        "destroy",
        "Could you get",
        "please fetch",
        "smash",
    ];
    const DETERMINERS: &[&str] = &["the", "a", "", "that"];
    /// The lab's adjectives, and words it does not know: among them signs and emoji, which are
    /// words too (dropping them made "the ★ vase" every vase).
    const ADJECTIVES: &[&str] = &[
        "red", "green", "fragile", "plastic", "wet", "blue", "shiny", "second", "★", "🏺", "#", "r3d",
    ];
    const NOUNS: &[&str] = &[
        "vase", "notebook", "mug", "gizmo", "cup", "one", "vases", "vase™", "v@se",
    ];
    /// Endings that must never be dropped: narrowings, negations, purposes, steps, junk.
    const TRAILING: &[&str] = &[
        "",
        ".",
        "!",
        ", please",
        " now",
        " for me",
        ", not the red one",
        ", not red",
        ", the green one",
        " not the red one",
        " to smash it",
        ", then destroy it",
        ", don't",
        " pls",
        ", the ★ one",
        ", Pepper",
        " that is not red",
        " but the red one",
        " which is green",
    ];

    fn scenes() -> Vec<crate::engine::scene::Scene> {
        vec![
            lab(),
            super::super::words_hostile::red_cup_and_notebook(),
            super::super::fixtures::office(),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(
            std::env::var("SCRUPLE_PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(1000)
        ))]

        /// Words with one the scene does not know are `unresolved` or `not_understood`, nothing
        /// offered and nothing acted on; and whatever is offered, confirmed or acted on is an
        /// object every content word is true of, and no narrowing word excludes.
        #[test]
        fn nothing_outside_what_the_words_say_is_offered_or_acted_on(
            verb in prop::sample::select(VERBS),
            determiner in prop::sample::select(DETERMINERS),
            adjectives in prop::collection::vec(prop::sample::select(ADJECTIVES), 0..3),
            noun in prop::sample::select(NOUNS),
            trailing in prop::sample::select(TRAILING),
            which in 0..3usize,
        ) {
            let mut words = vec![verb.to_owned()];
            words.extend([determiner].iter().filter(|d| !d.is_empty()).map(|d| (*d).to_owned()));
            words.extend(adjectives.iter().map(|a| (*a).to_owned()));
            words.push(noun.to_owned());
            let text = format!("{}{trailing}", words.join(" "));
            let scene = scenes().swap_remove(which);
            let decision = run(&request(Directive::Words { text: text.clone() }), &scene, &paper_norms());
            let known = |w: &str| scene.objects.iter().any(|o| {
                o.kind == w || o.properties.iter().any(|p| p == w) || o.attributes.values().any(|v| v == w)
            });
            // "vases" is every vase the rest says: one step each.
            let kind = if noun == "vases" { "vase" } else { noun };
            let unknown = !(noun == "one" || known(kind)) || adjectives.iter().any(|a| !known(a));
            if unknown {
                prop_assert!(
                    matches!(decision.kind, DecisionKind::Unresolved | DecisionKind::NotUnderstood),
                    "{text}: {} ({})", decision.utterance, decision.kind.as_str()
                );
                prop_assert!(decision.offered.is_empty() && decision.goal.is_none(), "{text}: {:?}", decision.offered);
            }
            // `did(self,verb(object))`, or `did(self,and(verb(o1),verb(o2),…))` for a plural.
            let acts = |action: &Term| -> Vec<Term> {
                match action.args().get(1) {
                    Some(reading) if crate::engine::describe::is_task(reading) => reading.args().to_vec(),
                    Some(reading) => vec![reading.clone()],
                    None => Vec::new(),
                }
            };
            for (action, act) in (decision.offered.iter().chain(&decision.goal)).flat_map(|a| acts(a).into_iter().map(move |s| (a, s))) {
                let Some(Term::Const(id)) = act.args().first() else {
                    return Err(TestCaseError::fail(format!("{text}: offered {action}")));
                };
                let object = scene.object(id).unwrap();
                prop_assert!(noun == "one" || object.kind == kind, "{text}: {} is a {}", id, object.kind);
                let true_of = |a: &str| object.properties.iter().any(|p| p == a) || object.attributes.values().any(|v| v == a);
                for a in &adjectives {
                    prop_assert!(true_of(a), "{text}: `{a}` is not true of {id}");
                }
                if trailing.contains("not the red") || trailing.contains("not red") || trailing.contains("but the red") {
                    prop_assert!(!true_of("red"), "{text}: {id} is red");
                }
                if trailing.contains("the green one") || trailing.contains("is green") {
                    prop_assert!(true_of("green"), "{text}: {id} is not green");
                }
            }
        }
    }
}

pub(super) fn said(text: &str) -> crate::engine::request::Request {
    request(Directive::Words { text: text.into() })
}

pub(super) fn answered(text: &str, answer: &str) -> crate::engine::request::Request {
    crate::engine::request::Request {
        answer: Some(crate::engine::request::Answer::Words(answer.into())),
        ..said(text)
    }
}

#[test]
fn an_objects_names_are_nouns_for_it_and_only_for_it() {
    let scene = super::fixtures::lab_with(|objects| objects[4].names = vec!["coffee cup".into(), "drink".into()]);
    assert_eq!(
        read("Get the coffee cup.", &scene),
        Ok(("get".into(), vec![ids(&["object5"])]))
    );
    assert_eq!(
        read("Get the drink.", &scene),
        Ok(("get".into(), vec![ids(&["object5"])]))
    );
    // A name another object does not have names nothing, rather than the nearest thing.
    assert_eq!(read("Get the soda.", &scene), Ok(("get".into(), vec![Vec::new()])));
}

#[test]
fn an_indefinite_reference_takes_the_first_acceptable_reading_and_explains_the_rest() {
    let norms = paper_norms();
    // Both notebooks may be got: "a notebook" is either, so the first is taken and said so.
    let d = run(&said("Get a notebook."), &lab(), &norms);
    assert_eq!(d.kind, DecisionKind::Assume);
    assert_eq!(d.utterance, "I am assuming you want me to get the green notebook.");
    // One vase is forbidden: as for "the vase", the other is assumed and the first explained.
    let d = run(&said("Get a vase."), &lab(), &norms);
    assert_eq!(d.kind, DecisionKind::Assume);
    assert!(
        d.utterance
            .ends_with("I cannot get the fragile vase because it requires a forbidden state."),
        "{}",
        d.utterance
    );
    // "the" still asks: the human named one notebook, and the robot does not pick it.
    assert_eq!(run(&said("Get the notebook."), &lab(), &norms).kind, DecisionKind::Ask);
    // Nothing may be destroyed: an indefinite does not make a forbidden reading acceptable.
    assert_eq!(
        run(&said("Destroy a notebook."), &lab(), &norms).kind,
        DecisionKind::Explain
    );
}

#[test]
fn follow_up_answers_in_words() {
    let norms = paper_norms();
    let pick = |answer: &str| run(&answered("Get the notebook.", answer), &lab(), &norms);
    for (answer, goal) in [
        ("the red one", "did(self,get(object1))"),
        ("The green notebook.", "did(self,get(object2))"),
        // The question names the green notebook first, then the red one.
        ("the second one", "did(self,get(object1))"),
        ("first", "did(self,get(object2))"),
        ("object2", "did(self,get(object2))"),
        ("I mean the red one, please", "did(self,get(object1))"),
    ] {
        let d = pick(answer);
        assert_eq!(
            d.goal.as_ref().map(|g| g.to_string()).as_deref(),
            Some(goal),
            "{answer}: {}",
            d.utterance
        );
    }
    // An answer with a word the scene does not know keeps nothing.
    assert_eq!(pick("the blue one").kind, DecisionKind::Unresolved);
    // "yes" and "no" answer a question to confirm; after anything else they answer nothing.
    assert_eq!(pick("yes").kind, DecisionKind::NotUnderstood);
    let confirm = |answer: &str| {
        let request = super::fixtures::confirming(answered("Get the vase.", answer));
        run(&request, &lab(), &norms)
    };
    let yes = confirm("yes");
    assert_eq!(yes.kind, DecisionKind::Comply);
    assert_eq!(yes.goal.as_ref().unwrap().to_string(), "did(self,get(object4))");
    let no = confirm("No.");
    assert_eq!(no.kind, DecisionKind::Cancelled);
    assert_eq!(no.utterance, "Okay, I will not.");
    assert_eq!(no.speech_act.to_string(), "acknowledge(self,cancel(human))");
    assert!(no.goal.is_none() && no.interpretations.is_empty() && no.offered.is_empty());
}

/// Each construction's negative: words that look like it but are not it, and what they are
/// read as instead. None of them picks an object the human did not name.
#[test]
fn what_each_construction_does_not_take() {
    let lab = lab();
    type Expected = Result<(&'static str, &'static [&'static [&'static str]]), Unclear>;
    let cases: &[(&str, Expected)] = &[
        // A vocative is one or two words: three are no name; the first word is then taken as
        // an unknown verb, and its reference, words it cannot place, names nothing.
        ("Pepper the robot, get the mug.", Ok(("pepper", &[&[]]))),
        // "can I" asks for information, not for an action.
        ("Can I see the mug?", Err(Unclear::Question)),
        // "pick" alone is no verb's word: the unknown verb it names, not `get`.
        ("Pick the mug.", Ok(("pick", &[&["object5"]]))),
        // Two references with no joiner between them do not say which is which.
        ("Put the mug the notebook.", Err(Unclear::Unplaced)),
        // "in" joins put's arguments, but "under" does not: the words stay in the reference.
        ("Put the mug under the red notebook.", Err(Unclear::Unplaced)),
        // "go" with no verb after it is not the "go X" frame.
        ("Go to the mug.", Err(Unclear::Unplaced)),
        // A beneficiary needs a reference after it.
        ("Get me.", Ok(("get", &[&[]]))),
        // An adjunct word inside a reference cuts it short; what is left names nothing.
        ("Get the quickly mug.", Ok(("get", &[&[]]))),
        // A preposition or a pronoun is never the unknown verb an imperative names.
        ("On the mug.", Err(Unclear::Unplaced)),
        ("It the mug.", Err(Unclear::Unplaced)),
        // "this" alone is a pronoun, and there is no focus.
        ("Destroy this.", Ok(("destroy", &[&[]]))),
    ];
    for (text, expected) in cases {
        let expected = (*expected)
            .map(|(verb, candidates)| (verb.to_owned(), candidates.iter().map(|c| ids(c)).collect::<Vec<_>>()));
        assert_eq!(read(text, &lab).map_err(|e| e.0), expected, "{text}");
    }
}

#[test]
fn a_verb_of_no_arguments_takes_no_reference() {
    let mut library = Library::default_library();
    let wave: crate::engine::action::ActionInput =
        serde_json::from_str(r#"{"parameters": [], "methods": [{}], "words": ["wave"]}"#).unwrap();
    library.insert(wave.validate("wave").unwrap()).unwrap();
    for (text, taken) in [
        ("Wave.", true),
        ("Could you wave now, please?", true),
        ("Wave the mug.", false),
    ] {
        let understood = understand(text, &lab(), &library, heard(&[]), &|| false);
        let is_wave = matches!(&understood, Understanding::Directive { directive: Directive::Action { verb, arguments, .. }, .. } if verb == "wave" && arguments.is_empty());
        assert_eq!(is_wave, taken, "{text}: {understood:?}");
    }
}

#[test]
fn a_sign_or_an_emoji_is_a_word_not_known_and_the_robot_says_it() {
    let norms = paper_norms();
    for (text, unknown) in [
        ("Get the ★ vase.", "the ★ vase"),
        ("Get the 🏺.", "the 🏺"),
        ("Get the vase™.", "the vase™"),
        ("Destroy the # notebook!", "the # notebook"),
    ] {
        let d = run(&said(text), &lab(), &norms);
        assert_eq!(d.kind, DecisionKind::Unresolved, "{text}: {}", d.utterance);
        assert_eq!(
            d.utterance,
            format!("I do not know what you mean by {unknown}."),
            "{text}"
        );
    }
    // The punctuation of a sentence, quotes and invisible characters are still no words.
    for text in [
        "Get the «vase»!?",
        "Get the “vase”…",
        "Get the va\u{200b}se.",
        "\u{feff}Get the vase.",
    ] {
        assert_eq!(run(&said(text), &lab(), &norms).kind, DecisionKind::Assume, "{text}");
    }
}

/// Exclusion and relative clauses inside one reference (the references issue's first part):
/// what follows "that is", "but", "except", "other than" narrows, and words it cannot place
/// make the reference match nothing.
#[test]
fn exclusion_and_relative_clauses_narrow_a_reference() {
    let lab = lab();
    for (text, expected) in [
        (
            "Get the notebook that is not red.",
            Ok(("get", vec![ids(&["object2"])])),
        ),
        ("Get the notebook which is red.", Ok(("get", vec![ids(&["object1"])]))),
        ("Get the vase that is fragile.", Ok(("get", vec![ids(&["object3"])]))),
        (
            "Get any notebook but the red one.",
            Ok(("get", vec![ids(&["object2"])])),
        ),
        (
            "Get any vase except the fragile one.",
            Ok(("get", vec![ids(&["object4"])])),
        ),
        (
            "Get a vase other than the plastic one.",
            Ok(("get", vec![ids(&["object3"])])),
        ),
        ("Get any notebook.", Ok(("get", vec![ids(&["object1", "object2"])]))),
        // Words the scene does not know after the clause: nothing, never every notebook.
        ("Get the notebook that is not wet.", Ok(("get", vec![vec![]]))),
        ("Get the notebook but the ★ one.", Ok(("get", vec![vec![]]))),
        ("Get the notebook but.", Ok(("get", vec![vec![]]))),
        ("Get the notebook that is on the table.", Ok(("get", vec![vec![]]))),
    ] {
        let got = read(text, &lab);
        let expected = expected.map(|(verb, candidates): (&str, Vec<Vec<String>>)| (verb.to_owned(), candidates));
        assert_eq!(got, expected, "{text}");
    }
    // "any" is an indefinite: any acceptable one will do.
    let d = run(&said("Get any notebook but the red one."), &lab, &paper_norms());
    assert_eq!(
        d.goal.as_ref().map(ToString::to_string).as_deref(),
        Some("did(self,get(object2))")
    );
    let d = run(&said("Get any vase."), &lab, &paper_norms());
    assert_eq!(d.kind, DecisionKind::Assume, "{}", d.utterance);
}
