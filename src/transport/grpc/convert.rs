//! Proto messages to and from the wire body types, field for field.
//!
//! Must not: check anything the REST path checks; only what proto3 cannot say the same way
//! (a fixed-length list, an absent message) is caught here, with the same field pointers.

use std::collections::BTreeMap;

use super::pb;
use crate::engine::action::{ActionInput, MethodInput};
use crate::engine::decision::Style;
use crate::engine::input::Spelled;
use crate::engine::request::{Alternatives, SinglePermissible, SoftNorms, Strategy};
use crate::error::Error;
use crate::wire::{
    AgentBody, AnswerBody, BindingBody, CheckBody, CheckDto, CheckOptionsBody, ChoiceBody, ClarifyBody, DecisionDto,
    DirectiveBody, InterpretationDto, NormBody, NormDto, ObjectBody, OptionsBody, PersonBody, ReasonDto, ReferenceBody,
    ReferenceParseDto, RelationBody, Scalar, SceneBody, ShapeBody, StepArgumentBody, StepBody,
};

fn missing(field: &str) -> Error {
    let name = field.rsplit('/').next().unwrap_or(field);
    Error::invalid(field, format!("missing field `{name}`"))
}

/// A repeated double that stands for a fixed-length JSON array.
/// `values` as exactly `N` numbers; `field` names them, and is made only when they are not.
fn fixed<const N: usize>(field: impl FnOnce() -> String, values: Vec<f64>) -> Result<[f64; N], Error> {
    let count = values.len();
    <[f64; N]>::try_from(values).map_err(|_| Error::invalid(field(), format!("expected {N} numbers, got {count}")))
}

/// One of an option's words, spelled as the engine spells it.
pub(super) fn word<T: Spelled>(field: &str, value: Option<String>) -> Result<Option<T>, Error> {
    value
        .map(|text| {
            T::parse(&text)
                .ok_or_else(|| Error::invalid(field, format!("unknown variant `{text}`, expected {}", T::expected())))
        })
        .transpose()
}

impl TryFrom<pb::ClarifyRequest> for ClarifyBody {
    type Error = Error;

    fn try_from(request: pb::ClarifyRequest) -> Result<Self, Error> {
        let directive = request.directive.ok_or_else(|| missing("/directive"))?;
        let scene = request.scene.ok_or_else(|| missing("/scene"))?;
        let options = request
            .options
            .map(|o| -> Result<OptionsBody, Error> {
                Ok(OptionsBody {
                    strategy: word::<Strategy>("/options/strategy", o.strategy)?,
                    single_permissible: word::<SinglePermissible>("/options/single_permissible", o.single_permissible)?,
                    style: word::<Style>("/options/style", o.style)?,
                    max_spoken: o.max_spoken,
                    max_readings: o.max_readings,
                    deadline_ms: o.deadline_ms,
                    confirm_above_ratio: o.confirm_above_ratio,
                    soft_norms: word::<SoftNorms>("/options/soft_norms", o.soft_norms)?,
                    alternatives: word::<Alternatives>("/options/alternatives", o.alternatives)?,
                })
            })
            .transpose()?;
        let answer = request.answer.map(|a| -> Result<AnswerBody, Error> {
            let choice = match (a.choice, a.alternative) {
                (at, false) => at.map(ChoiceBody::At),
                (None, true) => Some(ChoiceBody::Alternative),
                (Some(_), true) => {
                    return Err(Error::invalid(
                        "/answer",
                        "give exactly one of `choice`, `alternative`, `id`, `reference`, `text`",
                    ));
                }
            };
            Ok(AnswerBody {
                choice,
                id: a.id,
                reference: a.reference.map(ReferenceBody::from),
                text: a.text,
            })
        });
        Ok(ClarifyBody {
            speaker: request.speaker,
            directive: directive.into(),
            scene: scene.try_into()?,
            context: request.context,
            options,
            speaker_roles: (!request.speaker_roles.is_empty()).then_some(request.speaker_roles),
            answer: answer.transpose()?,
            focus: (!request.focus.is_empty()).then_some(request.focus),
        })
    }
}

