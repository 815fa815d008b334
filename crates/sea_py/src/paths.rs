//! Path arguments checked before use.

use crate::errors::argument_error;
use pyo3::prelude::*;
use std::path::PathBuf;

/// `package_dirs` (none: empty), each an existing folder; else a `ValueError` naming
/// `package_dirs` and the entry (a missing folder or a file would be searched in vain).
pub fn package_dirs(dirs: Option<Vec<PathBuf>>) -> PyResult<Vec<PathBuf>> {
    let dirs = dirs.unwrap_or_default();
    for dir in &dirs {
        let problem = match std::fs::metadata(dir) {
            Ok(meta) if meta.is_dir() => continue,
            Ok(_) => "a file".to_string(),
            Err(e) => e.to_string(),
        };
        let actual = format!("'{}' ({problem})", dir.display());
        return Err(argument_error("package_dirs", "existing folders", actual));
    }
    Ok(dirs)
}
