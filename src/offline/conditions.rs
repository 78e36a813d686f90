//! An experiment's conditions (`replay --conditions`, `--conditions-file`) and what every line
//! of a replay is given that it does not say itself (`--scene`).
//!
//! Must not: decide (that is `replay`'s, through the core), or change a line's own words: a
//! condition sets request options only, and a default scene fills only a scene that is absent.

use std::path::Path;

use serde::de::{Deserializer, MapAccess, Visitor};
use serde_json::{Map, Value};

use super::{Failure, Limits, read_input};
use crate::engine::input::{escape_unseen, pointer_segment};
use crate::engine::request::Options;
use crate::error::{Error, Problem};
use crate::wire::{ClarifyBody, OptionsBody, SceneBody, parse_json};

/// The conditions every name stands for without a conditions file: the paper's two.
const BUILT_IN: [(&str, &str); 2] = [("moral", "moral"), ("reflexive", "reflexive")];

/// One condition of an experiment: a name, and the request options it sets over each line's.
#[derive(Clone, Debug, PartialEq)]
pub struct Condition {
    pub name: String,
    /// Members of a clarify body's `options`, each checked to be one (`OptionsBody`).
    options: Map<String, Value>,
}

/// A conditions file: a JSON object, condition name → the `options` it sets, in the file's
/// order (`{"moral": {"strategy": "moral"}, "reflexive+confirm": {"strategy": "reflexive", ...}}`).
struct ConditionsFile(Vec<(String, OptionsBody)>);

impl<'de> serde::Deserialize<'de> for ConditionsFile {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Named;
        impl<'de> Visitor<'de> for Named {
            type Value = ConditionsFile;

            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("an object of conditions: {\"name\": {options...}, ...}")
            }

            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<ConditionsFile, A::Error> {
                let mut conditions: Vec<(String, OptionsBody)> = Vec::new();
                while let Some(name) = map.next_key::<String>()? {
                    let options = map.next_value::<OptionsBody>()?;
                    if let Some(why) = bad_name(&name) {
                        return Err(serde::de::Error::custom(format!(
                            "condition `{}`: {why}",
                            escape_unseen(&name)
                        )));
                    }
                    if conditions.iter().any(|(seen, _)| *seen == name) {
                        return Err(serde::de::Error::custom(format!(
                            "condition `{}` is named twice",
                            escape_unseen(&name)
                        )));
                    }
                    conditions.push((name, options));
                }
                Ok(ConditionsFile(conditions))
            }
        }
        deserializer.deserialize_map(Named)
    }
}

/// Why a condition cannot be called `name`, if it cannot: `--conditions` lists names between
/// commas, and a report prints them.
fn bad_name(name: &str) -> Option<&'static str> {
    if name.trim().is_empty() {
        Some("a condition needs a name")
    } else if name.contains(',') {
        Some("a name cannot hold `,` (--conditions separates names with it)")
    } else if name.trim() != name {
        Some("a name cannot begin or end with a space")
    } else {
        None
    }
}

