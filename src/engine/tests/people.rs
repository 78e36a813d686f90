//! People in a scene: referents by name, role, "me" and id; never objects to handle; a norm on
//! a recipient's role holds however the recipient is named, by the default `give(X,P)` (its
//! method declares `person(P)`).

use std::collections::BTreeSet;

use super::fixtures::{fa, norms, request, when};
use super::*;
use crate::engine::input::RequestLimits;
use crate::engine::scene::{AgentInput, ObjectInput, PersonInput, SceneInput};

fn library() -> Library {
    Library::default_library()
}

fn thing(id: &str, kind: &str, y: f64) -> ObjectInput {
    ObjectInput {
        id: id.into(),
        kind: kind.into(),
        properties: vec![],
        attributes: Default::default(),
        position: [0.5, y, 0.8],
        shape: None,
        rotation: None,
        mass: None,
        names: vec![],
    }
}

fn person(id: &str, name: Option<&str>, roles: &[&str], x: f64) -> PersonInput {
    PersonInput {
        id: id.into(),
        names: name.into_iter().map(String::from).collect(),
        roles: roles.iter().map(|r| r.to_string()).collect(),
        position: [x, 0.3, 0.8],
    }
}

/// `knives` knives and a cup within reach; `people` as given.
fn kitchen_input(knives: usize, people: Vec<PersonInput>) -> SceneInput {
    SceneInput {
        agent: AgentInput {
            id: None,
            position: [0.0, 0.0, 0.75],
            reach: 1.2,
            gripper_aperture: None,
            payload: None,
            gripper_size: None,
            rotation: None,
        },
        objects: (1..=knives)
            .map(|k| thing(&format!("knife{k}"), "knife", -0.2 * k as f64))
            .chain([thing("cup1", "cup", 0.2)])
            .collect(),
        facts: vec![],
        people,
    }
}

fn kitchen(knives: usize, people: Vec<PersonInput>) -> Scene {
    Scene::from_input(kitchen_input(knives, people), &RequestLimits::default()).unwrap()
}

/// One knife, a cup, a child, a parent and a visitor out of reach.
fn household() -> Scene {
    kitchen(
        1,
        vec![
            person("bob", Some("Bob"), &["child"], 0.6),
            person("alice", Some("Alice"), &["parent"], 0.7),
            person("p3", None, &["visitor"], 3.0),
        ],
    )
}

fn no_knives_for_children() -> CompiledNorms {
    norms(&[when(fa("give(X,P)"), &["knife(X)", "role(P,child)"])])
}

fn said(text: &str, speaker: &str) -> Request {
    Request {
        speaker: Sym::from(speaker),
        ..request(Directive::Words { text: text.into() })
    }
}

fn decide(request: &Request, scene: &Scene) -> Decision {
    clarify(request, scene, &no_knives_for_children(), &library(), &|| false).unwrap()
}

#[test]
fn a_person_is_named_by_name_role_and_me_and_spoken_by_name() {
    let scene = household();
    for (text, speaker, kind, goal, utterance) in [
        (
            "Give the knife to Alice.",
            "human",
            Comply,
            Some("did(self,give(knife1,alice))"),
            None,
        ),
        (
            "Give the cup to Alice.",
            "human",
            Comply,
            Some("did(self,give(cup1,alice))"),
            None,
        ),
        (
            "Pass the cup to the parent.",
            "human",
            Comply,
            Some("did(self,give(cup1,alice))"),
            None,
        ),
        (
            "Give the cup to me.",
            "alice",
            Comply,
            Some("did(self,give(cup1,alice))"),
            None,
        ),
        ("Point to Bob.", "human", Comply, Some("did(self,pointTo(bob))"), None),
        (
            "Point to the person.",
            "human",
            Ask,
            None,
            Some(
                "Do you mean that you want me to point to Alice or that you want me to point to Bob or that \
                 you want me to point to the visitor?",
            ),
        ),
        // A speaker the scene does not place is handed things all the same: they come for them.
        (
            "Give the cup to me.",
            "human",
            Comply,
            Some("did(self,give(cup1,human))"),
            Some("Okay."),
        ),
        (
            "Bring me the cup.",
            "human",
            Comply,
            Some("did(self,give(cup1,human))"),
            None,
        ),
        (
            "Hand me the cup.",
            "bob",
            Comply,
            Some("did(self,give(cup1,bob))"),
            None,
        ),
        (
            "Get me.",
            "human",
            Refuse,
            None,
            Some("I cannot get you because you are a person, not an object to handle."),
        ),
    ] {
        let d = decide(&said(text, speaker), &scene);
        assert_eq!(d.kind, kind, "{text} ({speaker}): {}", d.utterance);
        assert_eq!(d.goal.as_ref().map(|g| g.to_string()).as_deref(), goal, "{text}");
        if let Some(utterance) = utterance {
            assert_eq!(d.utterance, utterance, "{text}");
        }
    }
}

