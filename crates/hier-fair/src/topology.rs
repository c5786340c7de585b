//! Where surfaces meet: the sampling rules that decide whether a side lies on another surface's
//! side, in which part of an assembly a surface is, and how densely a join is sampled. The
//! hierarchy finder ([`crate::build`]), the shared edges ([`crate::edges`]), the bare patches'
//! shared sides ([`crate::patches`]) and the framework's kept frames ([`crate::framework`]) all
//! read them here, below every one of them.

use nurbs_core::{BSplineSurface, Side};

use crate::model::Model;

/// Points sampled along each side, both ends included (an end touches every surface of its
/// vertex, which does not make the side lie on them: the largest gap decides). 17 points put
/// one in every sixteenth of the side: a trimmed-off end (a fillet running past its face) is
/// seen.
pub const SIDE_SAMPLES: usize = 17;

/// Largest normal angle (degrees) along a shared edge at which the two patches count as meeting
/// tangentially, so that their tangency is kept. A designed tangent join is within a few
/// thousandths of a degree (a Bézier teapot's 1.7e-6°, a CAD export's 1e-4°); a crease between
/// patches is meant as one and is tens of degrees; 1° is the angle below which CAD systems'
/// checkers call an edge smooth.
pub const TANGENT_EDGE_DEG: f64 = 1.0;

/// Samples along a slave side lying inside its master whose knot spans the master keeps
/// (the framework's interior join points, and the points of a surface carrying a shared edge
/// in [`crate::edges`]): 64 intervals, so a master span is skipped only when the join crosses
/// it in less than 1/64 of the side — and a span crossed that briefly is also held by its
/// neighbours' supports, which overlap it by p of its control points.
pub const JOIN_SAMPLES: usize = 64;

/// Samples along a side, ends included, that must lie on another surface's boundary curve for
/// the side to lie on that side ([`lies_on_side`]): the two ends and the quarter points. It
/// tells a side that runs along the boundary from one that meets it at a vertex and leaves it;
/// a side that leaves the boundary over less than a quarter of its length (a trimmed-off end)
/// can pass it, which is why the hierarchy finder samples [`SIDE_SAMPLES`] instead.
pub const ON_SIDE_SAMPLES: usize = 5;

/// Whether `slave`'s side `slave_side` lies on `master`'s boundary side `master_side`:
/// [`ON_SIDE_SAMPLES`] samples along the slave side are within `tol` of the master's exact
/// boundary isocurve. A slave side that lies inside a (trimmed) master is on no side.
pub fn lies_on_side(
    slave: &BSplineSurface,
    slave_side: Side,
    master: &BSplineSurface,
    master_side: Side,
    tol: f64,
) -> bool {
    let cross = master_side.boundary_param(master);
    let Ok(curve) = master.isocurve(master_side.cross_direction(), cross) else {
        return false;
    };
    let Ok(ts) = g_continuity::sampling::uniform_side_params(slave, slave_side, ON_SIDE_SAMPLES)
    else {
        return false;
    };
    let params = nurbs_core::ProjectionParams::default();
    ts.into_iter().all(|t| {
        let (u, v) = slave_side.params(slave, t);
        let p = slave.derivatives(u, v).point;
        nurbs_core::projection::project_to_curve(&curve, &p, &params).distance <= tol
    })
}

/// The box of `s`'s control points, grown by `grow` on every side.
pub fn net_box(s: &BSplineSurface, grow: f64) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in s.control_points() {
        for d in 0..3 {
            lo[d] = lo[d].min(p[d] - grow);
            hi[d] = hi[d].max(p[d] + grow);
        }
    }
    (lo, hi)
}

/// Whether surfaces `a` and `b` belong to different parts of an assembly: two parts that
/// merely touch are not one surface model, and no link joins them.
pub fn other_part(model: &Model, a: usize, b: usize) -> bool {
    match (&model.surfaces[a].part, &model.surfaces[b].part) {
        (Some(x), Some(y)) => x != y,
        _ => false,
    }
}
