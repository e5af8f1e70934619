//! The FMI call boundary, the only `unsafe` code of the master: loading an FMU's shared
//! library with libloading, resolving its functions, and calling them. `fmi2` and `fmi3` each
//! offer an instance type whose methods are safe: they take and give Rust slices and strings
//! and return the FMU's status; everything the FMU could do wrong (a missing function, a status
//! outside the enum, a NULL instance) is turned into a `Status` or an `Error` here. The logger
//! callbacks catch every panic, so none crosses into C.
//! Uses libloading, fmi_shared's C types and error.rs.

pub mod fmi2;
pub mod fmi3;

use crate::error::{Error, Result};
use std::path::Path;
use std::sync::Mutex;

/// An FMI status, either version (the numeric values of fmi2Status and fmi3Status agree).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Status {
    /// OK.
    Ok,
    /// Warning.
    Warning,
    /// Discard.
    Discard,
    /// Error.
    Error,
    /// Fatal.
    Fatal,
    /// Pending (FMI 2.0 asynchronous steps) or a value outside the enum.
    Pending,
}

impl Status {
    fn from_c(v: i32) -> Status {
        match v {
            0 => Status::Ok,
            1 => Status::Warning,
            2 => Status::Discard,
            3 => Status::Error,
            4 => Status::Fatal,
            _ => Status::Pending,
        }
    }
    /// OK or Warning.
    pub fn ok(self) -> bool {
        matches!(self, Status::Ok | Status::Warning)
    }
    /// The name, with its version's prefix (`fmi2Error`).
    pub fn name(self, prefix: &str) -> String {
        let s = match self {
            Status::Ok => "OK",
            Status::Warning => "Warning",
            Status::Discard => "Discard",
            Status::Error => "Error",
            Status::Fatal => "Fatal",
            Status::Pending => "Pending",
        };
        format!("{prefix}{s}")
    }
}

/// What an instance logged, kept for the message of a failing call (the last few lines).
#[derive(Debug, Default)]
pub struct LogSink {
    lines: Mutex<Vec<String>>,
    /// Echo every line to stderr (`--log`).
    pub echo: bool,
}

const KEPT_LINES: usize = 8;

impl LogSink {
    /// A sink that echoes to stderr when `echo` is set.
    pub fn new(echo: bool) -> LogSink {
        LogSink {
            lines: Mutex::new(Vec::new()),
            echo,
        }
    }
    fn push(&self, line: String) {
        if self.echo {
            eprintln!("{line}");
        }
        if let Ok(mut l) = self.lines.lock() {
            if l.len() == KEPT_LINES {
                l.remove(0);
            }
            l.push(line);
        }
    }
    /// The lines logged since the last call, joined; empties the sink.
    pub fn take(&self) -> String {
        self.lines
            .lock()
            .map(|mut l| std::mem::take(&mut *l).join("; "))
            .unwrap_or_default()
    }
}

/// A loaded shared library.
pub struct Library(libloading::Library);

impl Library {
    /// Loads the library at `path`.
    pub fn open(path: &Path) -> Result<Library> {
        if !path.is_file() {
            return Err(Error::new(format!(
                "the FMU has no binary for this platform: {} is missing",
                path.display()
            )));
        }
        // SAFETY: loading a library runs its initialisers; an FMU's binary is trusted as
        // the code the user asked to run (as in every FMI importer).
        let lib = unsafe { libloading::Library::new(path) }
            .map_err(|e| Error::new(format!("cannot load {}: {e}", path.display())))?;
        Ok(Library(lib))
    }

    /// The function `name` of type `T` (a C function pointer type), if exported.
    fn symbol<T: Copy>(&self, name: &str) -> Option<T> {
        // SAFETY: T is one of the FMI function pointer types of fmi2.rs / fmi3.rs, declared
        // with the standard's C signature for `name`.
        unsafe { self.0.get::<T>(name.as_bytes()).ok().map(|s| *s) }
    }

    /// The function `name`, or an error naming it.
    fn require<T: Copy>(&self, name: &str) -> Result<T> {
        self.symbol(name).ok_or_else(|| {
            Error::new(format!("the FMU's library does not export {name}")).function(name)
        })
    }
}

/// Converts a C string to Rust (lossy), or "" for NULL.
///
/// # Safety
/// `p` is NULL or points to a NUL-terminated string.
unsafe fn c_str(p: *const std::ffi::c_char) -> String {
    if p.is_null() {
        String::new()
    } else {
        // SAFETY: the caller passes a NUL-terminated string.
        unsafe { std::ffi::CStr::from_ptr(p) }
            .to_string_lossy()
            .into_owned()
    }
}

/// Hands a logged line to the `LogSink` behind `env` (an instance's environment pointer); the
/// loggers of both versions call it, and no panic leaves it.
///
/// # Safety
/// `env` is NULL or the `LogSink` pointer given at instantiation, alive with the instance.
unsafe fn log_to(env: *mut std::ffi::c_void, line: impl FnOnce() -> String) {
    let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        if env.is_null() {
            return;
        }
        // SAFETY: see the function's contract.
        let sink = unsafe { &*(env as *const LogSink) };
        sink.push(line());
    }));
}
