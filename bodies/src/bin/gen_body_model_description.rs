//! Writes bodies/modelDescription/Body.xml (FMI 2.0) and bodies/modelDescription/fmi3/Body.xml
//! (FMI 3.0) from the variable table. Uses `body_fmu::model_description` only.
//! Usage: `cargo run --bin gen_body_model_description -- [folder]` (default: the crate's
//! `modelDescription`).

use body_fmu::model_description::{fmi2, fmi3};
use body_fmu::variables::MODEL_IDENTIFIER;
use std::path::PathBuf;

fn main() -> std::io::Result<()> {
    let dir = std::env::args().nth(1).map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("modelDescription"),
        PathBuf::from,
    );
    let dir3 = dir.join("fmi3");
    std::fs::create_dir_all(&dir3)?;
    for (path, xml) in [
        (
            dir.join(format!("{MODEL_IDENTIFIER}.xml")),
            fmi2::model_description(),
        ),
        (
            dir3.join(format!("{MODEL_IDENTIFIER}.xml")),
            fmi3::model_description(),
        ),
    ] {
        std::fs::write(&path, xml)?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
