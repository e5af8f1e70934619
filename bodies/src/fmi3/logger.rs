//! The instance's `LogSink` over the importer's `fmi3LogMessageCallback` (which may be NULL:
//! then nothing is written). Uses `super::types`, the FMI 2.0 logger's C strings and
//! `crate::instance::LogSink`.

use super::types::{fmi3InstanceEnvironment, fmi3LogMessageCallback, fmi3Status};
use crate::error::{Category, Level};
use crate::fmi2::logger::{c_string, category_names, Env};
use crate::instance::LogSink;
use std::ffi::CString;

/// Writes log messages through the importer's callback, if any.
pub(crate) struct CallbackLogger {
    callback: Option<fmi3LogMessageCallback>,
    env: Env,
    categories: [CString; 2],
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
            categories: category_names(),
        }
    }
}

impl LogSink for CallbackLogger {
    fn log(&self, level: Level, category: Category, message: &str) {
        let Some(callback) = self.callback else {
            return;
        };
        // FMI 3.0 messages are plain text, not a printf format: '%' stays as it is
        let text = c_string(message);
        let cat = &self.categories[usize::from(category == Category::All)];
        // SAFETY: `callback` is the importer's logger, valid until fmi3FreeInstance (FMI 3.0
        // §2.3.1); it is called with exactly its four arguments and both C strings are
        // NUL-terminated and outlive the call.
        unsafe {
            callback(
                self.env.0,
                fmi3Status::from(level),
                cat.as_ptr(),
                text.as_ptr(),
            )
        }
    }
}
