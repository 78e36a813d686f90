//! Transports: thin adapters that convert wire formats, call `core`, and convert back.
//!
//! Owns: what REST and gRPC share: the state handed to handlers and the admin-token check.
//! Must not: decide anything or validate domain input.

pub mod grpc;
pub mod rest;

use std::sync::Arc;

use subtle::ConstantTimeEq;

use crate::core::Core;
use crate::error::Error;

/// What every handler of either transport shares.
#[derive(Clone)]
pub struct AppState {
    pub core: Arc<Core>,
    /// When set, requests that change norms must carry `Authorization: Bearer <token>`.
    pub admin_token: Option<Arc<str>>,
    /// Largest REST request body accepted, bytes.
    pub max_body_bytes: usize,
}

impl AppState {
    /// Whether a request with this `authorization` value (HTTP header or gRPC metadata) may
    /// change norms: always when no admin token is set; otherwise only with `Bearer <token>`,
    /// compared in constant time. Missing or not a bearer credential: 401; wrong token: 403.
    pub fn authorize_write(&self, authorization: Option<&str>) -> Result<(), Error> {
        let Some(expected) = &self.admin_token else {
            return Ok(());
        };
        let sent = authorization
            .and_then(|v| v.strip_prefix("Bearer ").or_else(|| v.strip_prefix("bearer ")))
            .map(str::trim)
            .ok_or(Error::Unauthenticated)?;
        if bool::from(sent.as_bytes().ct_eq(expected.as_bytes())) {
            Ok(())
        } else {
            Err(Error::Forbidden)
        }
    }
}
