//! The scene a request carries: the agent, the objects with their geometry, and extra facts.
//!
//! Owns: the validated scene model and its constructor (`Scene::from_input`, every fault named by
//! its field), the facts each object yields, and reach (a parry3d distance query). Must not:
//! parse JSON or know about norms; a `Scene` that exists is valid.

use std::collections::BTreeMap;
use std::sync::OnceLock;

use hashbrown::HashTable;
use parry3d::bounding_volume::Aabb;
use parry3d::math::{Isometry, Point, Real, Translation, Vector};
use parry3d::na::{Quaternion, UnitQuaternion};
use parry3d::partitioning::{Bvh, BvhBuildStrategy};
use parry3d::query::{self, ShapeCastOptions};
use parry3d::shape::{Ball, Cuboid, Cylinder};

use super::input::{Invalid, RequestLimits, constant, finite, pointer_segment, positive};
use super::term::{Sym, Term};

mod facts;
mod people;
pub mod relate;
mod spoken;

pub use people::{DEFAULT_SPEAKER, PERSON, Person, PersonInput, person_predicate, speaker_facts};
use spoken::names_of;
pub use spoken::{MAX_NAMES, invisible, spoken, spoken_into, spoken_is, spoken_onto};

/// The robot itself.
#[derive(Clone, Debug, PartialEq)]
pub struct Agent {
    pub id: String,
    /// Centre of the arm's base, metres, world frame (right-handed, z up).
    pub position: [f64; 3],
    /// Largest distance, metres, from `position` to an object's shape the gripper can still touch.
    pub reach: f64,
    /// Widest object, metres, the gripper can close around; `None`: grasp is not checked.
    pub gripper_aperture: Option<f64>,
    /// Heaviest object, kilograms, the arm can lift; `None`: payload is not checked.
    pub payload: Option<f64>,
    /// Radius, metres, of the ball the gripper sweeps from `position` to an object; `None`:
    /// clearance is not checked.
    pub gripper_size: Option<f64>,
    /// Unit quaternion `[x, y, z, w]` turning the agent's point of view (x forward, y left, z
    /// up) into the world frame; `None` is the identity. Left and right are said from it.
    pub rotation: Option<[f64; 4]>,
}

/// An object's shape, in its own frame, centred on the object's `position`.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// Radius in metres.
    Ball { radius: f64 },
    /// Half the side lengths along the object's x, y and z, metres.
    Cuboid { half_extents: [f64; 3] },
    /// Axis along the object's z; radius and half the height, metres.
    Cylinder { radius: f64, half_height: f64 },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// Interned once, when the scene is checked: its facts, its index and every effect a
    /// reading has on it share this one symbol.
    pub id: Sym,
    pub kind: String,
    /// In the order given: the Incremental Algorithm tries them in this order.
    pub properties: Vec<String>,
    /// Keyed in byte order, which is the order the Incremental Algorithm tries them.
    pub attributes: BTreeMap<String, String>,
    /// Centre of the shape, metres, world frame.
    pub position: [f64; 3],
    /// `None`: the object is a point at `position`.
    pub shape: Option<Shape>,
    /// Unit quaternion `[x, y, z, w]` turning the shape about its centre; `None` is the identity.
    pub rotation: Option<[f64; 4]>,
    /// Kilograms; `None`: payload is not checked for this object.
    pub mass: Option<f64>,
    /// More nouns the object may be called by in words ("drink" for a soda can), lower case.
    pub names: Vec<String>,
}

/// Each object's index in the scene's list, found by its id. Keyed by the hash each id's
/// symbol already holds, so an object's id is hashed once, when it is interned; an entry is
/// only an index, read against the scene's list.
#[derive(Debug)]
pub(super) struct Ids(HashTable<usize>);

