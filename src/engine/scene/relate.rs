//! Where objects stand to one another, as the contract's relations, superlatives and ordinals
//! say: from `scene.facts`, or from the objects' world-frame axis-aligned boxes seen from the
//! agent. Metres throughout; the world frame is right-handed with z up.
//!
//! Owns: the contract's thresholds and rules, each object's box, and an index of the boxes
//! built once per request so that a relation is checked against nearby candidates only. Must
//! not: read words, resolve references or speak; every answer here is decided, never guessed.

use parry3d::bounding_volume::Aabb;
use parry3d::math::{Point, Real};
use parry3d::na::{Quaternion, UnitQuaternion, Vector3};
use parry3d::partitioning::{Bvh, BvhBuildStrategy};
use std::sync::{Mutex, OnceLock};

use rustc_hash::{FxHashMap, FxHashSet};

use super::{Object, Scene, Shape};

/// `on(a,b)`: a's bottom is within this of b's top.
pub const ON_GAP: f64 = 0.03;
/// `near(a,b)`: the boxes are at most this far apart.
pub const NEAR_GAP: f64 = 0.25;
/// `left_of` and the like: a's centre is more than this further in the direction than b's...
pub const SIDE_MARGIN: f64 = 0.05;
/// ...and the boxes are at most this far apart.
pub const SIDE_GAP: f64 = 1.0;
/// Superlatives: values within this share of the best tie with it.
pub const TIE_SHARE: f64 = 0.05;

/// A relation whose smaller side has at most this many objects on its other side is checked
/// pair by pair; a larger one asks the index of the boxes.
const PAIRS: usize = 64;

/// Pairs checked between two askings of the deadline (a few hundred microseconds' work).
const ASK_EVERY: usize = 4096;

/// A relation between two objects, as the contract names it in facts and structured requests.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Relation {
    On,
    In,
    Under,
    Near,
    LeftOf,
    RightOf,
    Behind,
    InFrontOf,
    /// A source, "the cup from the shelf": on it or in it.
    From,
}

impl Relation {
    /// Every relation, in the contract's order (which descriptions try landmarks in).
    pub const ALL: [Relation; 9] = [
        Relation::On,
        Relation::In,
        Relation::Under,
        Relation::Near,
        Relation::LeftOf,
        Relation::RightOf,
        Relation::Behind,
        Relation::InFrontOf,
        Relation::From,
    ];

    /// The name in facts (`on(a,b)`) and in a structured reference's `relations`.
    pub fn name(self) -> &'static str {
        match self {
            Relation::On => "on",
            Relation::In => "in",
            Relation::Under => "under",
            Relation::Near => "near",
            Relation::LeftOf => "left_of",
            Relation::RightOf => "right_of",
            Relation::Behind => "behind",
            Relation::InFrontOf => "in_front_of",
            Relation::From => "from",
        }
    }

    /// The relations of place, in the contract's order: every one but "from", a source (the
    /// last of [`Relation::ALL`]).
    pub const PLACES: &'static [Relation] = match Relation::ALL.split_last() {
        Some((Relation::From, places)) => places,
        _ => panic!("Relation::ALL ends with From"),
    };

    pub fn from_name(name: &str) -> Option<Relation> {
        Relation::ALL.into_iter().find(|r| r.name() == name)
    }

    /// As the robot says it before the landmark: "on", "to the left of".
    pub fn spoken(self) -> &'static str {
        match self {
            Relation::LeftOf => "to the left of",
            Relation::RightOf => "to the right of",
            Relation::InFrontOf => "in front of",
            other => other.name(),
        }
    }

    /// The relations a fact may state for this one: "from" is stated as `on` or `in`.
    fn stated_as(self) -> &'static [Relation] {
        match self {
            Relation::From => &[Relation::On, Relation::In],
            Relation::On => &[Relation::On],
            Relation::In => &[Relation::In],
            Relation::Under => &[Relation::Under],
            Relation::Near => &[Relation::Near],
            Relation::LeftOf => &[Relation::LeftOf],
            Relation::RightOf => &[Relation::RightOf],
            Relation::Behind => &[Relation::Behind],
            Relation::InFrontOf => &[Relation::InFrontOf],
        }
    }

    /// How far apart two boxes may be, metres, and the relation still hold; `None`: any
    /// distance along z (`under`), within touching in x and y.
    fn reach(self) -> Option<f64> {
        match self {
            Relation::On | Relation::From => Some(ON_GAP),
            Relation::In => Some(0.0),
            Relation::Under => None,
            Relation::Near => Some(NEAR_GAP),
            Relation::LeftOf | Relation::RightOf | Relation::Behind | Relation::InFrontOf => Some(SIDE_GAP),
        }
    }
}

