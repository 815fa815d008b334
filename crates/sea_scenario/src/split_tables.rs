//! Tables whose keys belong to several types: `[controller]` (its own keys and the `sea_ctrl`
//! settings it reads directly) and `[controller.contact]` (the contact surface and the QP's
//! own choices). Each is a struct some of whose fields are [`Part`]s, settings types that read
//! their own keys from the same flat table: the table is split by the parts' keys, each part
//! read by its type and the rest by the struct, with any other key reported as unknown
//! against every key of the table ([`flat_keys`]: the struct's fields in order, each part's
//! field replaced by its type's keys).

use super::parse::{field_names, split, table_as, TableError, TableResult};
use super::schema::ControllerConfig;
use sea_ctrl::controller::ControllerTuning;
use sea_ctrl::excitation::ExcitationSettings;
use sea_ctrl::external_wrench::ExternalWrenchSettings;
use sea_ctrl::joint_loop::JointLoopSettings;
use sea_ctrl::qp::ContactConstraints;
use sea_ctrl::stiffness_id::IdentificationSettings;
use sea_dyn::ContactSurface;
use serde::de::{DeserializeOwned, Error as _};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A field of the struct `C` of a flat table whose type reads its own keys of the table.
pub(crate) struct Part<C> {
    /// The field's name in `C` (no key of the table).
    field: &'static str,
    /// The keys its type reads.
    keys: &'static [&'static str],
    /// Reads the part's keys (a table of them alone) into the field.
    read: fn(toml::Table, &mut C) -> TableResult<()>,
    /// The part's keys as written.
    write: fn(&C) -> Result<toml::Table, toml::ser::Error>,
}

/// The part of `C` held by the field `field` of type `T`, read and written by `T`'s serde
/// (its keys: [`field_names`]).
macro_rules! part {
    ($config:ty, $field:ident: $part:ty) => {
        Part::<$config> {
            field: stringify!($field),
            keys: field_names::<$part>(),
            read: |table, config: &mut $config| {
                config.$field = table_as::<$part>(table, &[])?;
                Ok(())
            },
            write: |config: &$config| toml::Table::try_from(&config.$field),
        }
    };
}

/// The parts of `[controller]`: the `sea_ctrl` settings it reads directly.
fn controller_parts() -> [Part<ControllerConfig>; 5] {
    [
        part!(ControllerConfig, joint_loops: JointLoopSettings),
        part!(ControllerConfig, identification: IdentificationSettings),
        part!(ControllerConfig, excitation: ExcitationSettings),
        part!(ControllerConfig, wrench_observer: ExternalWrenchSettings),
        part!(ControllerConfig, tuning: ControllerTuning),
    ]
}

/// The part of `[controller.contact]`: the contact surface.
fn contact_parts() -> [Part<ContactConstraints>; 1] {
    [part!(ContactConstraints, surface: ContactSurface)]
}

/// Every key of the flat table of `C` with `parts`: `C`'s fields in order, each part's field
/// replaced by its keys.
fn flat_keys<'de, C: Deserialize<'de>>(parts: &[Part<C>]) -> Vec<&'static str> {
    field_names::<C>()
        .iter()
        .flat_map(|key| match parts.iter().find(|part| part.field == *key) {
            Some(part) => part.keys,
            None => std::slice::from_ref(key),
        })
        .copied()
        .collect()
}

/// Reads the flat table of `C` with `parts`: a key that is none of [`flat_keys`] is unknown;
/// the keys of each part are read by the part's type, the rest by `C` (whose part fields
/// are left at their defaults, then set).
fn read_flat<C: DeserializeOwned>(table: toml::Table, parts: &[Part<C>]) -> TableResult<C> {
    let keys = flat_keys(parts);
    if let Some(unknown) = table.keys().find(|key| !keys.contains(&key.as_str())) {
        return Err(TableError::unknown_field(unknown, &keys));
    }
    let mut own = table;
    let mut part_tables = Vec::with_capacity(parts.len());
    for part in parts {
        let (taken, rest) = split(own, part.keys);
        part_tables.push(taken);
        own = rest;
    }
    let mut config: C = table_as(own, &[])?;
    for (part, taken) in parts.iter().zip(part_tables) {
        (part.read)(taken, &mut config)?;
    }
    Ok(config)
}