impl Ids {
    /// The index of every object of `objects`, whose ids are unique: for scenes a test builds.
    #[cfg(test)]
    pub(super) fn of(objects: &[Object]) -> Ids {
        let mut ids = Ids(HashTable::with_capacity(objects.len()));
        for i in 0..objects.len() {
            ids.insert(objects, i);
        }
        ids
    }

    /// Where `id` is in `objects`, the list this index was built over.
    fn get(&self, objects: &[Object], id: &str) -> Option<usize> {
        self.0.find(Sym::hash_of(id), |&i| objects[i].id == id).copied()
    }

    /// Whether an object of `objects` has the id `id`: by the hash the symbol holds, and one
    /// comparison of symbols, so the text is not hashed again.
    fn has(&self, objects: &[Object], id: &Sym) -> bool {
        self.0.find(id.text_hash(), |&i| objects[i].id == *id).is_some()
    }

    /// Adds `objects[i]`, whose id no object before it has.
    fn insert(&mut self, objects: &[Object], i: usize) {
        self.0
            .insert_unique(objects[i].id.text_hash(), i, |&j| objects[j].id.text_hash());
    }
}

/// A validated scene: ids are unique, geometry is finite and positive.
#[derive(Debug)]
pub struct Scene {
    pub agent: Agent,
    pub objects: Vec<Object>,
    /// Ground facts given beside the objects.
    pub facts: Vec<Term>,
    /// The people of `scene.people`, each also an object of type `person` in `objects`,
    /// after the scene's own objects.
    pub people: Vec<Person>,
    by_id: Ids,
    /// Reachability per object, computed at most once per request and only for objects asked about.
    reach_cache: Vec<OnceLock<bool>>,
    /// The first object in the way to each object, likewise computed at most once.
    clearance_cache: Vec<OnceLock<Option<usize>>>,
    /// Bounding-volume hierarchy over the world-frame boxes of the objects that have a shape,
    /// built at the first clearance query of a request, with the object index of each leaf.
    /// Leaves are numbered 0.. in that order, never by object index: parry's builder assumes
    /// leaves 0 and 1 when it is given one or two, and panics on a scene like [point, ball].
    bvh: OnceLock<(Bvh, Vec<usize>)>,
    /// Every object's box and the relations facts state, built at the first relation asked.
    layout: OnceLock<relate::Layout>,
}

/// The agent as a request describes it, before it is checked.
#[derive(Clone, Debug)]
pub struct AgentInput {
    /// Absent: `self`.
    pub id: Option<String>,
    pub position: [f64; 3],
    pub reach: f64,
    pub gripper_aperture: Option<f64>,
    pub payload: Option<f64>,
    pub gripper_size: Option<f64>,
    pub rotation: Option<[f64; 4]>,
}

/// An object as a request describes it, before it is checked; attribute values already as text.
#[derive(Clone, Debug)]
pub struct ObjectInput {
    pub id: String,
    pub kind: String,
    pub properties: Vec<String>,
    pub attributes: BTreeMap<String, String>,
    pub position: [f64; 3],
    pub shape: Option<Shape>,
    pub rotation: Option<[f64; 4]>,
    pub mass: Option<f64>,
    pub names: Vec<String>,
}

/// A scene as a request describes it: facts as text.
#[derive(Clone, Debug)]
pub struct SceneInput {
    pub agent: AgentInput,
    pub objects: Vec<ObjectInput>,
    pub facts: Vec<String>,
    pub people: Vec<PersonInput>,
}

impl Shape {
    /// A shape whose sizes are all positive; fields named relative to the shape.
    fn checked(self) -> Result<Shape, Invalid> {
        match &self {
            Shape::Ball { radius } => positive("/ball/radius", *radius)?,
            Shape::Cuboid { half_extents } => {
                // Pointers written out: no text is made for a size that is fine.
                let fields = [
                    "/cuboid/half_extents/0",
                    "/cuboid/half_extents/1",
                    "/cuboid/half_extents/2",
                ];
                for (field, h) in fields.into_iter().zip(half_extents) {
                    positive(field, *h)?;
                }
            }
            Shape::Cylinder { radius, half_height } => {
                positive("/cylinder/radius", *radius)?;
                positive("/cylinder/half_height", *half_height)?;
            }
        }
        Ok(self)
    }
}

