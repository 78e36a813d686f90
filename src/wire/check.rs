//! A check of steps while acting, and its verdict, as JSON.

use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use super::clarify::{LimitsDto, ReasonDto, SceneBody, reason_dtos};
use crate::engine::check::{Check, CheckInput};
use crate::engine::decision::Style;
use crate::engine::term::Term;

/// Steps to check in order from the current scene, e.g. `["get(object4)", "put(object4,tray1)"]`.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct CheckBody {
    pub scene: SceneBody,
    /// Ground action terms, 1 to 1000, done in this order.
    pub steps: Vec<String>,
    #[serde(default)]
    pub context: Option<String>,
    #[serde(default)]
    pub speaker_roles: Option<Vec<String>>,
    #[serde(default)]
    pub options: Option<CheckOptionsBody>,
}

#[derive(Clone, Debug, Default, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct CheckOptionsBody {
    /// `diarc` (default) or `natural`.
    #[serde(default)]
    pub style: Option<Style>,
    /// Milliseconds the check may take, from the request's arrival (1..=60000, default 2000);
    /// past it, the steps not checked to the end are not permitted and `limits` says so.
    #[serde(default)]
    #[schema(minimum = 1, maximum = 60000)]
    pub deadline_ms: Option<u64>,
}

impl From<CheckBody> for CheckInput {
    fn from(body: CheckBody) -> Self {
        let options = body.options.unwrap_or_default();
        CheckInput {
            scene: body.scene.into(),
            steps: body.steps,
            context: body.context,
            speaker_roles: body.speaker_roles,
            style: options.style,
            deadline_ms: options.deadline_ms,
        }
    }
}

#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct StepCheckDto {
    pub step: String,
    pub permissible: bool,
    pub feasible: bool,
    pub reasons: Vec<ReasonDto>,
    /// The primitive steps simulated for it, in order.
    pub plan: Vec<String>,
}

#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, ToSchema)]
pub struct CheckDto {
    /// Every step is permissible and feasible under the norms in force now.
    pub permitted: bool,
    pub steps: Vec<StepCheckDto>,
    /// "Okay.", or why not the first step that may not be done.
    pub utterance: String,
    pub norm_version: i64,
    /// Present when the deadline kept steps from being checked to the end.
    #[serde(skip_serializing_if = "Option::is_none", default)]
    pub limits: Option<LimitsDto>,
}

impl From<&Check> for CheckDto {
    fn from(check: &Check) -> Self {
        CheckDto {
            permitted: check.permitted(),
            steps: check
                .steps
                .iter()
                .map(|s| StepCheckDto {
                    step: s.step.text(),
                    permissible: s.outcome.permissible(),
                    feasible: s.outcome.feasible(),
                    reasons: reason_dtos(&s.outcome.reasons, &s.reason_words),
                    plan: s.outcome.plan.iter().map(Term::text).collect(),
                })
                .collect(),
            utterance: check.utterance.clone(),
            norm_version: check.norm_version,
            limits: check.limits.as_ref().map(LimitsDto::from),
        }
    }
}