/// What a superlative compares, and which end wins.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Superlative {
    /// Box volume: biggest, largest (most); smallest (least).
    Volume { most: bool },
    /// Box height: tallest (most); shortest (least).
    Height { most: bool },
    /// `mass`: heaviest (most); lightest (least).
    Mass { most: bool },
    /// Distance from the agent's position to the object's centre: farthest (most); nearest,
    /// closest (least).
    Distance { most: bool },
    /// How far left of the agent the centre is: leftmost (most); rightmost (least).
    Left { most: bool },
    /// The centre's height: highest (most); lowest (least).
    Elevation { most: bool },
}

impl Superlative {
    /// The measure of one object, or `None` when the object lacks what is compared.
    fn measure(self, scene: &Scene, object: &Object) -> Option<f64> {
        let b = world_box(object);
        match self {
            Superlative::Volume { .. } => object
                .shape
                .as_ref()
                .map(|_| (0..3).map(|i| b.max[i] - b.min[i]).product()),
            Superlative::Height { .. } => object.shape.as_ref().map(|_| b.max[2] - b.min[2]),
            Superlative::Mass { .. } => object.mass,
            Superlative::Distance { .. } => Some(distance(&object.position, &scene.agent.position)),
            Superlative::Left { .. } => Some(scene.frame().left(&object.position, &scene.agent.position)),
            Superlative::Elevation { .. } => Some(object.position[2]),
        }
    }

    fn most(self) -> bool {
        match self {
            Superlative::Volume { most }
            | Superlative::Height { most }
            | Superlative::Mass { most }
            | Superlative::Distance { most }
            | Superlative::Left { most }
            | Superlative::Elevation { most } => most,
        }
    }

    /// What an object must be known for, as "I do not know how big every box is" says it.
    pub fn unknown(self) -> &'static str {
        match self {
            Superlative::Volume { .. } => "how big",
            Superlative::Height { .. } => "how tall",
            Superlative::Mass { .. } => "how heavy",
            // Positions are always given: these are never unknown.
            Superlative::Distance { .. } => "how far",
            Superlative::Left { .. } | Superlative::Elevation { .. } => "where",
        }
    }
}

/// Which way an ordinal counts: "from the left" counts the leftmost first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Direction {
    Left,
    Right,
    /// Nearest the agent first, along its forward axis.
    Front,
    Back,
}

impl Direction {
    pub fn spoken(self) -> &'static str {
        match self {
            Direction::Left => "left",
            Direction::Right => "right",
            Direction::Front => "front",
            Direction::Back => "back",
        }
    }
}

/// An axis-aligned box in the world frame, metres; a point object's is its position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Box3 {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl Box3 {
    /// The distance between two boxes; zero when they touch or overlap.
    pub fn gap(&self, other: &Box3) -> f64 {
        let gap = |i: usize| (self.min[i] - other.max[i]).max(other.min[i] - self.max[i]).max(0.0);
        norm([gap(0), gap(1), gap(2)])
    }

    fn overlaps_on(&self, other: &Box3, axis: usize) -> bool {
        self.min[axis] <= other.max[axis] && other.min[axis] <= self.max[axis]
    }

    fn holds_point(&self, p: &[f64; 3], axes: usize) -> bool {
        (0..axes).all(|i| self.min[i] <= p[i] && p[i] <= self.max[i])
    }
}

