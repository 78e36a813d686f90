//! The words table: each construction of the grammar, with a case it takes and one it must not;
//! every kind of words that are not a directive; and that a word the scene does not know
//! inside a reference makes it match nothing (never another object).

use super::fixtures::{lab, office, paper_norms, request, run};
use crate::engine::action::Library;
use crate::engine::decision::{DecisionKind, Unclear};
use crate::engine::request::Directive;
use crate::engine::resolve::Reference;
use crate::engine::scene::Scene;
use crate::engine::words::{Understanding, inflects, understand};

/// A verb and each reference's candidates in the scene.
type Read = (String, Vec<Vec<String>>);

/// The directive the words are read as, in the structured form's terms: the verb and each
/// reference's candidates in the scene.
fn read(text: &str, scene: &Scene) -> Result<Read, (Unclear, String)> {
    match understand(text, scene, &Library::default_library(), &[], &|| false) {
        Understanding::Directive {
            directive: Directive::Action { verb, arguments },
            ..
        } => {
            let candidates = arguments
                .iter()
                .map(|r| {
                    (scene.objects.iter())
                        .filter(|o| r.matches(o))
                        .map(|o| o.id.to_string())
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

fn ids(list: &[&str]) -> Vec<String> {
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
        ("Hand me the mug.", &lab, "get", &[&["object5"]]),
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
        "Get the mugs.",
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
        ("Can I get the mug?", Unclear::Question),
        ("Don't destroy the notebook.", Unclear::Negated),
        ("Do not destroy the notebook.", Unclear::Negated),
        ("Get the mug and destroy the vase.", Unclear::Several),
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
    match understand("Get it.", &lab, &Library::default_library(), &focus, &|| false) {
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
    ];

    fn scenes() -> Vec<crate::engine::scene::Scene> {
        vec![lab(), super::red_cup_and_notebook(), super::super::fixtures::office()]
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
            let unknown = !(noun == "one" || known(noun)) || adjectives.iter().any(|a| !known(a));
            if unknown {
                prop_assert!(
                    matches!(decision.kind, DecisionKind::Unresolved | DecisionKind::NotUnderstood),
                    "{text}: {} ({})", decision.utterance, decision.kind.as_str()
                );
                prop_assert!(decision.offered.is_empty() && decision.goal.is_none(), "{text}: {:?}", decision.offered);
            }
            for action in decision.offered.iter().chain(&decision.goal) {
                // `did(self,verb(object))`.
                let Some(Term::Const(id)) = action.args().get(1).and_then(|action| action.args().first()) else {
                    return Err(TestCaseError::fail(format!("{text}: offered {action}")));
                };
                let object = scene.object(id).unwrap();
                prop_assert!(noun == "one" || object.kind == noun, "{text}: {} is a {}", id, object.kind);
                let true_of = |a: &str| object.properties.iter().any(|p| p == a) || object.attributes.values().any(|v| v == a);
                for a in &adjectives {
                    prop_assert!(true_of(a), "{text}: `{a}` is not true of {id}");
                }
                if trailing.contains("not the red") || trailing.contains("not red") {
                    prop_assert!(!true_of("red"), "{text}: {id} is red");
                }
                if trailing.contains("the green one") {
                    prop_assert!(true_of("green"), "{text}: {id} is not green");
                }
            }
        }
    }
}

fn said(text: &str) -> crate::engine::request::Request {
    request(Directive::Words { text: text.into() })
}

fn answered(text: &str, answer: &str) -> crate::engine::request::Request {
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

/// One red cup and one red notebook (issue 50's scene): words after the reference that narrow
/// or negate it were taken as an addressee or left out, and the red object obeyed.
fn red_cup_and_notebook() -> Scene {
    use super::fixtures::{obj, scene};
    scene(
        vec![
            obj("cup1", "cup", &[], &[("color", "red")], [0.5, 0.0, 0.8], None),
            obj(
                "notebook1",
                "notebook",
                &[],
                &[("color", "red")],
                [0.5, 0.2, 0.76],
                None,
            ),
            obj("fork1", "fork", &[], &[], [0.5, 0.4, 0.76], None),
        ],
        &[],
    )
}

#[test]
fn trailing_words_that_narrow_or_negate_are_never_an_addressee_or_left_out() {
    let scene = red_cup_and_notebook();
    let norms = paper_norms();
    for text in [
        "Get the cup, blue one.",
        "Get the cup, not red.",
        "Get the cup now, the blue one.",
        "Get the notebook for me, not the red one.",
        "Get the cup, don't.",
        "Get the cup not the red one.",
        "Get the cup to the right of the fork.",
        "Get the cup, the ★ one.",
        "Get the cup, not the ★ one.",
    ] {
        let d = run(&said(text), &scene, &norms);
        assert!(d.goal.is_none(), "{text}: {} ({})", d.utterance, d.kind.as_str());
        assert!(
            matches!(d.kind, DecisionKind::Unresolved | DecisionKind::NotUnderstood),
            "{text}: {}",
            d.kind.as_str()
        );
        assert!(
            d.parse.as_ref().is_none_or(|p| p.addressee.is_none()),
            "{text}: {:?}",
            d.parse
        );
    }
    // What narrows is read, not dropped: the words the human added to the reference hold too.
    for (text, goal) in [
        ("Get the cup, the red one.", "did(self,get(cup1))"),
        ("Get the cup, red one.", "did(self,get(cup1))"),
        ("Get the notebook now, the red one.", "did(self,get(notebook1))"),
    ] {
        let d = run(&said(text), &scene, &norms);
        assert_eq!(
            d.goal.as_ref().map(ToString::to_string).as_deref(),
            Some(goal),
            "{text}: {}",
            d.utterance
        );
    }
    let lab = lab();
    for (text, goal) in [
        ("Get the notebook, not the red one.", "did(self,get(object2))"),
        ("Get the notebook, not red.", "did(self,get(object2))"),
        ("Get the notebook not the green one", "did(self,get(object1))"),
    ] {
        let d = run(&said(text), &lab, &norms);
        assert_eq!(
            d.goal.as_ref().map(ToString::to_string).as_deref(),
            Some(goal),
            "{text}: {}",
            d.utterance
        );
    }
}

#[test]
fn a_vocative_is_a_name_never_a_verb_or_the_words_of_a_reference() {
    let lab = lab();
    let focus = ids(&["object5"]);
    for text in [
        "Grab it, Pepper.",
        "Grab it, please.",
        "Pepper, grab it.",
        "Grab it, please, Pepper.",
    ] {
        let understood = understand(text, &lab, &Library::default_library(), &focus, &|| false);
        let Understanding::Directive { directive, parse } = understood else {
            panic!("{text}: {understood:?}")
        };
        assert_eq!(
            directive,
            Directive::Action {
                verb: "get".into(),
                arguments: vec![Reference::Id("object5".into())]
            },
            "{text}"
        );
        let expected = text.contains("Pepper").then(|| "pepper".to_owned());
        assert_eq!(parse.addressee, expected, "{text}");
    }
}

#[test]
fn a_purpose_or_a_further_step_is_never_left_out() {
    let lab = lab();
    let norms = paper_norms();
    for (text, why) in [
        // "smash" is destroy's word: a purpose the norms could forbid is not read yet.
        ("Grab the mug to smash the vase.", Unclear::Unplaced),
        ("Grab the mug in order to destroy the notebook.", Unclear::Unplaced),
        ("Grab the mug so I can smash it.", Unclear::Unplaced),
        ("Get the mug for smashing the vase.", Unclear::Unplaced),
        ("Get the mug to not reheat it.", Unclear::Unplaced),
        ("Grab the mug, then smash.", Unclear::Several),
        ("Grab the mug, and destroy the vase.", Unclear::Several),
    ] {
        let d = run(&said(text), &lab, &norms);
        assert_eq!(d.kind, DecisionKind::NotUnderstood, "{text}: {}", d.utterance);
        assert_eq!(d.parse.as_ref().and_then(|p| p.unclear), Some(why), "{text}");
        assert!(d.goal.is_none());
    }
    let d = run(&said("Grab the mug to smash the vase."), &lab, &norms);
    assert_eq!(d.utterance, "I did not understand \"to smash the vase\".");
    // A purpose of a verb the robot does not know changes nothing, and is shown.
    let d = run(&said("Get the mug for reheating."), &lab, &norms);
    assert_eq!(d.kind, DecisionKind::Comply);
    assert_eq!(d.parse.as_ref().unwrap().ignored, vec!["for reheating".to_owned()]);
}

#[test]
fn only_words_of_how_and_when_are_left_out() {
    let lab = lab();
    let norms = paper_norms();
    for (text, ignored) in [
        ("Get the mug now.", &["now"][..]),
        ("Quickly get the mug, please.", &["quickly"]),
        ("Get the mug right now, carefully.", &["right now", "carefully"]),
        ("Get the mug for me, thanks.", &[]),
    ] {
        let d = run(&said(text), &lab, &norms);
        assert_eq!(d.kind, DecisionKind::Comply, "{text}: {}", d.utterance);
        assert_eq!(d.parse.as_ref().unwrap().ignored, ignored, "{text}");
    }
    // Anything else is read: a word after the reference that cannot be placed is said back.
    let d = run(&said("Get the mug pls."), &lab, &norms);
    assert_eq!(d.kind, DecisionKind::Unresolved);
    assert_eq!(d.utterance, "I do not understand \"pls\" in \"the mug pls\".");
    let natural = super::fixtures::natural(said("Get the second notebook."));
    let d = run(&natural, &lab, &norms);
    assert_eq!(
        d.utterance,
        "I do not understand \"second\" in \"the second notebook\"."
    );
    // Words understood that describe nothing here are still "cannot find".
    let d = run(&super::fixtures::natural(said("Get the wet mug.")), &lab, &norms);
    assert_eq!(d.utterance, "I can't find the wet mug here.");
}

#[test]
fn a_mark_inside_a_word_is_part_of_it() {
    use super::fixtures::{obj, scene};
    let scene = scene(
        vec![
            obj("b15", "bottle", &[], &[("volume", "15")], [0.5, 0.0, 0.8], None),
            obj("b1_5", "bottle", &[], &[("volume", "1.5")], [0.5, 0.1, 0.8], None),
            obj("soda", "dr.pepper", &[], &[], [0.5, 0.2, 0.8], None),
            obj("soda2", "drpepper", &[], &[], [0.5, 0.3, 0.8], None),
        ],
        &[],
    );
    for (text, candidates) in [
        ("Get the 1.5 bottle.", &["b1_5"][..]),
        ("Get the 15 bottle.", &["b15"]),
        ("Get the dr.pepper.", &["soda"]),
        ("Get the drpepper!", &["soda2"]),
        ("Get the 1,5 bottle.", &[]),
    ] {
        assert_eq!(read(text, &scene), Ok(("get".into(), vec![ids(candidates)])), "{text}");
    }
}

#[test]
fn an_answer_by_id_is_the_id_as_written() {
    use super::fixtures::{obj, scene};
    let scene = scene(
        vec![
            obj("c.1", "cup", &[], &[], [0.5, 0.0, 0.8], None),
            obj("c1", "cup", &[], &[], [0.5, 0.1, 0.8], None),
            obj("cA", "cup", &[], &[], [0.5, 0.2, 0.8], None),
            obj("ca", "cup", &[], &[], [0.5, 0.3, 0.8], None),
        ],
        &[],
    );
    let norms = paper_norms();
    for (answer, goal) in [("c.1", "c.1"), ("cA", "cA"), ("c1.", "c1"), (" ca ", "ca")] {
        let request = crate::engine::request::Request {
            answer: Some(crate::engine::request::Answer::Words(answer.into())),
            ..said("Get the cup.")
        };
        let d = run(&request, &scene, &norms);
        assert_eq!(
            d.goal.as_ref().map(ToString::to_string),
            Some(format!("did(self,get({goal}))")),
            "{answer}: {}",
            d.utterance
        );
    }
}

#[test]
fn answers_that_take_back_the_question_or_ask_afresh() {
    let norms = paper_norms();
    for answer in [
        "never mind",
        "Cancel.",
        "forget it",
        "neither",
        "None of them.",
        "nothing",
    ] {
        let d = run(&answered("Get the notebook.", answer), &lab(), &norms);
        assert_eq!(d.kind, DecisionKind::Cancelled, "{answer}: {}", d.utterance);
        assert_eq!(d.utterance, "Okay, I will not.");
        assert!(d.goal.is_none() && d.offered.is_empty());
    }
    // Nothing was asked: there is nothing to take back.
    let d = run(&answered("Get the mug.", "never mind"), &lab(), &norms);
    assert_eq!(d.kind, DecisionKind::NotUnderstood);
    assert_eq!(d.utterance, "I did not ask anything that \"never mind\" answers.");
    // A whole directive answers by being decided afresh.
    let d = run(&answered("Get the notebook.", "Get the vase."), &lab(), &norms);
    assert_eq!(d.kind, DecisionKind::Assume, "{}", d.utterance);
    assert_eq!(d.goal.as_ref().unwrap().to_string(), "did(self,get(object4))");
    let d = run(
        &answered("Get the notebook.", "Destroy the mug instead."),
        &lab(),
        &norms,
    );
    assert_eq!(d.kind, DecisionKind::Refuse, "{}", d.utterance);
    // "not the red one" excludes.
    let d = run(&answered("Get the notebook.", "not the red one"), &lab(), &norms);
    assert_eq!(d.goal.as_ref().unwrap().to_string(), "did(self,get(object2))");
    let d = run(&answered("Get the notebook.", "not the ★ one"), &lab(), &norms);
    assert!(d.goal.is_none(), "{}", d.utterance);
}

#[test]
fn direction_controls_in_the_words_are_never_echoed() {
    let norms = paper_norms();
    for text in [
        "What is \u{202e}the mug?",
        "Get the \u{202e}wet mug.",
        "Get the mug \u{2066}pls\u{2069}.",
    ] {
        let d = run(&said(text), &lab(), &norms);
        assert!(
            !d.utterance.chars().any(crate::engine::scene::invisible),
            "{text:?}: {:?}",
            d.utterance
        );
    }
}

#[test]
fn a_reading_past_the_deadline_is_never_acted_on() {
    let d = clarify_expired(&said("Get the mug."));
    assert_eq!(d.kind, DecisionKind::NotUnderstood);
    assert_eq!(d.parse.as_ref().unwrap().unclear, Some(Unclear::Deadline));
    assert_eq!(
        d.limits.map(|l| l.kind),
        Some(crate::engine::decision::LimitKind::Deadline)
    );
}

fn clarify_expired(request: &crate::engine::request::Request) -> crate::engine::decision::Decision {
    crate::engine::clarify::clarify(request, &lab(), &paper_norms(), &Library::default_library(), &|| true)
        .expect("clarify")
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
        ("Can I get the mug?", Err(Unclear::Question)),
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
        let understood = understand(text, &lab(), &library, &[], &|| false);
        let is_wave = matches!(&understood, Understanding::Directive { directive: Directive::Action { verb, arguments }, .. } if verb == "wave" && arguments.is_empty());
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

/// Issue 50, §3.12: "İstanbul" and a decomposed "café" were refused as names "not of letters";
/// and "the first one" after "I do not know which cup you mean." answered a 422 about "1
/// readings".
#[test]
fn names_with_combining_marks_are_letters_and_an_ordinal_after_which_is_explained() {
    use crate::engine::input::RequestLimits;
    use crate::engine::scene::{AgentInput, ObjectInput, SceneInput};
    let input = |names: Vec<String>| SceneInput {
        agent: AgentInput {
            id: None,
            position: [0.0, 0.0, 0.75],
            reach: 0.9,
            gripper_aperture: None,
            payload: None,
            gripper_size: None,
        },
        objects: vec![ObjectInput {
            id: "m1".into(),
            kind: "mug".into(),
            properties: vec![],
            attributes: Default::default(),
            position: [0.5, 0.0, 0.8],
            shape: None,
            rotation: None,
            mass: None,
            names,
        }],
        facts: vec![],
    };
    let scene = Scene::from_input(
        input(vec!["İstanbul".into(), "cafe\u{301}".into()]),
        &RequestLimits::default(),
    )
    .expect("letters with their marks are a name");
    assert_eq!(
        read("Get the İstanbul.", &scene),
        Ok(("get".into(), vec![ids(&["m1"])]))
    );
    assert_eq!(
        read("Get the cafe\u{301}.", &scene),
        Ok(("get".into(), vec![ids(&["m1"])]))
    );
    assert!(Scene::from_input(input(vec!["\u{301}cafe".into()]), &RequestLimits::default()).is_err());

    use super::fixtures::{obj, scene as make};
    let cups = make(
        (0..6)
            .map(|i| obj(&format!("c{i}"), "cup", &[], &[], [0.5, 0.1 * i as f64, 0.8], None))
            .collect(),
        &[],
    );
    let request = crate::engine::request::Request {
        answer: Some(crate::engine::request::Answer::Words("the first one".into())),
        ..said("Get the cup.")
    };
    let err = crate::engine::clarify::clarify(&request, &cups, &paper_norms(), &Library::default_library(), &|| false)
        .unwrap_err();
    assert_eq!(
        err.to_string(),
        "the question asked which cup you mean and named no readings to choose from: answer with a description (\"the red one\") or an object's id"
    );
    assert_eq!(
        crate::engine::clarify::EngineError::BadChoice { choice: 1, offered: 1 }.to_string(),
        "choice 1 is not among the 1 reading the question named"
    );
}
