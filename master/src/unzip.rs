//! Unpacking an archive (an FMU or an SSP) into a folder of its own that is removed when the
//! run ends. An entry whose path would leave that folder (absolute, `..`, a drive or a
//! backslash path) is refused before anything is written. Uses zip and error.rs.

use crate::error::{Error, Result};
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// A folder the archive was unpacked into; removed on drop.
#[derive(Debug)]
pub struct Unpacked {
    /// The folder.
    pub dir: PathBuf,
}

impl Drop for Unpacked {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

static COUNTER: AtomicU64 = AtomicU64::new(0);

fn fresh_dir() -> Result<PathBuf> {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("fmi_master_{}_{nanos}_{n}", std::process::id()));
    std::fs::create_dir_all(&dir)
        .map_err(|e| Error::new(format!("cannot create the folder {}: {e}", dir.display())))?;
    Ok(dir)
}

/// The entry's path relative to the folder, or why it would leave it.
pub fn safe_path(name: &str) -> std::result::Result<PathBuf, &'static str> {
    if name.contains('\\') {
        return Err("it contains a backslash");
    }
    let mut out = PathBuf::new();
    for c in Path::new(name).components() {
        match c {
            Component::Normal(p) => out.push(p),
            Component::CurDir => {}
            Component::ParentDir => return Err("it goes up with '..'"),
            Component::RootDir | Component::Prefix(_) => return Err("it is absolute"),
        }
    }
    Ok(out)
}

/// Unpacks the zip file `archive` (named `what` in messages) into a fresh folder.
pub fn unpack(archive: &Path) -> Result<Unpacked> {
    let shown = archive.display().to_string();
    let file = std::fs::File::open(archive)
        .map_err(|e| Error::new(format!("cannot open it: {e}")).element(&shown))?;
    let mut zip = zip::ZipArchive::new(file)
        .map_err(|e| Error::new(format!("not a zip archive: {e}")).element(&shown))?;
    // check every name before writing anything
    for i in 0..zip.len() {
        let entry = zip
            .by_index_raw(i)
            .map_err(|e| Error::new(format!("unreadable entry {i}: {e}")).element(&shown))?;
        let name = entry_name_of(&entry).map_err(|e| e.element(&shown))?;
        if let Err(why) = safe_path(&name) {
            return Err(Error::new(format!(
                "the zip entry '{name}' would leave the extraction folder: {why}"
            ))
            .element(&shown));
        }
    }
    let unpacked = Unpacked { dir: fresh_dir()? };
    for i in 0..zip.len() {
        let mut entry = zip
            .by_index(i)
            .map_err(|e| Error::new(format!("unreadable entry {i}: {e}")).element(&shown))?;
        let name = entry_name_of(&entry).map_err(|e| e.element(&shown))?;
        let rel = safe_path(&name).map_err(|why| Error::new(why).element(&shown))?;
        let target = unpacked.dir.join(rel);
        let io = |e: std::io::Error| {
            Error::new(format!("cannot unpack '{}': {e}", entry_name(&target))).element(&shown)
        };
        if entry.is_dir() {
            std::fs::create_dir_all(&target).map_err(io)?;
            continue;
        }
        if let Some(parent) = target.parent() {
            std::fs::create_dir_all(parent).map_err(io)?;
        }
        let mut out = std::fs::File::create(&target).map_err(io)?;
        std::io::copy(&mut entry, &mut out).map_err(io)?;
    }
    Ok(unpacked)
}

fn entry_name_of<R: std::io::Read>(entry: &zip::read::ZipFile<'_, R>) -> Result<String> {
    entry
        .name()
        .map(|n| n.into_owned())
        .map_err(|e| Error::new(format!("an entry's name is unreadable: {e}")))
}

fn entry_name(p: &Path) -> String {
    p.display().to_string()
}

#[cfg(test)]
mod tests {
    use super::safe_path;

    #[test]
    fn paths_that_leave_are_refused() {
        assert!(safe_path("../evil.so").is_err());
        assert!(safe_path("resources/../../x").is_err());
        assert!(safe_path("/etc/passwd").is_err());
        assert!(safe_path("a\\..\\b").is_err());
        assert_eq!(
            safe_path("./resources/a.ssv").unwrap(),
            std::path::PathBuf::from("resources/a.ssv")
        );
    }
}
