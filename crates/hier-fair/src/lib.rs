//! # hier-fair
//!
//! The model of `model-format.md` — primary, connecting and corner surfaces with continuity links,
//! corner groups and tolerances — and the framework order of Salvi–Várady ([SV] §1.1, §3.2):
//! masters before slaves, primaries first. [`check_model`] measures every link;
//! [`connect`] sets continuity slave by slave (no fairing) with g-continuity.
//!
//! This crate alone knows the hierarchy order and the model format; it takes and returns values
//! (JSON text, models, reports), never paths. References (keys in brackets) are listed in
//! `docs/references.md`.

pub mod build;
pub mod check;
pub mod connect;
pub mod corners;
pub mod error;
pub mod framework;
pub mod methods;
pub mod model;
pub mod patches;
pub mod plots;
pub mod render;
pub mod report;
pub mod synthetic;

pub use build::{BuildLog, build_hierarchy};
pub use check::{LinkCheck, Preset, TOUCH_FACTOR, check_model, measure_model};
pub use connect::{ConnectOptions, LinkConnect, ModelConnectReport, SurfaceConnect, connect};
pub use error::{Error, Result};
pub use framework::{
    FairModelReport, FairParams, LinkFair, Problem, ProblemKind, Progress, Stage, StageReport,
    SurfaceFair, fair_model, fair_model_with,
};
pub use methods::{BuiltMethods, Fairers, Method, RoleMethods};
pub use model::{CornerGroup, Link, Model, ModelSurface, ModelTolerances, Role, parse_continuity};
pub use report::{report_json, report_markdown, report_markdown_in};