impl From<pb::Directive> for DirectiveBody {
    fn from(d: pb::Directive) -> Self {
        let bindings = (!d.bindings.is_empty()).then(|| {
            d.bindings
                .into_iter()
                .map(|(variable, list)| {
                    let candidates = list
                        .candidates
                        .into_iter()
                        .map(|c| match c.score {
                            None => BindingBody::Id(c.id),
                            Some(score) => BindingBody::Scored { id: c.id, score },
                        })
                        .collect();
                    (variable, candidates)
                })
                .collect()
        });
        DirectiveBody {
            arguments: (d.action.is_some() || !d.arguments.is_empty())
                .then(|| d.arguments.into_iter().map(ReferenceBody::from).collect()),
            action: d.action,
            form: d.form,
            bindings,
            text: d.text,
            joiner: d.joiner,
            steps: (!d.steps.is_empty()).then(|| d.steps.into_iter().map(StepBody::from).collect()),
        }
    }
}

impl From<pb::Step> for StepBody {
    fn from(s: pb::Step) -> Self {
        StepBody {
            action: s.action,
            arguments: (s.arguments.into_iter())
                .map(|a| StepArgumentBody {
                    id: a.id,
                    kind: a.r#type,
                    attributes: (!a.attributes.is_empty())
                        .then(|| a.attributes.into_iter().map(|(k, v)| (k, Scalar::Text(v))).collect()),
                    properties: (!a.properties.is_empty()).then_some(a.properties),
                    relations: relations(a.relations),
                    count: a.count,
                    all: a.all,
                    step: a.step,
                    argument: a.argument,
                })
                .collect(),
            joiner: s.joiner,
        }
    }
}

impl From<pb::Reference> for ReferenceBody {
    fn from(r: pb::Reference) -> Self {
        ReferenceBody {
            id: r.id,
            kind: r.r#type,
            attributes: (!r.attributes.is_empty())
                .then(|| r.attributes.into_iter().map(|(k, v)| (k, Scalar::Text(v))).collect()),
            properties: (!r.properties.is_empty()).then_some(r.properties),
            relations: relations(r.relations),
            count: r.count,
            all: r.all,
        }
    }
}

/// A missing `to` is an empty reference, refused as one where the engine checks it.
fn relations(relations: Vec<pb::Relation>) -> Vec<RelationBody> {
    (relations.into_iter())
        .map(|r| RelationBody {
            relation: r.relation,
            to: Box::new(r.to.map(ReferenceBody::from).unwrap_or_default()),
        })
        .collect()
}

impl TryFrom<pb::Scene> for SceneBody {
    type Error = Error;

    fn try_from(scene: pb::Scene) -> Result<Self, Error> {
        let agent = scene.agent.ok_or_else(|| missing("/scene/agent"))?;
        let objects = scene
            .objects
            .into_iter()
            .enumerate()
            .map(|(i, o)| object(i, o))
            .collect::<Result<_, _>>()?;
        Ok(SceneBody {
            agent: AgentBody {
                id: agent.id,
                position: fixed(|| "/scene/agent/position".to_owned(), agent.position)?,
                reach: agent.reach.ok_or_else(|| missing("/scene/agent/reach"))?,
                gripper_aperture: agent.gripper_aperture,
                payload: agent.payload,
                gripper_size: agent.gripper_size,
                rotation: match agent.rotation.is_empty() {
                    true => None,
                    false => Some(fixed(|| "/scene/agent/rotation".to_owned(), agent.rotation)?),
                },
            },
            objects,
            facts: scene.facts,
            people: (scene.people.into_iter().enumerate())
                .map(|(k, p)| {
                    Ok(PersonBody {
                        position: fixed(|| format!("/scene/people/{k}/position"), p.position)?,
                        id: p.id,
                        names: p.names,
                        roles: p.roles,
                    })
                })
                .collect::<Result<_, Error>>()?,
        })
    }
}

