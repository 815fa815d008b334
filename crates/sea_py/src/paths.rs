//! Path arguments checked before use.

use crate::errors::argument_error;
use pyo3::prelude::*;
use std::path::PathBuf;

/// `package_dirs` (none: empty), each an existing folder; else a `ValueError` naming
/// `package_dirs` and the entry (a missing folder or a file would be searched in vain).
pub fn package_dirs(dirs: Option<Vec<PathBuf>>) -> PyResult<Vec<PathBuf>> {
    let dirs = dirs.unwrap_or_default();
    match dirs
        .iter()
        .find_map(|dir| sea_dyn::files::not_a_folder(dir).map(|problem| (dir, problem)))
    {
        Some((dir, problem)) => {
            let actual = format!("'{}' ({problem})", dir.display());
            Err(argument_error("package_dirs", "existing folders", actual))
        }
        None => Ok(dirs),
    }
}
