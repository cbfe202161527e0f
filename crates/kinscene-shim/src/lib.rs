//! Run-time side of kinscene's C++ shims.
//!
//! Each backend shim is a shared object with a C ABI (see `kinscene-build`). This crate loads it
//! with `dlopen(RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND)`, so that the shim and the libraries it
//! links resolve symbols inside their own dependency tree first. That keeps, for example,
//! Pinocchio's boost 1.90 and OMPL's boost 1.74 from binding to each other's code when both are
//! in one process. It also turns the shim's status-and-message convention (`ks_common.h`) into
//! typed Rust errors.

use std::ffi::{CStr, c_char, c_int};
use std::mem::MaybeUninit;
use std::path::{Path, PathBuf};

/// Size of the error-message buffer handed to every fallible shim call.
pub const ERR_LEN: usize = 1024;

const KS_INVALID_ARGUMENT: c_int = 2;

/// Loading a shim failed.
#[derive(Debug, Clone, thiserror::Error)]
#[error("cannot load the {backend} shim from {}: {reason}", path.display())]
pub struct LoadError {
    /// Which backend ("OMPL", "Pinocchio", "CasADi").
    pub backend: &'static str,
    /// The shared object that was tried.
    pub path: PathBuf,
    /// The loader's message (`dlerror`), or why no path was available.
    pub reason: String,
}

/// A shim call reported failure.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CallError {
    /// The C++ library threw an exception; its `what()` is kept.
    #[error("{function}: C++ exception: {message}")]
    Exception {
        /// The shim function that failed.
        function: &'static str,
        /// The exception's message.
        message: String,
    },
    /// The shim rejected its input.
    #[error("{function}: invalid argument: {message}")]
    InvalidArgument {
        /// The shim function that failed.
        function: &'static str,
        /// What was wrong.
        message: String,
    },
}

/// A loaded shim. Symbols borrowed from it stay valid while it lives; backends keep it in a
/// `static OnceLock` for the whole process.
#[derive(Debug)]
pub struct Shim {
    lib: libloading::os::unix::Library,
    backend: &'static str,
    path: PathBuf,
}

impl Shim {
    /// Loads the shim for `backend`: from the environment variable `env_override` if set,
    /// otherwise from `built`, the path its build script produced (`None` when the native build
    /// was skipped, e.g. on docs.rs).
    ///
    /// # Errors
    /// [`LoadError`] when the file is missing or the loader rejects it (unresolved symbol,
    /// missing dependency), with the loader's message.
    pub fn open(
        backend: &'static str,
        env_override: &str,
        built: Option<&'static str>,
    ) -> Result<Shim, LoadError> {
        let path = match std::env::var_os(env_override).filter(|v| !v.is_empty()) {
            Some(p) => PathBuf::from(p),
            None => match built {
                Some(p) => PathBuf::from(p),
                None => {
                    return Err(LoadError {
                        backend,
                        path: PathBuf::new(),
                        reason: format!(
                            "the C++ shim was not built (DOCS_RS build); set {env_override} to a built shim"
                        ),
                    });
                }
            },
        };
        if !path.is_file() {
            return Err(LoadError {
                backend,
                reason: format!(
                    "file not found (the build directory moved or was cleaned? rebuild, or set {env_override})"
                ),
                path,
            });
        }
        let flags = libc::RTLD_NOW | libc::RTLD_LOCAL | libc::RTLD_DEEPBIND;
        // SAFETY: loading runs the shim's static initialisers; the shims are our own C++ code and
        // the libraries they link, which have no unsound initialisers.
        let lib =
            unsafe { libloading::os::unix::Library::open(Some(&path), flags) }.map_err(|e| {
                LoadError {
                    backend,
                    path: path.clone(),
                    reason: e.to_string(),
                }
            })?;
        Ok(Shim { lib, backend, path })
    }

    /// Looks up a function by its C name.
    ///
    /// # Safety
    /// `T` must be the exact `extern "C"` function-pointer type of the symbol as declared in the
    /// shim's header.
    ///
    /// # Errors
    /// [`LoadError`] when the symbol is missing (a stale shim).
    pub unsafe fn function<T: Copy>(&self, name: &str) -> Result<T, LoadError> {
        let mut cname = name.as_bytes().to_vec();
        cname.push(0);
        // SAFETY: the caller guarantees `T` matches the symbol's type.
        unsafe { self.lib.get::<T>(&cname) }
            .map(|s| *s)
            .map_err(|e| LoadError {
                backend: self.backend,
                path: self.path.clone(),
                reason: format!("symbol {name}: {e}"),
            })
    }

    /// The path the shim was loaded from.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// Calls a fallible shim function with a fresh error buffer and maps its status.
///
/// `f` receives `(err, err_len)` to pass as the shim function's last two arguments.
///
/// # Errors
/// [`CallError`] when the status is non-zero, carrying the C++ message.
pub fn call(
    function: &'static str,
    f: impl FnOnce(*mut c_char, usize) -> c_int,
) -> Result<(), CallError> {
    // Only the first byte is initialised: the shim NUL-terminates whatever it writes
    // (ks::set_error), so a reader never goes past written bytes. Zeroing 1 KiB per call cost
    // ~30 ns, a noticeable share of a ~600 ns FK call.
    let mut buf = [MaybeUninit::<c_char>::uninit(); ERR_LEN];
    buf[0].write(0);
    let ptr = buf.as_mut_ptr().cast::<c_char>();
    let status = f(ptr, ERR_LEN);
    if status == 0 {
        return Ok(());
    }
    // SAFETY: buf[0] was initialised to NUL and the shim writes a NUL-terminated message within
    // ERR_LEN, so the scan stops inside initialised bytes.
    let message = unsafe { CStr::from_ptr(ptr) }
        .to_string_lossy()
        .into_owned();
    Err(if status == KS_INVALID_ARGUMENT {
        CallError::InvalidArgument { function, message }
    } else {
        CallError::Exception { function, message }
    })
}
