//! Build-script support shared by kinscene's backend crates.
//!
//! Every backend (OMPL, Pinocchio, CasADi) is a thin C++ shim compiled into its **own shared
//! object** with a C ABI, a `RPATH` into the library prefix it was built against, `-Bsymbolic`
//! and hidden visibility. The Rust side loads it lazily with
//! `dlopen(RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND)` (see the `kinscene-shim` crate). This is how
//! OMPL's boost 1.74 and Pinocchio's boost 1.90 coexist in one process, and why binaries of
//! downstream crates run without `LD_LIBRARY_PATH` (cargo does not propagate link arguments such
//! as `-rpath` from a dependency's build script to its dependents).
//!
//! Library discovery order, the same for every backend: environment override, then the
//! project-local prefix `.deps/venv` written by `setup.sh` (found by walking up from the crate's
//! manifest directory), then system locations (`pkg-config`, the `python3` on `PATH`). When
//! nothing is found, [`fail`] prints one message naming what to install or set.

use std::path::{Path, PathBuf};
use std::process::Command;

mod shared_object;
pub use shared_object::SharedObject;

/// True when building on docs.rs (or when the user asks to skip the C++ build for docs).
///
/// Backend crates then skip compiling their shim; the Rust API still type-checks and documents,
/// and any call returns a load error at run time.
pub fn skip_native_build() -> bool {
    println!("cargo:rerun-if-env-changed=DOCS_RS");
    std::env::var_os("DOCS_RS").is_some()
}

/// Reads an environment override and registers it for rebuilds.
pub fn env_path(name: &str) -> Option<PathBuf> {
    println!("cargo:rerun-if-env-changed={name}");
    std::env::var_os(name)
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
}

/// An explicit override: `None` when `name` is unset; the path when it is set and `is_valid`
/// accepts it; otherwise the build stops (via [`fail`]) instead of silently falling back to
/// another copy of the library, which would not be what the user asked for.
pub fn env_override(
    name: &str,
    backend: &str,
    requirement: &str,
    is_valid: impl Fn(&Path) -> bool,
) -> Option<PathBuf> {
    let dir = env_path(name)?;
    if is_valid(&dir) {
        return Some(dir);
    }
    fail(
        backend,
        &[format!(
            "{name}={}: expected a directory that {requirement}",
            dir.display()
        )],
        &format!("{name} to a directory that {requirement}, or unset it"),
    )
}

/// `site-packages` directories that may hold the backend wheels, best first: the project-local
/// venv (`<ancestor>/.deps/venv`, as written by `setup.sh`), then those of `python3` on `PATH`.
pub fn site_packages_candidates() -> Vec<PathBuf> {
    let mut out = Vec::new();
    let manifest = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    for dir in manifest.ancestors() {
        let lib = dir.join(".deps/venv/lib");
        if let Ok(entries) = std::fs::read_dir(&lib) {
            let mut found: Vec<PathBuf> = entries
                .filter_map(|e| e.ok())
                .map(|e| e.path().join("site-packages"))
                .filter(|p| p.is_dir())
                .collect();
            found.sort();
            println!("cargo:rerun-if-changed={}", lib.display());
            out.extend(found);
            break;
        }
    }
    if let Ok(output) = Command::new("python3")
        .args([
            "-c",
            "import site,sys; print('\\n'.join(site.getsitepackages()+[site.getusersitepackages()]))",
        ])
        .output()
    {
        if output.status.success() {
            for line in String::from_utf8_lossy(&output.stdout).lines() {
                let p = PathBuf::from(line.trim());
                if p.is_dir() && !out.contains(&p) {
                    out.push(p);
                }
            }
        }
    }
    out
}

/// The first candidate `site-packages/<relative>` that contains every file in `must_contain`.
pub fn find_in_site_packages(relative: &str, must_contain: &[&str]) -> Option<PathBuf> {
    site_packages_candidates()
        .into_iter()
        .map(|sp| sp.join(relative))
        .find(|dir| must_contain.iter().all(|f| dir.join(f).exists()))
}

/// Include directories reported by `pkg-config --cflags-only-I` (never its `Libs:` line, which
/// is broken in Debian's `ompl.pc`).
pub fn pkg_config_include_dirs(package: &str) -> Option<Vec<PathBuf>> {
    let output = Command::new("pkg-config")
        .args(["--cflags-only-I", package])
        .output()
        .ok()?;
    if !output.status.success() {
        return None;
    }
    Some(
        String::from_utf8_lossy(&output.stdout)
            .split_whitespace()
            .filter_map(|f| f.strip_prefix("-I"))
            .map(PathBuf::from)
            .collect(),
    )
}

/// Stops the build script with one message that says what is missing and what to do.
///
/// `backend` is the library ("OMPL"), `searched` lists where we looked, `override_hint` names
/// the environment variables that point the build elsewhere.
pub fn fail(backend: &str, searched: &[String], override_hint: &str) -> ! {
    let mut msg = format!("kinscene: {backend} was not found.\n  searched:");
    if searched.is_empty() {
        msg.push_str(" (nothing)");
    }
    for s in searched {
        msg.push_str(&format!("\n    - {s}"));
    }
    msg.push_str(&format!(
        "\n  fix: run `bash setup.sh` in the kinscene repository (installs everything), or set {override_hint},\n       or build without the C++ backends: `cargo build --no-default-features`."
    ));
    eprintln!("{msg}");
    println!("cargo:warning=kinscene: {backend} was not found; see the build script's stderr");
    std::process::exit(1);
}

/// The directory of the shared C header (`ks_common.h`) with the C-ABI error conventions.
pub fn common_include_dir() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/include"))
}
