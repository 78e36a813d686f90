//! Issue 50's findings about words, each pinned: what narrows, negates, adds a step or states a
//! purpose is never dropped; a vocative is only a name; a mark inside a word is part of it; an
//! id answers as written; answers take a question back or ask afresh; the deadline ends reading.

use super::fixtures::{lab, paper_norms, run};
use super::words::{answered, ids, read, said};
use crate::engine::action::Library;
use crate::engine::decision::{DecisionKind, Unclear};
use crate::engine::request::Directive;
use crate::engine::resolve::Reference;
use crate::engine::scene::Scene;
use crate::engine::words::{Understanding, heard, understand};

/// One red cup and one red notebook (issue 50's scene): words after the reference that narrow
/// or negate it were taken as an addressee or left out, and the red object obeyed.
pub(super) fn red_cup_and_notebook() -> Scene {
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
        // The cup is to the right of the fork (seen from the agent): read, not dropped.
        "Get the cup to the left of the fork.",
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
        ("Get the cup, the red one please.", "did(self,get(cup1))"),
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
        "Pepper! Grab it.",
        "Grab it, Pepper.",
        "Grab it, please.",
        "Pepper, grab it.",
        "Grab it, please, Pepper.",
    ] {
        let understood = understand(text, &lab, &Library::default_library(), heard(&focus), &|| false);
        let Understanding::Directive { directive, parse } = understood else {
            panic!("{text}: {understood:?}")
        };
        assert_eq!(
            directive,
            Directive::Action {
                verb: "get".into(),
                arguments: vec![Reference::Id("object5".into())],
                joiner: None,
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
    // Destroying is forbidden: a purpose or a step that destroys is read and refused, never
    // left out and obeyed.
    for (text, kind) in [
        ("Grab the mug to smash the vase.", DecisionKind::Refuse),
        ("Grab the mug in order to destroy the notebook.", DecisionKind::Refuse),
        ("Grab the mug so I can smash it.", DecisionKind::Refuse),
        ("Get the mug for smashing the vase.", DecisionKind::Refuse),
        ("Grab the mug, and destroy the vase.", DecisionKind::Explain),
        ("Get the mug.Destroy the vase.", DecisionKind::Explain),
        ("Get the mug; destroy the vase", DecisionKind::Explain),
    ] {
        let d = run(&said(text), &lab, &norms);
        assert_eq!(d.kind, kind, "{text}: {}", d.utterance);
        assert!(d.goal.is_none(), "{text}");
    }
    let d = run(&said("Grab the mug to smash the vase."), &lab, &norms);
    // Either vase: the purpose is said as the human said it, never as one of them.
    assert_eq!(
        d.utterance,
        "I cannot get the mug to destroy the vase because destroy is forbidden action."
    );
    let d = run(&said("Grab the mug so I can smash it."), &lab, &norms);
    assert_eq!(
        d.utterance,
        "I cannot get the mug to destroy it because destroy is forbidden action."
    );
    // A step with nothing to act on, or a negated purpose, is not understood as a whole.
    for text in ["Get the mug to not reheat it.", "Grab the mug, then smash."] {
        let d = run(&said(text), &lab, &norms);
        assert_eq!(d.kind, DecisionKind::NotUnderstood, "{text}: {}", d.utterance);
        assert_eq!(
            d.parse.as_ref().and_then(|p| p.unclear),
            Some(Unclear::Unplaced),
            "{text}"
        );
    }
    // Two steps the norms allow are a task, done whole.
    let d = run(&said("Get the mug. Put it on the red notebook."), &lab, &norms);
    assert_eq!(
        d.goal.as_ref().map(ToString::to_string).as_deref(),
        Some("did(self,and(get(object5),put(object5,object1)))")
    );
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
            rotation: None,
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
        people: vec![],
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

/// Issue 50, §2: "put X in Y" was spoken and simulated as "on": a norm on `in(X,Y)` never
/// fired and "Put the fork in the microwave." was complied with. The joiner said is spoken and
/// names the relation the verb makes true.
#[test]
fn put_in_is_spoken_and_simulated_as_in() {
    use super::fixtures::{fs, norms, obj, scene};
    let kitchen = scene(
        vec![
            obj("fork1", "fork", &["metal"], &[], [0.5, 0.0, 0.8], None),
            obj("microwave1", "microwave", &[], &[], [0.5, 0.3, 0.8], None),
        ],
        &[],
    );
    let in_microwave = norms(&[fs("in(X,microwave1)")]);
    for (text, kind, utterance) in [
        (
            "Put the fork in the microwave.",
            DecisionKind::Refuse,
            "I cannot put the fork in the microwave because it requires a forbidden state.",
        ),
        (
            "Place the fork inside the microwave.",
            DecisionKind::Refuse,
            "I cannot put the fork inside the microwave because it requires a forbidden state.",
        ),
        ("Put the fork on the microwave.", DecisionKind::Comply, "Okay."),
    ] {
        let d = run(&said(text), &kitchen, &in_microwave);
        assert_eq!((d.kind, d.utterance.as_str()), (kind, utterance), "{text}");
    }
    // The plan shows what was made true.
    let d = run(&said("Put the fork into the microwave."), &kitchen, &norms(&[]));
    assert_eq!(d.kind, DecisionKind::Comply);
    let natural = super::fixtures::natural(said("Put the fork into the microwave."));
    assert_eq!(
        run(&natural, &kitchen, &norms(&[])).utterance,
        "Okay, I will put the fork into the microwave."
    );
    // Structured, the same; a joiner the verb does not take is the client's error.
    let structured = |joiner: &str| crate::engine::request::Request {
        directive: Directive::Action {
            verb: "put".into(),
            arguments: vec![super::fixtures::id("fork1"), super::fixtures::id("microwave1")],
            joiner: Some(joiner.into()),
        },
        ..said("")
    };
    assert_eq!(
        run(&structured("in"), &kitchen, &in_microwave).kind,
        DecisionKind::Refuse
    );
    assert_eq!(
        run(&structured("on"), &kitchen, &in_microwave).kind,
        DecisionKind::Comply
    );
    let err = crate::engine::clarify::clarify(
        &structured("with"),
        &kitchen,
        &in_microwave,
        &Library::default_library(),
        &|| false,
    )
    .unwrap_err();
    assert_eq!(err.to_string(), "`with` does not join the arguments of `put`");
}
