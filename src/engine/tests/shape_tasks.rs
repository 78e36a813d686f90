//! The shapes of tasks for the safety property of `shapes.rs`: well-formed words of several
//! steps, lists, "or", needs and purposes; structured steps; and the check that a task offered,
//! confirmed or acted on passes step by step on `/v1/check`'s path.

use super::*;
use crate::engine::check::check as check_steps;
use crate::engine::decision::Style;
use crate::engine::describe::is_task;
use crate::engine::norms::Scope;
use crate::engine::request::Answer;

use super::shapes::KINDS;

/// What of a case the task check reads.
pub(super) struct Said<'a> {
    pub(super) words: Option<&'a str>,
    pub(super) answer: &'a Option<Answer>,
    pub(super) norms: &'a [NormInput],
    pub(super) roles: &'a [&'static str],
    pub(super) context: &'a str,
}

/// Well-formed words of tasks and purposes: a first clause the scene can place, then another
/// step, a list, an "or", or a purpose.
pub(super) fn arb_task_words() -> impl Strategy<Value = String> {
    let verb = prop::sample::select(vec![
        "get",
        "grab",
        "take",
        "destroy",
        "tidy up",
        "juggle",
        "I need",
        "Can I have",
    ]);
    let colour = prop::sample::select(vec!["", "red ", "green ", "blue "]);
    let kind = prop::sample::select(KINDS.to_vec());
    let then = prop::sample::select(vec![
        " and put it on the box",
        " and then destroy it",
        ". Put it on the red box.",
        " and the mug",
        " or the box",
        " so I can smash it",
        " to smash the box",
        " for smashing the vase",
        " to put it on the box",
        ", then get the vase and put it on the mug",
        " and juggle it",
    ]);
    (verb, colour, kind, then).prop_map(|(verb, colour, kind, then)| format!("{verb} the {colour}{kind}{then}"))
}

pub(super) fn arb_steps() -> impl Strategy<Value = Vec<(&'static str, usize, bool)>> {
    prop::collection::vec(
        (
            prop::sample::select(vec!["get", "destroy", "put", "tidy", "pointTo"]),
            0..3usize,
            any::<bool>(),
        ),
        1..=4,
    )
}

/// A task offered, confirmed or acted on passes when its steps are checked alone, in order, in
/// one world (`/v1/check`'s path, which shares no code with a task's readings but the
/// simulation of one step); and a purpose the norms forbid outright (destroying, for anyone,
/// anywhere) is never obeyed or offered.
pub(super) fn check_tasks(
    d: &Decision,
    case: &Said<'_>,
    scene: &Scene,
    norms: &CompiledNorms,
    library: &Library,
) -> Result<(), TestCaseError> {
    let roles: Vec<String> = case.roles.iter().map(|r| (*r).to_owned()).collect();
    let scope = Scope {
        context: case.context,
        roles: &roles,
        soft: true,
    };
    let said_in = case.words.is_some_and(|w| w.contains(" in "));
    for action in d.offered.iter().chain(&d.goal) {
        let Some(task) = action.args().get(1).filter(|a| is_task(a)) else {
            continue;
        };
        if said_in {
            continue;
        }
        let checked = check_steps(task.args(), scene, norms, library, scope, Style::Diarc, &|| false);
        prop_assert!(
            checked.permitted(),
            "offered {} ({}): {}",
            action,
            d.kind.as_str(),
            checked.utterance
        );
    }
    let destroy_forbidden = case.norms.iter().any(|n| {
        n.kind.as_deref() == Some("forbidden_action")
            && n.action.as_deref() == Some("destroy")
            && n.when.is_none()
            && n.roles.is_none()
            && n.exempt_roles.is_none()
            && n.context.is_none()
    });
    let purposed = |w: &str| {
        ["so I can smash it", "to smash the box", "for smashing the vase"]
            .iter()
            .any(|p| w.contains(p))
    };
    // An answer that is a whole new directive ("Get the vase.") is decided afresh, without it.
    let afresh = matches!(&case.answer, Some(Answer::Words(w)) if w.ends_with('.'));
    if destroy_forbidden && !afresh && case.words.is_some_and(purposed) {
        prop_assert!(
            d.goal.is_none() && d.offered.is_empty(),
            "a forbidden purpose went along: {}",
            d.utterance
        );
    }
    Ok(())
}
