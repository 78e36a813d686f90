//! The schema of the engine's option enums, under the names the published document has always
//! given them. The values come from each enum's one list and spelling (`Spelled`), which serde
//! uses too (a test in the engine holds the two together).

use std::borrow::Cow;

use utoipa::openapi::RefOr;
use utoipa::openapi::schema::{ObjectBuilder, Schema, Type};
use utoipa::{PartialSchema, ToSchema};

use crate::engine::decision::Style;
use crate::engine::input::Spelled;
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
