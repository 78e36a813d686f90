//! Scruple: simulate every reading of an ambiguous directive against the robot's norms and
//! abilities, then ask, assume or explain without implying it would do something wrong.

pub mod allocator;
pub mod app;
pub mod core;
pub mod engine;
pub mod error;
pub mod metrics;
pub mod offline;
pub mod storage;
pub mod transport;
pub mod wire;
