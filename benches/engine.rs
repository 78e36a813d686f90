//! Engine benchmarks: the paper's "Get the vase." (structured and in words, and with 100 soft
//! norms beside the paper's), reading the paper's sentence against the office, tasks of
//! several steps (reading five, deciding two against one), a reference with two relations
//! against a plain one over 10,000 objects, readings ×
//! objects × norms, checking a request's scene, and the cost of one world copy. `cargo bench --bench engine`; results in BENCHMARKS.md.
//!
//! The scene is built once per benchmark and reused, as the engine sees one per request: its
//! per-request caches (reach, clearance) are warm after the first iteration.

use std::hint::black_box;
use std::time::Duration;

use criterion::{BatchSize, BenchmarkId, Criterion, criterion_group, criterion_main};
use scruple::engine::input::RequestLimits;
use scruple::engine::norms::{CompiledNorms, Norm};
use scruple::engine::request::{Checked, Request};
use scruple::engine::world::{Base, World};
use scruple::engine::{Library, clarify};
use scruple::wire::ClarifyBody;
use serde_json::{Value, json};

/// The service's allocator (`src/main.rs`), so that the engine is measured as it runs there.
#[global_allocator]
static ALLOCATOR: scruple::allocator::Allocator = scruple::allocator::Allocator;

fn paper() -> Value {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/scenarios/paper-demo.json");
    serde_json::from_str(&std::fs::read_to_string(path).expect("../shared/scenarios/paper-demo.json")).unwrap()
}

fn input(body: Value) -> Checked {
    let body: ClarifyBody = serde_json::from_value(body).unwrap();
    Request::from_input(body.into(), &RequestLimits::default()).unwrap()
}

fn compile(norms: &[Value]) -> CompiledNorms {
    let norms = norms
        .iter()
        .enumerate()
        .map(|(i, n)| {
            let body: scruple::wire::NormBody = serde_json::from_value(n.clone()).unwrap();
            Norm {
                id: i as i64 + 1,
                revision: 0,
                spec: body.into_input().validate().unwrap(),
            }
        })
        .collect();
    CompiledNorms::compile(1, norms)
}

/// `count` cups with small box shapes, spread within reach; every tenth is fragile.
fn objects(count: usize) -> Vec<Value> {
    (0..count)
        .map(|i| {
            let angle = i as f64 * 0.61;
            let r = 0.3 + 0.5 * ((i * 7919) % 1000) as f64 / 1000.0;
            let mut o = json!({"id": format!("o{i}"), "type": "cup", "position": [r * angle.cos(), r * angle.sin(), 0.8],
                               "shape": {"cuboid": {"half_extents": [0.03, 0.03, 0.05]}}});
            if i % 10 == 0 {
                o["properties"] = json!(["fragile"]);
            }
            o
        })
        .collect()
}

/// 100 norms of every kind, most of which never match, as a real norm set would be.
fn hundred_norms() -> Vec<Value> {
    let mut norms = Vec::new();
    for i in 0..40 {
        norms.push(json!({"kind": "forbidden_state", "state": format!("on(o{i},o{})", i + 1)}));
    }
    for i in 0..30 {
        norms.push(json!({"kind": "forbidden_action", "action": format!("destroy(o{i})")}));
    }
    for i in 0..20 {
        norms.push(json!({"kind": "forbidden_state", "state": "holding(self,X)", "when": ["fragile(X)", format!("near{i}(X)")]}));
    }
    for i in 0..9 {
        norms.push(json!({"kind": "forbidden_action", "action": format!("verb{i}")}));
    }
    norms.push(json!({"kind": "forbidden_action", "action": "put(X,Y)", "when": ["fragile(X)"]}));
    norms
}