/// The object's world-frame axis-aligned box, computed in double precision from its shape and
/// rotation: a rotated cuboid's half extent along axis i is the sum of |R_ij| h_j; a cylinder's
/// is its half height times |a_i| plus its radius times the sine between its axis a and axis i.
pub fn world_box(object: &Object) -> Box3 {
    let rotation = match object.rotation {
        Some([x, y, z, w]) => UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z)),
        None => UnitQuaternion::identity(),
    };
    let half: [f64; 3] = match &object.shape {
        None => [0.0; 3],
        Some(Shape::Ball { radius }) => [*radius; 3],
        Some(Shape::Cuboid { half_extents: h }) => {
            let r = rotation.to_rotation_matrix();
            let m = r.matrix();
            std::array::from_fn(|i| (0..3).map(|j| m[(i, j)].abs() * h[j]).sum())
        }
        Some(Shape::Cylinder { radius, half_height }) => {
            let axis = rotation * Vector3::z();
            std::array::from_fn(|i| half_height * axis[i].abs() + radius * (1.0 - axis[i] * axis[i]).max(0.0).sqrt())
        }
    };
    let p = object.position;
    Box3 {
        min: std::array::from_fn(|i| p[i] - half[i]),
        max: std::array::from_fn(|i| p[i] + half[i]),
    }
}

/// The agent's point of view: its forward and left axes in the world frame (x and y turned by
/// its rotation; without one, x forward and y left).
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    forward: [f64; 3],
    left: [f64; 3],
}

impl Frame {
    pub fn of(rotation: Option<[f64; 4]>) -> Frame {
        let rotation = match rotation {
            Some([x, y, z, w]) => UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z)),
            None => UnitQuaternion::identity(),
        };
        let f = rotation * Vector3::x();
        let l = rotation * Vector3::y();
        Frame {
            forward: [f.x, f.y, f.z],
            left: [l.x, l.y, l.z],
        }
    }

    /// How far left of `from` the point `p` is, metres (negative: to the right).
    pub fn left(&self, p: &[f64; 3], from: &[f64; 3]) -> f64 {
        (0..3).map(|i| (p[i] - from[i]) * self.left[i]).sum()
    }

    /// How far ahead of `from` the point `p` is, metres (negative: behind it).
    pub fn ahead(&self, p: &[f64; 3], from: &[f64; 3]) -> f64 {
        (0..3).map(|i| (p[i] - from[i]) * self.forward[i]).sum()
    }
}

/// Euclidean, without overflow for positions far apart (1e300 m squared is infinite).
fn distance(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    norm([a[0] - b[0], a[1] - b[1], a[2] - b[2]])
}

/// The length of `v`, scaled by its largest component so that no square overflows; infinite
/// only when a component is (two positions 1e308 m apart either way).
fn norm(v: [f64; 3]) -> f64 {
    let scale = v.iter().fold(0.0f64, |m, c| m.max(c.abs()));
    if scale == 0.0 || !scale.is_finite() {
        return scale;
    }
    scale * v.iter().map(|c| (c / scale).powi(2)).sum::<f64>().sqrt()
}

/// What a reference selected (object indices) and what the scene could not tell of it.
pub type Remembered = (Vec<usize>, Option<String>);

/// The scene's boxes, its stated relations and an index over the boxes; built at the first
/// relation a request asks about.
#[derive(Debug)]
pub struct Layout {
    boxes: Vec<Box3>,
    /// Leaf i is object i; boxes widened to single precision outward. Built at the first
    /// relation whose two sides are both too many to pair up.
    index: OnceLock<Bvh>,
    /// `(relation, a, b)` for each fact `relation(a,b)` between two objects of the scene.
    stated: FxHashSet<(Relation, usize, usize)>,
    /// The same, listed per relation in the order given, for walking them.
    listed: Vec<(Relation, usize, usize)>,
    /// What each reference with relations, a superlative or an ordinal selected, by its
    /// structure written out: a request asks for the same reference when resolving it and
    /// again when showing its parse.
    selected: Mutex<FxHashMap<String, Remembered>>,
}

