//! Files written safely: atomic replacement of regular files only. A base-level module (no
//! rocklab types) so the study, the sweep's results store and the report can all use it.

use std::io::Write;
use std::path::{Path, PathBuf};

/// Why a file could not be written safely.
#[derive(Debug, thiserror::Error)]
pub enum FsError {
    #[error("{} exists and is not a regular file; refusing to replace it", .0.display())]
    NotRegular(PathBuf),
    #[error("{}: too many levels of symbolic links", .0.display())]
    LinkLoop(PathBuf),
    /// What was being done, and the cause.
    #[error("{context}")]
    Failed {
        context: String,
        #[source]
        source: Box<dyn std::error::Error + Send + Sync + 'static>,
    },
    #[error(transparent)]
    Io(#[from] std::io::Error),
}

/// `result`'s error as the cause of `context()`.
fn failed<T, E: std::error::Error + Send + Sync + 'static>(
    result: Result<T, E>,
    context: impl FnOnce() -> String,
) -> Result<T, FsError> {
    result.map_err(|e| FsError::Failed {
        context: context(),
        source: Box::new(e),
    })
}

/// Write `bytes` to `path` atomically: a temporary file in the same directory, synced, then
/// renamed over the target and the directory synced, so a reader (or a power loss) never sees
/// a half-written file.
///
/// Only regular files are replaced: a directory, device or socket at `path` is an error (a
/// rename would silently replace `/dev/full` or a results directory). A symlink is followed
/// to its target, as editors do, so the link survives. An existing file keeps its mode; a new
/// one is readable by all (0644), since results are for sharing.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), FsError> {
    let target = resolve_symlink(path)?;
    let mode = match std::fs::metadata(&target) {
        Ok(meta) if meta.is_file() => Some(meta.permissions()),
        Ok(_) => return Err(FsError::NotRegular(target)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => {
            return failed(Err(e), || format!("cannot inspect {}", target.display()));
        }
    };
    let dir = parent_dir(&target);
    let mut tmp = failed(tempfile::NamedTempFile::new_in(dir), || {
        format!("cannot create a file in {}", dir.display())
    })?;
    failed(
        tmp.write_all(bytes).and_then(|()| tmp.as_file().sync_all()),
        || format!("cannot write {}", target.display()),
    )?;
    match mode {
        Some(perms) => tmp.as_file().set_permissions(perms)?,
        None => readable_by_all(tmp.as_file())?,
    }
    failed(tmp.persist(&target), || {
        format!("cannot write {}", target.display())
    })?;
    sync_dir(dir);
    Ok(())
}

/// The directory holding `path` ("." for a bare file name).
pub fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// Make a rename in `dir` durable. Best effort: some file systems refuse to sync a directory,
/// and the file's own data is already synced.
pub fn sync_dir(dir: &Path) {
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
}

/// The file a symlink chain at `path` ends in (the path itself if it is no link).
fn resolve_symlink(path: &Path) -> Result<PathBuf, FsError> {
    let mut current = path.to_path_buf();
    // A bounded walk: a link loop is an error, not a hang.
    for _ in 0..40 {
        match std::fs::symlink_metadata(&current) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let link = failed(std::fs::read_link(&current), || {
                    format!("cannot read the link {}", current.display())
                })?;
                current = parent_dir(&current).join(link);
            }
            _ => return Ok(current),
        }
    }
    Err(FsError::LinkLoop(path.to_path_buf()))
}

/// Temporary files are created private (0600); results are for sharing (0644).
pub fn readable_by_all(file: &std::fs::File) -> Result<(), FsError> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        file.set_permissions(std::fs::Permissions::from_mode(0o644))?;
    }
    #[cfg(not(unix))]
    let _ = file;
    Ok(())
}

/// A name safe to use as one path component: `.`/`..` parts dropped, the rest joined by `_`,
/// control characters replaced, no leading dot, so a study named "../../x" is "x" and
/// "/etc/y" is "etc_y", both inside `out/`.
pub fn single_component(name: &str) -> String {
    let joined = name
        .split(['/', '\\'])
        .map(str::trim)
        .filter(|part| !part.is_empty() && *part != "." && *part != "..")
        .collect::<Vec<_>>()
        .join("_");
    let cleaned: String = joined
        .chars()
        .map(|c| {
            if c == '/' || c == '\\' || c.is_control() || c == ':' {
                '_'
            } else {
                c
            }
        })
        .collect();
    let cleaned = cleaned.trim().trim_start_matches('.').to_string();
    if cleaned.is_empty() {
        "study".into()
    } else {
        cleaned
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_stay_one_component() {
        for name in [
            "../../x",
            "/etc/passwd",
            "..",
            ".",
            "",
            "a/b",
            "..\\..\\c",
            " .hidden",
        ] {
            let c = single_component(name);
            assert_eq!(Path::new(&c).components().count(), 1, "{name:?} -> {c:?}");
            assert!(!c.starts_with('.') && !c.contains('/'), "{name:?} -> {c:?}");
        }
        assert_eq!(single_component("fig12_rigid"), "fig12_rigid");
        assert_eq!(single_component("../../x"), "x");
        assert_eq!(single_component("/etc/y"), "etc_y");
    }

    #[test]
    fn refuses_to_replace_a_directory() {
        let dir = tempfile::tempdir().unwrap();
        let sub = dir.path().join("results.json");
        std::fs::create_dir(&sub).unwrap();
        let err = write_atomic(&sub, b"x").unwrap_err().to_string();
        assert!(err.contains("not a regular file"), "{err}");
        assert!(sub.is_dir());
    }

    #[cfg(unix)]
    #[test]
    fn follows_symlinks_and_keeps_the_mode() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.ron");
        std::fs::write(&real, b"old").unwrap();
        std::fs::set_permissions(&real, std::fs::Permissions::from_mode(0o444)).unwrap();
        let link = dir.path().join("link.ron");
        std::os::unix::fs::symlink("real.ron", &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(
            std::fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(std::fs::read(&real).unwrap(), b"new");
        let mode = std::fs::metadata(&real).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o444);
        // A new file is shared.
        let fresh = dir.path().join("fresh.json");
        write_atomic(&fresh, b"{}").unwrap();
        let mode = std::fs::metadata(&fresh).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o644);
    }

    #[cfg(unix)]
    #[test]
    fn refuses_device_nodes() {
        let err = write_atomic(Path::new("/dev/null"), b"x")
            .unwrap_err()
            .to_string();
        assert!(err.contains("not a regular file"), "{err}");
    }
}
