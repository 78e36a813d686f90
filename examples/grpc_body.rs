//! Turns a REST `/v1/clarify` JSON body into the same request framed for gRPC (flag byte, 4-byte
//! big-endian length, protobuf), for h2load in `scripts/bench-load.sh` and `scripts/pgo-build.sh`:
//! the two transports are loaded with one case by construction. Every field of the REST body has
//! its field in `proto/`; a key it does not know, or a value of the wrong JSON type, is an error
//! naming it, never dropped. Usage: `grpc_body BODY.json OUT`.

use std::collections::HashMap;
use std::process::ExitCode;

use prost::Message;
use scruple::transport::grpc::pb;
use serde_json::{Map, Value};

type Result<T> = std::result::Result<T, String>;

/// One JSON object of the body, with where it is, so that every error names the field.
struct Fields<'a> {
    at: String,
    map: &'a Map<String, Value>,
}

impl<'a> Fields<'a> {
    /// `value` at `at` must be an object holding only `known` keys.
    fn of(value: &'a Value, at: &str, known: &[&str]) -> Result<Self> {
        let map = value.as_object().ok_or_else(|| format!("{at}: not an object"))?;
        if let Some(key) = map.keys().find(|k| !known.contains(&k.as_str())) {
            return Err(format!("{at}.{key}: not a field gRPC carries"));
        }
        Ok(Fields { at: at.into(), map })
    }

    fn path(&self, key: &str) -> String {
        format!("{}.{key}", self.at)
    }

    /// The value at `key`, absent when missing or null (REST's optional fields take both).
    fn get(&self, key: &str) -> Option<&'a Value> {
        self.map.get(key).filter(|v| !v.is_null())
    }

    fn string(&self, key: &str) -> Result<Option<String>> {
        self.typed(key, |v| v.as_str().map(str::to_owned), "not a string")
    }

    /// The value at `key` as `read` takes it, `what` naming what it must be; absent when
    /// missing or null.
    fn typed<T>(&self, key: &str, read: fn(&Value) -> Option<T>, what: &str) -> Result<Option<T>> {
        self.get(key)
            .map(|v| read(v).ok_or_else(|| format!("{}: {what}", self.path(key))))
            .transpose()
    }

    fn number(&self, key: &str) -> Result<Option<f64>> {
        self.typed(key, Value::as_f64, "not a number")
    }

    fn count(&self, key: &str) -> Result<Option<u64>> {
        self.typed(key, Value::as_u64, "not a whole number ≥ 0")
    }

    fn flag(&self, key: &str) -> Result<Option<bool>> {
        self.typed(key, Value::as_bool, "not true or false")
    }

    fn list(&self, key: &str) -> Result<Vec<(String, &'a Value)>> {
        match self.get(key) {
            None => Ok(Vec::new()),
            Some(Value::Array(items)) => Ok(items
                .iter()
                .enumerate()
                .map(|(i, v)| (format!("{}[{i}]", self.path(key)), v))
                .collect()),
            Some(_) => Err(format!("{}: not an array", self.path(key))),
        }
    }

    fn strings(&self, key: &str) -> Result<Vec<String>> {
        self.list(key)?
            .into_iter()
            .map(|(at, v)| {
                v.as_str()
                    .map(str::to_owned)
                    .ok_or_else(|| format!("{at}: not a string"))
            })
            .collect()
    }

    fn numbers(&self, key: &str) -> Result<Vec<f64>> {
        self.list(key)?
            .into_iter()
            .map(|(at, v)| v.as_f64().ok_or_else(|| format!("{at}: not a number")))
            .collect()
    }

    fn string_map(&self, key: &str) -> Result<HashMap<String, String>> {
        let Some(value) = self.get(key) else {
            return Ok(HashMap::new());
        };
        let map = value
            .as_object()
            .ok_or_else(|| format!("{}: not an object", self.path(key)))?;
        map.iter()
            .map(|(k, v)| match v.as_str() {
                Some(s) => Ok((k.clone(), s.to_owned())),
                None => Err(format!("{}.{k}: not a string", self.path(key))),
            })
            .collect()
    }

    /// The object at `key` read by `read`, absent when missing or null.
    fn nested<T>(&self, key: &str, read: impl FnOnce(&'a Value, &str) -> Result<T>) -> Result<Option<T>> {
        self.get(key).map(|v| read(v, &self.path(key))).transpose()
    }
}

fn reference(value: &Value, at: &str) -> Result<pb::Reference> {
    let known = ["id", "type", "attributes", "properties", "relations", "count", "all"];
    let f = Fields::of(value, at, &known)?;
    Ok(pb::Reference {
        id: f.string("id")?,
        r#type: f.string("type")?,
        attributes: f.string_map("attributes")?,
        properties: f.strings("properties")?,
        relations: relations(&f)?,
        count: f.count("count")?,
        all: f.flag("all")?,
    })
}

