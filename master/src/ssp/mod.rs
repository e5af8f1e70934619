//! SSP 1.0 archives: the archive is unpacked (safely, unzip.rs), its SystemStructure.ssd and
//! parameter sets read (ssd.rs, ssv.rs) into a flat `Description`; nothing else reads the
//! archive's XML. Uses unzip.rs and error.rs.

pub mod ssd;
pub mod ssv;

use crate::error::{Error, Result};
use crate::unzip::{self, Unpacked};
use std::path::Path;

/// An unpacked archive and its system.
pub struct Archive {
    /// The system, flat.
    pub description: ssd::Description,
    /// Where it is unpacked (FMU sources are relative to it).
    pub unpacked: Unpacked,
}

/// Opens the `.ssp` archive at `path`.
pub fn open(path: &Path) -> Result<Archive> {
    let unpacked = unzip::unpack(path)?;
    let dir = unpacked.dir.clone();
    let ssd_path = dir.join(ssd::SSD);
    let text = std::fs::read_to_string(&ssd_path).map_err(|e| {
        Error::new(format!("the archive has no readable {}: {e}", ssd::SSD))
            .element(path.display().to_string())
    })?;
    let files = |rel: &str| -> Option<std::io::Result<String>> {
        let rel = unzip::safe_path(rel).ok()?;
        let p = dir.join(rel);
        p.is_file().then(|| std::fs::read_to_string(p))
    };
    let description = ssd::parse(&text, &files)?;
    Ok(Archive {
        description,
        unpacked,
    })
}
