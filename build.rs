//! Compiles `proto/` with the pure-Rust protox (no `protoc` needed) into tonic/prost code, and
//! keeps the encoded descriptor set for server reflection. Hands an ordinary release build's
//! linker the hot path's layout (`link/hot-text.ld`). Records the commit built, for `/version`.

use std::path::PathBuf;

use prost::Message;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!("cargo:rerun-if-changed=proto");
    let descriptors = protox::compile(["scruple/v1/scruple.proto"], ["proto"])?;
    let out = PathBuf::from(std::env::var("OUT_DIR")?);
    std::fs::write(out.join("scruple_descriptor.bin"), descriptors.encode_to_vec())?;
    tonic_prost_build::configure()
        .build_server(true)
        .build_client(true)
        .compile_fds(descriptors)?;
    commit();
    hot_text()
}

/// `SCRUPLE_COMMIT` for the crate: `SCRUPLE_BUILD_COMMIT` when the build is given it (an image
/// built without `.git`), else git's `HEAD` when the source is a checkout; unset otherwise
/// (`/version` then says `null`). Rebuilt when `HEAD` moves.
fn commit() {
    println!("cargo:rerun-if-env-changed=SCRUPLE_BUILD_COMMIT");
    let git = |args: &[&str]| {
        let out = std::process::Command::new("git").args(args).output().ok()?;
        let text = String::from_utf8(out.stdout).ok()?;
        out.status.success().then(|| text.trim().to_owned())
    };
    let given = std::env::var("SCRUPLE_BUILD_COMMIT")
        .ok()
        .filter(|c| !c.trim().is_empty());
    let commit = given.or_else(|| {
        // HEAD names a branch whose ref file (or the packed refs) moves with each commit.
        for path in ["HEAD", "packed-refs"] {
            if let Some(file) = git(&["rev-parse", "--git-path", path]) {
                println!("cargo:rerun-if-changed={file}");
            }
        }
        if let Some(file) = git(&["symbolic-ref", "-q", "HEAD"]).and_then(|r| git(&["rev-parse", "--git-path", &r])) {
            println!("cargo:rerun-if-changed={file}");
        }
        git(&["rev-parse", "--short=12", "HEAD"])
    });
    if let Some(commit) = commit.filter(|c| c.bytes().all(|b| b.is_ascii_alphanumeric())) {
        println!("cargo:rustc-env=SCRUPLE_COMMIT={commit}");
    }
}

/// The functions one request runs, laid out together in the server binary (ARCHITECTURE.md,
/// "The hot path's code layout"): an ELF linker script that only inserts a section, so the
/// default layout stays otherwise. Only for release builds of the binary on Linux; not for a
/// profile-guided build (`-Cprofile-use`/`-Cprofile-generate`), whose layout follows its profile.
fn hot_text() -> Result<(), Box<dyn std::error::Error>> {
    let script = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR")?).join("link/hot-text.ld");
    println!("cargo:rerun-if-changed=link/hot-text.ld");
    let release = std::env::var("PROFILE").as_deref() == Ok("release");
    let linux = std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("linux");
    let profiled = std::env::var("CARGO_ENCODED_RUSTFLAGS")
        .is_ok_and(|flags| flags.contains("profile-use") || flags.contains("profile-generate"));
    if release && linux && !profiled && script.is_file() {
        println!("cargo:rustc-link-arg-bins=-Wl,-T,{}", script.display());
    }
    Ok(())
}
