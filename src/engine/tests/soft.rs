//! Soft norms: "should" and "should not" rank the acceptable readings by strength; they never
//! make one impermissible, and never rescue a forbidden one.

use super::*;
use crate::engine::decision::Style;
use crate::engine::request::SoftNorms;

const DA: &str = "discouraged_action";
const DS: &str = "discouraged_state";
const PA: &str = "preferred_action";

fn soft(kind: &str, term: &str, severity: i64) -> NormInput {
    let (action, state) = if kind.ends_with("_action") {
        (Some(term.to_owned()), None)
    } else {
        (None, Some(term.to_owned()))
    };
    NormInput {
        kind: Some(kind.into()),
        action,
        state,
        severity: Some(severity),
        ..NormInput::default()
    }
}

fn noted(norm: NormInput, note: &str) -> NormInput {
    NormInput {
        note: Some(note.into()),
        ..norm
    }
}

fn for_roles(norm: NormInput, roles: &[&str], exempt: &[&str]) -> NormInput {
    NormInput {
        roles: Some(roles.iter().map(|r| r.to_string()).collect()),
        exempt_roles: Some(exempt.iter().map(|r| r.to_string()).collect()),
        ..norm
    }
}

/// A mug on the serving tray, in reach: `clean` or `dirty`, and a colour to tell mugs apart.
fn mug(id: &str, state: &str, color: &str, y: f64) -> Object {
    obj(id, "mug", &[state], &[("color", color)], [0.5, y, 0.8], None)
}

fn tray(mugs: Vec<Object>) -> Scene {
    scene(mugs, &[])
}

/// A clean mug and a dirty one.
fn clean_and_dirty() -> Scene {
    tray(vec![
        mug("mug1", "clean", "blue", 0.1),
        mug("mug2", "dirty", "green", -0.1),
    ])
}

/// Today's question about the clean and the dirty mug, when no soft norm is in force.
const WHICH_MUG: &str = "Do you mean that you want me to get the clean mug or that you want me to get the dirty mug?";

/// Serving: one serves with clean things; handing over a dirty one is not wrong, only worse.
fn serving() -> NormInput {
    in_context(when(soft(DA, "get(X)", 2), &["dirty(X)"]), "serving")
}

fn in_serving(request: Request) -> Request {
    with_context(request, "serving")
}

fn get_me_the_mug() -> Request {
    in_serving(request(Directive::Words {
        text: "Get me the mug.".into(),
    }))
}

fn with_options(request: Request, change: impl FnOnce(&mut Options)) -> Request {
    let mut options = request.options;
    change(&mut options);
    Request { options, ..request }
}

/// The floor to tidy: a broken plate (a hazard) and a dirty cup, both to be picked up.
fn floor() -> Scene {
    scene(
        vec![
            obj("plate1", "plate", &["broken"], &[], [0.5, 0.2, 0.1], None),
            obj("cup1", "cup", &["dirty"], &[], [0.5, -0.2, 0.1], None),
        ],
        &["on(plate1,floor1)", "on(cup1,floor1)"],
    )
}

fn tidying() -> CompiledNorms {
    norms(&[
        in_context(when(soft(PA, "get(X)", 2), &["dirty(X)", "on(X,floor1)"]), "tidying"),
        in_context(when(soft(PA, "get(X)", 4), &["broken(X)"]), "tidying"),
    ])
}

fn pick_up_the_thing_on_the_floor() -> Request {
    with_context(form("get(X)", &[("X", &["plate1", "cup1"])]), "tidying")
}

