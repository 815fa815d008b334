//! Where the files a URDF names are: `package://NAME/PATH`, `file://PATH`, absolute and
//! relative paths (meshes of `<visual>` and `<collision>`, or a robot description named by
//! URI), resolved the way ROS and Pinocchio do.
//!
//! A `package://NAME/PATH` URI is looked up, in this order:
//!
//! 1. in the package directories given by the user ([`PackageDirs::new`]), then those of the
//!    environment ([`PackageDirs::from_environment`]): every entry of `ROS_PACKAGE_PATH`, the
//!    `share/` folder of every prefix of `AMENT_PREFIX_PATH` and `CMAKE_PREFIX_PATH` (ROS 2
//!    install spaces), and the `share/` folder of the cmeel prefixes of Python: those of the
//!    interpreter this process runs in when it is Python (its `sys.path` folders, registered
//!    by the Python module at import: [`register_python_site_packages`]; no `activate` needed),
//!    then that of the active environment (`$VIRTUAL_ENV/lib/python3.*/site-packages/cmeel.prefix`),
//!    where the PyPI packages `example-robot-data` and `pin` install their ROS-style share
//!    folders. In a
//!    directory `D`, the package is `D/NAME`, or `D` itself when `D` is named `NAME` (a
//!    `ROS_PACKAGE_PATH` entry that is the package). This is Pinocchio's rule
//!    (`package_dirs`, then `ROS_PACKAGE_PATH` and `AMENT_PREFIX_PATH`).
//! 2. then beside the URDF: the first folder above the URDF's that is named `NAME` or holds a
//!    folder `NAME`. Robot packages ship their URDF inside the package (`iCub/robots/.../model.urdf`,
//!    `talos_data/robots/talos_reduced.urdf`), so a file copied with its package resolves
//!    with no setup.
//!
//! A URI that resolves nowhere is an error naming it and every directory searched.

use crate::error::{Error, Result};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Scheme of ROS package URIs.
const PACKAGE_SCHEME: &str = "package://";
/// Scheme of file URIs.
const FILE_SCHEME: &str = "file://";

/// The `site-packages` folders (and other `sys.path` entries) of the Python interpreter this
/// process runs in, registered by [`register_python_site_packages`].
static PYTHON_SITE_PACKAGES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Registers the folders of the running Python interpreter's `sys.path` (the Python module does
/// at import): the `share/` folder of the cmeel prefix of each that has one
/// (`DIR/cmeel.prefix/share`) is then searched by [`PackageDirs::from_environment`], whether or
/// not `VIRTUAL_ENV` is set (IDEs, Jupyter kernels and cron start Python without `activate`).
/// Each folder is kept once.
pub fn register_python_site_packages(dirs: impl IntoIterator<Item = PathBuf>) {
    let mut registered = PYTHON_SITE_PACKAGES
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    for dir in dirs {
        if !registered.contains(&dir) {
            registered.push(dir);
        }
    }
}

/// The `share/` folders of the cmeel prefixes in the registered Python folders.
fn python_cmeel_share_dirs() -> Vec<PathBuf> {
    let registered = PYTHON_SITE_PACKAGES
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    registered
        .iter()
        .map(|dir| dir.join("cmeel.prefix/share"))
        .filter(|share| share.is_dir())
        .collect()
}

/// The package directories searched for `package://` URIs, in order (module doc).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PackageDirs {
    /// Searched in this order.
    pub dirs: Vec<PathBuf>,
}

impl PackageDirs {
    /// Exactly `dirs` (no environment).
    pub fn new(dirs: impl IntoIterator<Item = impl Into<PathBuf>>) -> Self {
        Self {
            dirs: dirs.into_iter().map(Into::into).collect(),
        }
    }

    /// `user` first, then the environment's directories (module doc), each once.
    pub fn from_environment(user: impl IntoIterator<Item = impl Into<PathBuf>>) -> Self {
        let mut found = Self::new(user);
        let variable = |name: &str| std::env::var_os(name).unwrap_or_default();
        found.extend(std::env::split_paths(&variable("ROS_PACKAGE_PATH")));
        for prefixes in ["AMENT_PREFIX_PATH", "CMAKE_PREFIX_PATH"] {
            let prefixes = variable(prefixes);
            found.extend(std::env::split_paths(&prefixes).map(|p| p.join("share")));
        }
        found.extend(python_cmeel_share_dirs());
        if let Some(env) = std::env::var_os("VIRTUAL_ENV") {
            found.extend(cmeel_share_dirs(Path::new(&env)));
        }
        found
    }