impl Agent {
    /// Fields named relative to the agent.
    fn from_input(input: AgentInput) -> Result<Agent, Invalid> {
        let id = input.id.unwrap_or_else(|| "self".to_owned());
        constant("/id", &id, "the agent id")?;
        finite("/position", &input.position)?;
        if !(input.reach.is_finite() && input.reach >= 0.0) {
            return Err(Invalid::new("/reach", "must be a non-negative number of metres"));
        }
        for (field, value) in [
            ("/gripper_aperture", input.gripper_aperture),
            ("/payload", input.payload),
            ("/gripper_size", input.gripper_size),
        ] {
            if let Some(v) = value {
                positive(field, v)?;
            }
        }
        Ok(Agent {
            id,
            position: input.position,
            reach: input.reach,
            gripper_aperture: input.gripper_aperture,
            payload: input.payload,
            gripper_size: input.gripper_size,
            rotation: unit_rotation(input.rotation)?,
        })
    }
}

/// A rotation as given, normalised; one whose norm is off by more than a thousandth is refused.
fn unit_rotation(rotation: Option<[f64; 4]>) -> Result<Option<[f64; 4]>, Invalid> {
    let Some(q) = rotation else {
        return Ok(None);
    };
    finite("/rotation", &q)?;
    let norm = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    if (norm - 1.0).abs() > 1e-3 {
        return Err(Invalid::new(
            "/rotation",
            format!("must be a unit quaternion [x,y,z,w]; its norm is {norm}"),
        ));
    }
    Ok(Some(q.map(|c| c / norm)))
}

impl Object {
    /// Every field but the id's uniqueness, which only the scene can see; named relative to the
    /// object. The rotation is normalised.
    fn from_input(id: Sym, o: ObjectInput) -> Result<Object, Invalid> {
        constant("/type", &o.kind, "a type")?;
        for (j, p) in o.properties.iter().enumerate() {
            constant("", p, "a property").map_err(|e| e.within(&format!("/properties/{j}")))?;
        }
        for (key, value) in &o.attributes {
            let at = || format!("/attributes/{}", pointer_segment(key));
            constant("", key, "an attribute name").map_err(|e| e.within(&at()))?;
            constant("", value, "an attribute value").map_err(|e| e.within(&at()))?;
        }
        finite("/position", &o.position)?;
        let shape = o
            .shape
            .map(|s| s.checked().map_err(|e| e.within("/shape")))
            .transpose()?;
        let rotation = unit_rotation(o.rotation)?;
        if let Some(mass) = o.mass
            && !(mass.is_finite() && mass >= 0.0)
        {
            return Err(Invalid::new("/mass", "must be a non-negative number of kilograms"));
        }
        let names = names_of(o.names)?;
        Ok(Object {
            id,
            kind: o.kind,
            properties: o.properties,
            attributes: o.attributes,
            position: o.position,
            shape,
            rotation,
            mass: o.mass,
            names,
        })
    }
}

