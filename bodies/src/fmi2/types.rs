//! The C types of FMI 2.0: `fmi_shared::fmi2` (the typedefs, `fmi2Status`, the `FMI2_*` values
//! of the enums C sends, the callback struct; shared with the connector FMU), re-exported here
//! with the mapping of this crate's status levels (`crate::error::Level`) onto `fmi2Status`.
//! Uses `fmi_shared` and `crate::error`; the FMI 2.0 boundary and logger use it.

pub use fmi_shared::fmi2::*;

use crate::error::Level;

impl From<Level> for fmi2Status {
    fn from(l: Level) -> Self {
        match l {
            Level::Ok => fmi2Status::OK,
            Level::Error => fmi2Status::Error,
            Level::Fatal => fmi2Status::Fatal,
        }
    }
}
