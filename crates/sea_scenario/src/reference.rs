//! The reference page of every scenario key (`docs/reference/scenario_keys.md`), written from
//! the JSON Schema of [`super::schema::json_schema`]: one row per key with its type, default,
//! unit, allowed values and description. `sea-sim schema --markdown` prints it; a test checks
//! that the committed page is current.

use serde_json::{Map, Value};

/// A schema object (an empty one for a schema that is not an object).
type Object = Map<String, Value>;

/// The page's introduction.
const INTRODUCTION: &str = "\
# Scenario keys

Generated from the scenario file's JSON Schema (`schemas/scenario.schema.json`, derived from the
Rust types that read the file) by `sea-sim schema --markdown`; do not edit by hand. A key left
out takes its default. A default its description calls the robot description's comes from
the scenario's robot description (`robot.description`, the paper's iCub by default); the
defaults shown are the paper's iCub's. Units are SI. A table of numbers by name
(`actuators.overrides`, `controller.link_mass_estimate_scales`, ...) is keyed by joint or link
names of the robot.
";

/// The page: the introduction and one table per top-level table of the scenario file.
pub fn markdown(schema: &Value) -> String {
    let mut rows = Vec::new();
    let root = schema.as_object().cloned().unwrap_or_default();
    keys(schema, &root, "", &mut rows);
    let mut page = String::from(INTRODUCTION);
    let mut section = None;
    for row in rows {
        let table = row
            .key
            .split(['.', '['])
            .next()
            .unwrap_or_default()
            .to_string();
        if section.as_ref() != Some(&table) {
            page.push_str(&format!("\n## `{table}`\n\n"));
            page.push_str("| Key | Type | Default | Unit | Allowed | Description |\n");
            page.push_str("|---|---|---|---|---|---|\n");
            section = Some(table);
        }
        page.push_str(&row.line());
    }
    page
}

/// One key of the page.
struct Row {
    key: String,
    kind: String,
    default: String,
    unit: String,
    allowed: String,
    description: String,
}

impl Row {
    /// The row of the key `key` described by `schema` (its own description first, then its
    /// type's).
    fn of(root: &Value, key: &str, schema: &Object) -> Self {
        let target = resolved(root, schema);
        let description = text(schema, "description")
            .or_else(|| text(&target, "description"))
            .unwrap_or_default();
        let variants = variants(&target);
        let mut description = description.to_string();
        let named = |name: &String| description.contains(&format!("\"{name}\""));
        if !variants.iter().all(|(name, _)| named(name)) {
            let listed: Vec<String> = variants
                .iter()
                .map(|(name, what)| format!("`\"{name}\"`: {what}"))
                .collect();
            description = format!("{description} {}", listed.join(" "));
        }
        Self {
            key: key.to_string(),
            kind: kind(root, &target),
            default: schema
                .get("default")
                .map(|d| format!("`{d}`"))
                .unwrap_or_default(),
            unit: unit(&description),
            allowed: allowed(&target, &variants),
            description,
        }
    }

    /// The row as a line of a Markdown table.
    fn line(&self) -> String {
        let cells = [
            format!("`{}`", self.key),
            self.kind.clone(),
            self.default.clone(),
            self.unit.clone(),
            self.allowed.clone(),
            self.description.clone(),
        ];
        let cells: Vec<String> = cells.iter().map(|c| c.replace('|', "\\|")).collect();
        format!("| {} |\n", cells.join(" | "))
    }
}

/// Appends the rows of the keys of the table `schema` (under the dotted `prefix`) to `rows`,
/// a sub-table's keys after the sub-table's row.
fn keys(root: &Value, schema: &Object, prefix: &str, rows: &mut Vec<Row>) {
    let target = resolved(root, schema);
    let Some(properties) = target.get("properties").and_then(Value::as_object) else {
        return;
    };
    for (name, property) in properties {
        let property = property.as_object().cloned().unwrap_or_default();
        let key = if prefix.is_empty() {
            name.clone()
        } else {
            format!("{prefix}.{name}")
        };
        let inner = resolved(root, &property);
        if inner.contains_key("properties") {
            keys(root, &property, &key, rows);
        } else if let Some(items) = table_items(&inner) {
            rows.push(Row::of(root, &key, &property));
            keys(root, &items, &format!("{key}[]"), rows);
        } else if let Some(table) = table_variant(root, &inner) {
            rows.push(Row::of(root, &key, &property));
            keys(root, &table, &key, rows);
        } else {
            rows.push(Row::of(root, &key, &property));
        }
    }
}