impl Layout {
    pub(super) fn build(scene: &Scene) -> Layout {
        let boxes: Vec<Box3> = scene.objects.iter().map(world_box).collect();
        let mut stated = FxHashSet::default();
        let mut listed = Vec::new();
        for fact in &scene.facts {
            let (Some(name), [a, b]) = (fact.name(), fact.args()) else {
                continue;
            };
            let Some(relation) = Relation::from_name(name.as_str()).filter(|r| *r != Relation::From) else {
                continue;
            };
            let object =
                |t: &crate::engine::term::Term| t.name().filter(|_| t.arity() == 0).and_then(|n| scene.index_of(n));
            if let (Some(a), Some(b)) = (object(a), object(b))
                && stated.insert((relation, a, b))
            {
                listed.push((relation, a, b));
            }
        }
        Layout {
            boxes,
            index: OnceLock::new(),
            stated,
            listed,
            selected: Mutex::default(),
        }
    }

    /// What `key` selected earlier in this request (and what the scene could not tell), if it
    /// was asked.
    pub fn selected(&self, key: &str) -> Option<Remembered> {
        self.selected.lock().ok()?.get(key).cloned()
    }

    /// Notes what `key` selected, for the next asking.
    pub fn remember(&self, key: String, objects: &[usize], untold: Option<String>) {
        if let Ok(mut selected) = self.selected.lock() {
            selected.insert(key, (objects.to_vec(), untold));
        }
    }

    pub fn boxes(&self) -> &[Box3] {
        &self.boxes
    }

    fn index(&self) -> &Bvh {
        self.index.get_or_init(|| {
            let leaves: Vec<Aabb> = self.boxes.iter().map(single).collect();
            Bvh::from_leaves(BvhBuildStrategy::default(), &leaves)
        })
    }

    /// Whether `relation(a,b)` holds for objects `a` and `b` (indices): stated, or so by the
    /// geometry. An object stands in no relation to itself.
    pub fn holds(&self, scene: &Scene, relation: Relation, a: usize, b: usize) -> bool {
        a != b
            && (relation.stated_as().iter().any(|r| self.stated.contains(&(*r, a, b)))
                || self.geometry(scene, relation, a, b))
    }

    /// The contract's rule for each relation over the two boxes.
    fn geometry(&self, scene: &Scene, relation: Relation, a: usize, b: usize) -> bool {
        let (ba, bb) = (&self.boxes[a], &self.boxes[b]);
        let (ca, cb) = (&scene.objects[a].position, &scene.objects[b].position);
        let frame = scene.frame();
        match relation {
            Relation::On => (ba.min[2] - bb.max[2]).abs() <= ON_GAP && bb.holds_point(ca, 2),
            Relation::In => bb.holds_point(ca, 3) && !self.holds(scene, Relation::On, a, b),
            Relation::Under => ba.max[2] < bb.min[2] && ba.overlaps_on(bb, 0) && ba.overlaps_on(bb, 1),
            Relation::Near => {
                ba.gap(bb) <= NEAR_GAP
                    && ![(a, b), (b, a)]
                        .iter()
                        .any(|&(x, y)| self.holds(scene, Relation::On, x, y) || self.holds(scene, Relation::In, x, y))
            }
            Relation::LeftOf => frame.left(ca, cb) > SIDE_MARGIN && ba.gap(bb) <= SIDE_GAP,
            Relation::RightOf => frame.left(cb, ca) > SIDE_MARGIN && ba.gap(bb) <= SIDE_GAP,
            Relation::Behind => frame.ahead(ca, cb) > SIDE_MARGIN && ba.gap(bb) <= SIDE_GAP,
            Relation::InFrontOf => frame.ahead(cb, ca) > SIDE_MARGIN && ba.gap(bb) <= SIDE_GAP,
            Relation::From => self.geometry(scene, Relation::On, a, b) || self.geometry(scene, Relation::In, a, b),
        }
    }

