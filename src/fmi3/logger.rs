//! The instance's `LogSink` over the importer's `fmi3LogMessageCallback`.

use super::types::{fmi3InstanceEnvironment, fmi3LogMessageCallback, fmi3Status};
use crate::error::{Category, Level};
use crate::instance::LogSink;
use std::ffi::CString;

/// The importer's `instanceEnvironment`: never dereferenced here, only handed back to its own
/// logger.
struct Env(fmi3InstanceEnvironment);

// SAFETY: the pointer is opaque to the FMU and only passed back to the importer's callback.
// FMI 3.0 lets an instance be used from any thread as long as calls on one instance are not
// concurrent, and requires the callback and instanceEnvironment to stay valid until
// fmi3FreeInstance; moving the instance (and this pointer) to another thread is therefore
// within the importer's callback contract.
unsafe impl Send for Env {}

/// Writes log messages through the importer's callback; without one (FMI 3.0 allows a NULL
/// logMessage) nothing is written.
pub(crate) struct CallbackLogger {
    callback: Option<fmi3LogMessageCallback>,
    env: Env,
    /// Category names as C strings, in `Category::ALL` order.
    categories: [CString; 4],
}

/// A C string of `s`, with interior NUL bytes made visible instead of truncating the text.
fn c_string(s: &str) -> CString {
    CString::new(s.replace('\0', "\\0")).unwrap_or_default()
}

impl CallbackLogger {
    /// A logger through `callback` (None: silent).
    pub(crate) fn new(
        callback: Option<fmi3LogMessageCallback>,
        env: fmi3InstanceEnvironment,
    ) -> Self {
        CallbackLogger {
            callback,
            env: Env(env),
            categories: Category::ALL.map(|c| c_string(c.name())),
        }
    }
}

impl LogSink for CallbackLogger {
    fn log(&self, level: Level, category: Category, message: &str) {
        let Some(callback) = self.callback else {
            return;
        };
        // FMI 3.0 messages are plain text (not a printf format): '%' stays as it is
        let text = c_string(message);
        let i = Category::ALL
            .iter()
            .position(|&c| c == category)
            .unwrap_or(0);
        // SAFETY: `callback` is the importer's logger, valid until fmi3FreeInstance (FMI 3.0
        // §2.3.1); it is called with exactly its four arguments and both C strings are
        // NUL-terminated and outlive the call.
        unsafe {
            callback(
                self.env.0,
                fmi3Status::from(level),
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

    #[test]
    fn a_missing_callback_is_silent() {
        let l = CallbackLogger::new(None, std::ptr::null_mut());
        assert!(l.callback.is_none());
        l.log(Level::Error, Category::Error, "nowhere");
    }
}