/// A reference's relations: each `{relation, to}`, `to` a reference of its own.
fn relations(f: &Fields<'_>) -> Result<Vec<pb::Relation>> {
    (f.list("relations")?.into_iter())
        .map(|(at, v)| {
            let r = Fields::of(v, &at, &["relation", "to"])?;
            Ok(pb::Relation {
                relation: r.string("relation")?.ok_or_else(|| format!("{at}.relation: missing"))?,
                to: r.nested("to", reference)?,
            })
        })
        .collect()
}

/// A candidate is an id, or `{id, score}`.
fn candidate(value: &Value, at: &str) -> Result<pb::Candidate> {
    if let Some(id) = value.as_str() {
        return Ok(pb::Candidate {
            id: id.into(),
            score: None,
        });
    }
    let f = Fields::of(value, at, &["id", "score"])?;
    Ok(pb::Candidate {
        id: f.string("id")?.ok_or_else(|| format!("{at}.id: missing"))?,
        score: f.number("score")?,
    })
}

fn directive(value: &Value, at: &str) -> Result<pb::Directive> {
    let f = Fields::of(
        value,
        at,
        &["action", "arguments", "form", "bindings", "text", "joiner", "steps"],
    )?;
    let mut bindings = HashMap::new();
    if let Some(map) = f.get("bindings") {
        let map = map
            .as_object()
            .ok_or_else(|| format!("{}: not an object", f.path("bindings")))?;
        for (variable, list) in map {
            let at = format!("{}.{variable}", f.path("bindings"));
            let items = list.as_array().ok_or_else(|| format!("{at}: not an array"))?;
            let candidates = items
                .iter()
                .enumerate()
                .map(|(i, c)| candidate(c, &format!("{at}[{i}]")))
                .collect::<Result<_>>()?;
            bindings.insert(variable.clone(), pb::Candidates { candidates });
        }
    }
    Ok(pb::Directive {
        action: f.string("action")?,
        arguments: f
            .list("arguments")?
            .into_iter()
            .map(|(at, v)| reference(v, &at))
            .collect::<Result<_>>()?,
        form: f.string("form")?,
        bindings,
        text: f.string("text")?,
        joiner: f.string("joiner")?,
        steps: f
            .list("steps")?
            .into_iter()
            .map(|(at, v)| step(v, &at))
            .collect::<Result<_>>()?,
    })
}

/// A step of a task: a verb, its arguments (a reference, or `step` and `argument`), a joiner.
fn step(value: &Value, at: &str) -> Result<pb::Step> {
    let f = Fields::of(value, at, &["action", "arguments", "joiner"])?;
    let arguments = (f.list("arguments")?.into_iter())
        .map(|(at, v)| {
            let known = [
                "id",
                "type",
                "attributes",
                "properties",
                "relations",
                "count",
                "all",
                "step",
                "argument",
            ];
            let a = Fields::of(v, &at, &known)?;
            Ok(pb::StepArgument {
                id: a.string("id")?,
                r#type: a.string("type")?,
                attributes: a.string_map("attributes")?,
                properties: a.strings("properties")?,
                relations: relations(&a)?,
                count: a.count("count")?,
                all: a.flag("all")?,
                step: a.count("step")?,
                argument: a.count("argument")?,
            })
        })
        .collect::<Result<_>>()?;
    Ok(pb::Step {
        action: f.string("action")?.ok_or_else(|| format!("{at}.action: missing"))?,
        arguments,
        joiner: f.string("joiner")?,
    })
}

fn shape(value: &Value, at: &str) -> Result<pb::Shape> {
    let f = Fields::of(value, at, &["ball", "cuboid", "cylinder"])?;
    if f.map.values().filter(|v| !v.is_null()).count() != 1 {
        return Err(format!("{at}: exactly one of ball, cuboid, cylinder"));
    }
    let required = |g: &Fields, key: &str| g.number(key)?.ok_or_else(|| format!("{}: missing", g.path(key)));
    let kind = if let Some(v) = f.get("ball") {
        let g = Fields::of(v, &f.path("ball"), &["radius"])?;
        pb::shape::Kind::Ball(pb::Ball {
            radius: required(&g, "radius")?,
        })
    } else if let Some(v) = f.get("cuboid") {
        let g = Fields::of(v, &f.path("cuboid"), &["half_extents"])?;
        pb::shape::Kind::Cuboid(pb::Cuboid {
            half_extents: g.numbers("half_extents")?,
        })
    } else {
        let g = Fields::of(
            f.get("cylinder").unwrap_or(&Value::Null),
            &f.path("cylinder"),
            &["radius", "half_height"],
        )?;
        pb::shape::Kind::Cylinder(pb::Cylinder {
            radius: required(&g, "radius")?,
            half_height: required(&g, "half_height")?,
        })
    };
    Ok(pb::Shape { kind: Some(kind) })
}

