//! Importing an FMU: unpack it once into a folder of its own, read its model description and
//! load its library for this platform (`binaries/linux64` for FMI 2.0, `binaries/x86_64-linux`
//! for FMI 3.0, and the other platforms' names), ready to make instances. Uses unzip.rs,
//! model_description.rs, ffi/ and error.rs.

use crate::error::{Error, Result};
use crate::ffi::fmi2::Fmi2Library;
use crate::ffi::fmi3::Fmi3Library;
use crate::ffi::Library;
use crate::model_description::{self, ModelDescription, Version};
use crate::unzip::{self, Unpacked};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A loaded library of either version.
pub enum Loaded {
    /// FMI 2.0.
    V2(Fmi2Library),
    /// FMI 3.0.
    V3(Fmi3Library),
}

/// An imported FMU.
pub struct Fmu {
    /// Its path as the user or the archive named it.
    pub source: String,
    /// Its model description.
    pub md: Arc<ModelDescription>,
    /// Its library.
    pub lib: Loaded,
    /// Where it is unpacked.
    pub unpacked: Unpacked,
}

fn platform_dirs(version: Version) -> &'static [&'static str] {
    match (version, std::env::consts::OS, std::env::consts::ARCH) {
        (Version::Fmi2, "linux", "x86_64") => &["linux64"],
        (Version::Fmi2, "linux", _) => &["linux32"],
        (Version::Fmi2, "macos", _) => &["darwin64"],
        (Version::Fmi2, "windows", "x86_64") => &["win64"],
        (Version::Fmi2, _, _) => &["win32"],
        (Version::Fmi3, "linux", "x86_64") => &["x86_64-linux"],
        (Version::Fmi3, "linux", "aarch64") => &["aarch64-linux"],
        (Version::Fmi3, "macos", "aarch64") => &["aarch64-darwin"],
        (Version::Fmi3, "macos", _) => &["x86_64-darwin"],
        (Version::Fmi3, _, _) => &["x86_64-windows"],
    }
}

fn library_path(dir: &Path, md: &ModelDescription) -> PathBuf {
    let ext = match std::env::consts::OS {
        "macos" => "dylib",
        "windows" => "dll",
        _ => "so",
    };
    let platform = platform_dirs(md.version)[0];
    dir.join("binaries")
        .join(platform)
        .join(format!("{}.{ext}", md.model_identifier))
}

impl Fmu {
    /// Imports the FMU file at `path` (`source`: how messages name it).
    pub fn load(path: &Path, source: &str) -> Result<Fmu> {
        let in_fmu = |e: Error| e.element(source);
        if !path.is_file() {
            return Err(Error::new("the FMU does not exist").element(source));
        }
        let unpacked = unzip::unpack(path).map_err(|e| Error {
            element: Some(source.to_string()),
            ..e
        })?;
        let md_path = unpacked.dir.join("modelDescription.xml");
        let text = std::fs::read_to_string(&md_path).map_err(|e| {
            Error::new(format!("cannot read it: {e}"))
                .element(format!("{source}: modelDescription.xml"))
        })?;
        let md = model_description::parse(&text)
            .map_err(|e| e.element(format!("{source}: modelDescription.xml")))?;
        let lib = Library::open(&library_path(&unpacked.dir, &md)).map_err(in_fmu)?;
        let lib = match md.version {
            Version::Fmi2 => Loaded::V2(Fmi2Library::new(lib).map_err(in_fmu)?),
            Version::Fmi3 => Loaded::V3(Fmi3Library::new(lib).map_err(in_fmu)?),
        };
        Ok(Fmu {
            source: source.to_string(),
            md: Arc::new(md),
            lib,
            unpacked,
        })
    }

    /// The resources folder as the version wants it: a file URI (2.0) or a path ending in a
    /// separator (3.0).
    pub fn resources(&self) -> String {
        let dir = self.unpacked.dir.join("resources");
        match self.md.version {
            Version::Fmi2 => format!("file://{}", dir.display()),
            Version::Fmi3 => format!("{}{}", dir.display(), std::path::MAIN_SEPARATOR),
        }
    }
}
