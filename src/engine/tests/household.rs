//! The household verbs of the default library (give, heat, open, close, discard, clean, pour,
//! cut, switchOn, switchOff): their words, effects and preconditions; arguments left unsaid
//! (implied by facts, or the speaker as recipient); and the property that an implied argument
//! never binds an object that does not meet its facts.

use super::fixtures::{act, fa, norms, obj, request, run, scene, ty, when};
use super::*;

/// A kitchen within reach: soup, a metal can, a microwave and a stove (both heaters), a
/// knife, bread, a cup, a closed fridge, a dirty plate.
fn kitchen() -> Scene {
    kitchen_with(&["closed(fridge1)", "dirty(plate1)"], &["microwave", "stove"])
}

/// The kitchen with `facts`, and a heater of each of `heaters`' types.
fn kitchen_with(facts: &[&str], heaters: &[&str]) -> Scene {
    let mut objects = vec![
        obj("soup1", "soup", &[], &[], [0.5, 0.0, 0.8], None),
        obj("can1", "can", &["metal"], &[], [0.5, 0.2, 0.8], None),
        obj("knife1", "knife", &[], &[], [0.4, 0.1, 0.8], None),
        obj("bread1", "bread", &[], &[], [0.4, -0.1, 0.8], None),
        obj("cup1", "cup", &[], &[], [0.3, -0.2, 0.8], None),
        obj("fridge1", "fridge", &[], &[], [0.6, 0.0, 0.8], None),
        obj("plate1", "plate", &[], &[], [0.3, 0.2, 0.8], None),
    ];
    for (i, kind) in heaters.iter().enumerate() {
        let y = -0.3 + 0.15 * i as f64;
        objects.push(obj(&format!("{kind}1"), kind, &["heater"], &[], [0.6, y, 0.8], None));
    }
    scene(objects, facts)
}

fn words(text: &str) -> Request {
    request(Directive::Words { text: text.into() })
}

/// Cans must not go in the microwave.
fn no_cans_in_the_microwave() -> CompiledNorms {
    norms(&[when(fa("heat(X,Y)"), &["metal(X)", "microwave(Y)"])])
}

#[test]
fn each_household_verb_is_named_by_its_words_and_does_what_it_says() {
    let kitchen = kitchen();
    // (words, decision, goal, the verb's own step's effects that hold after it)
    let cases: &[(&str, DecisionKind, &str)] = &[
        ("Give the cup to me.", Comply, "did(self,give(cup1,human))"),
        ("Hand me the cup.", Comply, "did(self,give(cup1,human))"),
        ("Pass me the cup.", Comply, "did(self,give(cup1,human))"),
        ("Bring the cup.", Comply, "did(self,give(cup1,human))"),
        ("Bring me the cup.", Comply, "did(self,give(cup1,human))"),
        ("Heat the soup with the stove.", Comply, "did(self,heat(soup1,stove1))"),
        (
            "Warm up the soup in the microwave.",
            Comply,
            "did(self,heat(soup1,microwave1))",
        ),
        ("Open the fridge.", Comply, "did(self,open(fridge1))"),
        ("Throw away the cup.", Comply, "did(self,discard(cup1))"),
        ("Throw the cup away.", Comply, "did(self,discard(cup1))"),
        ("Get rid of the cup.", Comply, "did(self,discard(cup1))"),
        ("Dispose of the cup.", Comply, "did(self,discard(cup1))"),
        ("Wash the plate.", Comply, "did(self,clean(plate1))"),
        ("Rinse the cup.", Comply, "did(self,clean(cup1))"),
        ("Pour the soup into the cup.", Comply, "did(self,pour(soup1,cup1))"),
        ("Slice the bread.", Comply, "did(self,cut(bread1,knife1))"),
        ("Cut the bread with the knife.", Comply, "did(self,cut(bread1,knife1))"),
        ("Turn on the stove.", Comply, "did(self,switchOn(stove1))"),
        ("Switch the stove off.", Comply, "did(self,switchOff(stove1))"),
    ];
    for (text, kind, goal) in cases {
        let d = run(&words(text), &kitchen, &norms(&[]));
        assert_eq!(d.kind, *kind, "{text}: {}", d.utterance);
        assert_eq!(d.goal.as_ref().map(Term::to_string).as_deref(), Some(*goal), "{text}");
    }
    // Plans: the verbs that handle an object get it first.
    let d = run(&words("Give the cup to me."), &kitchen, &norms(&[]));
    let plan: Vec<String> = d.interpretations[0].outcome.plan.iter().map(Term::to_string).collect();
    assert_eq!(plan, ["get(cup1)", "give(cup1,human)"]);
    let d = run(&words("Slice the bread."), &kitchen, &norms(&[]));
    let plan: Vec<String> = d.interpretations[0].outcome.plan.iter().map(Term::to_string).collect();
    assert_eq!(plan, ["get(knife1)", "cut(bread1,knife1)"]);
}