/// The `i`th object of the scene. Its pointer is made only for an error: a scene of 10,000
/// objects is converted on every request.
fn object(i: usize, o: pb::Object) -> Result<ObjectBody, Error> {
    let at = |member: &str| format!("/scene/objects/{i}/{member}");
    let shape = match o.shape {
        None => None,
        Some(pb::Shape { kind: None }) => {
            return Err(Error::invalid(
                at("shape"),
                "expected one of `ball`, `cuboid`, `cylinder`",
            ));
        }
        Some(pb::Shape { kind: Some(kind) }) => Some(match kind {
            pb::shape::Kind::Ball(b) => ShapeBody::Ball { radius: b.radius },
            pb::shape::Kind::Cuboid(c) => ShapeBody::Cuboid {
                half_extents: fixed(|| at("shape/cuboid/half_extents"), c.half_extents)?,
            },
            pb::shape::Kind::Cylinder(c) => ShapeBody::Cylinder {
                radius: c.radius,
                half_height: c.half_height,
            },
        }),
    };
    let rotation = if o.rotation.is_empty() {
        None
    } else {
        Some(fixed(|| at("rotation"), o.rotation)?)
    };
    Ok(ObjectBody {
        position: fixed(|| at("position"), o.position)?,
        id: o.id,
        kind: o.r#type,
        properties: o.properties,
        attributes: o
            .attributes
            .into_iter()
            .map(|(k, v)| (k, Scalar::Text(v)))
            .collect::<BTreeMap<_, _>>(),
        shape,
        rotation,
        mass: o.mass,
        names: o.names,
    })
}

impl From<DecisionDto> for pb::ClarifyResponse {
    fn from(d: DecisionDto) -> Self {
        pb::ClarifyResponse {
            decision: d.decision,
            utterance: d.utterance,
            speech_act: d.speech_act,
            goal: d.goal,
            interpretations: d.interpretations.into_iter().map(Into::into).collect(),
            norm_version: d.norm_version,
            library_version: d.library_version,
            text: d.text,
            alternative: d.alternative,
            offered: d.offered,
            limits: d.limits.map(limits),
            parse: d.parse.map(|p| pb::Parse {
                act: p.act,
                addressee: p.addressee,
                form: p.form,
                references: p.references.into_iter().map(parsed_reference).collect(),
                ignored: p.ignored,
                unclear: p.unclear,
                steps: (p.steps.into_iter())
                    .map(|s| pb::ParsedStep {
                        act: s.act,
                        form: s.form,
                        references: s.references.into_iter().map(parsed_reference).collect(),
                        pronouns: (s.pronouns.into_iter())
                            .map(|p| pb::ParsedPronoun {
                                words: p.words,
                                argument: p.argument,
                                bound_to: p.bound_to,
                                step: p.step,
                                step_argument: p.step_argument,
                                focus: p.focus,
                            })
                            .collect(),
                    })
                    .collect(),
                purposes: (p.purposes.into_iter())
                    .map(|p| pb::ParsedPurpose {
                        words: p.words,
                        form: p.form,
                        after: p.after,
                    })
                    .collect(),
            }),
        }
    }
}

/// One reference of a parse (of the words, or of one step of a task).
fn parsed_reference(r: ReferenceParseDto) -> pb::ParsedReference {
    pb::ParsedReference {
        words: r.words,
        candidates: r.candidates,
    }
}

impl From<InterpretationDto> for pb::Interpretation {
    fn from(i: InterpretationDto) -> Self {
        pb::Interpretation {
            action: i.action,
            description: i.description,
            permissible: i.permissible,
            feasible: i.feasible,
            reasons: i.reasons.into_iter().map(Into::into).collect(),
            plan: i.plan,
            score: i.score,
            norm_score: i.norm_score,
        }
    }
}

impl From<ReasonDto> for pb::Reason {
    fn from(r: ReasonDto) -> Self {
        pb::Reason {
            kind: r.kind,
            detail: r.detail,
            norm_id: r.norm_id,
            severity: r.severity.map(u32::from),
            words: r.words,
        }
    }
}

impl From<pb::CreateNormRequest> for NormBody {
    fn from(n: pb::CreateNormRequest) -> Self {
        NormBody {
            id: None,
            revision: None,
            kind: n.kind,
            action: n.action,
            state: n.state,
            when: (!n.when.is_empty()).then_some(n.when),
            context: n.context,
            severity: n.severity,
            note: n.note,
            roles: (!n.roles.is_empty()).then_some(n.roles),
            exempt_roles: (!n.exempt_roles.is_empty()).then_some(n.exempt_roles),
        }
    }
}

