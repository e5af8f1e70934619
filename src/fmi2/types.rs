//! The C types of FMI 2.0: `fmi_shared::fmi2` (the typedefs, `fmi2Status`, `fmi2Type`,
//! `fmi2StatusKind`, the callback struct; shared with the Body FMU), re-exported here with the
//! mapping of this crate's status levels (`crate::error::Level`) onto `fmi2Status`. Uses
//! `fmi_shared` and `crate::error`; the FMI 2.0 boundary (and through it the FMI 3.0 one) uses it.

pub use fmi_shared::fmi2::*;

use crate::error::Level;

impl From<Level> for fmi2Status {
    fn from(l: Level) -> Self {
        match l {
            Level::Ok => fmi2Status::OK,
            Level::Warning => fmi2Status::Warning,
            Level::Discard => fmi2Status::Discard,
            Level::Error => fmi2Status::Error,
            Level::Fatal => fmi2Status::Fatal,
        }
    }
}