impl Scene {
    /// Checks every field of a scene within the operator's limits; the first fault is reported,
    /// named relative to the scene (`/objects/2/id`).
    pub fn from_input(input: SceneInput, limits: &RequestLimits) -> Result<Scene, Invalid> {
        // People are referents too: they count against the same limit.
        let (objects, all) = (input.objects.len(), input.objects.len() + input.people.len());
        if all > limits.max_objects {
            let (field, what) = match objects > limits.max_objects {
                true => ("/objects", format!("{objects} objects")),
                false => ("/people", format!("{all} objects and people")),
            };
            return Err(Invalid::new(
                field,
                format!(
                    "{what} is over the limit of {} per scene (--max-objects)",
                    limits.max_objects
                ),
            ));
        }
        let agent = Agent::from_input(input.agent).map_err(|e| e.within("/agent"))?;
        let mut by_id = Ids(HashTable::with_capacity(all));
        let mut objects = Vec::with_capacity(all);
        for (i, o) in input.objects.into_iter().enumerate() {
            let at = || format!("/objects/{i}");
            constant("/id", &o.id, "an object id").map_err(|e| e.within(&at()))?;
            let id = Sym::new(&o.id);
            // A duplicate is named before the object's other faults, as its id comes first.
            if by_id.has(&objects, &id) {
                return Err(Invalid::new(
                    format!("{}/id", at()),
                    format!("duplicate object id `{}`", o.id),
                ));
            }
            objects.push(Object::from_input(id, o).map_err(|e| e.within(&at()))?);
            by_id.insert(&objects, i);
        }
        let mut people = Vec::with_capacity(input.people.len());
        for (k, p) in input.people.into_iter().enumerate() {
            let at = || format!("/people/{k}");
            constant("/id", &p.id, "a person id").map_err(|e| e.within(&at()))?;
            let id = Sym::new(&p.id);
            if by_id.has(&objects, &id) {
                return Err(Invalid::new(
                    format!("{}/id", at()),
                    format!("duplicate id `{}`: an object or person has it already", p.id),
                ));
            }
            let (object, person) = p.checked(id, objects.len()).map_err(|e| e.within(&at()))?;
            objects.push(object);
            by_id.insert(&objects, person.index);
            people.push(person);
        }
        let mut facts = Vec::with_capacity(input.facts.len());
        for (k, text) in input.facts.iter().enumerate() {
            let field = || format!("/facts/{k}");
            let fact = Term::parse_within(text, limits.terms)
                .map_err(|e| Invalid::new(field(), format!("not a term: {e}")))?;
            if !fact.is_ground() || fact.is_var() {
                return Err(Invalid::new(field(), "a scene fact must be ground (no variables)"));
            }
            facts.push(fact);
        }
        people::settle(&mut people, &objects);
        let mut scene = Scene::indexed(agent, objects, facts, by_id);
        scene.people = people;
        Ok(scene)
    }

    /// Builds the scene from values already checked.
    pub(super) fn indexed(agent: Agent, objects: Vec<Object>, facts: Vec<Term>, by_id: Ids) -> Scene {
        let reach_cache = objects.iter().map(|_| OnceLock::new()).collect();
        let clearance_cache = objects.iter().map(|_| OnceLock::new()).collect();
        Scene {
            agent,
            objects,
            facts,
            people: Vec::new(),
            by_id,
            reach_cache,
            clearance_cache,
            bvh: OnceLock::new(),
            layout: OnceLock::new(),
        }
    }

    pub fn object(&self, id: &str) -> Option<&Object> {
        self.index_of(id).map(|i| &self.objects[i])
    }

    pub fn index_of(&self, id: &str) -> Option<usize> {
        self.by_id.get(&self.objects, id)
    }

    /// Whether the agent can touch the object: the distance from the agent's position to the
    /// object's shape (zero inside it) is at most `reach`. `None` when no such object exists.
    pub fn within_reach(&self, id: &str) -> Option<bool> {
        let index = self.index_of(id)?;
        Some(
            *self.reach_cache[index]
                .get_or_init(|| distance_to_shape(&self.objects[index], &self.agent.position) <= self.agent.reach),
        )
    }

    /// The object in the way when the gripper (a ball of `gripper_size`) moves in a straight line
    /// from the agent's position to the object: the first other object it would touch before
    /// touching the target. Objects the ball already overlaps at the start (the robot's own
    /// table, say) are not in the way. `None` when the path is clear or clearance is not checked.
    pub fn blocked_by(&self, id: &str) -> Option<&Object> {
        let size = self.agent.gripper_size?;
        let index = self.index_of(id)?;
        let blocker = *self.clearance_cache[index].get_or_init(|| first_in_the_way(self, index, size));
        blocker.map(|i| &self.objects[i])
    }

