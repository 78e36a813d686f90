//! What every test binary shares: reqwest clients built the one way that works here.
//!
//! The tests' reqwest carries rustls without a built-in crypto provider (the TLS tests configure
//! their own), so ring must be the process default before any client is built, even a cleartext one.

/// Makes ring the process's crypto provider; later calls are no-ops.
pub fn install_ring() {
    let _ = rustls::crypto::ring::default_provider().install_default();
}

/// A plain reqwest client.
pub fn http_client() -> reqwest::Client {
    install_ring();
    reqwest::Client::new()
}
