//! Compiles `proto/` with the pure-Rust protox (no `protoc` needed) into tonic/prost code, and
//! keeps the encoded descriptor set for server reflection. Hands an ordinary release build's
//! linker the hot path's layout (`link/hot-text.ld`).

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
    hot_text()
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
