//! A checked scene's index of its objects: each object is found by its own id and by nothing
//! else, however many objects share a hash bucket or a prefix, and a repeated id is refused
//! where it repeats.

use super::*;
use crate::engine::input::RequestLimits;
use crate::engine::scene::{AgentInput, ObjectInput, SceneInput};

fn input(ids: &[String]) -> SceneInput {
    SceneInput {
        agent: AgentInput {
            id: None,
            position: [0.0; 3],
            reach: 1.0,
            gripper_aperture: None,
            payload: None,
            gripper_size: None,
            rotation: None,
        },
        objects: (ids.iter())
            .map(|id| ObjectInput {
                id: id.clone(),
                kind: "thing".into(),
                properties: vec![],
                attributes: BTreeMap::new(),
                position: [0.0; 3],
                shape: None,
                rotation: None,
                mass: None,
                names: vec![],
            })
            .collect(),
        facts: vec![],
        people: vec![],
    }
}

proptest! {
    #[test]
    fn a_scene_finds_each_object_by_its_id_and_by_nothing_else(
        ids in proptest::collection::btree_set("[a-z][a-z0-9_]{0,6}", 0..300),
        others in proptest::collection::vec("[a-z][a-z0-9_]{0,7}", 0..20),
    ) {
        let ids: Vec<String> = ids.into_iter().collect();
        let scene = Scene::from_input(input(&ids), &RequestLimits::default()).unwrap();
        for (i, id) in ids.iter().enumerate() {
            prop_assert_eq!(scene.index_of(id), Some(i));
            prop_assert_eq!(scene.object(id).map(|o| o.id.as_str()), Some(id.as_str()));
        }
        for other in others.iter().filter(|o| !ids.contains(o)) {
            prop_assert_eq!(scene.index_of(other), None);
        }
        // Every object states its type with its own id, the one symbol its index knows.
        let named: Vec<String> = scene.all_facts().iter().map(|f| f.args()[0].to_string()).collect();
        prop_assert_eq!(named, ids);
    }

    #[test]
    fn a_repeated_id_is_refused_at_its_second_place(
        ids in proptest::collection::btree_set("[a-z][a-z0-9]{0,5}", 1..100),
        repeat in any::<prop::sample::Index>(),
        at in any::<prop::sample::Index>(),
    ) {
        let mut ids: Vec<String> = ids.into_iter().collect();
        let first = repeat.index(ids.len());
        let second = first + 1 + at.index(ids.len() - first);
        ids.insert(second, ids[first].clone());
        let error = Scene::from_input(input(&ids), &RequestLimits::default()).unwrap_err();
        prop_assert_eq!(error.field, format!("/objects/{second}/id"));
        prop_assert_eq!(error.message, format!("duplicate object id `{}`", ids[first]));
    }
}