#[test]
fn preconditions_and_effects_are_checked_like_any_verbs() {
    let kitchen = kitchen();
    // Closing needs it open; it is closed.
    let d = run(&words("Close the fridge."), &kitchen, &norms(&[]));
    assert_eq!(d.kind, Refuse, "{}", d.utterance);
    assert_eq!(d.utterance, "I cannot close the fridge because the fridge is not open.");
    // Opening needs it closed: the cup is not said to be.
    let d = run(&words("Open the cup."), &kitchen, &norms(&[]));
    assert_eq!(d.utterance, "I cannot open the cup because the cup is not closed.");
    // A state the effects enter is judged: a clean plate, an open fridge, a discarded cup.
    for (text, state, kind, utterance) in [
        (
            "Open the fridge.",
            "open(X)",
            "fridge(X)",
            "I cannot open the fridge because the fridge being open is forbidden.",
        ),
        (
            "Throw away the cup.",
            "discarded(X)",
            "cup(X)",
            "I cannot discard the cup because the cup being discarded is forbidden.",
        ),
        (
            "Turn on the stove.",
            "powered(X)",
            "stove(X)",
            "I cannot switch on the stove because the stove being powered is forbidden.",
        ),
        (
            "Heat the soup on the stove.",
            "hot(X)",
            "soup(X)",
            "I cannot heat the soup on the stove because the soup being hot is forbidden.",
        ),
    ] {
        let norm = when(super::fixtures::fs(state), &[kind]);
        let d = run(&words(text), &kitchen, &norms(&[norm]));
        assert_eq!(d.kind, Refuse, "{text}: {}", d.utterance);
        assert_eq!(d.utterance, utterance, "{text}");
    }
    // A said instrument must be one: the bread is no heater, the cup no knife.
    let d = run(&words("Heat the soup with the bread."), &kitchen, &norms(&[]));
    assert_eq!(
        d.utterance,
        "I cannot heat the soup with the bread because the bread is not heater."
    );
    let d = run(&words("Cut the bread with the cup."), &kitchen, &norms(&[]));
    assert_eq!(d.kind, Refuse, "{}", d.utterance);
    // A recipient must be a person: the cup is not.
    let d = run(&words("Give the soup to the cup."), &kitchen, &norms(&[]));
    assert_eq!(
        d.utterance,
        "I cannot give the soup to the cup because the cup is not a person."
    );
}

