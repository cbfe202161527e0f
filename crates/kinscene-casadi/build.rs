//! Compiles the CasADi shim (`cpp/shim.cpp`) into its own shared object.
//!
//! Discovery: `KINSCENE_CASADI_PREFIX` (the directory holding `include/casadi/casadi.hpp` and
//! `libcasadi.so`), else the `casadi` package of the project-local venv or of `python3`.

use std::path::{Path, PathBuf};

const OVERRIDE: &str = "KINSCENE_CASADI_PREFIX";
const MUST_CONTAIN: [&str; 2] = ["include/casadi/casadi.hpp", "libcasadi.so"];

/// Compile definitions every consumer of CasADi must use (they change class layouts, e.g. atomic
/// reference counts). Read from the wheel's CMake export when present; these are the values of
/// the 3.8.2 wheel otherwise.
const FALLBACK_DEFINES: [&str; 3] = [
    "CASADI_SNPRINTF=snprintf",
    "CASADI_WITH_THREADSAFE_SYMBOLICS",
    "CASADI_WITH_THREAD",
];

fn main() {
    if kinscene_build::skip_native_build() {
        return;
    }
    let prefix = find_prefix();
    let manifest = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let mut so = kinscene_build::SharedObject::new("kinscene_casadi_shim")
        .source(manifest.join("cpp/shim.cpp"))
        .header(manifest.join("cpp/shim.h"))
        .include(manifest.join("cpp"))
        .include(prefix.join("include"))
        .flag("-std=c++17")
        .lib_dir(&prefix)
        .lib("casadi");
    for d in compile_definitions(&prefix) {
        so = so.define(d);
    }
    so.build("KINSCENE_CASADI_SHIM_BUILT");
}

fn find_prefix() -> PathBuf {
    let mut searched = Vec::new();
    let has_all = |p: &Path| MUST_CONTAIN.iter().all(|f| p.join(f).exists());
    let requirement = format!("holds {}", MUST_CONTAIN.join(" and "));
    if let Some(p) = kinscene_build::env_override(OVERRIDE, "CasADi", &requirement, has_all) {
        return p;
    }
    if let Some(p) = kinscene_build::find_in_site_packages("casadi", &MUST_CONTAIN) {
        return p;
    }
    for sp in kinscene_build::site_packages_candidates() {
        searched.push(format!("{}/casadi", sp.display()));
    }
    kinscene_build::fail(
        "CasADi",
        &searched,
        &format!(
            "{OVERRIDE} to a directory containing include/casadi/casadi.hpp and libcasadi.so (`pip install casadi==3.8.2`)"
        ),
    )
}

/// `INTERFACE_COMPILE_DEFINITIONS` of the `casadi::casadi` CMake target.
fn compile_definitions(prefix: &Path) -> Vec<String> {
    let file = prefix.join("cmake/casadi-targets.cmake");
    println!("cargo:rerun-if-changed={}", file.display());
    let parsed = std::fs::read_to_string(&file).ok().and_then(|text| {
        let line = text
            .lines()
            .find(|l| l.trim_start().starts_with("INTERFACE_COMPILE_DEFINITIONS"))?;
        let value = line.split('"').nth(1)?;
        Some(
            value
                .split(';')
                .filter(|d| !d.is_empty())
                .map(String::from)
                .collect(),
        )
    });
    parsed.unwrap_or_else(|| FALLBACK_DEFINES.iter().map(|d| d.to_string()).collect())
}
