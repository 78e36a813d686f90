//! One integration-test binary: the real service on port 0 with a fresh database per test.

mod actions;
mod auth;
mod backends;
mod beyond;
mod binary;
mod coherence;
mod connections;
mod crash;
mod errors;
mod fail_closed;
mod golden;
mod grpc;
mod hardening;
mod helpers;
mod integrity;
mod leases;
mod limits;
mod migrations;
mod never_drop;
mod norms;
mod number;
mod observability;
mod openapi;
mod paper_demo;
mod people;
mod playground;
mod references;
mod replicas;
mod soft;
#[path = "../support/mod.rs"]
mod support;
mod tasks;
mod tls;
mod web;
mod words;