#[test]
fn serving_and_tidying() {
    run_cases(vec![
        case(
            "serving: the clean mug is assumed, the dirty one explained",
            clean_and_dirty(),
            norms(&[serving()]),
            get_me_the_mug(),
            expect(
                Assume,
                Some("did(self,get(mug1))"),
                "I am assuming you want me to get the clean mug. I would rather not get the dirty mug because the dirty mug is dirty.",
            )
            .act("assume(self,mean(human,did(self,get(mug1))))")
            .interps(vec![
                interp("did(self,get(mug1))", "the clean mug", vec![], &["get(mug1)"]),
                interp(
                    "did(self,get(mug2))",
                    "the dirty mug",
                    vec![(DA, "get(mug2)", Some(1))],
                    &["get(mug2)"],
                ),
            ]),
        ),
        case(
            "serving: two clean and a dirty one: which clean one, the dirty one not named",
            tray(vec![
                mug("mug1", "clean", "blue", 0.1),
                mug("mug2", "dirty", "green", -0.1),
                mug("mug3", "clean", "red", 0.2),
            ]),
            norms(&[serving()]),
            get_me_the_mug(),
            expect(
                Ask,
                None,
                "Do you mean that you want me to get the clean blue mug or that you want me to get the clean red mug?",
            )
            .act("want_know(self,mean(human,or(did(self,get(mug1)),did(self,get(mug3)))))"),
        ),
        case(
            "serving: only a dirty mug: complied with, saying so",
            tray(vec![mug("mug2", "dirty", "green", -0.1)]),
            norms(&[serving()]),
            get_me_the_mug(),
            expect(Comply, Some("did(self,get(mug2))"), "Okay, although the mug is dirty.")
                .act("acknowledge(self,mean(human,did(self,get(mug2))))"),
        ),
        case(
            "outside the serving context the norm is not in force: today's question",
            clean_and_dirty(),
            norms(&[serving()]),
            with_context(get_me_the_mug(), "default"),
            expect(Ask, None, WHICH_MUG),
        ),
        case(
            "soft_norms: ignore gives today's answer",
            clean_and_dirty(),
            norms(&[serving()]),
            with_options(get_me_the_mug(), |o| o.soft_norms = SoftNorms::Ignore),
            expect(Ask, None, WHICH_MUG)
            .interps(vec![
                interp("did(self,get(mug1))", "the clean mug", vec![], &["get(mug1)"]),
                interp("did(self,get(mug2))", "the dirty mug", vec![], &["get(mug2)"]),
            ]),
        ),
        case(
            "the reflexive strategy ignores soft norms as it ignores all norms",
            clean_and_dirty(),
            norms(&[serving()]),
            reflexive(get_me_the_mug()),
            expect(Ask, None, WHICH_MUG),
        ),
        case(
            "serving, confirming: the clean mug is asked about, the dirty one explained",
            clean_and_dirty(),
            norms(&[serving()]),
            confirming(get_me_the_mug()),
            expect(
                Confirm,
                None,
                "Do you want me to get the clean mug? I would rather not get the dirty mug because the dirty mug is dirty.",
            ),
        ),
        case(
            "a hazard (4) before a dirty item (2): the stronger norm wins",
            floor(),
            tidying(),
            pick_up_the_thing_on_the_floor(),
            expect(
                Assume,
                Some("did(self,get(plate1))"),
                "I am assuming you want me to get the plate. I would rather not get the cup because it is less preferred than getting the plate.",
            )
            .interps(vec![
                interp("did(self,get(cup1))", "the cup", vec![(PA, "get(cup1)", Some(1))], &["get(cup1)"]),
                interp(
                    "did(self,get(plate1))",
                    "the plate",
                    vec![(PA, "get(plate1)", Some(2))],
                    &["get(plate1)"],
                ),
            ]),
        ),
        case(
            "a preferred norm and a stronger discouraged one on the same reading: it loses",
            tray(vec![
                obj("mug1", "mug", &["clean", "chipped"], &[], [0.5, 0.1, 0.8], None),
                obj("mug2", "mug", &[], &[], [0.5, -0.1, 0.8], None),
            ]),
            norms(&[
                when(soft(PA, "get(X)", 2), &["clean(X)"]),
                when(soft(DA, "get(X)", 4), &["chipped(X)"]),
            ]),
            act("get", vec![ty("mug")]),
            expect(
                Assume,
                Some("did(self,get(mug2))"),
                "I am assuming you want me to get the right mug. I would rather not get the clean mug because the clean mug is chipped.",
            ),
        ),
        case(
            "a forbidden reading is never rescued by a preferred norm",
            clean_and_dirty(),
            norms(&[
                when(soft(PA, "get(X)", 5), &["dirty(X)"]),
                fs("did(self,get(mug2))"),
            ]),
            act("get", vec![ty("mug")]),
            expect(
                Assume,
                Some("did(self,get(mug1))"),
                "I am assuming you want me to get the clean mug. I cannot get the dirty mug because it requires a forbidden state.",
            )
            .act("assume(self,mean(human,did(self,get(mug1))))"),
        ),
        case(
            "a forbidden lone reading is refused with its hard reason, not the soft one",
            tray(vec![mug("mug2", "dirty", "green", -0.1)]),
            norms(&[
                when(soft(DA, "get(X)", 2), &["dirty(X)"]),
                fs("did(self,get(mug2))"),
            ]),
            act("get", vec![ty("mug")]),
            expect(
                Refuse,
                None,
                "I cannot get the mug because it requires a forbidden state.",
            )
            .act("cannot(did(self,get(mug2)),because(forbiddenState(did(self,get(mug2)))))"),
        ),
        case(
            "equal norm scores keep today's order and question",
            clean_and_dirty(),
            norms(&[soft(PA, "get(X)", 3)]),
            act("get", vec![ty("mug")]),
            expect(Ask, None, WHICH_MUG),
        ),
    ]);
}