    /// Those of `subjects` (object indices, ascending) that stand in `relation` to one of
    /// `landmarks`, ascending. Each side is walked from the smaller, each object asking the
    /// index for the boxes within the relation's reach: never every pair. `None` when the
    /// deadline passed on the way.
    pub fn related(
        &self,
        scene: &Scene,
        subjects: &[usize],
        relation: Relation,
        landmarks: &[usize],
        expired: &dyn Fn() -> bool,
    ) -> Option<Vec<usize>> {
        let n = self.boxes.len();
        let mut is_subject = vec![false; n];
        subjects.iter().for_each(|&i| is_subject[i] = true);
        let mut is_landmark = vec![false; n];
        landmarks.iter().for_each(|&i| is_landmark[i] = true);
        let mut kept = vec![false; n];
        for &(r, a, b) in &self.listed {
            if relation.stated_as().contains(&r) && is_subject[a] && is_landmark[b] && a != b {
                kept[a] = true;
            }
        }
        let by_subject = subjects.len() <= landmarks.len();
        let (walked, other) = if by_subject {
            (subjects, landmarks)
        } else {
            (landmarks, subjects)
        };
        // Pairs checked since the deadline was last asked: one object may be near thousands.
        let mut checked = 0usize;
        for &x in walked {
            if by_subject && kept[x] {
                continue;
            }
            // Whether the pair (x, y) settles x, so that nothing more is asked about it.
            let mut settles = |y: usize| {
                checked += 1;
                let (a, b) = if by_subject { (x, y) } else { (y, x) };
                let wanted = if by_subject {
                    is_landmark[b]
                } else {
                    is_subject[a] && !kept[a]
                };
                if wanted && a != b && self.geometry(scene, relation, a, b) {
                    kept[a] = true;
                    return by_subject;
                }
                false
            };
            if other.len() <= PAIRS {
                for &y in other {
                    if settles(y) {
                        break;
                    }
                }
            } else {
                for leaf in self.index().intersect_aabb(&self.reach_of(x, relation)) {
                    if settles(leaf as usize) {
                        break;
                    }
                }
            }
            if checked >= ASK_EVERY {
                checked = 0;
                if expired() {
                    return None;
                }
            }
        }
        Some(subjects.iter().copied().filter(|&i| kept[i]).collect())
    }

