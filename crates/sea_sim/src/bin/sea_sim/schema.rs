//! `sea-sim schema`: the scenario file's JSON Schema, or the reference page of every key.

use crate::common::print_text;
use clap::Args;

/// Options of `sea-sim schema`.
#[derive(Args, Debug)]
pub(crate) struct SchemaArgs {
    /// Print the reference page of every key (Markdown; the shipped copy is
    /// docs/reference/scenario_keys.md) instead of the schema.
    #[arg(long)]
    markdown: bool,
}

/// `sea-sim schema`: the scenario file's JSON Schema, or its reference page, on stdout.
///
/// Errors: [`sea_sim::Error::Io`] on `stdout` when it cannot be written.
pub(crate) fn print_schema(args: &SchemaArgs) -> sea_sim::Result<()> {
    if args.markdown {
        let schema = sea_sim::scenario::schema::json_schema();
        print_text(sea_sim::scenario::reference::markdown(&schema))
    } else {
        print_text(sea_sim::scenario::schema::json_schema_text())
    }
}