#[test]
fn soft_norms_by_role_state_and_words() {
    let guests = || {
        norms(&[for_roles(
            when(soft(DA, "get(X)", 3), &["dirty(X)"]),
            &["guest"],
            &["staff"],
        )])
    };
    let as_roles = |roles: &[&str]| Request {
        speaker_roles: roles.iter().map(|r| r.to_string()).collect(),
        ..act("get", vec![ty("mug")])
    };
    run_cases(vec![
        case(
            "a norm for guests, asked by a guest",
            clean_and_dirty(),
            guests(),
            as_roles(&["guest"]),
            expect(
                Assume,
                Some("did(self,get(mug1))"),
                "I am assuming you want me to get the clean mug. I would rather not get the dirty mug because the dirty mug is dirty.",
            ),
        ),
        case(
            "a norm for guests, asked by someone else",
            clean_and_dirty(),
            guests(),
            as_roles(&["cook"]),
            expect(Ask, None, WHICH_MUG),
        ),
        case(
            "a norm for guests that exempts staff, asked by a guest on the staff",
            clean_and_dirty(),
            guests(),
            as_roles(&["guest", "staff"]),
            expect(Ask, None, WHICH_MUG),
        ),
        case(
            "a discouraged state, entered by the plan: holding a dirty mug",
            clean_and_dirty(),
            norms(&[when(soft(DS, "holding(self,X)", 3), &["dirty(X)"])]),
            act("get", vec![ty("mug")]),
            expect(
                Assume,
                Some("did(self,get(mug1))"),
                "I am assuming you want me to get the clean mug. I would rather not get the dirty mug because the dirty mug is dirty.",
            )
            .interps(vec![
                interp("did(self,get(mug1))", "the clean mug", vec![], &["get(mug1)"]),
                interp(
                    "did(self,get(mug2))",
                    "the dirty mug",
                    vec![(DS, "holding(self,mug2)", Some(1))],
                    &["get(mug2)"],
                ),
            ]),
        ),
        case(
            "a `when` about the reading's object is named",
            clean_and_dirty(),
            norms(&[noted(when(soft(DA, "get(X)", 3), &["dirty(X)"]), "not from the dishwasher")]),
            act("get", vec![id("mug2")]),
            expect(Comply, Some("did(self,get(mug2))"), "Okay, although the dirty mug is dirty."),
        ),
        case(
            "no `when` about the reading's objects: the note is the reason",
            scene(
                vec![mug("mug1", "clean", "blue", 0.1), mug("mug2", "dirty", "green", -0.1)],
                &["busy(kitchen1)"],
            ),
            norms(&[noted(
                when(soft(DA, "get(X)", 3), &["busy(kitchen1)"]),
                "we do not serve while the kitchen is busy",
            )]),
            act("get", vec![id("mug2")]),
            expect(
                Comply,
                Some("did(self,get(mug2))"),
                "Okay, although we do not serve while the kitchen is busy.",
            ),
        ),
        case(
            "no `when` at all: the note",
            clean_and_dirty(),
            norms(&[noted(soft(DA, "get(mug2)", 3), "that mug is reserved")]),
            act("get", vec![id("mug2")]),
            expect(Comply, Some("did(self,get(mug2))"), "Okay, although that mug is reserved."),
        ),
        case(
            "a note's control and direction characters are not spoken",
            clean_and_dirty(),
            norms(&[noted(soft(DA, "get(mug2)", 3), "\u{202e}that mug\u{0} is\nreserved.")]),
            act("get", vec![id("mug2")]),
            expect(Comply, Some("did(self,get(mug2))"), "Okay, although that mug is reserved."),
        ),
        case(
            "a note of nothing visible: the default words",
            clean_and_dirty(),
            norms(&[noted(soft(DA, "get(mug2)", 3), "\u{202e}\u{0} ")]),
            act("get", vec![id("mug2")]),
            expect(Comply, Some("did(self,get(mug2))"), "Okay, although it is discouraged."),
        ),
        case(
            "no `when` and no note: the default words",
            clean_and_dirty(),
            norms(&[soft(DA, "get(mug2)", 3)]),
            act("get", vec![ty("mug")]),
            expect(
                Assume,
                Some("did(self,get(mug1))"),
                "I am assuming you want me to get the clean mug. I would rather not get the dirty mug because it is discouraged.",
            ),
        ),
        case(
            "a preferred norm with nothing to name is said of the reading chosen",
            clean_and_dirty(),
            norms(&[soft(PA, "get(mug1)", 3)]),
            act("get", vec![ty("mug")]),
            expect(
                Assume,
                Some("did(self,get(mug1))"),
                "I am assuming you want me to get the clean mug. I would rather not get the dirty mug because it is less preferred than getting the clean mug.",
            ),
        ),
        case(
            "an indefinite: any clean mug will do, the dirty one is explained",
            tray(vec![
                mug("mug1", "clean", "blue", 0.1),
                mug("mug2", "dirty", "green", -0.1),
                mug("mug3", "clean", "red", 0.2),
            ]),
            norms(&[serving()]),
            in_serving(request(Directive::Words {
                text: "Get a mug.".into(),
            })),
            expect(
                Assume,
                Some("did(self,get(mug1))"),
                "I am assuming you want me to get the clean blue mug. I would rather not get the dirty mug because the dirty mug is dirty.",
            ),
        ),
    ]);
}