#[test]
fn an_implied_argument_ranges_over_what_meets_its_facts() {
    // Several: asked, as any ambiguity is.
    let d = run(&words("Heat up the soup."), &kitchen(), &norms(&[]));
    assert_eq!(d.kind, Ask, "{}", d.utterance);
    assert_eq!(
        d.utterance,
        "Do you mean that you want me to heat the soup with the microwave or that you want me to heat the soup with the stove?"
    );
    // One: done with it.
    let stove = kitchen_with(&[], &["stove"]);
    let d = run(&words("Heat up the soup."), &stove, &norms(&[]));
    assert_eq!(d.kind, Comply, "{}", d.utterance);
    assert_eq!(d.goal.as_ref().unwrap().to_string(), "did(self,heat(soup1,stove1))");
    // None: unresolved, saying what is missing.
    let none = kitchen_with(&[], &[]);
    for (text, utterance) in [
        ("Heat up the soup.", "I do not see anything to heat the soup with."),
        ("Warm the cup.", "I do not see anything to heat the cup with."),
    ] {
        let d = run(&words(text), &none, &norms(&[]));
        assert_eq!(d.kind, Unresolved, "{text}: {}", d.utterance);
        assert_eq!(d.utterance, utterance);
    }
    let no_knife = scene(vec![obj("bread1", "bread", &[], &[], [0.4, 0.0, 0.8], None)], &[]);
    let d = run(&words("Cut the bread."), &no_knife, &norms(&[]));
    assert_eq!(d.utterance, "I do not see anything to cut the bread with.");
    // A fact of the scene meets it as a property does.
    let by_fact = scene(
        vec![
            obj("soup1", "soup", &[], &[], [0.5, 0.0, 0.8], None),
            obj("hob1", "hob", &[], &[], [0.6, 0.0, 0.8], None),
        ],
        &["heater(hob1)"],
    );
    let d = run(&words("Heat up the soup."), &by_fact, &norms(&[]));
    assert_eq!(d.goal.as_ref().unwrap().to_string(), "did(self,heat(soup1,hob1))");
    // Structured: an action given fewer arguments than its verb has, the rest implied.
    let d = run(&act("heat", vec![ty("soup")]), &stove, &norms(&[]));
    assert_eq!(d.goal.as_ref().unwrap().to_string(), "did(self,heat(soup1,stove1))");
    // A verb that implies nothing still needs every argument.
    let d = run(&act("put", vec![ty("soup")]), &stove, &norms(&[]));
    assert_eq!(d.kind, Refuse, "{}", d.utterance);
    assert_eq!(d.interpretations[0].outcome.reasons[0].kind(), "unknown_action");
}

/// The paper's plastic vase, in the kitchen: the norm picks the stove for the can.
#[test]
fn a_norm_picks_the_implied_argument_as_it_picks_an_object() {
    let d = run(&words("Heat up the can."), &kitchen(), &no_cans_in_the_microwave());
    assert_eq!(d.kind, Assume, "{}", d.utterance);
    assert_eq!(d.goal.as_ref().unwrap().to_string(), "did(self,heat(can1,stove1))");
    assert_eq!(
        d.utterance,
        "I am assuming you want me to heat the can with the stove. I cannot heat the can with the microwave because heating the can with the microwave is forbidden when the can is metal."
    );
    // The soup is not metal: both are asked about.
    let d = run(&words("Heat up the soup."), &kitchen(), &no_cans_in_the_microwave());
    assert_eq!(d.kind, Ask, "{}", d.utterance);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Whatever the heaters and which of them the scene says are heaters, an implied argument
    /// binds only an object that meets its facts, and no reading the norm forbids is acted on.
    #[test]
    fn an_implied_argument_binds_only_what_meets_its_facts(
        kinds in proptest::collection::vec(0usize..4, 0..6),
        heater in proptest::collection::vec(any::<bool>(), 6),
        by_fact in proptest::collection::vec(any::<bool>(), 6),
        text in 0usize..4,
    ) {
        const KINDS: [&str; 4] = ["microwave", "stove", "oven", "shelf"];
        let mut objects = vec![
            obj("soup1", "soup", &[], &[], [0.5, 0.0, 0.8], None),
            obj("can1", "can", &["metal"], &[], [0.5, 0.2, 0.8], None),
        ];
        let mut facts = Vec::new();
        let mut heaters = Vec::new();
        for (i, k) in kinds.iter().enumerate() {
            let id = format!("{}{i}", KINDS[*k]);
            let props: &[&str] = if heater[i] && !by_fact[i] { &["heater"] } else { &[] };
            if heater[i] && by_fact[i] {
                facts.push(format!("heater({id})"));
            }
            if heater[i] {
                heaters.push(id.clone());
            }
            objects.push(obj(&id, KINDS[*k], props, &[], [0.6, -0.3 + 0.1 * i as f64, 0.8], None));
        }
        let facts: Vec<&str> = facts.iter().map(String::as_str).collect();
        let scene = scene(objects, &facts);
        let said = ["Heat up the soup.", "Heat up the can.", "Warm the can.", "Heat the can."][text];
        let d = run(&words(said), &scene, &no_cans_in_the_microwave());
        for i in &d.interpretations {
            let heat = &i.action.args()[1];
            let with = heat.args()[1].to_string();
            prop_assert!(heaters.contains(&with), "{} binds {with}, not a heater", i.action);
        }
        if heaters.is_empty() {
            prop_assert_eq!(d.kind, Unresolved);
        }
        if let Some(goal) = &d.goal {
            let chosen = d.interpretations.iter().find(|i| &i.action == goal).unwrap();
            prop_assert!(chosen.permissible() && chosen.feasible(), "{} acted on: {}", goal, d.utterance);
        }
    }
}

