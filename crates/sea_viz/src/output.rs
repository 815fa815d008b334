//! Output files that never destroy an earlier good file: checked before a run, written beside
//! their target and renamed over it only when finished.
//!
//! [`OutputFile::create`] checks that the target's folder exists, then creates (or reuses) the
//! hidden file `.NAME.partial` beside the target `NAME`, takes an advisory exclusive lock on it
//! (a second writer of the same target is refused with an error instead of corrupting the file)
//! and truncates it. The caller writes into [`OutputFile::path`]; [`OutputFile::commit`] renames
//! the partial file over the target, so the target is replaced in one step or not at all. An
//! output dropped without `commit` removes its partial file (an error stopped the run); a
//! process killed outright (SIGKILL, power loss) leaves the partial file behind with whatever
//! it had flushed, and the target untouched. The next run to the same target reuses the partial
//! file.
//!
//! Targets that are not regular files (`/dev/null`, `/dev/full`, a FIFO) cannot be replaced by a
//! rename: they are written directly, without a lock.
//!
//! [`check_distinct`] refuses an output that is also an input (the scenario, the URDF) or
//! another output, before anything is written.

use crate::error::{Error, Result};
use fs4::fs_std::FileExt;
use std::ffi::OsString;
use std::fs::{File, OpenOptions};
use std::io::{ErrorKind, Write};
use std::path::{Path, PathBuf};

/// An output being written: the partial file beside the target (locked), or the target itself
/// when it is a device or a pipe.
#[derive(Debug)]
pub struct OutputFile {
    target: PathBuf,
    /// Where the bytes go.
    writing: PathBuf,
    /// The open, locked handle of `writing` (the lock lives as long as it).
    file: File,
    /// Whether `commit` renames `writing` over `target` (false for devices and pipes).
    replace: bool,
    committed: bool,
}

/// An I/O error naming `path`.
fn io_error(path: &Path, kind: ErrorKind, message: impl Into<String>) -> Error {
    Error::Io {
        path: path.display().to_string(),
        source: std::io::Error::new(kind, message.into()),
    }
}

/// Wraps an OS error with the path it concerns.
fn with_path(path: &Path) -> impl FnOnce(std::io::Error) -> Error + '_ {
    move |source| Error::Io {
        path: path.display().to_string(),
        source,
    }
}

/// Wraps an OS error on `partial`, the file written for `target`, so that it names the path the
/// user gave: `target (written as partial)`, the format of [`OutputFile::explain`].
fn on_partial<'a>(
    target: &'a Path,
    partial: &'a Path,
) -> impl FnOnce(std::io::Error) -> Error + 'a {
    move |source| Error::Io {
        path: format!("{} (written as {})", target.display(), partial.display()),
        source,
    }
}

/// The folder holding `path` (`.` for a bare file name).
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    }
}

/// `folder/.NAME.partial` for `folder/NAME`.
pub fn partial_path(target: &Path) -> PathBuf {
    let mut name = OsString::from(".");
    name.push(target.file_name().unwrap_or_default());
    name.push(".partial");
    folder_of(target).join(name)
}

/// The target must name a file in an existing folder, and must not be a folder itself.
fn check_target(target: &Path) -> Result<()> {
    if target.file_name().is_none() {
        return Err(io_error(target, ErrorKind::InvalidInput, "not a file name"));
    }
    let folder = folder_of(target);
    if !folder.is_dir() {
        return Err(io_error(
            target,
            ErrorKind::NotFound,
            format!("the folder '{}' does not exist", folder.display()),
        ));
    }
    if target.is_dir() {
        return Err(io_error(target, ErrorKind::IsADirectory, "is a folder"));
    }
    Ok(())
}

/// The error of an output at `path` that must be a regular file (`why`) and is not.
pub(crate) fn not_a_regular_file(path: &Path, why: &str) -> Error {
    io_error(
        path,
        ErrorKind::InvalidInput,
        format!("must be a regular file ({why}), not a device or a pipe"),
    )
}

