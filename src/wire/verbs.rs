//! The verb's schema for the API's document. The engine's `ActionInput` is what the handlers
//! take and give (serde); the engine names no schema crate, so its shape is declared here,
//! member for member, and a test holds the two together.

use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

/// A verb as a curator writes it, as the API carries it and as the store keeps it: terms as
/// text.
#[derive(Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(as = Action)]
pub struct ActionSchema {
    /// The verb's name; when sent, it must equal the name it is stored as (the request's path).
    #[serde(default)]
    pub name: Option<String>,
    /// Variables such as `X`, bound to the arguments in order.
    #[serde(default)]
    pub parameters: Vec<String>,
    /// The word joining the arguments when spoken: `on` for "put the cup on the plate".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joiner: Option<String>,
    /// The arguments must name different objects (`put` does): a reading that names one object
    /// twice is infeasible (`same_object`) and never offered. Default false.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub distinct: bool,
    /// One or more ways of carrying the verb out; a reading is acceptable when any is.
    #[serde(default)]
    pub methods: Vec<MethodSchema>,
    /// Phrases (1 to 3 words of letters, at most 16) that name the verb when a directive comes
    /// in words: `["get", "grab", "pick up"]`. A phrase names one verb only; inflected forms
    /// ("gets", "got", "picking up") are understood.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub words: Vec<String>,
    /// For a verb of two parameters, the words (at most 8) understood between its arguments in
    /// words: `["on", "onto", "into"]`. `joiner` stays the one word spoken.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joiners: Vec<String>,
    /// Parameters a directive may leave unsaid, each with 1 to 32 facts over it alone that an
    /// object must meet to be its argument: `{"Y": ["heater(Y)"]}` ("heat the soup": with
    /// whichever heater the scene holds). Only the verb's last parameters, never its first.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub implied: std::collections::BTreeMap<String, Vec<String>>,
}

/// One way of carrying a verb out. Terms are written over the verb's parameters.
#[derive(Deserialize, Serialize, ToSchema)]
#[serde(deny_unknown_fields)]
#[schema(as = Method)]
pub struct MethodSchema {
    /// Action terms, and the word `itself` for the verb's own execution; default `["itself"]`,
    /// and `itself` is appended when not listed.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub steps: Vec<String>,
    /// Parameters whose object must be within reach, with a clear path, for `itself`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub reach: Vec<String>,
    /// Parameters whose object the gripper closes around (aperture and payload).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub grasp: Vec<String>,
    /// `[item, support]`: the support must have room for the item.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub place: Option<Vec<String>>,
    /// Facts that must hold when `itself` runs: `closed(X)`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub preconditions: Vec<String>,
    /// Facts `itself` makes true (besides `did(self,action)`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub adds: Vec<String>,
    /// Facts `itself` makes false.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub removes: Vec<String>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::action::{ActionInput, MethodInput};

    fn members(value: serde_json::Value) -> Vec<String> {
        value.as_object().unwrap().keys().cloned().collect()
    }

    fn schema_members<T: utoipa::PartialSchema>() -> Vec<String> {
        let schema = serde_json::to_value(T::schema()).unwrap();
        members(schema["properties"].clone())
    }

    /// The document's verb is the verb the handlers take: every member of a verb with every
    /// member set is in the schema, and nothing else is.
    #[test]
    fn the_verb_schema_has_the_members_of_the_verb() {
        let method = MethodInput {
            steps: vec!["itself".into()],
            reach: vec!["X".into()],
            grasp: vec!["X".into()],
            place: Some(vec!["X".into(), "Y".into()]),
            preconditions: vec!["closed(X)".into()],
            adds: vec!["open(X)".into()],
            removes: vec!["closed(X)".into()],
        };
        let verb = ActionInput {
            name: Some("open".into()),
            parameters: vec!["X".into(), "Y".into()],
            joiner: Some("on".into()),
            distinct: true,
            methods: vec![method.clone()],
            words: vec!["open".into()],
            joiners: vec!["with".into()],
            implied: [("Y".to_owned(), vec!["heater(Y)".to_owned()])].into(),
        };
        let mut written = members(serde_json::to_value(&verb).unwrap());
        let mut declared = schema_members::<ActionSchema>();
        written.sort();
        declared.sort();
        assert_eq!(written, declared);
        let mut written = members(serde_json::to_value(&method).unwrap());
        let mut declared = schema_members::<MethodSchema>();
        written.sort();
        declared.sort();
        assert_eq!(written, declared);
    }
}
