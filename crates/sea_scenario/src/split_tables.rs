//! Tables whose keys belong to several types: `[controller]` (its own keys and the `sea_ctrl`
//! settings it reads directly) and `[controller.contact]` (the contact surface and the QP's
//! own choices), each split by the keys of its types and each part read by its type, with any
//! other key reported as unknown against all of them.

use super::parse::{field_names, split, table_as, TableError, TableResult};
use super::schema::ControllerConfig;
use sea_ctrl::joint_loop::JointLoopSettings;
use sea_ctrl::qp::ContactConstraints;
use sea_ctrl::stiffness_id::IdentificationSettings;
use sea_dyn::ContactSurface;
use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// Reads `[controller.contact]`: `facets`, `min_normal_force` and `cop_margin`, the other keys
/// the contact surface's.
pub(crate) fn contact_constraints<'de, D>(
    deserializer: D,
) -> std::result::Result<ContactConstraints, D::Error>
where
    D: Deserializer<'de>,
{
    let table = toml::Table::deserialize(deserializer)?;
    contact_table(table).map_err(|e| D::Error::custom(e.within("")))
}

/// Writes `[controller.contact]` as it is read: one flat table, the surface's keys with
/// `facets`, `min_normal_force` and `cop_margin`.
pub(crate) fn contact_constraints_table<S: Serializer>(
    contact: &ContactConstraints,
    serializer: S,
) -> std::result::Result<S::Ok, S::Error> {
    use serde::ser::Error as _;
    let mut table = toml::Table::try_from(contact.surface).map_err(S::Error::custom)?;
    table.insert("facets".into(), toml::Value::Integer(contact.facets as i64));
    let min_normal_force = toml::Value::Float(contact.min_normal_force);
    table.insert("min_normal_force".into(), min_normal_force);
    let cop_margin = toml::Value::Float(contact.cop_margin);
    table.insert("cop_margin".into(), cop_margin);
    table.serialize(serializer)
}

/// Reads `[controller]` (`#[serde(deserialize_with)]` of `Scenario::controller`): the table
/// split by the keys of the `sea_ctrl` settings it reads directly ([`JointLoopSettings`],
/// [`IdentificationSettings`]) and its own, each part read by its type with unknown keys
/// refused; any other key is unknown, reported against every key of the table (in
/// [`ControllerConfig`]'s order, the settings' keys where their field is).
pub(crate) fn controller_table<'de, D>(
    deserializer: D,
) -> std::result::Result<ControllerConfig, D::Error>
where
    D: Deserializer<'de>,
{
    let table = toml::Table::deserialize(deserializer)?;
    read_controller(table).map_err(|e| D::Error::custom(e.within("")))
}

/// [`ControllerConfig`] of a `[controller]` table read on its own ([`controller_table`]).
fn read_controller(table: toml::Table) -> TableResult<ControllerConfig> {
    let joint_loop_keys = field_names::<JointLoopSettings>();
    let identification_keys = field_names::<IdentificationSettings>();
    let union: Vec<&str> = field_names::<ControllerConfig>()
        .iter()
        .flat_map(|key| match *key {
            "joint_loops" => joint_loop_keys,
            "identification" => identification_keys,
            _ => std::slice::from_ref(key),
        })
        .copied()
        .collect();
    if let Some(unknown) = table.keys().find(|key| !union.contains(&key.as_str())) {
        return Err(TableError::unknown_field(unknown, &union));
    }
    let (joint_loops, rest) = split(table, joint_loop_keys);
    let (identification, own) = split(rest, identification_keys);
    let mut config: ControllerConfig = table_as(own, &[])?;
    config.joint_loops = table_as(joint_loops, &[])?;
    config.identification = table_as(identification, &[])?;
    Ok(config)
}

/// [`ContactConstraints`] of a `[controller.contact]` table read on its own: the table split
/// by the keys of [`ContactSurface`] and of the QP's own choices (`facets`, ...), each part
/// read by its type; any other key is unknown, reported against both types' keys.
fn contact_table(table: toml::Table) -> TableResult<ContactConstraints> {
    let surface_keys = field_names::<ContactSurface>();
    let own_keys = field_names::<ContactConstraints>()
        .iter()
        .filter(|&&key| key != "surface");
    let union: Vec<&str> = own_keys.chain(surface_keys).copied().collect();
    if let Some(unknown) = table.keys().find(|key| !union.contains(&key.as_str())) {
        return Err(TableError::unknown_field(unknown, &union));
    }
    let (surface, own) = split(table, surface_keys);
    let mut constraints: ContactConstraints = table_as(own, &[])?;
    constraints.surface = table_as(surface, &[])?;
    Ok(constraints)
}