fn object(value: &Value, at: &str) -> Result<pb::Object> {
    let known = [
        "id",
        "type",
        "properties",
        "attributes",
        "position",
        "shape",
        "rotation",
        "mass",
        "names",
    ];
    let f = Fields::of(value, at, &known)?;
    Ok(pb::Object {
        id: f.string("id")?.unwrap_or_default(),
        r#type: f.string("type")?.unwrap_or_default(),
        properties: f.strings("properties")?,
        attributes: f.string_map("attributes")?,
        position: f.numbers("position")?,
        shape: f.nested("shape", shape)?,
        rotation: f.numbers("rotation")?,
        mass: f.number("mass")?,
        names: f.strings("names")?,
    })
}

fn scene(value: &Value, at: &str) -> Result<pb::Scene> {
    let f = Fields::of(value, at, &["agent", "objects", "facts", "people"])?;
    let agent = f.nested("agent", |v, at| {
        let known = [
            "id",
            "position",
            "reach",
            "gripper_aperture",
            "payload",
            "gripper_size",
            "rotation",
        ];
        let a = Fields::of(v, at, &known)?;
        Ok(pb::Agent {
            id: a.string("id")?,
            position: a.numbers("position")?,
            reach: a.number("reach")?,
            gripper_aperture: a.number("gripper_aperture")?,
            payload: a.number("payload")?,
            gripper_size: a.number("gripper_size")?,
            rotation: a.numbers("rotation")?,
        })
    })?;
    Ok(pb::Scene {
        agent,
        objects: f
            .list("objects")?
            .into_iter()
            .map(|(at, v)| object(v, &at))
            .collect::<Result<_>>()?,
        facts: f.strings("facts")?,
        people: f
            .list("people")?
            .into_iter()
            .map(|(at, v)| person(v, &at))
            .collect::<Result<_>>()?,
    })
}

fn person(value: &Value, at: &str) -> Result<pb::Person> {
    let f = Fields::of(value, at, &["id", "names", "roles", "position"])?;
    Ok(pb::Person {
        id: f.string("id")?.unwrap_or_default(),
        names: f.strings("names")?,
        roles: f.strings("roles")?,
        position: f.numbers("position")?,
    })
}

fn options(value: &Value, at: &str) -> Result<pb::Options> {
    let known = [
        "strategy",
        "single_permissible",
        "style",
        "max_spoken",
        "max_readings",
        "deadline_ms",
        "confirm_above_ratio",
        "soft_norms",
        "alternatives",
    ];
    let f = Fields::of(value, at, &known)?;
    Ok(pb::Options {
        strategy: f.string("strategy")?,
        single_permissible: f.string("single_permissible")?,
        style: f.string("style")?,
        max_spoken: f.count("max_spoken")?,
        max_readings: f.count("max_readings")?,
        deadline_ms: f.count("deadline_ms")?,
        confirm_above_ratio: f.number("confirm_above_ratio")?,
        soft_norms: f.string("soft_norms")?,
        alternatives: f.string("alternatives")?,
    })
}

fn answer(value: &Value, at: &str) -> Result<pb::Answer> {
    let f = Fields::of(value, at, &["choice", "id", "reference", "text"])?;
    // REST's `"choice": "alternative"` is gRPC's `alternative`.
    let alternative = f.get("choice").is_some_and(|c| c == "alternative");
    Ok(pb::Answer {
        choice: if alternative { None } else { f.count("choice")? },
        alternative,
        id: f.string("id")?,
        reference: f.nested("reference", reference)?,
        text: f.string("text")?,
    })
}

fn request(body: &Value) -> Result<pb::ClarifyRequest> {
    let known = [
        "speaker",
        "directive",
        "scene",
        "context",
        "options",
        "speaker_roles",
        "answer",
        "focus",
    ];
    let f = Fields::of(body, "body", &known)?;
    Ok(pb::ClarifyRequest {
        speaker: f.string("speaker")?,
        directive: f.nested("directive", directive)?,
        scene: f.nested("scene", scene)?,
        context: f.string("context")?,
        options: f.nested("options", options)?,
        speaker_roles: f.strings("speaker_roles")?,
        answer: f.nested("answer", answer)?,
        focus: f.strings("focus")?,
    })
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, output] = args.as_slice() else {
        eprintln!("usage: grpc_body BODY.json OUT");
        return ExitCode::from(2);
    };
    let converted = std::fs::read_to_string(input)
        .map_err(|e| format!("{input}: {e}"))
        .and_then(|text| serde_json::from_str::<Value>(&text).map_err(|e| format!("{input}: not JSON: {e}")))
        .and_then(|body| request(&body).map_err(|e| format!("{input}: {e}")));
    let message = match converted {
        Ok(request) => request.encode_to_vec(),
        Err(e) => {
            eprintln!("grpc_body: {e}");
            return ExitCode::FAILURE;
        }
    };
    let mut framed = vec![0u8];
    framed.extend_from_slice(&(message.len() as u32).to_be_bytes());
    framed.extend_from_slice(&message);
    if let Err(e) = std::fs::write(output, framed) {
        eprintln!("grpc_body: {output}: {e}");
        return ExitCode::FAILURE;
    }
    ExitCode::SUCCESS
}
