//! Where a scenario's robot description comes from: `[robot] description = NAME` (a built-in
//! description: "icub_paper", the default), `= "PATH.toml"` (a file, relative to the
//! scenario's folder) or `[robot.description]` (a table inline in the scenario, as
//! `sea-sim init` writes it).

use super::icub::{icub, ICUB_PAPER};
use super::RobotDescription;
use crate::error::{Error, Result};
use sea_dyn::files::{read_text_within, MAX_TOML_BYTES};
use std::path::{Path, PathBuf};

/// The scenario key naming the description.
pub const DESCRIPTION_KEY: &str = "robot.description";

/// A scenario's robot description and the folder its relative paths (its URDF) are
/// relative to.
#[derive(Clone, Debug, PartialEq)]
pub struct DescriptionSource {
    /// The description.
    pub description: RobotDescription,
    /// The folder of its file; the scenario's folder for a built-in or inline description.
    pub dir: PathBuf,
    /// Its file; `None` for a built-in or inline description.
    pub file: Option<PathBuf>,
}

/// The description `value` (the value of `robot.description`, `None` when absent) names, for a
/// scenario in `scenario_dir`.
pub fn load_description(
    value: Option<toml::Value>,
    scenario_dir: &Path,
) -> Result<DescriptionSource> {
    let of = |description| DescriptionSource {
        description,
        dir: scenario_dir.to_path_buf(),
        file: None,
    };
    match value {
        None => Ok(of(icub().clone())),
        Some(toml::Value::String(name)) if name == ICUB_PAPER => Ok(of(icub().clone())),
        Some(toml::Value::String(path)) => from_file(&path, scenario_dir),
        Some(toml::Value::Table(table)) => Ok(of(RobotDescription::from_table(table)?)),
        Some(other) => Err(Error::invalid(
            DESCRIPTION_KEY,
            format!("must be \"{ICUB_PAPER}\", the path of a robot description file or a table"),
            other,
        )),
    }
}

/// The description in the file `path` (relative to `scenario_dir` when it exists there).
fn from_file(path: &str, scenario_dir: &Path) -> Result<DescriptionSource> {
    let beside = scenario_dir.join(path);
    let file = if beside.is_file() {
        beside
    } else {
        PathBuf::from(path)
    };
    let text = read_text_within(&file, MAX_TOML_BYTES).map_err(|e| {
        Error::invalid(
            DESCRIPTION_KEY,
            format!("cannot read the robot description ({e}); built in: \"{ICUB_PAPER}\""),
            path,
        )
    })?;
    let description = RobotDescription::from_toml(&text, &file.display().to_string())?;
    let dir = file.parent().unwrap_or(Path::new(".")).to_path_buf();
    Ok(DescriptionSource {
        description,
        dir,
        file: Some(file),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn absent_and_builtin_name_are_the_papers_icub() {
        let dir = Path::new(".");
        assert_eq!(&load_description(None, dir).unwrap().description, icub());
        let named = Some(toml::Value::String(ICUB_PAPER.into()));
        assert_eq!(&load_description(named, dir).unwrap().description, icub());
    }

    #[test]
    fn a_missing_file_and_a_number_are_refused_naming_the_key() {
        let dir = Path::new(".");
        for value in [
            toml::Value::String("nowhere.toml".into()),
            toml::Value::Integer(3),
        ] {
            let message = load_description(Some(value), dir).unwrap_err().to_string();
            assert!(message.contains(DESCRIPTION_KEY), "{message}");
        }
    }

    #[test]
    fn an_inline_table_is_read() {
        let table: toml::Table = toml::from_str(super::super::icub::ICUB_PAPER_TOML).unwrap();
        let loaded = load_description(Some(toml::Value::Table(table)), Path::new(".")).unwrap();
        assert_eq!(&loaded.description, icub());
    }
}