/// The flat table of `config` with `parts`: its own keys (`own`, the parts' fields not
/// serialised) with every part's.
fn write_flat<C>(
    mut own: toml::Table,
    config: &C,
    parts: &[Part<C>],
) -> Result<toml::Table, toml::ser::Error> {
    for part in parts {
        own.extend((part.write)(config)?);
    }
    Ok(own)
}

/// Reads `[controller.contact]`: `facets`, `min_normal_force` and `cop_margin`, the other keys
/// the contact surface's.
pub(crate) fn contact_constraints<'de, D>(
    deserializer: D,
) -> std::result::Result<ContactConstraints, D::Error>
where
    D: Deserializer<'de>,
{
    let table = toml::Table::deserialize(deserializer)?;
    read_flat(table, &contact_parts()).map_err(|e| D::Error::custom(e.within("")))
}

/// Writes `[controller.contact]` as it is read: one flat table, the surface's keys with
/// `facets`, `min_normal_force` and `cop_margin`.
pub(crate) fn contact_constraints_table<S: Serializer>(
    contact: &ContactConstraints,
    serializer: S,
) -> std::result::Result<S::Ok, S::Error> {
    use serde::ser::Error as _;
    let mut own = toml::Table::new();
    own.insert("facets".into(), toml::Value::Integer(contact.facets as i64));
    let min_normal_force = toml::Value::Float(contact.min_normal_force);
    own.insert("min_normal_force".into(), min_normal_force);
    let cop_margin = toml::Value::Float(contact.cop_margin);
    own.insert("cop_margin".into(), cop_margin);
    let table = write_flat(own, contact, &contact_parts()).map_err(S::Error::custom)?;
    table.serialize(serializer)
}

/// Reads `[controller]` (`#[serde(deserialize_with)]` of `Scenario::controller`): the table
/// split by the keys of the `sea_ctrl` settings it reads directly ([`JointLoopSettings`],
/// [`IdentificationSettings`], [`ExcitationSettings`], [`ExternalWrenchSettings`],
/// [`ControllerTuning`]) and its own, each part read by its type with unknown keys refused;
/// any other key is unknown, reported against every key of the table (in
/// [`ControllerConfig`]'s order, the settings' keys where their field is).
pub(crate) fn controller_table<'de, D>(
    deserializer: D,
) -> std::result::Result<ControllerConfig, D::Error>
where
    D: Deserializer<'de>,
{
    let table = toml::Table::deserialize(deserializer)?;
    read_flat(table, &controller_parts()).map_err(|e| D::Error::custom(e.within("")))
}

/// `[controller]` as a scenario file writes it ([`ControllerConfig::table`]).
pub(crate) fn controller_flat_table(
    config: &ControllerConfig,
) -> Result<toml::Table, toml::ser::Error> {
    write_flat(toml::Table::try_from(config)?, config, &controller_parts())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_keys_of_a_flat_table_are_its_own_and_its_parts_in_field_order() {
        let keys = flat_keys(&controller_parts());
        for part in controller_parts() {
            assert!(!keys.contains(&part.field), "{} is no key", part.field);
            assert!(part.keys.iter().all(|key| keys.contains(key)));
        }
        let position = |key| keys.iter().position(|k| *k == key).unwrap();
        assert!(position("inner_rate_hz") < position("torque_bandwidth_hz"));
        assert!(position("torque_loop_paper_law") < position("stiffness_identification"));
        assert!(position("external_wrench_bandwidth_hz") < position("damping_estimate_scale"));
        assert_eq!(keys.last(), Some(&"contact"));
        let mut unique = keys.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), keys.len(), "no key read by two types");
        let contact = flat_keys(&contact_parts());
        assert_eq!(contact[..3], ["facets", "min_normal_force", "cop_margin"]);
        assert!(contact.contains(&"friction") && !contact.contains(&"surface"));
    }
}
