//! Contacts: a frame of the model (a URDF link, e.g. `l_sole`) or a point of a link given as
//! `LINK:x,y,z` (offset in the link's frame [m], axes of the link), for robots whose soles
//! are not frames (G1's soles are collision spheres under `*_ankle_roll_link`). A point
//! becomes a frame of the model named by the contact's text, with the link's axes.

use crate::error::{Error, Result};
use nalgebra::Vector3;
use sea_dyn::spatial::Pose;
use sea_dyn::{Frame, Model};

/// The scenario key of the contacts.
const CONTACTS_KEY: &str = "robot.contacts";

/// One contact as written.
#[derive(Clone, Debug, PartialEq)]
pub enum ContactSpec {
    /// A frame of the model.
    Frame(String),
    /// A point of a link: offset in the link's frame [m].
    LinkPoint {
        /// The link.
        link: String,
        /// The offset, link frame [m].
        offset: [f64; 3],
    },
}

impl ContactSpec {
    /// Reads `FRAME` or `LINK:x,y,z`; an error names the contact and the bad part.
    pub fn parse(text: &str) -> Result<Self> {
        let Some((link, numbers)) = text.split_once(':') else {
            return Ok(Self::Frame(text.to_string()));
        };
        let bad = |rule: String| Error::invalid(CONTACTS_KEY, rule, format!("'{text}'"));
        if link.is_empty() {
            return Err(bad("LINK:x,y,z needs a link name before ':'".into()));
        }
        let parts: Vec<&str> = numbers.split(',').collect();
        if parts.len() != 3 {
            return Err(bad(format!(
                "LINK:x,y,z needs three numbers after ':' (metres, link frame), got {}",
                parts.len()
            )));
        }
        let mut offset = [0.0; 3];
        for (slot, part) in offset.iter_mut().zip(&parts) {
            *slot = part
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad(format!("'{}' is not a finite number", part.trim())))?;
        }
        Ok(Self::LinkPoint {
            link: link.to_string(),
            offset,
        })
    }

    /// The contact written back (`LINK:x,y,z` with the shortest exact numbers).
    pub fn text(&self) -> String {
        match self {
            Self::Frame(name) => name.clone(),
            Self::LinkPoint { link, offset } => {
                format!("{link}:{},{},{}", offset[0], offset[1], offset[2])
            }
        }
    }

    /// The link (or frame) the contact is on.
    pub fn link(&self) -> &str {
        match self {
            Self::Frame(name) => name,
            Self::LinkPoint { link, .. } => link,
        }
    }
}

/// Adds to `model` a frame named by each `LINK:x,y,z` contact of `contacts` (frames are
/// checked to exist); an error names the contact that is neither.
pub fn add_contact_frames(model: &mut Model, contacts: &[String]) -> Result<()> {
    for text in contacts {
        match ContactSpec::parse(text)? {
            ContactSpec::Frame(name) => {
                model
                    .frame_id(&name)
                    .map_err(|_| unknown(&name, "frame", model))?;
            }
            ContactSpec::LinkPoint { link, offset } => {
                if model.frame_id(text).is_ok() {
                    continue;
                }
                let id = model
                    .frame_id(&link)
                    .map_err(|_| unknown(&link, "link", model))?;
                let frame = &model.frames[id];
                let link_h_point = Pose {
                    rotation: nalgebra::Matrix3::identity(),
                    translation: Vector3::from(offset),
                };
                let body_h_frame = frame.body_h_frame.compose(&link_h_point);
                let body = frame.body;
                model.frames.push(Frame {
                    name: text.clone(),
                    body,
                    body_h_frame,
                });
            }
        }
    }
    Ok(())
}

/// "unknown frame 'x'" with a few of the model's frame names that look alike.
fn unknown(name: &str, what: &str, model: &Model) -> Error {
    let lower = name.to_lowercase();
    let stem: String = lower.chars().take(3).collect();
    let similar: Vec<&str> = model
        .frames
        .iter()
        .map(|f| f.name.as_str())
        .filter(|n| n.to_lowercase().contains(&stem))
        .take(6)
        .collect();
    let hint = if similar.is_empty() {
        String::new()
    } else {
        format!(" (similar: {})", similar.join(", "))
    };
    Error::config(
        CONTACTS_KEY,
        format!("unknown {what} '{name}' in the URDF{hint}"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_and_link_points_read_and_write_back() {
        assert_eq!(
            ContactSpec::parse("l_sole").unwrap(),
            ContactSpec::Frame("l_sole".into())
        );
        let point = ContactSpec::parse("ankle:0.01, -0.5,0").unwrap();
        assert_eq!(
            point,
            ContactSpec::LinkPoint {
                link: "ankle".into(),
                offset: [0.01, -0.5, 0.0]
            }
        );
        assert_eq!(point.text(), "ankle:0.01,-0.5,0");
    }

    #[test]
    fn bad_link_points_are_refused_naming_the_contact_and_the_part() {
        for (text, part) in [
            ("ankle:0,x,0", "'x' is not a finite number"),
            ("ankle:0,0", "three numbers"),
            ("ankle:0,0,nan", "'nan' is not a finite number"),
            (":0,0,0", "needs a link name"),
        ] {
            let message = ContactSpec::parse(text).unwrap_err().to_string();
            assert!(
                message.contains(CONTACTS_KEY) && message.contains(part) && message.contains(text),
                "{message}"
            );
        }
    }
}