fn styled(text: &str, style: crate::engine::decision::Style) -> Request {
    let mut r = words(text);
    r.options.style = style;
    r
}

/// After a refusal under the moral strategy, the nearest acceptable reading: offered in the
/// natural style, off in the diarc style unless asked, never under the reflexive strategy;
/// "yes" decides it afresh, and one that became forbidden meanwhile is refused.
#[test]
fn a_refusal_offers_the_nearest_acceptable_reading_instead() {
    use crate::engine::decision::Style;
    use crate::engine::request::{Alternatives, Answer};
    let kitchen = kitchen();
    let text = "Heat the can in the microwave.";
    let d = run(&styled(text, Style::Natural), &kitchen, &no_cans_in_the_microwave());
    assert_eq!(d.kind, Refuse, "{}", d.utterance);
    assert_eq!(
        d.alternative.as_ref().map(Term::to_string).as_deref(),
        Some("did(self,heat(can1,stove1))")
    );
    assert_eq!(
        d.utterance,
        "I won't heat the can in the microwave: heating the can in the microwave is not allowed when the can is metal. \
         Shall I heat the can in the stove instead?"
    );
    // The diarc style keeps the paper's words unless asked.
    let d = run(&words(text), &kitchen, &no_cans_in_the_microwave());
    assert_eq!(d.alternative, None);
    assert!(!d.utterance.contains("instead"), "{}", d.utterance);
    let mut asked = words(text);
    asked.options.alternatives = Some(Alternatives::Offer);
    let d = run(&asked, &kitchen, &no_cans_in_the_microwave());
    assert!(
        d.utterance
            .ends_with(" Do you want me to heat the can in the stove instead?"),
        "{}",
        d.utterance
    );
    // Never under the reflexive strategy (which obeys), nor when switched off.
    let mut off = styled(text, Style::Natural);
    off.options.alternatives = Some(Alternatives::Off);
    assert_eq!(run(&off, &kitchen, &no_cans_in_the_microwave()).alternative, None);
    let mut reflexive = asked.clone();
    reflexive.options.strategy = ClarifyStrategy::Reflexive;
    assert_eq!(run(&reflexive, &kitchen, &no_cans_in_the_microwave()).alternative, None);
    // Never an object the words excluded: the stove is ruled out, and nothing else heats.
    let excluding = styled("Heat the can in the microwave, not the stove.", Style::Natural);
    let d = run(&excluding, &kitchen, &no_cans_in_the_microwave());
    assert_eq!((d.kind, d.alternative.clone()), (Refuse, None), "{}", d.utterance);
    assert!(!d.utterance.contains("stove"), "{}", d.utterance);
    // "yes": the alternative, decided afresh.
    let yes = Request {
        answer: Some(Answer::Yes),
        ..asked.clone()
    };
    let d = run(&yes, &kitchen, &no_cans_in_the_microwave());
    assert_eq!(d.kind, Comply, "{}", d.utterance);
    assert_eq!(d.goal.as_ref().unwrap().to_string(), "did(self,heat(can1,stove1))");
    // Said whole in the natural style: what is done, to what (it was "Okay, I will heat.").
    let natural = Request {
        answer: Some(Answer::Yes),
        ..styled(text, Style::Natural)
    };
    let said = run(&natural, &kitchen, &no_cans_in_the_microwave()).utterance.clone();
    assert_eq!(said, "Okay, I will heat the can in the stove.");
    // {"choice": "alternative"} is the same answer; with none offered, nothing was asked.
    let chosen = Request {
        answer: Some(Answer::Alternative),
        ..asked.clone()
    };
    assert_eq!(run(&chosen, &kitchen, &no_cans_in_the_microwave()).goal, d.goal.clone());
    let unasked = Request {
        answer: Some(Answer::Alternative),
        ..words(text)
    };
    let library = Library::default_library();
    let refused = clarify(&unasked, &kitchen, &no_cans_in_the_microwave(), &library, &|| false);
    assert!(refused.is_err(), "nothing was offered to choose");
    // Forbidden meanwhile: nothing is taken instead, the refusal stands.
    let stricter = norms(&[
        when(fa("heat(X,Y)"), &["metal(X)", "microwave(Y)"]),
        when(fa("heat(X,Y)"), &["metal(X)", "stove(Y)"]),
    ]);
    let d = run(&yes, &kitchen, &stricter);
    assert_eq!(d.kind, Refuse, "{}", d.utterance);
    assert_eq!(d.alternative, None);
    // None found: only one heater, forbidden.
    let one = kitchen_with(&[], &["microwave"]);
    let d = run(&styled(text, Style::Natural), &one, &no_cans_in_the_microwave());
    assert_eq!((d.kind, d.alternative.clone()), (Refuse, None), "{}", d.utterance);
    // The same verb only, one argument changed: the other mug, not a different act.
    let mugs = scene(
        vec![
            obj("mug1", "mug", &["fragile"], &[], [0.5, 0.0, 0.8], None),
            obj("mug2", "mug", &["red"], &[], [0.5, 0.2, 0.8], None),
            obj("mug3", "mug", &["fragile", "blue"], &[], [0.5, -0.2, 0.8], None),
        ],
        &[],
    );
    let fragile = norms(&[when(fa("get(X)"), &["fragile(X)"])]);
    let mut get = styled("Get the fragile mug.", Style::Natural);
    get.options.alternatives = Some(Alternatives::Offer);
    let d = run(&get, &mugs, &fragile);
    assert_eq!(d.kind, Explain, "{}", d.utterance);
    assert_eq!(d.alternative.as_ref().unwrap().to_string(), "did(self,get(mug2))");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Whatever the kitchen and the norms, an alternative is offered only after a refusal or an
    /// explanation, is none of the readings named, and is what "yes" then does: permissible
    /// and feasible when decided afresh.
    #[test]
    fn no_alternative_offered_is_forbidden_or_infeasible(
        heaters in proptest::collection::vec((0usize..3, any::<bool>()), 1..5),
        items in proptest::collection::vec((0usize..3, any::<bool>()), 1..5),
        forbid in proptest::collection::vec(any::<bool>(), 3),
        text in 0usize..5,
    ) {
        use crate::engine::decision::Style;
        use crate::engine::request::Answer;
        const HEATERS: [&str; 3] = ["microwave", "stove", "oven"];
        const ITEMS: [(&str, &[&str]); 3] = [("can", &["metal"]), ("soup", &[]), ("bowl", &["metal"])];
        let mut objects = Vec::new();
        for (i, (k, far)) in heaters.iter().enumerate() {
            let x = if *far { 3.0 } else { 0.6 };
            objects.push(obj(&format!("{}{i}", HEATERS[*k]), HEATERS[*k], &["heater"], &[], [x, 0.1 * i as f64, 0.8], None));
        }
        for (i, (k, far)) in items.iter().enumerate() {
            let x = if *far { 3.0 } else { 0.5 };
            let (kind, props) = ITEMS[*k];
            objects.push(obj(&format!("{kind}{i}"), kind, props, &[], [x, -0.1 * i as f64, 0.8], None));
        }
        let scene = scene(objects, &[]);
        let all = [
            when(fa("heat(X,Y)"), &["metal(X)", "microwave(Y)"]),
            when(fa("heat(X,Y)"), &["stove(Y)"]),
            when(fa("get(X)"), &["soup(X)"]),
        ];
        let chosen: Vec<NormInput> = all.iter().zip(&forbid).filter(|(_, f)| **f).map(|(n, _)| n.clone()).collect();
        let norms = norms(&chosen);
        let said = [
            "Heat the can in the microwave.",
            "Heat up the can.",
            "Heat the soup on the stove.",
            "Get the soup.",
            "Heat the bowl with the oven.",
        ][text];
        let d = run(&styled(said, Style::Natural), &scene, &norms);
        if let Some(alternative) = &d.alternative {
            prop_assert!(matches!(d.kind, Refuse | Explain), "{:?} offers {}", d.kind, alternative);
            prop_assert!(d.interpretations.iter().all(|i| &i.action != alternative), "{} was named", alternative);
            let yes = Request { answer: Some(Answer::Yes), ..styled(said, Style::Natural) };
            let taken = run(&yes, &scene, &norms);
            prop_assert_eq!(taken.goal.as_ref(), Some(alternative), "{}", taken.utterance);
            let reading = taken.interpretations.iter().find(|i| &i.action == alternative).unwrap();
            prop_assert!(reading.permissible() && reading.feasible(), "{} offered: {}", alternative, d.utterance);
        }
    }
}

