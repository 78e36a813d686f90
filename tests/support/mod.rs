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

/// Runs the command pinned to the first core: one worker thread, and one thread in rayon's pool.
#[allow(dead_code)] // only the replay tests run on chosen cores
pub fn on_one_core(command: &mut Command) -> &mut Command {
    use std::os::unix::process::CommandExt;
    // SAFETY: only async-signal-safe calls between fork and exec.
    unsafe {
        command.pre_exec(|| {
            let mut set: libc::cpu_set_t = std::mem::zeroed();
            libc::CPU_SET(0, &mut set);
            match libc::sched_setaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &set) {
                0 => Ok(()),
                _ => Err(std::io::Error::last_os_error()),
            }
        })
    }
}

/// Runs the command with a pool of at least four threads, so that it is parallel even where the
/// machine has one core.
#[allow(dead_code)] // only the replay tests run on chosen cores
pub fn on_every_core(command: &mut Command) -> &mut Command {
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    command.env("RAYON_NUM_THREADS", cores.max(4).to_string())
}