impl From<NormDto> for pb::Norm {
    fn from(n: NormDto) -> Self {
        pb::Norm {
            id: n.id,
            revision: n.revision,
            kind: n.kind,
            action: n.action,
            state: n.state,
            when: n.when,
            context: n.context,
            severity: u32::from(n.severity),
            note: n.note,
            roles: n.roles,
            exempt_roles: n.exempt_roles,
        }
    }
}

impl TryFrom<pb::CheckRequest> for CheckBody {
    type Error = Error;

    fn try_from(request: pb::CheckRequest) -> Result<Self, Error> {
        let scene = request.scene.ok_or_else(|| missing("/scene"))?;
        let deadline_ms = request.options.as_ref().and_then(|o| o.deadline_ms);
        let style = word::<Style>("/options/style", request.options.and_then(|o| o.style))?;
        Ok(CheckBody {
            scene: scene.try_into()?,
            steps: request.steps,
            context: request.context,
            speaker_roles: (!request.speaker_roles.is_empty()).then_some(request.speaker_roles),
            options: (style.is_some() || deadline_ms.is_some()).then_some(CheckOptionsBody { style, deadline_ms }),
        })
    }
}

fn limits(l: crate::wire::LimitsDto) -> pb::Limits {
    pb::Limits {
        reason: l.reason,
        readings: l.readings,
        simulated: l.simulated,
    }
}

impl From<CheckDto> for pb::CheckResponse {
    fn from(c: CheckDto) -> Self {
        pb::CheckResponse {
            permitted: c.permitted,
            steps: c
                .steps
                .into_iter()
                .map(|s| pb::StepCheck {
                    step: s.step,
                    permissible: s.permissible,
                    feasible: s.feasible,
                    reasons: s.reasons.into_iter().map(Into::into).collect(),
                    plan: s.plan,
                })
                .collect(),
            utterance: c.utterance,
            norm_version: c.norm_version,
            limits: c.limits.map(limits),
        }
    }
}

impl From<pb::Action> for ActionInput {
    fn from(a: pb::Action) -> Self {
        ActionInput {
            name: a.name,
            parameters: a.parameters,
            joiner: a.joiner,
            distinct: a.distinct,
            words: a.words,
            joiners: a.joiners,
            implied: (a.implied.into_iter())
                .map(|(parameter, facts)| (parameter, facts.facts))
                .collect(),
            methods: a
                .methods
                .into_iter()
                .map(|m| MethodInput {
                    steps: m.steps,
                    reach: m.reach,
                    grasp: m.grasp,
                    place: (!m.place.is_empty()).then_some(m.place),
                    preconditions: m.preconditions,
                    adds: m.adds,
                    removes: m.removes,
                })
                .collect(),
        }
    }
}

impl From<ActionInput> for pb::Action {
    fn from(a: ActionInput) -> Self {
        pb::Action {
            name: a.name,
            parameters: a.parameters,
            joiner: a.joiner,
            distinct: a.distinct,
            words: a.words,
            joiners: a.joiners,
            implied: (a.implied.into_iter())
                .map(|(parameter, facts)| (parameter, pb::ImpliedFacts { facts }))
                .collect(),
            methods: a
                .methods
                .into_iter()
                .map(|m| pb::Method {
                    steps: m.steps,
                    reach: m.reach,
                    grasp: m.grasp,
                    place: m.place.unwrap_or_default(),
                    preconditions: m.preconditions,
                    adds: m.adds,
                    removes: m.removes,
                })
                .collect(),
        }
    }
}

impl From<crate::wire::NormSetDto> for pb::NormSet {
    fn from(set: crate::wire::NormSetDto) -> Self {
        pb::NormSet {
            version: set.version,
            norms: set.norms.into_iter().map(Into::into).collect(),
        }
    }
}

impl From<crate::wire::AuditEntryDto> for pb::AuditEntry {
    fn from(e: crate::wire::AuditEntryDto) -> Self {
        pb::AuditEntry {
            id: e.id,
            at: e.at,
            actor: e.actor,
            subject: e.subject,
            operation: e.operation,
            target: e.target,
            before_json: e.before.map(|v| v.to_string()),
            after_json: e.after.map(|v| v.to_string()),
            version: e.version,
        }
    }
}