/// 100 soft norms, 10 of them bearing on the lab's vases (about getting or holding one, each on a
/// condition of its own: some hold of the fragile vase, some of the plastic one, some of
/// neither); the other 90 are on other verbs, objects, facts and contexts.
fn hundred_soft_norms() -> Vec<Value> {
    let on_vases = [
        ("discouraged_action", "get(X)", vec!["fragile(X)"]),
        ("discouraged_state", "holding(self,X)", vec!["material(X,glass)"]),
        ("preferred_action", "get(X)", vec!["material(X,plastic)"]),
        ("preferred_state", "holding(self,X)", vec!["vase(X)"]),
        ("discouraged_action", "get(X)", vec!["vase(X)", "heavy(X)"]),
        ("discouraged_state", "holding(self,X)", vec!["color(X,red)"]),
        ("preferred_action", "get(X)", vec!["vase(X)", "on(X,shelf1)"]),
        ("discouraged_action", "get(object3)", vec![]),
        ("preferred_state", "did(self,get(object4))", vec![]),
        (
            "discouraged_state",
            "holding(self,X)",
            vec!["fragile(X)", "on(self,ladder1)"],
        ),
    ];
    let mut norms: Vec<Value> = (on_vases.iter().enumerate())
        .map(|(i, (kind, term, when))| {
            let member = if kind.ends_with("_action") { "action" } else { "state" };
            json!({"kind": kind, member: term, "when": when, "severity": 1 + i % 5})
        })
        .collect();
    for i in 0..20 {
        norms.push(json!({"kind": "discouraged_state", "state": "on(X,Y)", "when": [format!("near{i}(X)")]}));
    }
    for i in 0..30 {
        norms.push(json!({"kind": "preferred_action", "action": format!("destroy(o{i})")}));
    }
    for i in 0..30 {
        norms.push(json!({"kind": "discouraged_state", "state": format!("on(o{i},o{})", i + 1)}));
    }
    for i in 0..10 {
        norms.push(json!({"kind": "preferred_action", "action": format!("verb{i}"), "context": "kitchen"}));
    }
    norms
}

fn bench_paper(c: &mut Criterion) {
    let demo = paper();
    let norms = compile(demo["norms"].as_array().unwrap());
    let library = Library::default_library();
    let vase =
        input(json!({"directive": {"action": "get", "arguments": [{"type": "vase"}]}, "scene": demo["scenes"]["lab"]}));
    c.bench_function("paper/get_the_vase", |b| {
        b.iter(|| clarify(black_box(&vase.request), &vase.scene, &norms, &library, &|| false).unwrap())
    });
    // The paper's norms and 100 soft ones (10 bearing on the vases), against the paper's alone.
    let mut with_soft = demo["norms"].as_array().unwrap().clone();
    with_soft.extend(hundred_soft_norms());
    let soft = compile(&with_soft);
    assert_eq!(soft.len(), 103);
    // The same 100 installed, with `soft_norms: ignore`: what merely having them costs.
    let ignoring = input(json!({"directive": {"action": "get", "arguments": [{"type": "vase"}]},
                                "scene": demo["scenes"]["lab"], "options": {"soft_norms": "ignore"}}));
    c.bench_function("soft/get_the_vase_100_ignored", |b| {
        b.iter(|| {
            clarify(black_box(&ignoring.request), &ignoring.scene, &soft, &library, &|| {
                false
            })
            .unwrap()
        })
    });
    for (name, norms) in [("soft/get_the_vase_none", &norms), ("soft/get_the_vase_100", &soft)] {
        c.bench_function(name, |b| {
            b.iter(|| clarify(black_box(&vase.request), &vase.scene, norms, &library, &|| false).unwrap())
        });
    }
    // The same decision from the human's words: the reading of the words is inside the loop.
    let words = input(json!({"directive": {"text": "Get the vase."}, "scene": demo["scenes"]["lab"]}));
    c.bench_function("paper/get_the_vase_in_words", |b| {
        b.iter(|| clarify(black_box(&words.request), &words.scene, &norms, &library, &|| false).unwrap())
    });
    let office = input(json!({"directive": {"action": "steal", "arguments": []}, "scene": demo["scenes"]["office"]}));
    c.bench_function("words/pepper_can_you_go_steal_the_cash_box", |b| {
        b.iter(|| {
            scruple::engine::words::understand(
                black_box("Pepper, can you go steal the cash box for me?"),
                &office.scene,
                &library,
                scruple::engine::words::heard(&[]),
                &|| false,
            )
        })
    });
}

