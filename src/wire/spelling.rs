//! The schema of the engine's option enums, under the names the published document has always
//! given them. The values come from each enum's one list and spelling (`Spelled`), which serde
//! uses too (a test in the engine holds the two together). And a follow-up's `choice`, which is
//! spelled as a position or as a word.

use std::borrow::Cow;

use utoipa::openapi::RefOr;
use utoipa::openapi::schema::{ObjectBuilder, Schema, Type};
use utoipa::{PartialSchema, ToSchema};

use crate::engine::decision::Style;
use crate::engine::input::Spelled;
use crate::engine::norms::NormSetMode;
use crate::engine::request::{Alternatives, SinglePermissible, SoftNorms, Strategy};

/// A string that is one of the enum's words.
fn words<T: Spelled>() -> RefOr<Schema> {
    ObjectBuilder::new()
        .schema_type(Type::String)
        .enum_values(Some(T::ALL.iter().map(|v| v.as_str())))
        .into()
}

macro_rules! spelled_schema {
    ($type:ty, $name:literal) => {
        impl PartialSchema for $type {
            fn schema() -> RefOr<Schema> {
                words::<$type>()
            }
        }

        impl ToSchema for $type {
            fn name() -> Cow<'static, str> {
                Cow::Borrowed($name)
            }
        }
    };
}

spelled_schema!(Strategy, "StrategyBody");
spelled_schema!(SinglePermissible, "SinglePermissibleBody");
spelled_schema!(Style, "StyleBody");
spelled_schema!(SoftNorms, "SoftNormsBody");
spelled_schema!(Alternatives, "AlternativesBody");
spelled_schema!(NormSetMode, "NormSetMode");

/// A follow-up's `choice`: a position, from 0, among the readings the question named, or
/// `"alternative"`: the alternative a refusal offered.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ChoiceBody {
    At(u64),
    Alternative,
}

/// The one word a `choice` may be.
const ALTERNATIVE: &str = "alternative";

impl serde::Serialize for ChoiceBody {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            ChoiceBody::At(at) => serializer.serialize_u64(*at),
            ChoiceBody::Alternative => serializer.serialize_str(ALTERNATIVE),
        }
    }
}

impl<'de> serde::Deserialize<'de> for ChoiceBody {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Choice;
        impl serde::de::Visitor<'_> for Choice {
            type Value = ChoiceBody;

            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "a position from 0, or \"{ALTERNATIVE}\"")
            }

            fn visit_u64<E: serde::de::Error>(self, at: u64) -> Result<ChoiceBody, E> {
                Ok(ChoiceBody::At(at))
            }

            fn visit_str<E: serde::de::Error>(self, word: &str) -> Result<ChoiceBody, E> {
                match word {
                    ALTERNATIVE => Ok(ChoiceBody::Alternative),
                    _ => Err(E::invalid_value(serde::de::Unexpected::Str(word), &self)),
                }
            }
        }
        deserializer.deserialize_any(Choice)
    }
}

impl PartialSchema for ChoiceBody {
    fn schema() -> RefOr<Schema> {
        let at = ObjectBuilder::new().schema_type(Type::Integer).minimum(Some(0));
        let word = ObjectBuilder::new()
            .schema_type(Type::String)
            .enum_values(Some([ALTERNATIVE]));
        utoipa::openapi::schema::OneOfBuilder::new().item(at).item(word).into()
    }
}

impl ToSchema for ChoiceBody {
    fn name() -> Cow<'static, str> {
        Cow::Borrowed("ChoiceBody")
    }
}

impl From<ChoiceBody> for crate::engine::request::Choice {
    fn from(choice: ChoiceBody) -> Self {
        match choice {
            ChoiceBody::At(at) => crate::engine::request::Choice::At(at),
            ChoiceBody::Alternative => crate::engine::request::Choice::Alternative,
        }
    }
}
