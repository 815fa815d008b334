//! Naming the URDF number that is not one: `urdf-rs` reports such a file as "invalid float
//! literal" with neither the element nor the attribute nor the line. When it refuses a file,
//! [`first_bad_number`] reads the numeric attributes of the URDF elements once more and names
//! the first that does not parse, with its link or joint and its line.

/// The URDF elements and their attributes that hold numbers (one or several, space separated).
const NUMERIC_ATTRIBUTES: &[(&str, &[&str])] = &[
    ("mass", &["value"]),
    ("inertia", &["ixx", "ixy", "ixz", "iyy", "iyz", "izz"]),
    ("origin", &["xyz", "rpy"]),
    ("axis", &["xyz"]),
    ("limit", &["lower", "upper", "effort", "velocity"]),
    ("dynamics", &["damping", "friction"]),
    ("box", &["size"]),
    ("cylinder", &["radius", "length"]),
    ("sphere", &["radius"]),
    ("capsule", &["radius", "length"]),
    ("mesh", &["scale"]),
    ("color", &["rgba"]),
    ("mimic", &["multiplier", "offset"]),
    ("calibration", &["rising", "falling"]),
    (
        "safety_controller",
        &[
            "soft_lower_limit",
            "soft_upper_limit",
            "k_position",
            "k_velocity",
        ],
    ),
];

/// The first numeric attribute of `text` (a URDF) with a value that is not a number, as
/// `joint 'knee' <limit effort="abc">: 'abc' is not a number (line 12)`; `None` when every
/// one parses or the text is not well-formed XML.
pub(crate) fn first_bad_number(text: &str) -> Option<String> {
    let options = roxmltree::ParsingOptions {
        allow_dtd: true,
        ..Default::default()
    };
    let document = roxmltree::Document::parse_with_options(text, options).ok()?;
    for node in document.descendants().filter(|node| node.is_element()) {
        let tag = node.tag_name().name();
        let Some((_, attributes)) = NUMERIC_ATTRIBUTES.iter().find(|(name, _)| *name == tag) else {
            continue;
        };
        for &attribute in *attributes {
            let Some(value) = node.attribute(attribute) else {
                continue;
            };
            let Some(bad) = value.split_whitespace().find(|t| t.parse::<f64>().is_err()) else {
                continue;
            };
            let owner = node
                .ancestors()
                .find(|a| a.has_tag_name("link") || a.has_tag_name("joint"))
                .map(|a| {
                    let name = a.attribute("name").unwrap_or("?");
                    format!("{} '{name}' ", a.tag_name().name())
                })
                .unwrap_or_default();
            let line = document.text_pos_at(node.range().start).row;
            return Some(format!(
                "{owner}<{tag} {attribute}=\"{value}\">: '{bad}' is not a number (line {line})"
            ));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bad_number_is_named_with_its_owner_and_line() {
        let urdf = "<robot name=\"r\">\n<link name=\"base\">\n<inertial><mass value=\"1\"/>\
                    </inertial></link>\n<joint name=\"knee\" type=\"revolute\">\n\
                    <limit lower=\"-1\" upper=\"1\" effort=\"abc\" velocity=\"1\"/></joint>\n\
                    </robot>";
        assert_eq!(
            first_bad_number(urdf).as_deref(),
            Some("joint 'knee' <limit effort=\"abc\">: 'abc' is not a number (line 5)")
        );
        assert_eq!(
            first_bad_number("<robot><origin xyz=\"0 0 1\"/></robot>"),
            None
        );
        assert_eq!(first_bad_number("<robot"), None);
    }
}