/// A purpose after a verb whose joiner is "to" is read, not taken for its recipient: "to" and
/// a verb the robot knows start a purpose, anything else after "to" is the second argument.
#[test]
fn a_purpose_after_a_to_joiner_is_read_and_judged() {
    let kitchen = kitchen();
    let destroy = norms(&[fa("destroy")]);
    for (text, kind, utterance) in [
        (
            "Bring me the cup to smash it.",
            Refuse,
            "I cannot give the cup to you to destroy it because destroy is forbidden action.",
        ),
        (
            "Give the cup to me to break the plate.",
            Refuse,
            "I cannot give the cup to you to destroy the plate because destroy is forbidden action.",
        ),
        ("Give the cup to me to wash it.", Comply, "Okay."),
        (
            "Give the cup to me to not smash it.",
            NotUnderstood,
            "I did not understand \"to not smash it\".",
        ),
    ] {
        let d = run(&words(text), &kitchen, &destroy);
        assert_eq!(d.kind, kind, "{text}: {}", d.utterance);
        assert_eq!(d.utterance, utterance, "{text}");
    }
    // A purpose the words name no object of is not dropped: it is not understood or unresolved.
    let d = run(&words("Give the cup to me to smash the vase."), &kitchen, &destroy);
    assert_eq!(d.kind, Unresolved, "{}", d.utterance);
}