/// Whether `path` exists and is something a rename must not replace (device, FIFO, socket).
fn is_special(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// Opens the device, FIFO or socket `target` for writing. A FIFO is opened without waiting for
/// a reader (which could never come, and a blocked `open` ignores the stop signals): with none
/// it is an error naming the target, with one it is written as usual (blocking writes).
#[cfg(unix)]
fn open_special(target: &Path) -> Result<File> {
    use rustix::fs::{fcntl_getfl, fcntl_setfl, OFlags};
    use std::os::unix::fs::{FileTypeExt, OpenOptionsExt};
    let fifo = std::fs::metadata(target).is_ok_and(|m| m.file_type().is_fifo());
    let mut options = OpenOptions::new();
    options.write(true);
    if fifo {
        options.custom_flags(OFlags::NONBLOCK.bits() as i32);
    }
    let file = options.open(target).map_err(|error| {
        // ENXIO: a FIFO with no reader, or a socket.
        if error.raw_os_error() == Some(rustix::io::Errno::NXIO.raw_os_error()) {
            io_error(
                target,
                ErrorKind::NotConnected,
                "a pipe or socket with no reader: start its reader first, or write a file",
            )
        } else {
            with_path(target)(error)
        }
    })?;
    if fifo {
        let blocking = fcntl_getfl(&file)
            .map(|flags| flags - OFlags::NONBLOCK)
            .and_then(|flags| fcntl_setfl(&file, flags));
        blocking.map_err(|errno| with_path(target)(errno.into()))?;
    }
    Ok(file)
}

#[cfg(not(unix))]
fn open_special(target: &Path) -> Result<File> {
    OpenOptions::new()
        .write(true)
        .open(target)
        .map_err(with_path(target))
}

/// Whether `file` is still the file at `path` (another writer may have renamed it between our
/// open and our lock).
#[cfg(unix)]
fn still_at(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn still_at(_file: &File, path: &Path) -> bool {
    path.exists()
}

/// Opens `partial` without truncating it, locks it exclusively, then truncates it.
fn open_locked(target: &Path, partial: &Path) -> Result<File> {
    // A few tries: a finishing writer may rename the partial file away between open and lock.
    for _ in 0..8 {
        let file = OpenOptions::new()
            .write(true)
            .create(true)
            .truncate(false)
            .open(partial)
            .map_err(on_partial(target, partial))?;
        let locked = FileExt::try_lock_exclusive(&file).map_err(on_partial(target, partial))?;
        if !locked {
            return Err(io_error(
                target,
                ErrorKind::WouldBlock,
                format!(
                    "another process is writing this file (it holds the lock on '{}'); \
                     wait for it to finish or choose another path",
                    partial.display()
                ),
            ));
        }
        if still_at(&file, partial) {
            file.set_len(0).map_err(on_partial(target, partial))?;
            return Ok(file);
        }
    }
    Err(io_error(
        target,
        ErrorKind::WouldBlock,
        "another process keeps replacing this file",
    ))
}

impl OutputFile {
    /// Checks `target` and opens its partial file (locked, empty); see the module
    /// documentation.
    ///
    /// Errors: [`Error::Io`] naming the target when its folder is missing or not writable, when
    /// it is a folder, or when another process is writing it.
    pub fn create(target: &Path) -> Result<Self> {
        check_target(target)?;
        if is_special(target) {
            let file = open_special(target)?;
            return Ok(Self {
                target: target.to_path_buf(),
                writing: target.to_path_buf(),
                file,
                replace: false,
                committed: false,
            });
        }
        let partial = partial_path(target);
        let file = open_locked(target, &partial)?;
        Ok(Self {
            target: target.to_path_buf(),
            writing: partial,
            file,
            replace: true,
            committed: false,
        })
    }

    /// [`OutputFile::create`] for an output that must be a regular file (an MCAP log, whose
    /// writer seeks): a device, a pipe or a socket at `target` is refused before it is opened
    /// (opening a FIFO without a reader would block), the error saying `why` it must be a file.
    ///
    /// Errors: as [`OutputFile::create`], and [`Error::Io`] (`InvalidInput`) naming the target
    /// when it is not a regular file.
    pub fn create_regular(target: &Path, why: &str) -> Result<Self> {
        check_target(target)?;
        if is_special(target) {
            return Err(not_a_regular_file(target, why));
        }
        Self::create(target)
    }

    /// The final path.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// The path to write now (the partial file, or the target for devices and pipes).
    pub fn path(&self) -> &Path {
        &self.writing
    }

    /// A handle of the file to write (shares the lock; writes go to [`Self::path`]).
    ///
    /// Errors: [`Error::Io`] when the handle cannot be duplicated.
    pub fn handle(&self) -> Result<File> {
        self.file.try_clone().map_err(with_path(&self.target))
    }

    /// `error` with an I/O failure on the partial file reported on the target, so the user
    /// reads the name they gave (`run.mcap (written as .run.mcap.partial): No space left on
    /// device`). Other errors pass through.
    pub fn explain(&self, error: Error) -> Error {
        match error {
            Error::Io { path, source } if self.replace && Path::new(&path) == self.writing => {
                Error::Io {
                    path: format!(
                        "{} (written as {})",
                        self.target.display(),
                        self.writing.display()
                    ),
                    source,
                }
            }
            other => other,
        }
    }

    /// Writes all of `bytes` and flushes them to the disk.
    ///
    /// Errors: [`Error::Io`] naming the target with the OS cause (e.g. "No space left on
    /// device").
    pub fn write_all(&mut self, bytes: &[u8]) -> Result<()> {
        self.file
            .write_all(bytes)
            .and_then(|()| self.file.flush())
            .map_err(with_path(&self.target))?;
        if self.replace {
            self.file.sync_all().map_err(with_path(&self.target))?;
        }
        Ok(())
    }

    /// Replaces the target by the finished file (one rename, then the folder is synced so the
    /// rename survives a crash).
    ///
    /// Errors: [`Error::Io`] naming the target when the rename fails.
    pub fn commit(mut self) -> Result<()> {
        if self.replace {
            self.file.sync_all().map_err(with_path(&self.target))?;
            std::fs::rename(&self.writing, &self.target).map_err(with_path(&self.target))?;
            // Best effort: not every file system can sync a folder.
            if let Ok(folder) = File::open(folder_of(&self.target)) {
                let _ = folder.sync_all();
            }
        }
        self.committed = true;
        Ok(())
    }
}

impl Drop for OutputFile {
    /// An output dropped unfinished removes its partial file (the target stays as it was).
    fn drop(&mut self) {
        if self.replace && !self.committed {
            let _ = std::fs::remove_file(&self.writing);
        }
    }
}

/// `path` made absolute with symbolic links resolved as far as it exists (its folder at least).
fn resolved(path: &Path) -> PathBuf {
    if let Ok(full) = path.canonicalize() {
        return full;
    }
    match (folder_of(path).canonicalize(), path.file_name()) {
        (Ok(folder), Some(name)) => folder.join(name),
        _ => path.to_path_buf(),
    }
}

/// Whether `a` and `b` are the same file (same resolved path, or the same inode when both
/// exist, which also catches hard links).
fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return ma.dev() == mb.dev() && ma.ino() == mb.ino();
        }
    }
    resolved(a) == resolved(b)
}

/// Refuses an output that is an input or another output. `inputs` and `outputs` are pairs of
/// (role, path), e.g. `("the scenario", path)` or `("--mcap", path)`; the message names both
/// roles and the path.
///
/// Errors: [`Error::Io`] with kind `InvalidInput`.
pub fn check_distinct<P: AsRef<Path>>(
    inputs: &[(&str, P)],
    outputs: &[(&str, &Path)],
) -> Result<()> {
    for (k, (role, output)) in outputs.iter().enumerate() {
        for (input_role, input) in inputs {
            if same_file(output, input.as_ref()) {
                return Err(io_error(
                    output,
                    ErrorKind::InvalidInput,
                    format!("{role} would overwrite {input_role}"),
                ));
            }
        }
        for (other_role, other) in &outputs[..k] {
            if same_file(output, other) {
                return Err(io_error(
                    output,
                    ErrorKind::InvalidInput,
                    format!("{role} and {other_role} name the same file"),
                ));
            }
        }
    }
    Ok(())
}
