//! Errors of the instance layer and their one mapping to an FMI status level.
//!
//! Uses std only; every layer above physics uses it.

use std::fmt;

/// Status levels an operation can end with (mirrors fmi2Status without FMI types).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Level {
    /// fmi2OK
    Ok,
    /// fmi2Warning
    Warning,
    /// fmi2Discard
    Discard,
    /// fmi2Error
    Error,
    /// fmi2Fatal
    Fatal,
}

/// Log categories declared in the model description.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Category {
    /// logStatusWarning
    Warning,
    /// logStatusError
    Error,
    /// logEvents: stick/slip and stop transitions
    Events,
    /// logAll: every call
    All,
}

impl Category {
    /// All categories, in model-description order.
    pub const ALL: [Category; 4] = [
        Category::Warning,
        Category::Error,
        Category::Events,
        Category::All,
    ];

    /// The category's name in the model description.
    pub fn name(self) -> &'static str {
        match self {
            Category::Warning => "logStatusWarning",
            Category::Error => "logStatusError",
            Category::Events => "logEvents",
            Category::All => "logAll",
        }
    }

    /// Description in the model description.
    pub fn description(self) -> &'static str {
        match self {
            Category::Warning => "fmi2Warning statuses and their causes",
            Category::Error => "fmi2Error, fmi2Discard and fmi2Fatal statuses and their causes",
            Category::Events => "stick/slip and stop transitions",
            Category::All => "every FMI call",
        }
    }

    /// Looks a category up by name.
    pub fn from_name(name: &str) -> Option<Category> {
        Category::ALL.into_iter().find(|c| c.name() == name)
    }
}

/// A non-OK outcome with the one message that explains it (names the variable or the cause).
#[derive(Clone, Debug, PartialEq)]
pub struct FmuError {
    /// Status level.
    pub level: Level,
    /// The message for the importer's log.
    pub message: String,
}

impl FmuError {
    /// An fmi2Error with a message.
    pub fn error(message: impl Into<String>) -> Self {
        FmuError {
            level: Level::Error,
            message: message.into(),
        }
    }

    /// An fmi2Discard with a message.
    pub fn discard(message: impl Into<String>) -> Self {
        FmuError {
            level: Level::Discard,
            message: message.into(),
        }
    }

    /// An fmi2Warning with a message (the operation was carried out).
    pub fn warning(message: impl Into<String>) -> Self {
        FmuError {
            level: Level::Warning,
            message: message.into(),
        }
    }

    /// The category a message of this level is logged under.
    pub fn category(&self) -> Category {
        if self.level == Level::Warning {
            Category::Warning
        } else {
            Category::Error
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
