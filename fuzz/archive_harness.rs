//! The archive reader of the native master (master/: SSD, SSV, zip) under arbitrary bytes: the
//! first byte picks what the rest is — an SSD's text (parsed with a parameter-set reader that
//! serves one fixed `.ssv`), an SSV's text, or a zip file (unpacked, then opened as an SSP).
//! Whatever the bytes, the reader returns a result and never panics; an unpacked archive holds
//! only files inside its folder. Used by fuzz/fuzz_targets/ssp_archive.rs (libFuzzer) and
//! master/tests/fuzz_smoke.rs (a short deterministic replay in `cargo test`).

use fmi_master::ssp::{self, ssd, ssv};
use fmi_master::unzip;
use std::path::{Path, PathBuf};

const SSV: &str = r#"<?xml version="1.0"?><ssv:ParameterSet xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="p"><ssv:Parameters><ssv:Parameter name="k"><ssv:Real value="1"/></ssv:Parameter></ssv:Parameters></ssv:ParameterSet>"#;

fn scratch() -> PathBuf {
    std::env::temp_dir().join(format!("fmi_master_fuzz_{}.zip", std::process::id()))
}

fn inside(root: &Path, dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        let meta = std::fs::symlink_metadata(&p).expect("an unpacked file is readable");
        assert!(
            !meta.file_type().is_symlink(),
            "an unpacked entry is a symlink: {}",
            p.display()
        );
        assert!(
            p.starts_with(root),
            "{} is outside {}",
            p.display(),
            root.display()
        );
        if meta.is_dir() {
            inside(root, &p);
        }
    }
}

/// One input.
pub fn run(data: &[u8]) {
    let Some((&mode, body)) = data.split_first() else {
        return;
    };
    match mode % 3 {
        0 => {
            let text = String::from_utf8_lossy(body);
            let files = |name: &str| (name.ends_with(".ssv")).then(|| Ok(SSV.to_string()));
            let _ = ssd::parse(&text, &files);
        }
        1 => {
            let _ = ssv::parse(&String::from_utf8_lossy(body), "fuzz.ssv");
        }
        _ => {
            let path = scratch();
            std::fs::write(&path, body).expect("the scratch file is writable");
            if let Ok(unpacked) = unzip::unpack(&path) {
                inside(&unpacked.dir, &unpacked.dir);
            }
            let _ = ssp::open(&path);
            let _ = std::fs::remove_file(&path);
        }
    }
}
