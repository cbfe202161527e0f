//! Compiles the OMPL shim (`cpp/shim.cpp`) into its own shared object.
//!
//! Discovery, first match wins:
//! - headers: `OMPL_INCLUDE_DIR` (the directory holding `ompl/config.h`), else the include
//!   paths of `pkg-config ompl`, else `/usr/include/ompl-1.5`;
//! - Eigen: `EIGEN3_INCLUDE_DIR` (holding `Eigen/Core`), else `pkg-config eigen3`, else
//!   `/usr/include/eigen3`;
//! - library: `OMPL_LIB_DIR` (holding `libompl.so`), else the compiler's default search path.
//!
//! Only the include paths of pkg-config are used: Debian's `ompl.pc` has a broken `Libs:` line,
//! so `-lompl` is linked here.

use std::path::{Path, PathBuf};

const OMPL_HEADER: &str = "ompl/config.h";
const EIGEN_HEADER: &str = "Eigen/Core";

fn main() {
    if kinscene_build::skip_native_build() {
        return;
    }
    let manifest = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let mut searched = Vec::new();
    let ompl = find_dir(
        "OMPL_INCLUDE_DIR",
        "ompl",
        "/usr/include/ompl-1.5",
        OMPL_HEADER,
        &mut searched,
    );
    let eigen = find_dir(
        "EIGEN3_INCLUDE_DIR",
        "eigen3",
        "/usr/include/eigen3",
        EIGEN_HEADER,
        &mut searched,
    );
    let (Some(ompl), Some(eigen)) = (ompl, eigen) else {
        kinscene_build::fail(
            "OMPL",
            &searched,
            "OMPL_INCLUDE_DIR (holding ompl/config.h), EIGEN3_INCLUDE_DIR (holding Eigen/Core) and OMPL_LIB_DIR (holding libompl.so); on Debian/Ubuntu `apt-get install libompl-dev libeigen3-dev`",
        );
    };
    let mut so = kinscene_build::SharedObject::new("kinscene_ompl_shim")
        .source(manifest.join("cpp/shim.cpp"))
        .header(manifest.join("cpp/shim.h"))
        .include(manifest.join("cpp"))
        .include(&ompl)
        .include(&eigen)
        .flag("-std=c++17");
    if let Some(lib_dir) =
        kinscene_build::env_override("OMPL_LIB_DIR", "OMPL", "holds libompl.so", |d: &Path| {
            d.join("libompl.so").exists()
        })
    {
        so = so.lib_dir(lib_dir);
    }
    so.lib("ompl").build("KINSCENE_OMPL_SHIM_BUILT");
}

/// The first of: the override variable, pkg-config's include paths, the Debian default, that
/// contains `header`. Records every place tried in `searched`.
fn find_dir(
    var: &str,
    package: &str,
    default: &str,
    header: &str,
    searched: &mut Vec<String>,
) -> Option<PathBuf> {
    let has = |d: &Path| d.join(header).exists();
    if let Some(dir) = kinscene_build::env_override(var, "OMPL", &format!("holds {header}"), has) {
        return Some(dir);
    }
    let from_pkg_config = kinscene_build::pkg_config_include_dirs(package).unwrap_or_default();
    for dir in from_pkg_config.into_iter().chain([PathBuf::from(default)]) {
        if has(&dir) {
            return Some(dir);
        }
        searched.push(format!(
            "{} (pkg-config {package} / default; lacks {header})",
            dir.display()
        ));
    }
    None
}
