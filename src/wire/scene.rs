//! The scene as a request's JSON gives it: the agent, the objects with their geometry, and
//! extra facts; converted member for member to the engine's scene input.
//!
//! Owns: those shapes. Must not: check a value (the engine's scene does, naming the field).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

use super::clarify::{Scalar, texts};
use crate::engine::scene::{AgentInput, ObjectInput, PersonInput, SceneInput, Shape};

#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
pub struct SceneBody {
    pub agent: AgentBody,
    #[serde(default)]
    pub objects: Vec<ObjectBody>,
    #[serde(default)]
    pub facts: Vec<String>,
    /// The people present: referents in words and directives, recipients, and the subjects of
    /// `person(p)` and `role(p,r)` facts; never objects to handle.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub people: Vec<PersonBody>,
}

/// A person in the scene. As a referent a person is of type `person`, called by their names and
/// by each role ("Bob", "the child"); a verb may take a person only where its method has the
/// precondition `person(P)`.
#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct PersonBody {
    /// Unique among the scene's objects and people.
    pub id: String,
    /// Proper names (`["Bob"]`), 1 to 3 words of letters each, at most 8; heard in any case,
    /// the first spoken as written.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub names: Vec<String>,
    /// Role names (`["child"]`): each yields `role(p,r)`, and is a noun for the person.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub roles: Vec<String>,
    /// Where the person stands, metres, world frame (z up).
    #[schema(min_items = 3, max_items = 3)]
    pub position: [f64; 3],
}

#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
pub struct AgentBody {
    #[serde(default)]
    pub id: Option<String>,
    /// Metres, world frame (z up).
    #[schema(min_items = 3, max_items = 3)]
    pub position: [f64; 3],
    /// Metres.
    pub reach: f64,
    /// Widest object, metres, the gripper can close around; absent: grasp is not checked.
    #[serde(default)]
    pub gripper_aperture: Option<f64>,
    /// Heaviest object, kilograms, the arm can lift; absent: payload is not checked.
    #[serde(default)]
    pub payload: Option<f64>,
    /// Radius, metres, of the ball the gripper sweeps on its way to an object; absent: clearance
    /// is not checked.
    #[serde(default)]
    pub gripper_size: Option<f64>,
    /// Unit quaternion `[x, y, z, w]` turning the agent's point of view (x forward, y left, z
    /// up) into the world frame; absent: x forward. "Left of" and "the leftmost" are said from it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schema(min_items = 4, max_items = 4)]
    pub rotation: Option<[f64; 4]>,
}

#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
pub struct ObjectBody {
    pub id: String,
    #[serde(rename = "type")]
    pub kind: String,
    #[serde(default)]
    pub properties: Vec<String>,
    #[serde(default)]
    pub attributes: BTreeMap<String, Scalar>,
    /// Centre of the shape, metres, world frame.
    #[schema(min_items = 3, max_items = 3)]
    pub position: [f64; 3],
    #[serde(default)]
    pub shape: Option<ShapeBody>,
    /// Unit quaternion `[x, y, z, w]`.
    #[serde(default)]
    #[schema(min_items = 4, max_items = 4)]
    pub rotation: Option<[f64; 4]>,
    /// Kilograms; absent: payload is not checked for this object.
    #[serde(default)]
    pub mass: Option<f64>,
    /// More nouns the object may be called by in words (`["drink", "soda"]`), 1 to 3 words
    /// each, at most 8.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub names: Vec<String>,
}

#[derive(Clone, Debug, Deserialize, Serialize, ToSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ShapeBody {
    Ball {
        radius: f64,
    },
    Cuboid {
        #[schema(min_items = 3, max_items = 3)]
        half_extents: [f64; 3],
    },
    Cylinder {
        radius: f64,
        half_height: f64,
    },
}

impl From<SceneBody> for SceneInput {
    fn from(s: SceneBody) -> Self {
        SceneInput {
            agent: AgentInput {
                id: s.agent.id,
                position: s.agent.position,
                reach: s.agent.reach,
                gripper_aperture: s.agent.gripper_aperture,
                payload: s.agent.payload,
                gripper_size: s.agent.gripper_size,
                rotation: s.agent.rotation,
            },
            objects: s.objects.into_iter().map(Into::into).collect(),
            facts: s.facts,
            people: (s.people.into_iter())
                .map(|p| PersonInput {
                    id: p.id,
                    names: p.names,
                    roles: p.roles,
                    position: p.position,
                })
                .collect(),
        }
    }
}

impl From<ObjectBody> for ObjectInput {
    fn from(o: ObjectBody) -> Self {
        ObjectInput {
            id: o.id,
            kind: o.kind,
            properties: o.properties,
            attributes: texts(o.attributes),
            position: o.position,
            shape: o.shape.map(|s| match s {
                ShapeBody::Ball { radius } => Shape::Ball { radius },
                ShapeBody::Cuboid { half_extents } => Shape::Cuboid { half_extents },
                ShapeBody::Cylinder { radius, half_height } => Shape::Cylinder { radius, half_height },
            }),
            rotation: o.rotation,
            mass: o.mass,
            names: o.names,
        }
    }
}