#[test]
fn natural_style_sets_the_tone_by_strength() {
    let natural = |request: Request| with_options(request, |o| o.style = Style::Natural);
    let by = |severity: i64| norms(&[when(soft(DA, "get(X)", severity), &["dirty(X)"])]);
    for (severity, said) in [
        (
            1,
            "I'll get the clean mug. I'd slightly prefer not to get the dirty mug: the dirty mug is dirty.",
        ),
        (
            3,
            "I'll get the clean mug. I'd rather not get the dirty mug: the dirty mug is dirty.",
        ),
        (
            5,
            "I'll get the clean mug. I really shouldn't get the dirty mug: the dirty mug is dirty.",
        ),
    ] {
        let d = run(&natural(act("get", vec![ty("mug")])), &clean_and_dirty(), &by(severity));
        assert_eq!(d.utterance, said, "severity {severity}");
    }
    let only_dirty = tray(vec![mug("mug2", "dirty", "green", -0.1)]);
    let d = run(&natural(act("get", vec![ty("mug")])), &only_dirty, &by(2));
    assert_eq!(d.utterance, "Okay, I will get the mug, although the mug is dirty.");
    let d = run(&natural(act("get", vec![ty("mug")])), &only_dirty, &by(4));
    assert_eq!(
        d.utterance,
        "Okay, I will get the mug, but you should know that the mug is dirty."
    );
}

