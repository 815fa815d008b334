#[test]
fn write_schema() {
    std::fs::write(
        "/tmp/s3_schema.json",
        sea_scenario::schema::json_schema_text(),
    )
    .unwrap();
    std::fs::write(
        "/tmp/s3_keys.md",
        sea_scenario::reference::markdown(&sea_scenario::schema::json_schema()),
    )
    .unwrap();
}