#[test]
fn a_norm_on_the_recipients_role_holds_however_the_recipient_is_named() {
    let scene = household();
    let refused = "I cannot give the knife to Bob because giving the knife to Bob is forbidden when Bob is a child.";
    for (text, speaker) in [
        ("Give the knife to Bob.", "human"),
        ("Give the knife to bob.", "human"),
        ("Give the knife to the child.", "human"),
        ("Give the knife to me.", "bob"),
    ] {
        let d = decide(&said(text, speaker), &scene);
        assert_eq!(d.kind, Refuse, "{text} ({speaker}): {}", d.utterance);
        // Spoken to Bob, Bob is "you".
        let refused = match speaker {
            "bob" => refused.replace("to Bob", "to you").replace("Bob is", "you are"),
            _ => refused.to_owned(),
        };
        assert_eq!(d.utterance, refused, "{text}");
        assert_eq!(d.interpretations[0].outcome.reasons[0].kind(), "forbidden_action");
    }
    // By id, structured.
    let d = decide(&act("give", vec![id("knife1"), id("bob")]), &scene);
    assert_eq!(d.kind, Refuse, "{}", d.utterance);
    // The speaker's roles make the speaker a child: "me" is refused too.
    let alice_as_child = Request {
        speaker_roles: vec!["child".into()],
        ..said("Give the knife to me.", "alice")
    };
    assert_eq!(decide(&alice_as_child, &scene).kind, Refuse);
    assert_eq!(decide(&said("Give the knife to me.", "alice"), &scene).kind, Comply);
    // Two knives: both readings are refused for the child.
    let two = kitchen(2, vec![person("bob", Some("Bob"), &["child"], 0.6)]);
    let d = decide(&said("Give the knife to the child.", "human"), &two);
    assert_eq!(d.kind, Explain, "{}", d.utterance);
}

#[test]
fn a_person_is_not_an_object_to_handle() {
    let scene = household();
    for (text, utterance) in [
        (
            "Get Bob.",
            "I cannot get Bob because Bob is a person, not an object to handle.",
        ),
        (
            "Destroy the child.",
            "I cannot destroy Bob because Bob is a person, not an object to handle.",
        ),
        (
            "Put the cup on Alice.",
            "I cannot put the cup on Alice because Alice is a person, not an object to handle.",
        ),
        (
            "Give the cup to the knife.",
            "I cannot give the cup to the knife because the knife is not a person.",
        ),
        (
            "Give the cup to the visitor.",
            "I cannot give the cup to the visitor because the visitor is out of reach.",
        ),
    ] {
        let d = decide(&said(text, "human"), &scene);
        assert_eq!(d.kind, Refuse, "{text}: {}", d.utterance);
        assert_eq!(d.utterance, utterance, "{text}");
        assert!(d.goal.is_none());
    }
    let d = decide(&said("Get Bob.", "human"), &scene);
    let reason = &d.interpretations[0].outcome.reasons[0];
    assert_eq!((reason.kind(), reason.detail()), ("person", "bob".to_owned()));
    assert_eq!(reason.term().to_string(), "isPerson(bob)");
    // Every person, by type: none may be got.
    let d = decide(&act("get", vec![ty("person")]), &scene);
    assert_eq!(d.kind, Explain, "{}", d.utterance);
}

#[test]
fn people_yield_person_and_role_facts_and_the_speaker_is_a_person() {
    let scene = household();
    let facts: Vec<String> = scene
        .facts_with_speaker("human", &["visitor".into()])
        .iter()
        .map(Term::to_string)
        .collect();
    for fact in [
        "person(bob)",
        "role(bob,child)",
        "role(alice,parent)",
        "person(human)",
        "role(human,visitor)",
    ] {
        assert!(facts.contains(&fact.to_owned()), "{fact} in {facts:?}");
    }
    assert!(!facts.iter().any(|f| f == "role(bob,parent)"));
    // Two people called Bob are told apart as people are, not by the name they share.
    let twins = kitchen(
        1,
        vec![
            person("bob1", Some("Bob"), &["child"], 0.6),
            person("bob2", Some("Bob"), &["parent"], 0.7),
        ],
    );
    let d = decide(&said("Point to Bob.", "human"), &twins);
    assert_eq!(
        d.utterance,
        "Do you mean that you want me to point to the child or that you want me to point to the parent?"
    );
    // A name as written, with stray spaces, is heard and spoken as one.
    let spaced = kitchen(1, vec![person("bob", Some("  Bob   Smith "), &["child"], 0.6)]);
    let d = decide(&said("Point to bob smith.", "human"), &spaced);
    assert_eq!(
        d.goal.as_ref().map(|g| g.to_string()).as_deref(),
        Some("did(self,pointTo(bob))")
    );
    let bob = spaced.object("bob").unwrap();
    assert_eq!(crate::engine::describe::describe_object(&spaced, bob), "Bob Smith");
}

/// What the oracle knows: each person's roles, from the scene and, for the speaker, the request.
#[derive(Clone, Debug)]
struct Household {
    roles: Vec<Vec<&'static str>>,
    speaker: usize,
    speaker_child: bool,
    said: usize,
    phrase: usize,
}

