//! Checks while acting: the next step, or the rest of a plan, against the norms in force now.
//!
//! Owns: simulating given steps in order in one private world, each starting where the last
//! left off. Must not: resolve references or choose among readings; the steps are ground.

use std::sync::Arc;

use super::action::Library;
use super::describe::Describer;
use super::norms::{CompiledNorms, Scope};
use super::scene::Scene;
use super::simulate::{Env, Outcome, simulate_from};
use super::speech::{self, Style};
use super::term::Term;
use super::world::{Base, World};

/// One step, simulated.
#[derive(Clone, Debug, PartialEq)]
pub struct StepCheck {
    pub step: Term,
    /// The step in words: "get the plastic vase".
    pub reading: String,
    pub outcome: Outcome,
    /// Each reason in words, in the request's style.
    pub reason_words: Vec<String>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Check {
    pub steps: Vec<StepCheck>,
    /// "Okay." when every step may be done; otherwise why not the first step that may not.
    pub utterance: String,
    pub norm_version: i64,
}

impl Check {
    /// Every step is permissible and feasible.
    pub fn permitted(&self) -> bool {
        self.steps
            .iter()
            .all(|s| s.outcome.permissible() && s.outcome.feasible())
    }
}

/// Simulates `steps` in order from `scene`, under the norms in force in `scope`.
pub fn check(
    steps: &[Term],
    scene: &Scene,
    norms: &CompiledNorms,
    library: &Library,
    scope: Scope<'_>,
    style: Style,
) -> Check {
    let env = Env {
        scene,
        norms,
        library,
        scope,
    };
    let mut describer = Describer::new(scene, library);
    let mut world = World::new(Arc::new(Base::new(scene.all_facts())));
    let mut checked = Vec::with_capacity(steps.len());
    for step in steps {
        let (outcome, after) = simulate_from(&env, world, step);
        world = after;
        let reason_words = outcome
            .reasons
            .iter()
            .map(|r| speech::reason_words(r, style, &mut describer))
            .collect();
        checked.push(StepCheck {
            step: step.clone(),
            reading: describer.reading(step),
            outcome,
            reason_words,
        });
    }
    let utterance = match checked
        .iter()
        .find(|s| !(s.outcome.permissible() && s.outcome.feasible()))
    {
        None => match style {
            Style::Diarc => "Okay.".to_owned(),
            Style::Natural => "Okay, I can go on.".to_owned(),
        },
        Some(first) => match style {
            Style::Diarc => format!("I cannot {} because {}.", first.reading, first.reason_words[0]),
            Style::Natural => format!("I can't go on to {}: {}.", first.reading, first.reason_words[0]),
        },
    };
    Check {
        steps: checked,
        utterance,
        norm_version: norms.version,
    }
}