    /// Appends the directories of `dirs` that exist and are not listed yet.
    fn extend(&mut self, dirs: impl IntoIterator<Item = PathBuf>) {
        for dir in dirs {
            if dir.is_dir() && !self.dirs.contains(&dir) {
                self.dirs.push(dir);
            }
        }
    }

    /// The file `uri` names, for a URDF in the folder `urdf_dir` (relative paths are relative
    /// to it): an existing file, or an error naming `uri` and where it was looked for.
    pub fn resolve(&self, uri: &str, urdf_dir: &Path) -> Result<PathBuf> {
        if let Some(rest) = uri.strip_prefix(PACKAGE_SCHEME) {
            return self.resolve_package(uri, rest, urdf_dir);
        }
        let path = Path::new(uri.strip_prefix(FILE_SCHEME).unwrap_or(uri));
        let path = if path.is_absolute() {
            path.to_path_buf()
        } else {
            urdf_dir.join(path)
        };
        let problem = match std::fs::metadata(&path) {
            Ok(metadata) if metadata.is_file() => return Ok(path),
            Ok(_) => "not a regular file",
            Err(_) => "no such file",
        };
        Err(Error::model(
            format!("file '{uri}'"),
            format!("{problem}: {}", path.display()),
        ))
    }

    /// `package://NAME/PATH` (`rest` = `NAME/PATH`).
    fn resolve_package(&self, uri: &str, rest: &str, urdf_dir: &Path) -> Result<PathBuf> {
        let (name, path) = rest.split_once('/').unwrap_or((rest, ""));
        if name.is_empty() || path.is_empty() {
            return Err(Error::model(
                format!("package URI '{uri}'"),
                "must read package://NAME/PATH",
            ));
        }
        let beside_urdf = urdf_dir.ancestors().map(Path::to_path_buf);
        let candidates = self.dirs.iter().cloned().chain(beside_urdf);
        for dir in candidates {
            for root in [dir.join(name), dir.clone()] {
                let named = root.file_name().is_some_and(|n| n == name);
                if named && root.join(path).is_file() {
                    return Ok(root.join(path));
                }
            }
        }
        Err(Error::model(
            format!("package URI '{uri}'"),
            format!(
                "no package '{name}' holding '{path}' in the package directories [{}] nor above \
                 the URDF's folder {}; give the folder that holds '{name}' (ROS_PACKAGE_PATH, \
                 or the package directories argument)",
                self.dirs
                    .iter()
                    .map(|d| d.display().to_string())
                    .collect::<Vec<_>>()
                    .join(", "),
                urdf_dir.display()
            ),
        ))
    }
}