/// The conditions asked for: the names of `--conditions` in their order (each from the file,
/// else built in: `moral`, `reflexive`), or every condition of `--conditions-file` in its order.
/// Empty when neither is given.
pub fn conditions(names: Option<&str>, file: Option<&Path>, limits: &Limits) -> Result<Vec<Condition>, Failure> {
    let defined = match file {
        Some(path) => {
            let input = |error| Failure::Input {
                file: path.display().to_string(),
                error,
            };
            let bytes = read_input(path, limits.max_body_bytes)?;
            let ConditionsFile(defined) = parse_json(&bytes).map_err(input)?;
            if defined.is_empty() {
                return Err(input(Error::invalid("", "the file defines no condition")));
            }
            // Checked as a request's options are (ranges, the deadline's limit), once, here:
            // a line never carries the blame for its condition.
            for (name, options) in &defined {
                if let Err(e) = Options::from_input(options.clone().into(), &limits.request) {
                    let member = e.field.strip_prefix("/options").unwrap_or(&e.field);
                    return Err(input(Error::invalid(
                        format!("/{}{member}", pointer_segment(name)),
                        e.message,
                    )));
                }
            }
            defined
        }
        None => Vec::new(),
    };
    let condition = |name: &str, options: &OptionsBody| -> Result<Condition, Failure> {
        let Ok(Value::Object(options)) = serde_json::to_value(options) else {
            return Err(Failure::Run {
                detail: format!("the options of condition `{}` do not serialize", escape_unseen(name)),
            });
        };
        let options = options.into_iter().filter(|(_, v)| !v.is_null()).collect();
        Ok(Condition {
            name: name.to_owned(),
            options,
        })
    };
    let Some(names) = names else {
        return defined.iter().map(|(name, options)| condition(name, options)).collect();
    };
    let mut chosen: Vec<Condition> = Vec::new();
    for name in names.split(',').map(str::trim) {
        let usage = |detail: String| Failure::Usage { detail };
        if let Some(why) = bad_name(name) {
            return Err(usage(format!("--conditions `{}`: {why}", escape_unseen(names))));
        }
        if chosen.iter().any(|c| c.name == name) {
            return Err(usage(format!("--conditions names `{}` twice", escape_unseen(name))));
        }
        let made = match defined.iter().find(|(defined, _)| defined == name) {
            Some((_, options)) => condition(name, options)?,
            None => match BUILT_IN.iter().find(|(built, _)| *built == name) {
                Some((_, strategy)) => Condition {
                    name: name.to_owned(),
                    options: Map::from_iter([("strategy".to_owned(), Value::from(*strategy))]),
                },
                None => {
                    return Err(usage(format!(
                        "--conditions: no condition `{}`: define it in --conditions-file, or use `moral` or `reflexive`",
                        escape_unseen(name)
                    )));
                }
            },
        };
        chosen.push(made);
    }
    Ok(chosen)
}

impl Condition {
    /// `body` under this condition: its options, with each this condition sets put over them.
    pub fn over(&self, body: &ClarifyBody) -> Result<ClarifyBody, Problem> {
        let mut options = match serde_json::to_value(&body.options) {
            Ok(Value::Object(options)) => options,
            _ => Map::new(),
        };
        options.extend(self.options.clone());
        let options: OptionsBody = serde_json::from_value(Value::Object(options)).map_err(|e| {
            let detail = format!("under condition `{}`: {e}", escape_unseen(&self.name));
            Error::invalid("/options", detail).problem()
        })?;
        let mut body = body.clone();
        body.options = Some(options);
        Ok(body)
    }
}

/// A `--scene` file: a clarify body's `scene`, checked for shape here (pointers into the file);
/// what the engine checks of it is checked with each line, as for a scene the line carries.
pub fn scene_file(path: &Path, limit: usize) -> Result<Value, Failure> {
    let bytes = read_input(path, limit)?;
    let input = |error| Failure::Input {
        file: path.display().to_string(),
        error,
    };
    parse_json::<SceneBody>(&bytes).map_err(input)?;
    parse_json::<Value>(&bytes).map_err(input)
}

/// A line's JSON with a scene put in where it has none (`--scene`): the request's own members
/// are untouched. `None` when the line is not an object (its parse then says so).
pub fn with_scene(bytes: &[u8], scene: &Value) -> Option<Vec<u8>> {
    let mut line: Value = serde_json::from_slice(bytes).ok()?;
    let members = line.as_object_mut()?;
    let request = match members.get_mut("request") {
        Some(Value::Object(request)) => request,
        Some(_) => return None,
        None => members,
    };
    if !request.contains_key("scene") {
        request.insert("scene".to_owned(), scene.clone());
    }
    serde_json::to_vec(&line).ok()
}
