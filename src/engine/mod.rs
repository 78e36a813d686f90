//! The pure domain: terms, scenes, worlds, norms, actions, simulation, Algorithm 1, utterances.
//!
//! Must not: do I/O, be async, or name a web, RPC or database type. Everything it needs arrives
//! as arguments, so it is tested without a runtime.

pub mod action;
pub mod algorithm;
pub mod check;
pub mod clarify;
pub mod decision;
pub mod describe;
pub mod input;
pub mod norms;
pub mod request;
pub mod resolve;
pub mod scene;
pub mod simulate;
pub mod speech;
pub mod sym;
pub mod task;
pub mod term;
pub mod words;
pub mod world;

#[cfg(test)]
mod tests;

pub use action::Library;
pub use clarify::clarify;
pub use decision::{Decision, DecisionKind};
pub use norms::CompiledNorms;
pub use request::Request;
pub use scene::Scene;
pub use term::Term;