/// Several steps in one directive: reading five steps against the paper's lab, and deciding a
/// task of two steps against the one step it starts with, both from words, in a kitchen.
fn bench_tasks(c: &mut Criterion) {
    let demo = paper();
    let norms = compile(demo["norms"].as_array().unwrap());
    let library = Library::default_library();
    let lab = input(json!({"directive": {"action": "get", "arguments": []}, "scene": demo["scenes"]["lab"]}));
    let five = "Get the mug and put it on the red notebook, then get the plastic vase and put it on the green \
                notebook and then point to the mug.";
    let read =
        scruple::engine::words::understand(five, &lab.scene, &library, scruple::engine::words::heard(&[]), &|| {
            false
        });
    assert!(
        matches!(&read, scruple::engine::words::Understanding::Directive { directive: scruple::engine::request::Directive::Task(t), .. } if t.steps.len() == 5),
        "{read:?}"
    );
    c.bench_function("words/five_steps_over_the_lab", |b| {
        b.iter(|| {
            scruple::engine::words::understand(
                black_box(five),
                &lab.scene,
                &library,
                scruple::engine::words::heard(&[]),
                &|| false,
            )
        })
    });
    let kitchen = json!({"agent": {"position": [0, 0, 0.75], "reach": 0.9}, "objects": [
        {"id": "m1", "type": "mug", "attributes": {"color": "red"}, "position": [0.5, 0.1, 0.8]},
        {"id": "m2", "type": "mug", "attributes": {"color": "blue"}, "position": [0.5, 0.3, 0.8]},
        {"id": "s1", "type": "sink", "position": [0.6, -0.2, 0.8]},
        {"id": "p1", "type": "plate", "position": [0.5, -0.3, 0.8]}]});
    for (name, text) in [
        ("tasks/get_the_red_mug", "Get the red mug."),
        (
            "tasks/get_the_red_mug_and_put_it_in_the_sink",
            "Get the red mug and put it in the sink.",
        ),
    ] {
        let request = input(json!({"directive": {"text": text}, "scene": kitchen}));
        // The reading of the words alone, for where the time of each goes.
        c.bench_function(&name.replace("tasks/", "tasks/read/"), |b| {
            b.iter(|| {
                scruple::engine::words::understand(
                    black_box(text),
                    &request.scene,
                    &library,
                    scruple::engine::words::heard(&[]),
                    &|| false,
                )
            })
        });
        let decided = clarify(&request.request, &request.scene, &norms, &library, &|| false).unwrap();
        assert!(decided.goal.is_some(), "{text}: {}", decided.utterance);
        c.bench_function(name, |b| {
            b.iter(|| clarify(black_box(&request.request), &request.scene, &norms, &library, &|| false).unwrap())
        });
    }
}

/// "the cup on the table next to the fork" against "the cup" over one scene of 10,000 objects:
/// a table with a cup and a fork on it among 9,997 plates, books and spoons. Both name the one
/// cup; the first reads two attachments of two relations and checks them against the scene.
fn bench_relations(c: &mut Criterion) {
    let norms = compile(&[]);
    let library = Library::default_library();
    let mut objects = vec![
        json!({"id": "t1", "type": "table", "position": [0.6, 0.0, 0.4], "shape": {"cuboid": {"half_extents": [0.3, 0.5, 0.4]}}}),
        json!({"id": "c1", "type": "cup", "position": [0.6, 0.1, 0.85], "shape": {"cylinder": {"radius": 0.04, "half_height": 0.05}}}),
        json!({"id": "f1", "type": "fork", "position": [0.6, 0.2, 0.805], "shape": {"cuboid": {"half_extents": [0.08, 0.01, 0.005]}}}),
    ];
    for i in 0..9_997 {
        let (x, y) = (2.0 + (i % 100) as f64 * 0.5, -25.0 + (i / 100) as f64 * 0.5);
        let kind = ["plate", "book", "spoon"][i % 3];
        objects.push(json!({"id": format!("o{i}"), "type": kind, "position": [x, y, 0.8],
                            "shape": {"cuboid": {"half_extents": [0.1, 0.1, 0.02]}}}));
    }
    let scene = json!({"agent": {"position": [0, 0, 0.75], "reach": 0.9}, "objects": objects});
    let mut group = c.benchmark_group("relations");
    group.sample_size(20);
    for (name, text) in [
        ("the_cup", "Get the cup."),
        (
            "the_cup_on_the_table_next_to_the_fork",
            "Get the cup on the table next to the fork.",
        ),
    ] {
        let body = json!({"directive": {"text": text}, "scene": scene});
        let request = input(body.clone());
        let decided = clarify(&request.request, &request.scene, &norms, &library, &|| false).unwrap();
        assert_eq!(
            decided.goal.as_ref().map(|g| g.to_string()).as_deref(),
            Some("did(self,get(c1))"),
            "{text}"
        );
        // A scene of its own each time: the boxes and their index are built once per request,
        // and that is part of what a relation costs.
        group.bench_function(name, |b| {
            b.iter_batched(
                || input(body.clone()),
                |request| clarify(&request.request, &request.scene, &norms, &library, &|| false).unwrap(),
                BatchSize::LargeInput,
            )
        });
    }
    group.finish();
}