/// The `share/` folders of the cmeel prefixes of the Python environment at `env`
/// (`lib/python3.*/site-packages/cmeel.prefix/share`).
fn cmeel_share_dirs(env: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(env.join("lib")) else {
        return Vec::new();
    };
    let mut dirs: Vec<PathBuf> = entries
        .filter_map(|entry| entry.ok())
        .filter(|entry| entry.file_name().to_string_lossy().starts_with("python3"))
        .map(|entry| entry.path().join("site-packages/cmeel.prefix/share"))
        .filter(|dir| dir.is_dir())
        .collect();
    dirs.sort();
    dirs
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;

    /// A temporary tree `root/share/robot_pkg/{meshes/a.stl, robots/r.urdf}` and
    /// `root/other/b.obj`.
    fn tree(tag: &str) -> PathBuf {
        let root =
            std::env::temp_dir().join(format!("sea_dyn_resources_{tag}_{}", std::process::id()));
        let _ = fs::remove_dir_all(&root);
        for dir in ["share/robot_pkg/meshes", "share/robot_pkg/robots", "other"] {
            fs::create_dir_all(root.join(dir)).unwrap();
        }
        for file in [
            "share/robot_pkg/meshes/a.stl",
            "share/robot_pkg/robots/r.urdf",
            "other/b.obj",
        ] {
            fs::write(root.join(file), b"x").unwrap();
        }
        root
    }

    #[test]
    fn package_uris_resolve_in_the_given_dirs_then_above_the_urdf() {
        let root = tree("order");
        let urdf_dir = root.join("share/robot_pkg/robots");
        let mesh = root.join("share/robot_pkg/meshes/a.stl");
        let given = PackageDirs::new([root.join("share")]);
        assert_eq!(
            given
                .resolve("package://robot_pkg/meshes/a.stl", Path::new("/"))
                .unwrap(),
            mesh
        );
        // No directory given: found above the URDF (the folder named like the package).
        let none = PackageDirs::default();
        assert_eq!(
            none.resolve("package://robot_pkg/meshes/a.stl", &urdf_dir)
                .unwrap(),
            mesh
        );
        // A directory that is the package itself (a ROS_PACKAGE_PATH entry).
        let itself = PackageDirs::new([root.join("share/robot_pkg")]);
        assert_eq!(
            itself
                .resolve("package://robot_pkg/meshes/a.stl", Path::new("/"))
                .unwrap(),
            mesh
        );
        fs::remove_dir_all(root).unwrap();
    }

    #[test]
    fn relative_absolute_and_file_uris_resolve() {
        let root = tree("paths");
        let urdf_dir = root.join("share/robot_pkg/robots");
        let none = PackageDirs::default();
        let mesh = root.join("share/robot_pkg/meshes/a.stl");
        assert_eq!(
            none.resolve("../meshes/a.stl", &urdf_dir).unwrap(),
            urdf_dir.join("../meshes/a.stl")
        );
        let absolute = mesh.display().to_string();
        assert_eq!(none.resolve(&absolute, &urdf_dir).unwrap(), mesh);
        assert_eq!(
            none.resolve(&format!("file://{absolute}"), &urdf_dir)
                .unwrap(),
            mesh
        );
        fs::remove_dir_all(root).unwrap();
    }

    #[test]
    fn unresolvable_uris_name_the_uri_and_the_dirs() {
        let root = tree("missing");
        let dirs = PackageDirs::new([root.join("other")]);
        let urdf_dir = root.join("share/robot_pkg/robots");
        let message = dirs
            .resolve("package://nope/meshes/a.stl", &urdf_dir)
            .unwrap_err()
            .to_string();
        assert!(message.contains("package://nope/meshes/a.stl"), "{message}");
        assert!(message.contains("no package 'nope'"), "{message}");
        assert!(
            message.contains(&root.join("other").display().to_string()),
            "{message}"
        );
        // The package exists but not the file.
        let message = dirs
            .resolve("package://robot_pkg/meshes/zz.stl", &urdf_dir)
            .unwrap_err()
            .to_string();
        assert!(message.contains("zz.stl"), "{message}");
        let message = dirs
            .resolve("meshes/missing.dae", &urdf_dir)
            .unwrap_err()
            .to_string();
        assert!(message.contains("file 'meshes/missing.dae'"), "{message}");
        assert!(dirs.resolve("package://only_name", &urdf_dir).is_err());
        fs::remove_dir_all(root).unwrap();
    }

    #[test]
    fn registered_python_folders_add_their_cmeel_share_without_virtual_env() {
        let root = tree("python");
        let site_packages = root.join("lib/python3.x/site-packages");
        let share = site_packages.join("cmeel.prefix/share");
        fs::create_dir_all(share.join("robot_pkg/meshes")).unwrap();
        fs::write(share.join("robot_pkg/meshes/c.stl"), b"x").unwrap();
        // A folder without a cmeel prefix adds nothing.
        register_python_site_packages([root.join("other"), site_packages.clone()]);
        register_python_site_packages([site_packages]);
        let dirs = PackageDirs::from_environment(Vec::<PathBuf>::new());
        assert_eq!(dirs.dirs.iter().filter(|d| **d == share).count(), 1);
        assert!(!dirs.dirs.contains(&root.join("other/cmeel.prefix/share")));
        assert_eq!(
            dirs.resolve("package://robot_pkg/meshes/c.stl", Path::new("/"))
                .unwrap(),
            share.join("robot_pkg/meshes/c.stl")
        );
        fs::remove_dir_all(root).unwrap();
    }

    #[test]
    fn the_environment_adds_existing_dirs_once_after_the_users() {
        let root = tree("env");
        let dirs = PackageDirs::from_environment([root.join("other")]);
        assert_eq!(dirs.dirs[0], root.join("other"));
        let unique: std::collections::HashSet<_> = dirs.dirs.iter().collect();
        assert_eq!(unique.len(), dirs.dirs.len());
        fs::remove_dir_all(root).unwrap();
    }
}
