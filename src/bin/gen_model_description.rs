//! Writes `modelDescription/<Variant>.xml` (FMI 2.0) and `modelDescription/fmi3/<Variant>.xml`
//! (FMI 3.0) for every variant from the variable tables.
//! Usage: `cargo run --bin gen_model_description -- [folder]` (default `modelDescription`).
//!
//! Uses the library's model descriptions and variable table; writes files, nothing uses it.

use connector_fmu::model_description::fmi2::model_description;
use connector_fmu::model_description::fmi3::model_description as model_description_fmi3;
use connector_fmu::variables::VARIANTS;
use std::path::PathBuf;

fn main() -> std::io::Result<()> {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "modelDescription".into()),
    );
    let dir3 = dir.join("fmi3");
    std::fs::create_dir_all(&dir3)?;
    for v in VARIANTS {
        let path = dir.join(format!("{}.xml", v.model_identifier));
        std::fs::write(&path, model_description(v.variant))?;
        println!("wrote {}", path.display());
        let path = dir3.join(format!("{}.xml", v.model_identifier));
        std::fs::write(&path, model_description_fmi3(v.variant))?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
