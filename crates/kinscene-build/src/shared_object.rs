//! Compiling a shim into a self-contained shared object.

use std::path::{Path, PathBuf};
use std::process::Command;

/// A C++ shim compiled and linked into `OUT_DIR/lib<name>.so`.
///
/// The object is linked with `-z defs` (every symbol resolved at link time, so a missing
/// library is a build error, not a run-time surprise), `-Bsymbolic` and hidden visibility (only
/// `KS_API` functions are exported), and a `DT_RPATH` to every library directory, which also
/// applies to the libraries' own dependencies. It is always optimised (`-O2 -DNDEBUG`): the
/// shims wrap numerical libraries whose header templates are slow without it.
#[derive(Debug, Clone, Default)]
pub struct SharedObject {
    name: String,
    sources: Vec<PathBuf>,
    headers: Vec<PathBuf>,
    include_dirs: Vec<PathBuf>,
    defines: Vec<String>,
    flags: Vec<String>,
    lib_dirs: Vec<PathBuf>,
    libs: Vec<String>,
}

impl SharedObject {
    /// A shared object named `lib<name>.so`.
    pub fn new(name: &str) -> Self {
        SharedObject {
            name: name.to_owned(),
            ..Default::default()
        }
        .include(crate::common_include_dir())
    }

    /// Adds a C++ source file (rebuilds when it changes).
    pub fn source(mut self, path: impl AsRef<Path>) -> Self {
        self.sources.push(path.as_ref().to_owned());
        self
    }

    /// Registers a header for rebuilds.
    pub fn header(mut self, path: impl AsRef<Path>) -> Self {
        self.headers.push(path.as_ref().to_owned());
        self
    }

    /// Adds an include directory.
    pub fn include(mut self, dir: impl AsRef<Path>) -> Self {
        self.include_dirs.push(dir.as_ref().to_owned());
        self
    }

    /// Adds a preprocessor definition (`NAME` or `NAME=VALUE`).
    pub fn define(mut self, def: impl Into<String>) -> Self {
        self.defines.push(def.into());
        self
    }

    /// Adds a raw compiler flag (e.g. `-std=c++17`).
    pub fn flag(mut self, flag: impl Into<String>) -> Self {
        self.flags.push(flag.into());
        self
    }

    /// Adds a library directory, searched at link time and recorded as RPATH.
    pub fn lib_dir(mut self, dir: impl AsRef<Path>) -> Self {
        self.lib_dirs.push(dir.as_ref().to_owned());
        self
    }

    /// Links a library: a name for `-l<name>`, or `:<file>` for an exact file name
    /// (`-l:libfoo.so.1.2`).
    pub fn lib(mut self, name: impl Into<String>) -> Self {
        self.libs.push(name.into());
        self
    }

    /// Compiles and links; returns the absolute path of the shared object.
    ///
    /// Also emits `cargo:rustc-env=<env_var>=<path>` so the crate can `env!` the location at
    /// compile time, plus the `rerun-if-changed` lines for sources and headers.
    pub fn build(&self, env_var: &str) -> PathBuf {
        let out_dir = PathBuf::from(std::env::var_os("OUT_DIR").expect("OUT_DIR is set by cargo"));
        let output = out_dir.join(format!("lib{}.so", self.name));
        for f in self.sources.iter().chain(&self.headers) {
            println!("cargo:rerun-if-changed={}", f.display());
        }
        println!(
            "cargo:rerun-if-changed={}",
            crate::common_include_dir().join("ks_common.h").display()
        );

        let tool = cc::Build::new()
            .cpp(true)
            .cargo_metadata(false)
            .cargo_warnings(false)
            .opt_level(2)
            .debug(false)
            .pic(true)
            .get_compiler();
        let mut cmd = Command::new(tool.path());
        // cc's defaults for this target (pic, target flags), minus any -O/-g it chose.
        for arg in tool.args() {
            let a = arg.to_string_lossy();
            if !(a.starts_with("-O") || a.starts_with("-g")) {
                cmd.arg(arg);
            }
        }
        cmd.args(["-shared", "-fPIC", "-O2", "-DNDEBUG", "-fvisibility=hidden"]);
        cmd.args(["-fvisibility-inlines-hidden", "-Wall", "-Wno-unused-parameter"]);
        cmd.args(&self.flags);
        for d in &self.defines {
            cmd.arg(format!("-D{d}"));
        }
        for i in &self.include_dirs {
            cmd.arg("-I").arg(i);
        }
        cmd.args(&self.sources);
        cmd.arg("-o").arg(&output);
        cmd.args([
            "-Wl,-z,defs",
            "-Wl,-Bsymbolic",
            "-Wl,--exclude-libs,ALL",
            "-Wl,--disable-new-dtags",
        ]);
        cmd.arg(format!("-Wl,-soname,lib{}.so", self.name));
        for d in &self.lib_dirs {
            cmd.arg(format!("-L{}", d.display()));
            cmd.arg(format!("-Wl,-rpath,{}", d.display()));
        }
        for l in &self.libs {
            cmd.arg(format!("-l{l}"));
        }
        let status = cmd
            .status()
            .unwrap_or_else(|e| panic!("kinscene: cannot run the C++ compiler {:?}: {e}", tool.path()));
        if !status.success() {
            eprintln!("kinscene: compiling the {} shim failed; command: {cmd:?}", self.name);
            std::process::exit(1);
        }
        println!("cargo:rustc-env={env_var}={}", output.display());
        output
    }
}
