//! The OpenAPI document's frame: title, tags, the admin-token scheme, and the paper's example.
//!
//! Must not: list operations by hand; they come from the routes themselves (`routes!`).

use serde::Serialize;
use serde_json::{Value, json};
use utoipa::openapi::security::{HttpAuthScheme, HttpBuilder, SecurityScheme};
use utoipa::{Modify, OpenApi, ToSchema};

#[derive(OpenApi)]
#[openapi(
    info(
        title = "Scruple",
        description = "Morally sensitive clarification of ambiguous robot directives: every reading is simulated against the norms and the robot's abilities before anything is asked, assumed or explained. Errors are application/problem+json (RFC 9457) with `field`, a JSON Pointer, where a field is at fault; so are the answers to requests that are not valid HTTP (400 `/problems/bad-request`, 414 `/problems/uri-too-long`, 431 `/problems/headers-too-large`) or do not arrive in time (408 `/problems/request-timeout`), after which the connection closes.",
        license(name = "Apache-2.0", identifier = "Apache-2.0"),
    ),
    tags(
        (name = "clarify", description = "Decisions about directives"),
        (name = "norms", description = "The norms every decision is checked against, their export and import, and the audit trail of every change. Writes need a write token (the admin token or a curator token) when any token is configured; reads need a token once reader tokens are configured"),
        (name = "actions", description = "The action library (verbs as data); tokens as for norms"),
        (name = "service", description = "Health"),
        (name = "playground", description = "A page that drives this API from a browser, served at `/`"),
    ),
    modifiers(&BearerToken),
)]
pub struct ApiDoc;

/// `Authorization: Bearer TOKEN`: on writes once any token is configured (`--admin-token`,
/// `--curator-token`), on reads of norms and verbs once a `--reader-token` is.
struct BearerToken;

impl Modify for BearerToken {
    fn modify(&self, openapi: &mut utoipa::openapi::OpenApi) {
        let components = openapi.components.get_or_insert_with(Default::default);
        components.add_security_scheme(
            "token",
            SecurityScheme::Http(HttpBuilder::new().scheme(HttpAuthScheme::Bearer).build()),
        );
    }
}

/// The readiness answer.
#[derive(Serialize, ToSchema)]
pub struct Health {
    /// Always `ok` when the status is 200.
    pub status: &'static str,
}

impl Health {
    pub fn ok() -> Health {
        Health { status: "ok" }
    }
}

/// The paper's "Get the vase." request.
pub fn vase_request() -> Value {
    let vase = |id: &str, y: f64| {
        json!({"id": id, "type": "vase", "position": [0.6, y, 0.85],
               "shape": {"cylinder": {"radius": 0.06, "half_height": 0.1}}})
    };
    let mut fragile = vase("object3", 0.15);
    fragile["properties"] = json!(["fragile"]);
    let mut plastic = vase("object4", 0.35);
    plastic["attributes"] = json!({"material": "plastic"});
    json!({
        "speaker": "human",
        "directive": {"action": "get", "arguments": [{"type": "vase"}], "text": "Get the vase."},
        "scene": {"agent": {"id": "self", "position": [0.0, 0.0, 0.75], "reach": 0.9}, "objects": [fragile, plastic]},
        "context": "default",
        "options": {"strategy": "moral", "single_permissible": "assume"}
    })
}

/// The answer to [`vase_request`] under the paper's norms, installed in order on a fresh store
/// (`tests/api/paper_demo.rs` checks the server gives exactly this).
pub fn vase_response() -> Value {
    json!({
        "decision": "assume",
        "utterance": "I am assuming you want me to get the plastic vase. I cannot get the fragile vase because it requires a forbidden state.",
        "speech_act": "assume(self,mean(human,did(self,get(object4))))",
        "goal": "did(self,get(object4))",
        "interpretations": [
            {"action": "did(self,get(object3))", "description": "the fragile vase", "permissible": false, "feasible": true,
             "reasons": [{"kind": "forbidden_state", "detail": "did(self,get(object3))", "norm_id": 2, "severity": 3,
                          "words": "it requires a forbidden state"}],
             "plan": ["get(object3)"], "score": 1.0},
            {"action": "did(self,get(object4))", "description": "the plastic vase", "permissible": true, "feasible": true,
             "reasons": [], "plan": ["get(object4)"], "score": 1.0}
        ],
        "offered": ["did(self,get(object4))"],
        "norm_version": 3,
        "library_version": 1,
        "text": "Get the vase."
    })
}