    fn bvh(&self) -> &(Bvh, Vec<usize>) {
        self.bvh.get_or_init(|| {
            let (objects, boxes): (Vec<usize>, Vec<Aabb>) = self
                .objects
                .iter()
                .enumerate()
                .filter_map(|(i, o)| parry_shape(o).map(|(pose, solid)| (i, solid.shape().compute_aabb(&pose))))
                .unzip();
            (Bvh::from_leaves(BvhBuildStrategy::default(), &boxes), objects)
        })
    }

    /// Where the objects stand to one another; built once per request, at the first asking.
    pub fn layout(&self) -> &relate::Layout {
        self.layout.get_or_init(|| relate::Layout::build(self))
    }

    /// The agent's point of view.
    pub fn frame(&self) -> relate::Frame {
        relate::Frame::of(self.agent.rotation)
    }

    /// Objects of the given type other than `id`, in scene order.
    pub fn same_kind<'a>(&'a self, kind: &'a str, id: &'a str) -> impl Iterator<Item = &'a Object> + 'a {
        self.objects.iter().filter(move |o| o.kind == kind && o.id != id)
    }
}

fn point(p: &[f64; 3]) -> Point<Real> {
    Point::new(p[0] as Real, p[1] as Real, p[2] as Real)
}

/// An object's shape as parry sees it, in its own frame, held by value: asked about once per
/// reading (room on a support) and once per object (reach, the BVH), it costs no allocation.
enum Solid {
    Ball(Ball),
    Cuboid(Cuboid),
    Cylinder(Cylinder),
}

impl Solid {
    fn shape(&self) -> &dyn parry3d::shape::Shape {
        match self {
            Solid::Ball(ball) => ball,
            Solid::Cuboid(cuboid) => cuboid,
            Solid::Cylinder(cylinder) => cylinder,
        }
    }
}

/// The object's shape as parry sees it, with its pose in the world frame; `None` for a point.
fn parry_shape(object: &Object) -> Option<(Isometry<Real>, Solid)> {
    let centre = point(&object.position).coords;
    let rotation = match object.rotation {
        Some([x, y, z, w]) => {
            UnitQuaternion::from_quaternion(Quaternion::new(w as Real, x as Real, y as Real, z as Real))
        }
        None => UnitQuaternion::identity(),
    };
    let pose = Isometry::from_parts(Translation::from(centre), rotation);
    Some(match object.shape.as_ref()? {
        Shape::Ball { radius } => (pose, Solid::Ball(Ball::new(*radius as Real))),
        Shape::Cuboid { half_extents: h } => (
            pose,
            Solid::Cuboid(Cuboid::new(Vector::new(h[0] as Real, h[1] as Real, h[2] as Real))),
        ),
        Shape::Cylinder { radius, half_height } => {
            // parry's cylinder stands along its local y; ours along the object's z. A quarter
            // turn about x carries local y onto z before the object's own rotation applies.
            let y_to_z = UnitQuaternion::from_axis_angle(&Vector::x_axis(), std::f32::consts::FRAC_PI_2);
            let pose = pose * Isometry::from_parts(Translation::identity(), y_to_z);
            (
                pose,
                Solid::Cylinder(Cylinder::new(*half_height as Real, *radius as Real)),
            )
        }
    })
}

/// Distance in metres from `point` (world frame) to the object's solid shape; zero inside it.
pub fn distance_to_shape(object: &Object, at: &[f64; 3]) -> f64 {
    match parry_shape(object) {
        None => euclid(&object.position, at),
        Some((pose, solid)) => f64::from(solid.shape().distance_to_point(&pose, &point(at), true)),
    }
}