#[test]
fn a_soft_norm_counts_once_per_reading_and_shows_its_score() {
    let scene = tray(vec![
        mug("mug1", "clean", "blue", 0.1),
        mug("mug2", "dirty", "green", -0.1),
    ]);
    // The directive's action is checked at (1) and again as the verb's own step: one reason.
    let norms = norms(&[
        when(soft(DA, "get(X)", 2), &["dirty(X)"]),
        when(soft(PA, "get(X)", 1), &["color(X,blue)"]),
    ]);
    let d = run(&act("get", vec![ty("mug")]), &scene, &norms);
    let scores: Vec<(String, i32)> = (d.interpretations.iter())
        .map(|i| (i.action.to_string(), i.norm_score()))
        .collect();
    assert_eq!(
        scores,
        [
            ("did(self,get(mug1))".to_owned(), 1),
            ("did(self,get(mug2))".to_owned(), -2)
        ]
    );
    let words: Vec<&[String]> = d.interpretations.iter().map(|i| i.reason_words.as_slice()).collect();
    assert_eq!(
        words,
        [
            &["the color of the clean mug is blue".to_owned()][..],
            &["the dirty mug is dirty".to_owned()][..]
        ]
    );
    assert_eq!(
        d.interpretations[0].outcome.reasons[0].term().to_string(),
        "preferredAction(get)"
    );
    assert!(d.interpretations.iter().all(|i| i.permissible() && i.feasible()));
}

#[test]
fn a_check_permits_a_step_that_breaks_a_discouraged_norm_and_says_why() {
    use crate::engine::check::check;
    use crate::engine::norms::Scope;
    let scene = tray(vec![mug("mug2", "dirty", "green", -0.1)]);
    let norms = norms(&[when(soft(DA, "get(X)", 2), &["dirty(X)"]), fa("destroy")]);
    let scope = Scope {
        context: "default",
        roles: &[],
        soft: true,
    };
    let library = Library::default_library();
    let checked = check(
        &[t("get(mug2)")],
        &scene,
        &norms,
        &library,
        scope,
        Style::Diarc,
        &|| false,
    );
    assert!(checked.permitted());
    assert_eq!(checked.utterance, "Okay, although the mug is dirty.");
    assert_eq!(checked.steps[0].outcome.reasons[0].kind(), DA);
    let refused = check(
        &[t("get(mug2)"), t("destroy(mug2)")],
        &scene,
        &norms,
        &library,
        scope,
        Style::Diarc,
        &|| false,
    );
    assert!(!refused.permitted());
    assert_eq!(
        refused.utterance,
        "I cannot destroy the mug because destroy is forbidden action."
    );
}

/// A follow-up's `choice` counts among the readings the question offered, which soft norms
/// change: a dispreferred reading first in the contract's order is never what "the first one"
/// picks.
#[test]
fn a_choice_counts_among_what_soft_norms_left_offered() {
    use crate::engine::request::Answer;
    let scene = scene(
        vec![
            obj("mug1", "mug", &["chipped"], &[], [0.5, 0.0, 0.8], None),
            obj("mug2", "mug", &["clean"], &[("color", "red")], [0.5, 0.1, 0.8], None),
            obj("mug3", "mug", &["clean"], &[("color", "green")], [0.5, 0.2, 0.8], None),
        ],
        &[],
    );
    let norms = norms(&[when(soft(DA, "get(X)", 3), &["chipped(X)"])]);
    let asked = run(&act("get", vec![ty("mug")]), &scene, &norms);
    assert_eq!(asked.kind, Ask);
    assert_eq!(asked.interpretations[0].description, "the chipped mug");
    let offered: Vec<String> = asked.offered.iter().map(ToString::to_string).collect();
    assert_eq!(offered, ["did(self,get(mug3))", "did(self,get(mug2))"]);
    for (choice, goal) in [(0, "did(self,get(mug3))"), (1, "did(self,get(mug2))")] {
        let request = Request {
            answer: Some(Answer::Choice(choice)),
            ..act("get", vec![ty("mug")])
        };
        let d = run(&request, &scene, &norms);
        assert_eq!(
            d.goal.as_ref().map(ToString::to_string).as_deref(),
            Some(goal),
            "{choice}"
        );
    }
    let third = Request {
        answer: Some(Answer::Choice(2)),
        ..act("get", vec![ty("mug")])
    };
    assert!(clarify(&third, &scene, &norms, &Library::default_library(), &|| false).is_err());
    // In words too: "the first one".
    let words = Request {
        answer: Some(Answer::Words("the first one".into())),
        ..act("get", vec![ty("mug")])
    };
    assert_eq!(
        run(&words, &scene, &norms)
            .goal
            .as_ref()
            .map(ToString::to_string)
            .as_deref(),
        Some("did(self,get(mug3))")
    );
}
