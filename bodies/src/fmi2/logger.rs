//! The instance's `LogSink` over the importer's `fmi2CallbackLogger`, and the C strings both
//! FMI versions' loggers pass. Uses `super::types`, `crate::error` and `crate::instance::LogSink`.

use super::types::{fmi2CallbackLogger, fmi2ComponentEnvironment, fmi2Status};
use crate::error::{Category, Level};
use crate::instance::LogSink;
use std::ffi::CString;

/// The importer's environment pointer (FMI 3.0: `instanceEnvironment`): never dereferenced
/// here, only handed back to its own logger.
pub(crate) struct Env(pub(crate) fmi2ComponentEnvironment);

// SAFETY: the pointer is opaque to the FMU and only passed back to the importer's callback.
// FMI 2.0 and 3.0 let an instance be used from any thread as long as calls on one instance are
// not concurrent, and require the callback and its environment to stay valid until the
// instance is freed; moving the instance (and this pointer) to another thread is therefore
// within the importer's callback contract.
unsafe impl Send for Env {}

/// A C string of `s`, interior NUL bytes made visible instead of truncating the text.
pub(crate) fn c_string(s: &str) -> CString {
    CString::new(s.replace('\0', "\\0")).unwrap_or_default()
}

/// The log categories' names as C strings.
pub(crate) fn category_names() -> [CString; 2] {
    Category::ALL.map(|c| c_string(c.name()))
}

/// Writes log messages through the importer's logger callback.
pub(crate) struct CallbackLogger {
    callback: fmi2CallbackLogger,
    env: Env,
    instance_name: CString,
    categories: [CString; 2],
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
            categories: category_names(),
        }
    }
}

impl LogSink for CallbackLogger {
    fn log(&self, level: Level, category: Category, message: &str) {
        // importers use `message` as a printf format: every '%' must reach them doubled
        let text = c_string(&message.replace('%', "%%"));
        let cat = &self.categories[usize::from(category == Category::All)];
        // SAFETY: `callback` is the importer's logger, valid until fmi2FreeInstance (FMI 2.0
        // §2.1.5); it is called with exactly its five fixed arguments, all C strings are
        // NUL-terminated and outlive the call, and no printf directive remains in `text`.
        unsafe {
            (self.callback)(
                self.env.0,
                self.instance_name.as_ptr(),
                fmi2Status::from(level),
                cat.as_ptr(),
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
        assert_eq!(category_names()[1].to_str().unwrap(), "logAll");
    }
}