/// The narrowest full width of the object's shape across its own axes, metres: what a
/// parallel gripper must open to. A point object is 0 wide.
pub fn grasp_width(object: &Object) -> f64 {
    match &object.shape {
        None => 0.0,
        Some(Shape::Ball { radius }) | Some(Shape::Cylinder { radius, .. }) => 2.0 * radius,
        Some(Shape::Cuboid { half_extents: h }) => 2.0 * h[0].min(h[1]).min(h[2]),
    }
}

/// Metres by which an item's footprint may exceed its support's and still fit: the boxes are
/// computed in single precision at the objects' positions, so two equal shapes differ by a
/// rounding that depends on where they stand (a notebook fitted on its twin one way and not the
/// other). A tenth of a millimetre is far above that rounding and far below any real misfit.
const ROOM_TOLERANCE: Real = 1e-4;

/// Whether `item` fits on top of `support`: the item's footprint (the x and y extents of its
/// world-frame bounding box) fits within the support's, in either orientation about z. A ball
/// has no flat top; a point item fits on any support with a shape.
pub fn room_on(support: &Object, item: &Object) -> bool {
    let Some((support_pose, support_shape)) = parry_shape(support) else {
        return false;
    };
    if matches!(support.shape, Some(Shape::Ball { .. })) {
        return false;
    }
    let footprint = |pose: &Isometry<Real>, solid: &Solid| {
        let aabb = solid.shape().compute_aabb(pose);
        let extents = aabb.extents();
        let (a, b) = (extents.x, extents.y);
        if a <= b { (a, b) } else { (b, a) }
    };
    let (room_a, room_b) = footprint(&support_pose, &support_shape);
    match parry_shape(item) {
        None => true,
        Some((pose, shape)) => {
            let (need_a, need_b) = footprint(&pose, &shape);
            need_a <= room_a + ROOM_TOLERANCE && need_b <= room_b + ROOM_TOLERANCE
        }
    }
}

/// See [`Scene::blocked_by`].
fn first_in_the_way(scene: &Scene, target: usize, size: f64) -> Option<usize> {
    let start = point(&scene.agent.position);
    let goal = &scene.objects[target];
    let offset = point(&goal.position) - start;
    let length = offset.norm();
    if length <= Real::EPSILON {
        return None;
    }
    let direction = offset / length;
    let gripper = Ball::new(size as Real);
    let at_start = Isometry::translation(start.x, start.y, start.z);
    let options = ShapeCastOptions::with_max_time_of_impact(length);
    // Time (in metres travelled, at unit speed) until the gripper touches an object's shape.
    let time_to = |object: &Object| -> Option<Real> {
        let (pose, solid) = parry_shape(object)?;
        if query::intersection_test(&at_start, &gripper, &pose, solid.shape()).unwrap_or(false) {
            return None;
        }
        let hit = query::cast_shapes(
            &at_start,
            &direction,
            &gripper,
            &pose,
            &Vector::zeros(),
            solid.shape(),
            options,
        );
        hit.ok().flatten().map(|h| h.time_of_impact)
    };
    let reach_goal = match parry_shape(goal) {
        Some(_) => time_to(goal).unwrap_or(0.0),
        None => (length - size as Real).max(0.0),
    };
    // Only objects whose boxes meet the box swept by the gripper can be in the way: the BVH
    // finds them in about logarithmic time, and only they are shape-cast.
    let end = start + direction * reach_goal;
    let radius = Vector::repeat(size as Real);
    let swept = Aabb::new(start.inf(&end) - radius, start.sup(&end) + radius);
    let (bvh, objects) = scene.bvh();
    let mut candidates: Vec<usize> = bvh.intersect_aabb(&swept).map(|leaf| objects[leaf as usize]).collect();
    candidates.sort_unstable();
    candidates
        .into_iter()
        .filter(|&i| i != target)
        .filter_map(|i| {
            time_to(&scene.objects[i])
                .filter(|t| *t + 1e-6 < reach_goal)
                .map(|t| (i, t))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
        .map(|(i, _)| i)
}

fn euclid(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[cfg(test)]
mod tests;
