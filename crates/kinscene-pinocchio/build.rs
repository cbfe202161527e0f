//! Compiles the Pinocchio shim (`cpp/shim.cpp`) into its own shared object.
//!
//! Discovery, first match wins:
//! - `KINSCENE_PINOCCHIO_PREFIX`: a cmeel prefix (the `cmeel.prefix` directory of the
//!   `libpinocchio` wheel, holding `include/pinocchio/` and `lib/libpinocchio_default.so`);
//! - `cmeel.prefix` in the project-local venv `.deps/venv` (written by `setup.sh`), then in the
//!   `site-packages` of the `python3` on `PATH`.
//!
//! Eigen comes from the same prefix (`include/eigen3`, wheel `cmeel-eigen`), and so do the
//! urdfdom headers the URDF parser's header includes (`include/urdfdom_headers`, wheel
//! `cmeel-urdfdom-headers`; listed first so that a system `urdf_model` is never picked). The
//! compile definitions Pinocchio's headers need (boost MPL/fusion limits, explicit template
//! instantiation, `PINOCCHIO_WITH_URDFDOM` and the urdfdom header version) are read from the
//! prefix's `lib/cmake/pinocchio/pinocchioTargets.cmake`, so they follow the installed version
//! instead of being hard-coded here.
//!
//! The shim links `pinocchio_default` (kinematics), `pinocchio_parsers` (URDF) and
//! `console_bridge` (to capture urdfdom's diagnostics), all from the prefix.

use std::path::{Path, PathBuf};

/// Files whose presence proves a usable prefix.
const MUST_CONTAIN: &[&str] = &[
    "include/pinocchio/multibody.hpp",
    "include/pinocchio/algorithm/frames.hpp",
    "include/eigen3/Eigen/Core",
    "include/pinocchio/parsers/urdf.hpp",
    "include/urdfdom_headers/urdf_model/model.h",
    "include/console_bridge/console.h",
    "lib/libpinocchio_default.so",
    "lib/libpinocchio_parsers.so",
    "lib/libconsole_bridge.so",
    "lib/cmake/pinocchio/pinocchioTargets.cmake",
];

/// Which wheel provides each entry of [`MUST_CONTAIN`], for the message when one is missing.
const PROVIDED_BY: &[(&str, &str)] = &[
    ("include/eigen3", "cmeel-eigen"),
    ("include/urdfdom_headers", "cmeel-urdfdom-headers"),
    ("include/console_bridge", "cmeel-console-bridge"),
    ("lib/libconsole_bridge", "cmeel-console-bridge"),
];

/// The CMake targets whose interface definitions a shim linking `pinocchio_default` and
/// `pinocchio_parsers` inherits.
const TARGETS: &[&str] = &[
    "pinocchio::pinocchio_headers",
    "pinocchio::pinocchio_default",
    "pinocchio::pinocchio_parsers",
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

    if !defines.iter().any(|d| d == "PINOCCHIO_WITH_URDFDOM") {
        println!(
            "cargo:warning=kinscene: no PINOCCHIO_WITH_URDFDOM in {}; the URDF parser may not compile",
            targets_file.display()
        );
    }

    let mut so = kinscene_build::SharedObject::new("kinscene_pinocchio_shim")
        .source(manifest.join("cpp/shim.cpp"))
        .source(manifest.join("cpp/urdf.cpp"))
        .header(manifest.join("cpp/shim.h"))
        .header(manifest.join("cpp/urdf.hpp"))
        .include(manifest.join("cpp"))
        .include(prefix.join("include/urdfdom_headers"))
        .include(prefix.join("include"))
        .include(prefix.join("include/eigen3"))
        .flag("-std=c++17")
        .lib_dir(prefix.join("lib"))
        .lib("pinocchio_parsers")
        .lib("pinocchio_default")
        .lib("console_bridge");
    for d in defines {
        so = so.define(d);
    }
    // The kinematics algorithms used by the shim are explicitly instantiated in
    // libpinocchio_default (the shim calls them with exactly those signatures); the URDF
    // parser's work happens in libpinocchio_parsers (`parseRootTreeFromXML`, called with the
    // header-defined visitor), and console_bridge provides the log handler hooks. `-z defs`
    // needs no other library: no boost.serialization, coal or urdfdom symbol is referenced from
    // the shim itself.
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
        let dir = sp.join("cmeel.prefix");
        let missing: Vec<String> = MUST_CONTAIN
            .iter()
            .filter(|f| dir.is_dir() && !dir.join(f).exists())
            .map(
                |f| match PROVIDED_BY.iter().find(|(p, _)| f.starts_with(p)) {
                    Some((_, wheel)) => format!("{f} (wheel {wheel})"),
                    None => (*f).to_owned(),
                },
            )
            .collect();
        if missing.is_empty() {
            searched.push(dir.display().to_string());
        } else {
            searched.push(format!("{} lacks {}", dir.display(), missing.join(", ")));
        }
    }
    kinscene_build::fail(
        "Pinocchio",
        &searched,
        "KINSCENE_PINOCCHIO_PREFIX to a cmeel prefix (`pip install libpinocchio cmeel-eigen cmeel-urdfdom-headers`, then `python -m cmeel cmake` prints it)",
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