    /// The objects that object `a` stands in `relation` to, ascending.
    pub fn landmarks_of(&self, scene: &Scene, a: usize, relation: Relation) -> Vec<usize> {
        let mut out: Vec<usize> = (self.listed.iter())
            .filter(|(r, x, b)| relation.stated_as().contains(r) && *x == a && *b != a)
            .map(|(_, _, b)| *b)
            .collect();
        for b in self
            .index()
            .intersect_aabb(&self.reach_of(a, relation))
            .map(|leaf| leaf as usize)
        {
            if b != a && self.geometry(scene, relation, a, b) {
                out.push(b);
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    /// The box that any object standing in `relation` with object `x` (either way round)
    /// touches: x's box widened by the relation's reach, and by single precision's rounding.
    fn reach_of(&self, x: usize, relation: Relation) -> Aabb {
        let b = &self.boxes[x];
        let mut aabb = single(b);
        let widen = |v: f64| v as Real + (v.abs() as Real) * 4.0 * Real::EPSILON + 1e-6;
        match relation.reach() {
            Some(reach) => {
                for i in 0..3 {
                    aabb.mins[i] -= widen(reach);
                    aabb.maxs[i] += widen(reach);
                }
            }
            None => {
                for i in 0..2 {
                    aabb.mins[i] -= widen(0.0);
                    aabb.maxs[i] += widen(0.0);
                }
                aabb.mins[2] = Real::MIN;
                aabb.maxs[2] = Real::MAX;
            }
        }
        aabb
    }
}

/// A box in single precision, never smaller than the double-precision one.
fn single(b: &Box3) -> Aabb {
    let down = |v: f64| {
        let s = v as Real;
        if f64::from(s) > v { s.next_down() } else { s }
    };
    let up = |v: f64| {
        let s = v as Real;
        if f64::from(s) < v { s.next_up() } else { s }
    };
    Aabb::new(
        Point::new(down(b.min[0]), down(b.min[1]), down(b.min[2])),
        Point::new(up(b.max[0]), up(b.max[1]), up(b.max[2])),
    )
}

/// An object a superlative compares lacks what is compared (no shape, no mass).
#[derive(Debug)]
pub struct Unmeasured;

/// The objects of `among` (indices) a superlative picks: the best and every one within
/// [`TIE_SHARE`] of it.
pub fn superlative(scene: &Scene, among: &[usize], superlative: Superlative) -> Result<Vec<usize>, Unmeasured> {
    let values: Vec<f64> = among
        .iter()
        .map(|&i| superlative.measure(scene, &scene.objects[i]).ok_or(Unmeasured))
        .collect::<Result<_, _>>()?;
    let best = values.iter().copied().reduce(|a, b| match superlative.most() {
        true => a.max(b),
        false => a.min(b),
    });
    let Some(best) = best else {
        return Ok(Vec::new());
    };
    Ok(among
        .iter()
        .zip(&values)
        // An infinite best (a volume past f64) ties only with itself.
        .filter(|(_, v)| **v == best || best.is_finite() && (*v - best).abs() <= TIE_SHARE * best.abs())
        .map(|(&i, _)| i)
        .collect())
}

/// The objects of `among` (indices, ascending) that may be the `nth` (from 1) counting from
/// `direction`: an object's place is uncertain by the others within [`SIDE_MARGIN`] of it, so
/// it may be nth when fewer than n lie clearly before it and at least n − 1 others do not lie
/// clearly after it.
pub fn ordinal(scene: &Scene, among: &[usize], nth: usize, direction: Direction) -> Vec<usize> {
    let frame = scene.frame();
    let agent = scene.agent.position;
    // How far along the count each object is; larger is earlier.
    let value = |i: usize| {
        let p = &scene.objects[i].position;
        match direction {
            Direction::Left => frame.left(p, &agent),
            Direction::Right => -frame.left(p, &agent),
            Direction::Front => -frame.ahead(p, &agent),
            Direction::Back => frame.ahead(p, &agent),
        }
    };
    let mut sorted: Vec<f64> = among.iter().map(|&i| value(i)).collect();
    sorted.sort_by(f64::total_cmp);
    let count_above = |v: f64| sorted.len() - sorted.partition_point(|&w| w <= v);
    let count_below = |v: f64| sorted.partition_point(|&w| w < v);
    among
        .iter()
        .copied()
        .filter(|&i| {
            let v = value(i);
            let before = count_above(v + SIDE_MARGIN);
            let after = count_below(v - SIDE_MARGIN);
            nth >= 1 && before < nth && nth <= among.len() - after
        })
        .collect()
}

#[cfg(test)]
mod tests {
    /// Positions far apart are far, not infinitely or NaN apart: a superlative compares them.
    #[test]
    fn distances_between_extreme_positions_do_not_overflow() {
        let d = super::distance(&[-1e300, 1e300, 1e300], &[1e12, 1e12, 0.0]);
        assert!((d / 1.7320508e300 - 1.0).abs() < 1e-6, "{d}");
        assert_eq!(super::distance(&[1.0, 2.0, 3.0], &[1.0, 2.0, 3.0]), 0.0);
        assert!((super::distance(&[0.0, 3.0, 4.0], &[0.0; 3]) - 5.0).abs() < 1e-12);
    }
}
