//! The `hier-fair` command line as a library: every subcommand is a function from parsed
//! arguments to output, so that tests and `xtask` drive it without spawning processes.
//! This crate (with `xtask`) is the only place with argument parsing, files and `anyhow`.

pub mod check;
pub mod connect;
pub mod eval;
pub mod exchange;
pub mod fair;
pub mod files;
pub mod label;
pub mod mesh;
pub mod pipeline;
pub mod summary;

/// A bundled surface (the hood panel of `fixtures/surfaces/`), for examples and tests.
pub const BUNDLED_SURFACE: &str = include_str!("../../../fixtures/surfaces/hood_panel.json");
