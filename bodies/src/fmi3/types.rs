//! The C types of FMI 3.0: `fmi_shared::fmi3` (the typedefs, `fmi3Status`, the callback
//! types; shared with the connector FMU), re-exported here with the mapping of this crate's
//! status levels (`crate::error::Level`) onto `fmi3Status`. Uses `fmi_shared` and
//! `crate::error`; the FMI 3.0 boundary and logger use it.

pub use fmi_shared::fmi3::*;

use crate::error::Level;

impl From<Level> for fmi3Status {
    fn from(l: Level) -> Self {
        match l {
            Level::Ok => fmi3Status::OK,
            Level::Error => fmi3Status::Error,
            Level::Fatal => fmi3Status::Fatal,
        }
    }
}
