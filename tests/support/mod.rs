//! What every test binary shares: reqwest clients built the one way that works here, and the one
//! way to start a process.
//!
//! The tests' reqwest carries rustls without a built-in crypto provider (the TLS tests configure
//! their own), so ring must be the process default before any client is built, even a cleartext one.
//!
//! Every process a test starts is made by [`command`] (the `scruple` binary by [`scruple`]), so
//! that none inherits the caller's `SCRUPLE_*` variables: a developer's `SCRUPLE_ADMIN_TOKEN` or
//! `SCRUPLE_DATABASE_URL` in the shell would otherwise change what a test tests. A test sets on
//! the command what it means to set. In `tests/api`, `binary::launchers_pass_none_of_the_callers_
//! scruple_variables` holds the launcher to this, and `binary::every_process_a_test_starts_is_
//! made_by_the_one_launcher` every test file to the launcher.

use std::ffi::OsStr;
use std::process::Command;

/// The `scruple` binary cargo built for these tests.
pub const SCRUPLE: &str = env!("CARGO_BIN_EXE_scruple");

/// Makes ring the process's crypto provider; later calls are no-ops.
pub fn install_ring() {
    let _ = rustls::crypto::ring::default_provider().install_default();
}

/// A plain reqwest client.
pub fn http_client() -> reqwest::Client {
    install_ring();
    reqwest::Client::new()
}

/// Whether an environment variable is one of the service's settings (or a test's own knob).
pub fn is_scruple_variable(name: &OsStr) -> bool {
    name.as_encoded_bytes().starts_with(b"SCRUPLE_")
}

/// A command for `program` that passes on the caller's environment except every `SCRUPLE_*`
/// variable in it (a shell that `exec`s the binary passes on none either).
pub fn command(program: impl AsRef<OsStr>) -> Command {
    let mut command = Command::new(program);
    for (name, _) in std::env::vars_os().filter(|(name, _)| is_scruple_variable(name)) {
        command.env_remove(name);
    }
    command
}

/// The `scruple` binary, with none of the caller's `SCRUPLE_*` variables.
pub fn scruple() -> Command {
    command(SCRUPLE)
}