/// The table among the alternatives of a value that is one of several kinds (`anyOf`, as a
/// number or a table of numbers by direction), if one is.
fn table_variant(root: &Value, schema: &Object) -> Option<Object> {
    let any = schema.get("anyOf").or_else(|| schema.get("oneOf"))?;
    any.as_array()?
        .iter()
        .filter_map(Value::as_object)
        .map(|variant| resolved(root, variant))
        .find(|variant| variant.contains_key("properties"))
}

/// The schema of the tables of an array of tables (`[[disturbances]]`), if `schema` is one.
fn table_items(schema: &Object) -> Option<Object> {
    let items = schema.get("items")?.as_object()?;
    items
        .contains_key("$ref")
        .then(|| items.clone())
        .filter(|items| !items.is_empty())
}

/// `schema` with a `$ref` (or an `allOf` of one `$ref`, or an optional table: an `anyOf` of one
/// `$ref` and `null`) replaced by the definition it names.
fn resolved(root: &Value, schema: &Object) -> Object {
    let reference = schema
        .get("$ref")
        .or_else(|| {
            let all = schema.get("allOf")?.as_array()?;
            (all.len() == 1).then(|| all[0].get("$ref"))?
        })
        .or_else(|| optional_reference(schema));
    let Some(path) = reference.and_then(Value::as_str) else {
        return schema.clone();
    };
    let pointer = path.trim_start_matches('#');
    match root.pointer(pointer).and_then(Value::as_object) {
        Some(target) => resolved(root, target),
        None => schema.clone(),
    }
}

/// The `$ref` of an `anyOf` of one `$ref` and `{"type": "null"}` (an `Option` of a table).
fn optional_reference(schema: &Object) -> Option<&Value> {
    let any = schema.get("anyOf")?.as_array()?;
    let is_null = |v: &Value| v.get("type").and_then(Value::as_str) == Some("null");
    match any.as_slice() {
        [a, b] if is_null(b) => a.get("$ref"),
        [a, b] if is_null(a) => b.get("$ref"),
        _ => None,
    }
}

/// The string at `name` in `schema`.
fn text<'a>(schema: &'a Object, name: &str) -> Option<&'a str> {
    schema.get(name).and_then(Value::as_str)
}

/// The type of a value: `number`, `integer`, `string`, `boolean`, `number[2]`, `array of
/// string`, `table of number`, `string or array of number`.
fn kind(root: &Value, schema: &Object) -> String {
    if let Some(any) = schema.get("anyOf").or_else(|| schema.get("oneOf")) {
        let mut kinds: Vec<String> = Vec::new();
        for option in any.as_array().into_iter().flatten() {
            let option = option.as_object().cloned().unwrap_or_default();
            let one = kind(root, &resolved(root, &option));
            if !kinds.contains(&one) {
                kinds.push(one);
            }
        }
        return kinds.join(" or ");
    }
    let types: Vec<&str> = match schema.get("type") {
        Some(Value::String(one)) => vec![one.as_str()],
        Some(Value::Array(many)) => many.iter().filter_map(Value::as_str).collect(),
        _ => vec![],
    };
    let names: Vec<String> = types
        .into_iter()
        .filter(|&t| t != "null")
        .map(|t| match t {
            "array" => array_kind(root, schema),
            "object" => object_kind(root, schema),
            other => other.to_string(),
        })
        .collect();
    names.join(" or ")
}

/// `number[2]` (a fixed length) or `array of T`.
fn array_kind(root: &Value, schema: &Object) -> String {
    let items = schema.get("items").and_then(Value::as_object);
    let item = items.map_or_else(String::new, |i| kind(root, &resolved(root, i)));
    let (least, most) = (schema.get("minItems"), schema.get("maxItems"));
    match (least, most) {
        (Some(n), Some(m)) if n == m => format!("{item}[{n}]"),
        _ if item.is_empty() => "array".into(),
        _ => format!("array of {item}"),
    }
}

