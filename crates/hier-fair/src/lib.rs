//! # hier-fair
//!
//! The model of `model-format.md` — primary, connecting and corner surfaces with continuity links,
//! corner groups and tolerances — and the framework order of Salvi–Várady (\[SV\] §1.1, §3.2):
//! masters before slaves, primaries first. [`check_model`] measures every link;
//! [`connect()`] sets continuity slave by slave (no fairing) with g-continuity.
//!
//! ```
//! use hier_fair::{FairParams, RoleMethods, check_model, fair_model, synthetic::block_grid};
//! // two filleted blocks: two primaries and the fillet between them (a connecting surface
//! // whose masters they are), faired in the framework order with the default energy method
//! let model = block_grid(2, 1).unwrap();
//! let (faired, report) =
//!     fair_model(&model, &RoleMethods::default(), None, &FairParams::default()).unwrap();
//! assert_eq!(faired.surfaces.len(), model.surfaces.len());
//! for s in &report.surfaces {
//!     assert!(s.max_deviation <= s.tolerance, "{}", s.name);
//! }
//! assert!(report.links.iter().all(|l| l.met));
//! let checks = check_model(&faired, &g_continuity::MeasureParams::default()).unwrap();
//! assert_eq!(checks.len(), model.links.len());
//! ```
//!
//! A model of surfaces from your own control points: a flat bilinear square as the primary and
//! a bicubic Bézier patch beside it (a 4 × 4 net, i over u) that starts on its edge x = 1 but
//! rises with slope 0.1 (a kink of 5.7°), linked G1 along its side u0 and connected.
//!
//! ```
//! use hier_fair::{ConnectOptions, Link, Model, Role, connect};
//! use nurbs_core::{BSplineSurface, Continuity, KnotVector, Point3, Side};
//! let net = |n: usize, x0: f64, slope: f64| -> Vec<Point3> {
//!     let at = |i: usize, j: usize| {
//!         let x = x0 + i as f64 / (n - 1) as f64;
//!         Point3::new(x, j as f64 / (n - 1) as f64, slope * (x - x0))
//!     };
//!     (0..n * n).map(|r| at(r / n, r % n)).collect()
//! };
//! let (k1, k3) = (KnotVector::bezier(1).unwrap(), KnotVector::bezier(3).unwrap());
//! let primary = BSplineSurface::new(k1.clone(), k1, net(2, 0.0, 0.0), None).unwrap();
//! let slave = BSplineSurface::new(k3.clone(), k3, net(4, 1.0, 0.1), None).unwrap();
//! let mut model = Model::from_primaries(vec![primary, slave]);
//! model.surfaces[1].role = Role::Connecting;
//! model.links.push(Link { slave: 1, side: Side::U0, master: 0, continuity: Continuity::G1 });
//! model.validate().unwrap();
//! let (connected, report) = connect(&model, &ConnectOptions::default()).unwrap();
//! let link = &report.links[0];
//! assert!((link.before.g1_deg.unwrap() - 0.1f64.atan().to_degrees()).abs() < 1e-6);
//! assert!(link.after.g0 < 1e-9 && link.after.g1_deg.unwrap() < 0.01, "{link:?}");
//! // the primary, a master, never moves
//! assert_eq!(connected.surfaces[0].surface, model.surfaces[0].surface);
//! ```
//!
//! A model of your own, from the JSON of `model-format.md`: two unit squares side by side, the
//! second a connecting surface linked G1 to the first along its side u0, checked.
//!
//! ```
//! let json = r#"{
//!   "surfaces": [
//!     {"name": "left", "role": "primary", "surface": {"degree_u": 1, "degree_v": 1,
//!       "control_points": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 0]]]}},
//!     {"name": "right", "role": "connecting", "surface": {"degree_u": 1, "degree_v": 1,
//!       "control_points": [[[1, 0, 0], [1, 1, 0]], [[2, 0, 0], [2, 1, 0]]]}}
//!   ],
//!   "links": [{"slave": "right", "side": "u0", "master": "left", "continuity": "G1"}]
//! }"#;
//! let model = hier_fair::Model::from_json(json).unwrap();
//! let checks =
//!     hier_fair::check_model(&model, &g_continuity::MeasureParams::default()).unwrap();
//! // the squares share their edge and are coplanar: no gap, no angle
//! let m = &checks[0].measure;
//! assert!(m.g0 < 1e-12 && m.g1_deg.unwrap() < 1e-9, "{}: {m:?}", checks[0].label);
//! ```
//!
//! This crate alone knows the hierarchy order and the model format; it takes and returns values
//! (JSON text, models, reports), never paths. References (keys in brackets) are listed in
//! `docs/references.md`.

pub mod bare;
pub mod build;
pub mod check;
pub mod connect;
pub mod corners;
pub mod edges;
pub mod error;
pub mod exchange;
pub mod fairness;
pub mod framework;
pub mod html;
pub mod methods;
pub mod model;
pub mod patches;
#[cfg(feature = "render")]
pub mod plots;
pub mod poles;
#[cfg(feature = "render")]
pub mod render;
pub mod report;
pub mod synthetic;
#[cfg(feature = "render")]
pub mod text;
pub mod topology;
pub mod trim;
pub mod zones;

pub use build::{BuildLog, build_hierarchy};
pub use check::{
    LinkCheck, Preset, SurfaceJoins, TOUCH_FACTOR, check_model, measure_model, surface_joins,
};
pub use connect::{ConnectOptions, LinkConnect, ModelConnectReport, SurfaceConnect, connect};
pub use error::{Error, Result};
pub use framework::{
    ENERGY_RISE_WHY, FairModelReport, FairParams, LinkFair, Problem, ProblemKind, Progress, Stage,
    StageReport, SurfaceFair, fair_model, fair_model_with,
};
pub use methods::{BuiltMethods, Fairers, Method, MethodEntry, MethodRegistry, RoleMethods};
pub use model::{CornerGroup, Link, Model, ModelSurface, ModelTolerances, Role, parse_continuity};
pub use report::{report_json, report_markdown, report_markdown_in};
