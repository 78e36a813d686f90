//! The wire model: request and response bodies as JSON shapes (serde) and their OpenAPI schema
//! (utoipa), and their plain conversion to and from the engine's input and output values.
//!
//! Owns: the shapes, `parse_json` (a JSON fault becomes a 400 or a 422 naming its member), and
//! member-for-member conversions. Must not: hold a rule about a value; every check belongs to the
//! engine constructor of the type it builds. Nothing inward of the transports imports it.

mod check;
mod clarify;
mod norms;
mod scene;
mod spelling;
mod verbs;

use serde::de::DeserializeOwned;

pub use crate::engine::input::pointer_segment;
use crate::error::Error;

pub use check::{CheckBody, CheckDto, CheckOptionsBody, StepCheckDto};
pub use clarify::{
    AgentBody, AnswerBody, BindingBody, ChoiceBody, ClarifyBody, DecisionDto, DirectiveBody, InterpretationDto,
    LimitsDto, ObjectBody, OptionsBody, ParseDto, PersonBody, PronounParseDto, PurposeParseDto, ReasonDto,
    ReferenceBody, ReferenceParseDto, RelationBody, Scalar, SceneBody, ShapeBody, StepArgumentBody, StepBody,
    StepParseDto,
};
pub use norms::{
    AuditEntryDto, AuditPageDto, NormBody, NormDto, NormSetBody, NormSetDto, NormSetImportSchema, NormSetObject,
};
pub use verbs::{ActionSchema, MethodSchema};

/// Parses a JSON body. Text that is not JSON is a 400; JSON of the wrong shape is a 422 whose
/// `field` points at the offending member.
pub fn parse_json<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, Error> {
    // A body that parses is parsed once, untracked: tracking the path costs an allocation per
    // member. Only a body that fails is read again, tracked, to name the member at fault; the
    // two readers accept exactly the same texts, so the answer is the same either way.
    match serde_json::from_slice(bytes) {
        Ok(value) => Ok(value),
        Err(_) => Err(explain_json::<T>(bytes)),
    }
}

/// The error of a body that did not parse as `T`, with the member at fault.
fn explain_json<T: DeserializeOwned>(bytes: &[u8]) -> Error {
    let mut deserializer = serde_json::Deserializer::from_slice(bytes);
    let result: Result<T, _> = serde_path_to_error::deserialize(&mut deserializer);
    let err = match result {
        // Trailing text after the value is a syntax error, not a shape error.
        Ok(_) => {
            return match deserializer.end() {
                Err(e) => Error::MalformedBody { detail: e.to_string() },
                Ok(()) => Error::MalformedBody {
                    detail: "the body did not parse, and parsed when read again".to_owned(),
                },
            };
        }
        Err(err) => err,
    };
    let inner = err.inner();
    // A shape error can be met before a syntax error further on: text that is not JSON at
    // all is reported as such, whatever its first bytes looked like.
    if let Err(syntax) = serde_json::from_slice::<serde::de::IgnoredAny>(bytes) {
        return Error::MalformedBody {
            detail: syntax.to_string(),
        };
    }
    // The text is JSON, so whatever the deserializer tripped on is the shape of a member:
    // a fixed-length array with more elements ("trailing characters" to serde), a shape with
    // no kind or two, a key given twice. Each is a 422 naming the member.
    let mut field = String::new();
    for segment in err.path().iter() {
        match segment {
            serde_path_to_error::Segment::Seq { index } => field.push_str(&format!("/{index}")),
            serde_path_to_error::Segment::Map { key } => {
                field.push('/');
                field.push_str(&pointer_segment(key));
            }
            serde_path_to_error::Segment::Enum { variant } => {
                field.push('/');
                field.push_str(&pointer_segment(variant));
            }
            serde_path_to_error::Segment::Unknown => {}
        }
    }
    let message = inner.to_string();
    // serde reports a missing or repeated member at its parent; point at the member itself.
    for prefix in ["missing field `", "duplicate field `"] {
        if let Some(rest) = message.strip_prefix(prefix)
            && let Some(name) = rest.split('`').next()
        {
            field.push('/');
            field.push_str(&pointer_segment(name));
        }
    }
    let detail = match message.rfind(" at line ") {
        Some(cut) => message[..cut].to_owned(),
        None => message,
    };
    let detail = shape_detail(&detail, &field);
    // An empty pointer is the whole document (RFC 6901).
    Error::invalid(field, detail)
}

/// serde's words for a member of the wrong shape, made plain where they would mislead.
fn shape_detail(detail: &str, field: &str) -> String {
    let last = field.rsplit('/').next().unwrap_or_default();
    let what = match last {
        "position" => Some("exactly 3 numbers [x, y, z]"),
        "half_extents" => Some("exactly 3 numbers"),
        "rotation" => Some("exactly 4 numbers [x, y, z, w]"),
        "shape" => Some("one of {\"ball\": ...}, {\"cuboid\": ...}, {\"cylinder\": ...}: exactly one kind"),
        _ => None,
    };
    match what {
        Some(what) if detail.starts_with("trailing characters") || detail.starts_with("invalid length") => {
            format!("must be {what}")
        }
        Some(what) if last == "shape" && !detail.starts_with("unknown variant") => format!("must be {what}"),
        _ if detail.starts_with("trailing characters") => "has more elements or members than it takes".to_owned(),
        _ => detail.to_owned(),
    }
}
