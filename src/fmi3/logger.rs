//! The instance's `LogSink` over the importer's `fmi3LogMessageCallback`.
//!
//! Uses the FMI 3.0 C types, fmi2's message formatting, the error levels and the instance's
//! `LogSink`; the FMI 3.0 boundary uses it.

use super::types::{fmi3InstanceEnvironment, fmi3LogMessageCallback, fmi3Status};
use crate::error::{Category, Level};
use crate::fmi2::logger::{c_string, CategoryNames, Env};
use crate::instance::LogSink;

/// Writes log messages through the importer's callback; without one (FMI 3.0 allows a NULL
/// logMessage) nothing is written.
pub(crate) struct CallbackLogger {
    callback: Option<fmi3LogMessageCallback>,
    env: Env,
    categories: CategoryNames,
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
            categories: CategoryNames::new(),
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
        // SAFETY: `callback` is the importer's logger, valid until fmi3FreeInstance (FMI 3.0
        // §2.3.1); it is called with exactly its four arguments and both C strings are
        // NUL-terminated and outlive the call.
        unsafe {
            callback(
                self.env.0,
                fmi3Status::from(level),
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

    #[test]
    fn a_missing_callback_is_silent() {
        let l = CallbackLogger::new(None, std::ptr::null_mut());
        assert!(l.callback.is_none());
        l.log(Level::Error, Category::Error, "nowhere");
    }
}
