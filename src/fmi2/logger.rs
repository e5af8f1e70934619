//! The instance's `LogSink` over the importer's `fmi2CallbackLogger`.

use super::types::{fmi2CallbackLogger, fmi2ComponentEnvironment, fmi2Status};
use crate::error::{Category, Level};
use crate::instance::LogSink;
use std::ffi::CString;

/// The importer's `componentEnvironment`: never dereferenced here, only handed back to its
/// own logger.
struct Env(fmi2ComponentEnvironment);

// SAFETY: the pointer is opaque to the FMU and only passed back to the importer's callback.
// FMI 2.0 lets an instance be used from any thread as long as calls on one instance are not
// concurrent, and requires the callbacks and componentEnvironment to stay valid until
// fmi2FreeInstance; moving the instance (and with it this pointer) to another thread is
// therefore within the importer's callback contract.
unsafe impl Send for Env {}

/// Writes log messages through the importer's logger callback.
pub(crate) struct CallbackLogger {
    callback: fmi2CallbackLogger,
    env: Env,
    instance_name: CString,
    /// Category names as C strings, in `Category::ALL` order.
    categories: [CString; 4],
}

/// A C string of `s`, with interior NUL bytes made visible instead of truncating the text.
fn c_string(s: &str) -> CString {
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
            categories: Category::ALL.map(|c| c_string(c.name())),
        }
    }
}

impl LogSink for CallbackLogger {
    fn log(&self, level: Level, category: Category, message: &str) {
        // importers use `message` as a printf format: every '%' must reach them doubled
        let text = c_string(&message.replace('%', "%%"));
        let i = Category::ALL
            .iter()
            .position(|&c| c == category)
            .unwrap_or(0);
        // SAFETY: `callback` is the importer's logger, valid until fmi2FreeInstance (FMI 2.0
        // §2.1.5); it is called with exactly its five fixed arguments, all C strings are
        // NUL-terminated and outlive the call, and no printf directive remains in `text`.
        unsafe {
            (self.callback)(
                self.env.0,
                self.instance_name.as_ptr(),
                fmi2Status::from(level),
                self.categories[i].as_ptr(),
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
