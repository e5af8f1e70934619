//! The instance's `LogSink` over the importer's `fmi2CallbackLogger`.
//!
//! Uses the FMI 2.0 C types, the error levels and the instance's `LogSink`; the boundaries use it.

use super::types::{fmi2CallbackLogger, fmi2ComponentEnvironment, fmi2Status};
use crate::error::{Category, Level};
use crate::instance::LogSink;
use std::ffi::CString;

/// The importer's `componentEnvironment` (FMI 3.0: `instanceEnvironment`, the same pointer
/// type): never dereferenced here, only handed back to its own logger.
pub(crate) struct Env(pub(crate) fmi2ComponentEnvironment);

// SAFETY: the pointer is opaque to the FMU and only passed back to the importer's callback.
// FMI 2.0 and 3.0 let an instance be used from any thread as long as calls on one instance are
// not concurrent, and require the callback and its environment to stay valid until the
// instance is freed; moving the instance (and with it this pointer) to another thread is
// therefore within the importer's callback contract.
unsafe impl Send for Env {}

/// Writes log messages through the importer's logger callback.
pub(crate) struct CallbackLogger {
    callback: fmi2CallbackLogger,
    env: Env,
    instance_name: CString,
    categories: CategoryNames,
}

/// The log categories' names as C strings (both FMI versions' loggers pass them).
pub(crate) struct CategoryNames([CString; 4]);

impl CategoryNames {
    pub(crate) fn new() -> Self {
        CategoryNames(Category::ALL.map(|c| c_string(c.name())))
    }

    /// The name of `category`, NUL-terminated.
    pub(crate) fn get(&self, category: Category) -> &CString {
        let i = Category::ALL
            .iter()
            .position(|&c| c == category)
            .unwrap_or(0);
        &self.0[i]
    }
}

/// A C string of `s`, with interior NUL bytes made visible instead of truncating the text.
pub(crate) fn c_string(s: &str) -> CString {
    CString::new(s.replace('\0', "\\0")).unwrap_or_default()
}

impl CallbackLogger {
    /// A logger for the instance `instance_name`.
    pub(crate) fn new(
        callback: fmi2CallbackLogger,
        env: fmi2ComponentEnvironment,
        instance_name: &str,
    ) -> Self {
        CallbackLogger {
            callback,
            env: Env(env),
            instance_name: c_string(instance_name),
            categories: CategoryNames::new(),
        }
    }
}

impl LogSink for CallbackLogger {
    fn log(&self, level: Level, category: Category, message: &str) {
        // importers use `message` as a printf format: every '%' must reach them doubled
        let text = c_string(&message.replace('%', "%%"));
        // SAFETY: `callback` is the importer's logger, valid until fmi2FreeInstance (FMI 2.0
        // §2.1.5); it is called with exactly its five fixed arguments, all C strings are
        // NUL-terminated and outlive the call, and no printf directive remains in `text`.
        unsafe {
            (self.callback)(
                self.env.0,
                self.instance_name.as_ptr(),
                fmi2Status::from(level),
                self.categories.get(category).as_ptr(),
                text.as_ptr(),
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interior_nul_is_made_visible_not_truncating() {
        assert_eq!(c_string("a\0b").to_str().unwrap(), "a\\0b");
    }
}