/// The problem answers every operation of a kind can give, defined once so that none is left
/// out of an operation that can return it.
pub mod problems {
    use std::collections::BTreeMap;

    use utoipa::openapi::{ContentBuilder, Ref, RefOr, ResponseBuilder, response::Response};

    use crate::error::PROBLEM_JSON;

    fn problem(description: &str) -> RefOr<Response> {
        let content = ContentBuilder::new()
            .schema(Some(Ref::from_schema_name("Problem")))
            .build();
        ResponseBuilder::new()
            .description(description)
            .content(PROBLEM_JSON, content)
            .build()
            .into()
    }

    fn set(rows: &[(&str, &str)]) -> BTreeMap<String, RefOr<Response>> {
        rows.iter()
            .map(|(status, description)| ((*status).to_owned(), problem(description)))
            .collect()
    }

    /// What reading a JSON body can end in (`rest::JsonBody`).
    pub struct JsonBody;

    impl utoipa::IntoResponses for JsonBody {
        fn responses() -> BTreeMap<String, RefOr<Response>> {
            set(&[
                ("400", "The body is not JSON"),
                ("408", "The body did not arrive whole within `--body-timeout-ms`"),
                ("413", "The body is over the size limit"),
                (
                    "415",
                    "The body is not sent as JSON, or in a Content-Encoding other than gzip",
                ),
            ])
        }
    }

    /// What a write's token check can end in (`rest::Writer`).
    pub struct WriteToken;

    impl utoipa::IntoResponses for WriteToken {
        fn responses() -> BTreeMap<String, RefOr<Response>> {
            set(&[
                ("401", "Tokens are configured and none was sent"),
                ("403", "The token sent may not make this change"),
            ])
        }
    }

    /// What a read's token check can end in (`rest::Reader`).
    pub struct ReadToken;

    impl utoipa::IntoResponses for ReadToken {
        fn responses() -> BTreeMap<String, RefOr<Response>> {
            set(&[
                ("401", "Reader tokens are configured and none was sent"),
                ("403", "The token sent is not one this service knows"),
            ])
        }
    }

    /// What an operation that reads or writes the store can end in when the store does not
    /// answer (`Error::NormsUnavailable`, `Error::Overloaded`).
    pub struct Store;

    impl utoipa::IntoResponses for Store {
        fn responses() -> BTreeMap<String, RefOr<Response>> {
            set(&[(
                "503",
                "The store cannot be read now, or is too busy; nothing was changed. `Retry-After` says when to try again",
            )])
        }
    }

    /// What a decision or a check ends in when the norms or verbs cannot be read: no answer
    /// rather than one made under no norms.
    pub struct FailClosed;

    impl utoipa::IntoResponses for FailClosed {
        fn responses() -> BTreeMap<String, RefOr<Response>> {
            set(&[(
                "503",
                "The norms or verbs cannot be read now, or the service is too busy: no decision is made (fail closed). `Retry-After` says when to try again",
            )])
        }
    }

    /// An operation on `/v1/norms/{id}` whose norm does not exist.
    pub struct NoNorm;

    impl utoipa::IntoResponses for NoNorm {
        fn responses() -> BTreeMap<String, RefOr<Response>> {
            set(&[("404", "No norm has that id")])
        }
    }

    /// An operation on `/v1/actions/{name}` whose verb does not exist.
    pub struct NoVerb;

    impl utoipa::IntoResponses for NoVerb {
        fn responses() -> BTreeMap<String, RefOr<Response>> {
            set(&[("404", "No such verb")])
        }
    }

    /// A conditional write (`If-Match`) whose precondition no longer holds (`Error::Stale`).
    pub struct Changed;

    impl utoipa::IntoResponses for Changed {
        fn responses() -> BTreeMap<String, RefOr<Response>> {
            set(&[(
                "412",
                "What `If-Match` names has changed since (its revision or version moved); nothing was written",
            )])
        }
    }
}
