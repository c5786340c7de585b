//! # g-continuity
//!
//! Numerical G0/G1/G2 continuity between a *slave* B-spline surface and its *masters* (Salvi–
//! Várady, [SV] §3.1, §3.3, §4): measuring it ([`measure_link`]: gap, normal angle, relative and
//! absolute normal-curvature difference in the slave's cross-boundary direction) and setting it by
//! moving the slave's frames only — row 0 for C0, row 1 for G1 ([SV] §4.1), row 2 for G2
//! ([SV] §4.2) — with consistent twists ([SV] §3.3) and knot insertion for more freedom
//! ([`connect_slave`]). Masters are found by projection, so they may be trimmed.
//!
//! The crate depends on nurbs-core only; it knows nothing of models or hierarchy order (that is
//! hier-fair's job). References (keys in brackets) are listed in `docs/references.md`.

pub mod error;
pub mod lead_in;
pub mod lsq;
pub mod measure;
pub mod params;
pub mod rows;
pub mod sampling;
pub mod slave;
pub mod transfer;

pub use error::{Error, Result};
pub use lead_in::{LEAD_IN_DEGREE, LeadInReport, MAX_LEAD_IN, with_lead_in};
pub use measure::{LinkMeasure, MeasureParams, SampleMeasure, measure_link};
pub use params::{ConnectParams, G2Method, SetParams, Tolerances};
pub use slave::{
    C0_FOR_G1_SHARE, ConnectReport, SideLink, SideReport, StepReport, connect_slave,
    degenerate_corner_blocks, new_breakpoints, new_knots, prepare_slave, set_g0, set_g1, set_g2,
    set_rows, set_step,
};
pub use transfer::{TransferReport, with_master_knots};