fn bench_readings(c: &mut Criterion) {
    let norms = compile(&hundred_norms());
    let library = Library::default_library();
    let mut group = c.benchmark_group("readings");
    group.sample_size(10).measurement_time(Duration::from_secs(3));
    for objects_count in [10usize, 1_000, 10_000] {
        let scene = json!({"agent": {"position": [0, 0, 0.75], "reach": 0.9}, "objects": objects(objects_count)});
        for readings in [1usize, 10, 100, 1_000, 10_000] {
            // put(X,Y) over the first a objects for X and the first b for Y: a × b readings.
            let (a, b) = match readings {
                1 => (1, 1),
                10 => (10, 1),
                100 => (10, 10),
                1_000 => (100, 10),
                _ => (100, 100),
            };
            if a > objects_count {
                continue;
            }
            let ids = |n: usize| (0..n).map(|i| json!(format!("o{i}"))).collect::<Vec<_>>();
            let request = input(json!({
                "directive": {"form": "did(self,put(X,Y))", "bindings": {"X": ids(a), "Y": ids(b)}},
                "scene": scene,
                "options": {"max_readings": 100_000}
            }));
            let id = BenchmarkId::new(format!("objects_{objects_count}"), readings);
            group.bench_with_input(id, &request, |bench, request| {
                bench.iter(|| clarify(&request.request, &request.scene, &norms, &library, &|| false).unwrap())
            });
        }
    }
    group.finish();
}

/// Checking a request of one reading over a scene of 10 or 10,000 objects: what each request
/// pays before the engine decides, so that work moved between checking and deciding shows.
fn bench_checking(c: &mut Criterion) {
    let mut group = c.benchmark_group("checking");
    group.sample_size(10).measurement_time(Duration::from_secs(3));
    for objects_count in [10usize, 10_000] {
        let body: ClarifyBody = serde_json::from_value(json!({
            "directive": {"form": "did(self,put(X,Y))", "bindings": {"X": ["o0"], "Y": ["o1"]}},
            "scene": {"agent": {"position": [0, 0, 0.75], "reach": 0.9}, "objects": objects(objects_count)},
        }))
        .unwrap();
        group.bench_with_input(BenchmarkId::new("objects", objects_count), &body, |bench, body| {
            bench.iter_batched(
                || body.clone(),
                |body| Request::from_input(body.into(), &RequestLimits::default()).unwrap(),
                BatchSize::LargeInput,
            )
        });
    }
    group.finish();
}

fn bench_world_copy(c: &mut Criterion) {
    let mut group = c.benchmark_group("world_copy");
    for count in [10usize, 10_000] {
        let facts = (0..count).flat_map(|i| {
            [
                scruple::engine::Term::compound("cup", vec![scruple::engine::Term::constant(&format!("o{i}"))]),
                scruple::engine::Term::compound(
                    "on",
                    vec![
                        scruple::engine::Term::constant(&format!("o{i}")),
                        scruple::engine::Term::constant("table"),
                    ],
                ),
            ]
        });
        let base = Base::new(facts);
        let world = World::new(&base);
        group.bench_with_input(BenchmarkId::from_parameter(count), &world, |b, world| {
            b.iter(|| black_box(world.clone()))
        });
    }
    group.finish();
}

criterion_group!(
    benches,
    bench_paper,
    bench_relations,
    bench_tasks,
    bench_readings,
    bench_checking,
    bench_world_copy
);
criterion_main!(benches);