const PEOPLE: [(&str, &str); 3] = [("bob", "Bob"), ("alice", "Alice"), ("carol", "Carol")];
const SPEAKERS: [&str; 4] = ["bob", "alice", "carol", "human"];
const ROLES: [&str; 3] = ["child", "parent", "visitor"];

fn arb_household() -> impl Strategy<Value = Household> {
    (
        proptest::collection::vec(proptest::sample::subsequence(ROLES.to_vec(), 0..=2), 3),
        0..SPEAKERS.len(),
        any::<bool>(),
        0..6usize,
        0..9usize,
    )
        .prop_map(|(roles, speaker, speaker_child, said, phrase)| Household {
            roles,
            speaker,
            speaker_child,
            said,
            phrase,
        })
}

impl Household {
    fn scene(&self) -> Scene {
        let people = (PEOPLE.iter().zip(&self.roles).enumerate())
            .map(|(i, ((id, name), roles))| person(id, Some(name), roles, 0.5 + 0.1 * i as f64))
            .collect();
        kitchen(2, people)
    }

    fn recipient(&self) -> String {
        [
            "Bob",
            "alice",
            "Carol",
            "me",
            "the child",
            "the parent",
            "the visitor",
            "the person",
            "knife2",
        ][self.phrase]
            .to_owned()
    }

    fn request(&self) -> Request {
        let r = self.recipient();
        let text = match self.said {
            0 => format!("Give the knife to {r}."),
            1 => format!("Give a knife to {r}."),
            2 => format!("Pass the cup to {r}."),
            3 => format!("Get {r}."),
            4 => format!("Destroy {r}."),
            _ => format!("Put the cup on {r}."),
        };
        Request {
            speaker_roles: if self.speaker_child {
                vec!["child".into()]
            } else {
                vec![]
            },
            ..said(&text, SPEAKERS[self.speaker])
        }
    }

    /// The ids of those the norm protects: a person with the role child, in the scene or, for
    /// the speaker, by the request's roles.
    fn children(&self) -> BTreeSet<&'static str> {
        let mut children: BTreeSet<&str> = (PEOPLE.iter().zip(&self.roles))
            .filter(|(_, roles)| roles.contains(&"child"))
            .map(|((id, _), _)| *id)
            .collect();
        if self.speaker_child {
            children.insert(SPEAKERS[self.speaker]);
        }
        children
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// No reading that hands a knife to a child, or handles a person, is ever acceptable, so
    /// none is offered, assumed or obeyed, whatever the words name the person by.
    #[test]
    fn no_knife_reaches_a_child_and_no_person_is_handled(case in arb_household()) {
        let scene = case.scene();
        let d = decide(&case.request(), &scene);
        let children = case.children();
        let people: BTreeSet<&str> = PEOPLE.iter().map(|(id, _)| *id).collect();
        for i in &d.interpretations {
            let step = &i.action.args()[1];
            let args: Vec<String> = step.args().iter().map(Term::to_string).collect();
            let acceptable = i.permissible() && i.feasible();
            let verb = step.name().map(|n| n.to_string()).unwrap_or_default();
            if verb == "give" && args[0].starts_with("knife") && children.contains(args[1].as_str()) {
                prop_assert!(!i.permissible(), "{} offered to a child: {}", i.action, d.utterance);
            }
            if ["get", "destroy", "put"].contains(&verb.as_str()) {
                prop_assert!(
                    !(args.iter().any(|a| people.contains(a.as_str())) && acceptable),
                    "{} handles a person",
                    i.action
                );
            }
            // The speaker is a person whether or not the scene places them.
            if verb == "give" && !people.contains(args[1].as_str()) && args[1] != SPEAKERS[case.speaker] {
                prop_assert!(!i.feasible(), "{} gives to an object", i.action);
            }
        }
        if let Some(goal) = &d.goal {
            prop_assert!(
                d.interpretations.iter().any(|i| &i.action == goal && i.permissible() && i.feasible()),
                "the goal {} is not an acceptable reading", goal
            );
        }
    }
}

#[test]
fn people_count_against_the_objects_limit_and_their_faults_are_named() {
    let limits = RequestLimits {
        max_objects: 4,
        ..RequestLimits::default()
    };
    let input = |people| kitchen_input(1, people);
    let two = || vec![person("bob", Some("Bob"), &[], 0.6), person("alice", None, &[], 0.7)];
    assert!(Scene::from_input(input(two()), &limits).is_ok());
    let mut three = two();
    three.push(person("carol", None, &[], 0.8));
    let err = Scene::from_input(input(three), &limits).unwrap_err();
    assert_eq!(err.field, "/people");
    assert!(err.message.contains("5 objects and people"), "{err}");
    let mut far = two();
    far[1].position = [f64::NAN, 0.0, 0.0];
    assert_eq!(
        Scene::from_input(input(far), &limits).unwrap_err().field,
        "/people/1/position"
    );
    let mut twice = two();
    twice[1].id = "bob".into();
    assert_eq!(
        Scene::from_input(input(twice), &limits).unwrap_err().field,
        "/people/1/id"
    );
}
