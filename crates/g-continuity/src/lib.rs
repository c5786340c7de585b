//! # g-continuity
//!
//! Numerical G0/G1/G2 continuity between a *slave* B-spline surface and its *masters* (Salvi–
//! Várady, \[SV\] §3.1, §3.3, §4): measuring it ([`SideLink::measure`], or [`measure_link`] with
//! the master first: gap, normal angle, relative and absolute normal-curvature difference in the
//! slave's cross-boundary direction) and setting it by moving the slave's frames only — row 0
//! for C0, row 1 for G1 (\[SV\] §4.1), row 2 for G2 (\[SV\] §4.2) — with consistent twists
//! (\[SV\] §3.3) and knot insertion for more freedom ([`connect_slave`]). Masters are found by
//! projection, so they may be trimmed.
//!
//! ```
//! use g_continuity::{ConnectParams, MeasureParams, SideLink, connect_slave, measure_link};
//! use nurbs_core::{Continuity, Point3, Side, Vector3, shapes::plane_patch};
//! // a slave plane that starts on the master's edge x = 1 but is bent up by 10°
//! let master = plane_patch(Point3::origin(), Vector3::x(), Vector3::y(), (0.0, 1.0), (0.0, 1.0))
//!     .unwrap();
//! let (c, s) = (10f64.to_radians().cos(), 10f64.to_radians().sin());
//! let slave = plane_patch(Point3::new(1.0, 0.0, 0.0), Vector3::new(c, 0.0, s), Vector3::y(),
//!     (0.0, 1.0), (0.0, 1.0)).unwrap();
//! let before = measure_link(&master, &slave, Side::U0, &MeasureParams::default()).unwrap();
//! assert!(before.g0 < 1e-12 && before.g1_deg.unwrap() > 9.9);
//! // set G1 along the slave's side u = 0: only its first two control rows move
//! let link = SideLink { side: Side::U0, master: &master, target: Continuity::G1, range: None, g2_zones: [0.0; 2] };
//! let (set, report) = connect_slave(&slave, &[link], &ConnectParams::default()).unwrap();
//! assert!(report.sides[0].met);
//! let after = measure_link(&master, &set, Side::U0, &MeasureParams::default()).unwrap();
//! assert!(after.g1_deg.unwrap() < 0.01);
//! ```
//!
//! Surfaces from your own control points: a flat bilinear master and a bicubic Bézier slave
//! (a 4 × 4 net, i over u) that starts on its edge x = 1 but rises with slope 0.1, set G1.
//!
//! ```
//! use g_continuity::{ConnectParams, MeasureParams, SideLink, connect_slave};
//! use nurbs_core::{BSplineSurface, Continuity, KnotVector, Point3, Side};
//! let net = |n: usize, x0: f64, slope: f64| -> Vec<Point3> {
//!     let at = |i: usize, j: usize| {
//!         let x = x0 + i as f64 / (n - 1) as f64;
//!         Point3::new(x, j as f64 / (n - 1) as f64, slope * (x - x0))
//!     };
//!     (0..n * n).map(|r| at(r / n, r % n)).collect()
//! };
//! let (k1, k3) = (KnotVector::bezier(1).unwrap(), KnotVector::bezier(3).unwrap());
//! let master = BSplineSurface::new(k1.clone(), k1, net(2, 0.0, 0.0), None).unwrap();
//! let slave = BSplineSurface::new(k3.clone(), k3, net(4, 1.0, 0.1), None).unwrap();
//! let link = SideLink { side: Side::U0, master: &master, target: Continuity::G1, range: None, g2_zones: [0.0; 2] };
//! let (set, report) = connect_slave(&slave, &[link], &ConnectParams::default()).unwrap();
//! assert!(report.sides[0].met);
//! let after = link.measure(&set, &MeasureParams::default()).unwrap();
//! assert!(after.g0 < 1e-9 && after.g1_deg.unwrap() < 0.01);
//! // row 0 stays on the master's edge: the slave's corner control points there do not move
//! assert_eq!(set.control_points()[0], slave.control_points()[0]);
//! ```
//!
//! Two surfaces read from the JSON format of `docs/model-format.md`: the link named by a
//! [`SideLink`] (the slave's side, its master, the target) and measured with
//! [`SideLink::measure`] — the slave passed by name, so the order of the two surfaces cannot
//! be mixed up ([`measure_link`] takes the master first):
//!
//! ```
//! use g_continuity::{MeasureParams, SideLink};
//! use nurbs_core::{Continuity, Side, io::surfaces_from_json};
//! // a flat master over x ∈ [0, 1] and a slave over x ∈ [1, 2] that starts on its edge x = 1
//! // and rises with slope 0.1 (a kink of 5.7°)
//! let json = r#"[
//!   {"degree_u": 1, "degree_v": 1, "control_points": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 0]]]},
//!   {"degree_u": 1, "degree_v": 1, "control_points": [[[1, 0, 0], [1, 1, 0]], [[2, 0, 0.1], [2, 1, 0.1]]]}
//! ]"#;
//! let s = surfaces_from_json(json).unwrap();
//! let link = SideLink { side: Side::U0, master: &s[0], target: Continuity::G1, range: None, g2_zones: [0.0; 2] };
//! let m = link.measure(&s[1], &MeasureParams::default()).unwrap();
//! assert!(m.g0 < 1e-12);
//! assert!((m.g1_deg.unwrap() - 0.1f64.atan().to_degrees()).abs() < 1e-6);
//! ```
//!
//! The crate depends on nurbs-core only; it knows nothing of models or hierarchy order (that is
//! hier-fair's job). References (keys in brackets) are listed in `docs/references.md`.

pub mod error;
pub mod joint;
mod knots;
mod ladder;
pub mod lead_in;
mod link;
pub mod lsq;
pub mod measure;
mod memo;
pub mod params;
pub mod rows;
pub mod sampling;
pub mod section;
pub mod slave;
mod system;
pub mod transfer;

pub use error::{Error, Result};
pub use joint::{JointReport, polish_joint};
pub use knots::{new_breakpoints, new_knots};
pub use lead_in::{LEAD_IN_DEGREE, LeadInReport, MAX_LEAD_IN, with_lead_in};
pub use link::SideLink;
pub use measure::{LinkMeasure, MeasureParams, SampleMeasure, measure_link};
pub use params::{ConnectParams, G2Method, SetParams, Tolerances};
pub use section::{MAX_RAMP, RampShape, one_hump_section, one_hump_section_by_sections};
pub use slave::{
    C0_FOR_G1_SHARE, ConnectReport, SideReport, StepReport, connect_slave,
    degenerate_corner_blocks, prepare_slave, set_g0, set_g1, set_g2, set_rows, set_step,
};
pub use transfer::{TransferReport, with_master_knots};