/// The recipient said first ("Hand Bob the knife."): read for a verb whose second argument is
/// a person; a narrowing after it narrows the object said last, never the recipient; words
/// that are not one short reference before the object are not read so.
#[test]
fn a_recipient_may_be_said_before_the_object() {
    use crate::engine::scene::{AgentInput, ObjectInput, PersonInput, SceneInput};
    let thing = |id: &str, kind: &str, colour: &str, y: f64| ObjectInput {
        id: id.into(),
        kind: kind.into(),
        properties: Vec::new(),
        attributes: [("colour".to_owned(), colour.to_owned())].into(),
        position: [0.5, y, 0.8],
        shape: None,
        rotation: None,
        mass: None,
        names: Vec::new(),
    };
    let input = SceneInput {
        agent: AgentInput {
            id: None,
            position: [0.0, 0.0, 0.75],
            reach: 1.5,
            gripper_aperture: None,
            payload: None,
            gripper_size: None,
            rotation: None,
        },
        objects: vec![thing("cup1", "cup", "red", 0.1), thing("cup2", "cup", "blue", -0.1)],
        facts: Vec::new(),
        people: vec![PersonInput {
            id: "bob".into(),
            names: vec!["Bob".into()],
            roles: vec!["child".into()],
            position: [0.8, 0.0, 0.0],
        }],
    };
    let scene = Scene::from_input(input, &crate::engine::input::RequestLimits::default()).unwrap();
    for (text, kind, goal) in [
        ("Hand Bob the red cup.", Comply, Some("did(self,give(cup1,bob))")),
        ("Give the child the blue cup.", Comply, Some("did(self,give(cup2,bob))")),
        // The narrowing is the object's: the blue cup, never the red one.
        (
            "Hand Bob the cup, not the red one.",
            Comply,
            Some("did(self,give(cup2,bob))"),
        ),
        (
            "Hand Bob the cups.",
            Comply,
            Some("did(self,and(give(cup1,bob),give(cup2,bob)))"),
        ),
        // Not one short reference before the object: not read as a recipient.
        ("Give the cup near Bob the cup.", Unresolved, None),
    ] {
        let d = run(&words(text), &scene, &norms(&[]));
        assert_eq!(d.kind, kind, "{text}: {}", d.utterance);
        assert_eq!(
            d.goal.as_ref().map(Term::to_string).as_deref(),
            goal,
            "{text}: {}",
            d.utterance
        );
    }
    let d = run(&words("Hand Bob the cups."), &scene, &norms(&[]));
    assert_eq!(d.utterance, "Okay.");
}
