//! Compiles the Pinocchio shim (`cpp/shim.cpp`) into its own shared object.
//!
//! Discovery, first match wins:
//! - `KINSCENE_PINOCCHIO_PREFIX`: a cmeel prefix (the `cmeel.prefix` directory of the
//!   `libpinocchio` wheel, holding `include/pinocchio/` and `lib/libpinocchio_default.so`);
//! - `cmeel.prefix` in the project-local venv `.deps/venv` (written by `setup.sh`), then in the
//!   `site-packages` of the `python3` on `PATH`.
//!
//! Eigen comes from the same prefix (`include/eigen3`, wheel `cmeel-eigen`). The compile
//! definitions Pinocchio's headers need (boost MPL/fusion limits, explicit template
//! instantiation) are read from the prefix's `lib/cmake/pinocchio/pinocchioTargets.cmake`, so
//! they follow the installed version instead of being hard-coded here.

use std::path::{Path, PathBuf};

/// Files whose presence proves a usable prefix.
const MUST_CONTAIN: &[&str] = &[
    "include/pinocchio/multibody.hpp",
    "include/pinocchio/algorithm/frames.hpp",
    "include/eigen3/Eigen/Core",
    "lib/libpinocchio_default.so",
    "lib/cmake/pinocchio/pinocchioTargets.cmake",
];

/// The CMake targets whose interface definitions a shim linking `pinocchio_default` inherits.
const TARGETS: &[&str] = &[
    "pinocchio::pinocchio_headers",
    "pinocchio::pinocchio_default",
];

fn main() {
    if kinscene_build::skip_native_build() {
        return;
    }
    let manifest = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let prefix = find_prefix();
    let targets_file = prefix.join("lib/cmake/pinocchio/pinocchioTargets.cmake");
    println!("cargo:rerun-if-changed={}", targets_file.display());
    let cmake = std::fs::read_to_string(&targets_file)
        .unwrap_or_else(|e| panic!("kinscene: cannot read {}: {e}", targets_file.display()));
    let defines = interface_definitions(&cmake, TARGETS);
    if !defines
        .iter()
        .any(|d| d.starts_with("BOOST_MPL_LIMIT_LIST_SIZE"))
    {
        println!(
            "cargo:warning=kinscene: no BOOST_MPL_LIMIT_LIST_SIZE in {}; the shim may not compile",
            targets_file.display()
        );
    }

    let mut so = kinscene_build::SharedObject::new("kinscene_pinocchio_shim")
        .source(manifest.join("cpp/shim.cpp"))
        .header(manifest.join("cpp/shim.h"))
        .include(manifest.join("cpp"))
        .include(prefix.join("include"))
        .include(prefix.join("include/eigen3"))
        .flag("-std=c++17")
        .lib_dir(prefix.join("lib"))
        .lib("pinocchio_default");
    for d in defines {
        so = so.define(d);
    }
    // The algorithms used by the shim are all explicitly instantiated in libpinocchio_default
    // (the shim calls them with exactly those signatures), so `-z defs` needs no other library:
    // no boost.serialization or coal symbol is referenced from the shim itself.
    so.build("KINSCENE_PINOCCHIO_SHIM_BUILT");
}

/// `KINSCENE_PINOCCHIO_PREFIX`, else the first `site-packages/cmeel.prefix` holding Pinocchio.
fn find_prefix() -> PathBuf {
    let has_all = |d: &Path| MUST_CONTAIN.iter().all(|f| d.join(f).exists());
    let mut searched = Vec::new();
    let requirement = format!("holds {}", MUST_CONTAIN.join(" and "));
    if let Some(dir) = kinscene_build::env_override(
        "KINSCENE_PINOCCHIO_PREFIX",
        "Pinocchio",
        &requirement,
        has_all,
    ) {
        return dir;
    }
    if let Some(dir) = kinscene_build::find_in_site_packages("cmeel.prefix", MUST_CONTAIN) {
        return dir;
    }
    for sp in kinscene_build::site_packages_candidates() {
        searched.push(format!("{}/cmeel.prefix", sp.display()));
    }
    kinscene_build::fail(
        "Pinocchio",
        &searched,
        "KINSCENE_PINOCCHIO_PREFIX to a cmeel prefix (`pip install libpinocchio cmeel-eigen`, then `python -m cmeel cmake` prints it)",
    );
}

/// The `INTERFACE_COMPILE_DEFINITIONS` of `targets`, in order, without duplicates and without
/// generator expressions (`$<...>`, which need CMake to evaluate).
fn interface_definitions(cmake: &str, targets: &[&str]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for target in targets {
        let opening = format!("set_target_properties({target} PROPERTIES");
        let Some(start) = cmake.find(&opening) else {
            println!("cargo:warning=kinscene: target {target} not found in pinocchioTargets.cmake");
            continue;
        };
        let block = &cmake[start..];
        let block = &block[..block.find("\n)").unwrap_or(block.len())];
        for line in block.lines() {
            let Some(rest) = line.trim().strip_prefix("INTERFACE_COMPILE_DEFINITIONS") else {
                continue;
            };
            let value = rest.trim().trim_matches('"');
            for item in value.split(';') {
                let item = item.trim();
                if item.is_empty() || item.contains("$<") || out.iter().any(|d| d == item) {
                    continue;
                }
                out.push(item.to_owned());
            }
        }
    }
    out
}
