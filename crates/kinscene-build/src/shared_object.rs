//! Compiling a shim into a self-contained shared object.

use std::hash::{Hash, Hasher};
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

    /// Compiles and links (or reuses a cached build); returns the absolute path of the shared
    /// object.
    ///
    /// The shim does not depend on cargo's profile (it is always `-O2`), so the result is cached
    /// under `<target>/kinscene-shims/lib<name>-<hash>.so`, keyed by a hash of the compiler, every
    /// argument and the contents of the sources and registered headers. Debug, release, bench
    /// and clippy builds therefore compile each shim once; editing a source or flag makes a new
    /// entry. Deleting `target/kinscene-shims` forces a rebuild.
    ///
    /// Emits `cargo:rustc-env=<env_var>=<path>` so the crate can `env!` the location, plus the
    /// `rerun-if-changed` lines for sources and headers.
    pub fn build(&self, env_var: &str) -> PathBuf {
        let out_dir = PathBuf::from(std::env::var_os("OUT_DIR").expect("OUT_DIR is set by cargo"));
        let common_header = crate::common_include_dir().join("ks_common.h");
        let inputs: Vec<&PathBuf> = self.sources.iter().chain(&self.headers).collect();
        for f in inputs.iter().copied().chain([&common_header]) {
            println!("cargo:rerun-if-changed={}", f.display());
        }

        let tool = cc::Build::new()
            .cpp(true)
            .cargo_metadata(false)
            .cargo_warnings(false)
            .opt_level(2)
            .debug(false)
            .pic(true)
            .get_compiler();
        let args = self.arguments(&tool);

        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        tool.path().hash(&mut hasher);
        args.hash(&mut hasher);
        for f in inputs.iter().copied().chain([&common_header]) {
            std::fs::read(f)
                .unwrap_or_else(|e| panic!("kinscene: cannot read {}: {e}", f.display()))
                .hash(&mut hasher);
        }
        let cache = cache_dir(&out_dir);
        std::fs::create_dir_all(&cache)
            .unwrap_or_else(|e| panic!("kinscene: cannot create {}: {e}", cache.display()));
        let output = cache.join(format!("lib{}-{:016x}.so", self.name, hasher.finish()));

        if !output.is_file() {
            // Build under a temporary name and rename, so concurrent builds never see a
            // half-written object.
            let partial = output.with_extension(format!("so.{}.partial", std::process::id()));
            let mut cmd = Command::new(tool.path());
            cmd.args(&args).arg("-o").arg(&partial);
            let status = cmd.status().unwrap_or_else(|e| {
                panic!(
                    "kinscene: cannot run the C++ compiler {:?}: {e}",
                    tool.path()
                )
            });
            if !status.success() {
                eprintln!(
                    "kinscene: compiling the {} shim failed; command: {cmd:?}",
                    self.name
                );
                std::process::exit(1);
            }
            std::fs::rename(&partial, &output)
                .unwrap_or_else(|e| panic!("kinscene: cannot move {}: {e}", partial.display()));
        }
        println!("cargo:rustc-env={env_var}={}", output.display());
        output
    }

    /// The compiler arguments, without the output file.
    fn arguments(&self, tool: &cc::Tool) -> Vec<String> {
        // cc's defaults for this target (pic, target flags), minus any -O/-g it chose.
        let mut args: Vec<String> = tool
            .args()
            .iter()
            .map(|a| a.to_string_lossy().into_owned())
            .filter(|a| !(a.starts_with("-O") || a.starts_with("-g")))
            .collect();
        args.extend(
            [
                "-shared",
                "-fPIC",
                "-O2",
                "-DNDEBUG",
                "-fvisibility=hidden",
                "-fvisibility-inlines-hidden",
                "-Wall",
                "-Wno-unused-parameter",
            ]
            .map(String::from),
        );
        args.extend(self.flags.iter().cloned());
        args.extend(self.defines.iter().map(|d| format!("-D{d}")));
        args.extend(
            self.include_dirs
                .iter()
                .map(|i| format!("-I{}", i.display())),
        );
        args.extend(self.sources.iter().map(|s| s.display().to_string()));
        args.extend(
            [
                "-Wl,-z,defs",
                "-Wl,-Bsymbolic",
                "-Wl,--exclude-libs,ALL",
                "-Wl,--disable-new-dtags",
            ]
            .map(String::from),
        );
        args.push(format!("-Wl,-soname,lib{}.so", self.name));
        for d in &self.lib_dirs {
            args.push(format!("-L{}", d.display()));
            args.push(format!("-Wl,-rpath,{}", d.display()));
        }
        args.extend(self.libs.iter().map(|l| format!("-l{l}")));
        args
    }
}

/// `<target>/kinscene-shims` for `OUT_DIR = <target>/<profile>/build/<pkg>-<hash>/out` (also
/// with a `<triple>/` level); `OUT_DIR` itself for any other layout.
fn cache_dir(out_dir: &Path) -> PathBuf {
    let mut up = out_dir.ancestors();
    match (up.nth(2), up.nth(1)) {
        (Some(build), Some(target)) if build.file_name() == Some("build".as_ref()) => {
            target.join("kinscene-shims")
        }
        _ => out_dir.to_owned(),
    }
}
