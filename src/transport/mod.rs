//! Transports: thin adapters that convert wire formats, call `core`, and convert back.

pub mod rest;