/// `table of T` (a map by name) or `table`.
fn object_kind(root: &Value, schema: &Object) -> String {
    match schema
        .get("additionalProperties")
        .and_then(Value::as_object)
    {
        Some(values) => format!("table of {}", kind(root, &resolved(root, values))),
        None => "table".into(),
    }
}

/// The names and descriptions of an enum-like setting's values (none for other types).
fn variants(schema: &Object) -> Vec<(String, String)> {
    let options = schema.get("oneOf").and_then(Value::as_array);
    let constant = |option: &Value| {
        let name = option.get("const")?.as_str()?.to_string();
        let what = option.get("description").and_then(Value::as_str);
        Some((name, what.unwrap_or_default().to_string()))
    };
    options
        .map(|options| options.iter().filter_map(constant).collect())
        .unwrap_or_default()
}

/// The allowed values: the setting's names, else the bounds (`> 0`, `>= 0, <= 1`, ...).
fn allowed(schema: &Object, variants: &[(String, String)]) -> String {
    if !variants.is_empty() {
        let names: Vec<String> = variants
            .iter()
            .map(|(name, _)| format!("`\"{name}\"`"))
            .collect();
        return names.join(", ");
    }
    let bounds = [
        ("exclusiveMinimum", ">"),
        ("minimum", ">="),
        ("exclusiveMaximum", "<"),
        ("maximum", "<="),
    ];
    let mut rules: Vec<String> = bounds
        .iter()
        .filter_map(|(name, sign)| Some(format!("{sign} {}", schema.get(*name)?)))
        .collect();
    if let Some(items) = schema.get("items").and_then(Value::as_object) {
        let inner = allowed(items, &[]);
        if !inner.is_empty() {
            rules.push(format!("each {inner}"));
        }
    }
    if let Some(values) = schema
        .get("additionalProperties")
        .and_then(Value::as_object)
    {
        let inner = allowed(values, &[]);
        if !inner.is_empty() {
            rules.push(format!("each {inner}"));
        }
    }
    rules.join(", ")
}

/// The unit of a description: its first `[...]` outside code spans ("[Hz]", "[Nm/rad]").
fn unit(description: &str) -> String {
    let mut in_code = false;
    for (i, c) in description.char_indices() {
        match c {
            '`' => in_code = !in_code,
            '[' if !in_code => {
                let rest = &description[i + 1..];
                if let Some(end) = rest.find(']') {
                    return rest[..end].to_string();
                }
            }
            _ => {}
        }
    }
    String::new()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_unit_is_the_first_bracket_outside_code() {
        assert_eq!(unit("Foot rectangle `[min, max]` [m]."), "m");
        assert_eq!(unit("Rate [Hz], a multiple of [s]"), "Hz");
        assert_eq!(unit("No unit."), "");
    }

    #[test]
    fn bounds_are_written_as_rules() {
        let schema = serde_json::json!({"type": "number", "exclusiveMinimum": 0.0, "maximum": 1.0});
        let schema = schema.as_object().unwrap();
        assert_eq!(allowed(schema, &[]), "> 0.0, <= 1.0");
    }

    #[test]
    fn every_key_of_the_scenario_schema_has_a_row() {
        let page = markdown(&super::super::schema::json_schema());
        for key in [
            "`controller.contact.friction`",
            "`actuators.overrides`",
            "`disturbances[].force`",
            "`robot.description`",
            "`simulation.duration_s`",
            "`walking.capture_margin`",
            "`walking.command.forward_velocity`",
            "`walking.footsteps[].yaw`",
        ] {
            assert!(page.contains(key), "{key} missing");
        }
    }

    #[test]
    fn a_number_or_table_key_lists_the_tables_keys_with_their_defaults() {
        let page = markdown(&super::super::schema::json_schema());
        let row = |key: &str| {
            page.lines()
                .find(|line| line.starts_with(&format!("| `{key}` |")))
                .unwrap_or_else(|| panic!("{key} missing"))
                .to_string()
        };
        assert!(row("walking.capture_margin").contains("number or table"));
        assert!(row("walking.capture_margin.forward").contains("| `0.01` |"));
        assert!(row("walking.capture_margin.sideways").contains("| `0.0` |"));
        assert!(row("walking.max_recovery_steps").contains("| >= 1 |"));
    }
}
