//! Errors of the instance layer, their status levels and the log categories. Uses nothing else
//! of the crate; the FMI boundaries map `Level` to fmi2Status / fmi3Status.

use std::fmt;

/// Status levels an operation can end with (fmi2Status / fmi3Status without FMI types).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Level {
    /// OK
    Ok,
    /// Error: the call was refused and changed nothing.
    Error,
    /// Fatal: a caught panic; only FreeInstance is left.
    Fatal,
}

/// Log categories declared in the model description.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Category {
    /// logStatusError: every refused call, with its cause (always logged).
    Error,
    /// logAll: every FMI call (when logging is on).
    All,
}

impl Category {
    /// All categories, in model-description order.
    pub const ALL: [Category; 2] = [Category::Error, Category::All];

    /// The category's name in the model description.
    pub fn name(self) -> &'static str {
        match self {
            Category::Error => "logStatusError",
            Category::All => "logAll",
        }
    }

    /// Its description in the model description of FMI version `fmi` ("fmi2" or "fmi3").
    pub fn description(self, fmi: &str) -> String {
        match self {
            Category::Error => {
                format!("{fmi}Error and {fmi}Fatal statuses and their causes (always logged)")
            }
            Category::All => "every FMI call".to_string(),
        }
    }

    /// Looks a category up by name.
    pub fn from_name(name: &str) -> Option<Category> {
        Category::ALL.into_iter().find(|c| c.name() == name)
    }
}

/// A refused call with the one message that explains it (names the variable or the cause).
#[derive(Clone, Debug, PartialEq)]
pub struct FmuError {
    /// Status level.
    pub level: Level,
    /// The message for the importer's log (the boundary puts the FMI function's name first).
    pub message: String,
}

impl FmuError {
    /// An Error with its message.
    pub fn error(message: impl Into<String>) -> Self {
        FmuError {
            level: Level::Error,
            message: message.into(),
        }
    }
}

impl fmt::Display for FmuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}: {}", self.level, self.message)
    }
}

/// Result type of the instance layer.
pub type FmuResult<T> = Result<T, FmuError>;
