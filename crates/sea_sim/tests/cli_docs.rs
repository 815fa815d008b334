//! docs/reference/cli.md against the binary: every flag `sea-sim COMMAND --help` lists is in
//! that command's section of the page, and every command has a section.

use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_sea-sim");
const REPO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

/// The commands the page documents (`schema` prints the scenario schema and is documented in
/// reference/scenario_keys.md).
const COMMANDS: [&str; 6] = ["run", "sweep", "margin", "push", "init", "bench"];

/// The long flags `sea-sim COMMAND --help` lists (without `--help`): on each line, what
/// stands before the description (the first run of two spaces) holds the flag names.
fn flags(command: &str) -> Vec<String> {
    let out = Command::new(BIN)
        .args([command, "--help"])
        .output()
        .unwrap();
    assert!(out.status.success(), "sea-sim {command} --help");
    let text = String::from_utf8(out.stdout).unwrap();
    let mut found = Vec::new();
    for line in text.lines().map(str::trim) {
        let names = line.split("  ").next().unwrap_or_default();
        for word in names.split([' ', ',']) {
            let Some(name) = word.strip_prefix("--") else {
                continue;
            };
            let name: String = name
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '-')
                .collect();
            if !name.is_empty() && name != "help" {
                found.push(format!("--{name}"));
            }
        }
    }
    found
}

/// Whether the page's `text` names `flag` in code: `` `--flag` `` or `` `--flag ARG` ``.
fn names(text: &str, flag: &str) -> bool {
    text.contains(&format!("`{flag}`")) || text.contains(&format!("`{flag} "))
}

/// The section of the page under the heading that starts with `` ## `sea-sim COMMAND ``.
fn section<'a>(page: &'a str, command: &str) -> &'a str {
    let heading = format!("## `sea-sim {command} ");
    let heading_bare = format!("## `sea-sim {command}`");
    let start = page
        .find(&heading)
        .or_else(|| page.find(&heading_bare))
        .unwrap_or_else(|| panic!("docs/reference/cli.md has no section for `sea-sim {command}`"));
    let rest = &page[start + 3..];
    &rest[..rest.find("\n## ").unwrap_or(rest.len())]
}

#[test]
fn every_flag_of_the_help_is_in_the_reference_page() {
    let page = std::fs::read_to_string(format!("{REPO}/docs/reference/cli.md")).unwrap();
    let mut missing = Vec::new();
    for command in COMMANDS {
        let text = section(&page, command);
        let listed = flags(command);
        assert!(!listed.is_empty(), "sea-sim {command} --help lists no flag");
        for flag in listed {
            if !names(text, &flag) {
                missing.push(format!("sea-sim {command} {flag}"));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "not in docs/reference/cli.md: {missing:?}"
    );
}
