//! Table-driven tests of the whole engine (scene, norms, simulation, Algorithm 1, utterances)
//! against CONTRACT.md and `../shared/scenarios/paper-demo.json`, and a property test of the
//! safety invariant: under the moral strategy no reading that violates a norm or cannot be done
//! is ever offered, assumed, confirmed or obeyed.

use std::collections::BTreeMap;

use proptest::prelude::*;

use super::action::Library;
use super::algorithm::FEW;
use super::clarify::clarify;
use super::decision::{Decision, DecisionKind, Interpretation};
use super::norms::{CompiledNorms, Norm, NormInput};
use super::request::{DEFAULT_MAX_SPOKEN, Directive, Options, Request, SinglePermissible, Strategy as ClarifyStrategy};
use super::resolve::{Candidate, Reference};
use super::scene::{Agent, Object, Scene, Shape};
use super::speech;
use super::term::{Sym, Term};

use DecisionKind::{Ask, Assume, Comply, Confirm, Explain, NotUnderstood, Refuse, Unresolved};

mod decisions;
mod feasibility;
mod fixtures;
mod household;
mod norms;
mod number;
mod number_props;
mod ordering;
mod paper;
mod people;
mod plans;
mod relation_props;
mod relation_refs;
mod relation_word_safety;
mod relation_words;
mod relations;
mod runner;
mod safety;
mod scenes;
mod shape_tasks;
mod shapes;
mod soft;
mod tasks;
mod verbs;
mod words;
mod words_hostile;

use fixtures::*;
use runner::*;
