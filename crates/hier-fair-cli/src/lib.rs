//! The `hier-fair` command line as a library: every subcommand is a function from parsed
//! arguments to output, so that tests and `xtask` drive it without spawning processes.
//! This crate (with `xtask`) is the only place with argument parsing, files and `anyhow`.
//!
//! ```
//! use hier_fair_cli::eval::{evaluate, parse_grid};
//! use nurbs_core::shapes::cylinder;
//! // `hier-fair eval SURFACE --grid 5,3` without the files: a 5 × 3 grid on an exact quarter
//! // cylinder of radius 2, every sample on the cylinder
//! let s = cylinder(2.0, 10.0).unwrap();
//! let (samples, _seconds) = evaluate(&s, &parse_grid("5,3").unwrap()).unwrap();
//! assert_eq!(samples.len(), 15);
//! for p in &samples {
//!     let x = s.point(p.u, p.v);
//!     assert!((x.x.hypot(x.y) - 2.0).abs() < 1e-12);
//! }
//! assert!(parse_grid("0,3").is_err());
//! ```

// citation keys are written `\[SV\]` (docs/references.md): a bare `[SV]` is a broken link
#![deny(rustdoc::broken_intra_doc_links)]

pub mod applies;
pub mod check;
pub mod cli;
pub mod connect;
pub mod corner_views;
pub mod eval;
pub mod exchange;
pub mod fair;
pub mod files;
pub mod kind;
pub mod label;
pub mod mesh;
pub mod options;
pub mod pipeline;
pub mod summary;
pub mod values;
pub mod verdict;

/// The fairing methods `--method` names: the built-in ones unless [`cli::main_with`] was given
/// others.
static METHODS: std::sync::OnceLock<hier_fair::MethodRegistry> = std::sync::OnceLock::new();

/// The method registry of this program ([`cli::main_with`]; the built-in methods otherwise).
pub fn methods() -> &'static hier_fair::MethodRegistry {
    METHODS.get_or_init(hier_fair::MethodRegistry::builtin)
}

/// Sets the method registry before anything reads it; an error (giving it back) once set.
pub fn set_methods(methods: hier_fair::MethodRegistry) -> Result<(), hier_fair::MethodRegistry> {
    METHODS.set(methods)
}

/// A bundled surface (the hood panel of `fixtures/surfaces/`), for examples and tests.
pub const BUNDLED_SURFACE: &str = include_str!("../../../fixtures/surfaces/hood_panel.json");
