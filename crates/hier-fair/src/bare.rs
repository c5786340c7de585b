//! One surface faired on its own, with no links: its boundary frames fixed (\[SV\] §3.1), one
//! [`SurfaceFairing`] method, the result checked against the problem's contract
//! ([`FairingProblem::solve`]) and kept only where it is fairer than the input — a fairing ends
//! fairer than it started or not at all. The `fair` command's bare surface files and the Python
//! module's `fair_surface` both run this.

use nurbs_core::{
    BSplineSurface, Continuity, ControlMask, FairingProblem, FairingReport, SurfaceFairing,
};

use crate::error::{Error, Result};

/// The mask that fixes the frame of `keep` (G0: the boundary rows, G1 two rows, G2 three) on all
/// four sides of `surface`; an error where no control point would be left free.
pub fn boundary_mask(surface: &BSplineSurface, keep: Continuity) -> Result<ControlMask> {
    let rows = keep.frame().rows();
    let need = 2 * rows + 1;
    if surface.num_u() < need || surface.num_v() < need {
        return Err(Error::Format {
            detail: format!(
                "the surface has {}×{} control points: too few to keep {keep:?} on all four sides ({need}×{need} needed to leave a point free)",
                surface.num_u(),
                surface.num_v()
            ),
        });
    }
    Ok(ControlMask::with_boundary_frame(surface, keep.frame()))
}

/// Fixes in `mask` (of `prepared`, `original` after knot insertion) the three columns at each of
/// `original`'s own tangent-continuous C0 knot lines (rational arcs joined by double knots), as
/// the framework's stages keep them: a fairing that moved them would crease the surface there.
pub fn fix_smooth_joins(
    original: &BSplineSurface,
    prepared: &BSplineSurface,
    mask: &mut ControlMask,
) {
    let g1 = crate::ModelTolerances::default().g1_deg;
    for (i, j) in crate::framework::smooth_join_points(original, prepared, g1) {
        mask.set_free(i, j, false);
    }
}

/// The mask of `surface` faired alone keeping `keep` on all four sides: its boundary frames
/// ([`boundary_mask`]) and its smooth joins ([`fix_smooth_joins`]) fixed.
pub fn alone_mask(surface: &BSplineSurface, keep: Continuity) -> Result<ControlMask> {
    let mut mask = boundary_mask(surface, keep)?;
    fix_smooth_joins(surface, surface, &mut mask);
    Ok(mask)
}

/// A surface faired alone: the surface kept (the input, where the method raised the energy),
/// the method's report, and why the input was kept where it was.
#[derive(Debug, Clone)]
pub struct FairedAlone {
    /// the result: the faired surface, or the input where the fairing raised its energy
    pub surface: BSplineSurface,
    /// the method's report (energies, deviation and iterations of its own result)
    pub report: FairingReport,
    /// why the input was kept (the method raised the thin-plate energy); `None`: faired
    pub kept: Option<String>,
}

/// Fairs `surface` moving only what `mask` frees, every control point within `tolerance`
/// (model units) of its place, with `method`; a result that moves a fixed point or leaves the
/// tolerance is an error, never an output.
pub fn fair_alone(
    surface: &BSplineSurface,
    mask: &ControlMask,
    tolerance: f64,
    method: &dyn SurfaceFairing,
) -> Result<FairedAlone> {
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(Error::BadTolerance {
            name: "tolerance",
            value: tolerance,
        });
    }
    let (faired, report) = FairingProblem::new(surface, mask, tolerance).solve(method)?;
    let raised = report.energy_after > report.energy_before;
    let kept = raised.then(|| {
        format!(
            "{} raised the thin-plate energy from {:.4e} to {:.4e}: kept as it was",
            report.method, report.energy_before, report.energy_after
        )
    });
    Ok(FairedAlone {
        surface: if raised { surface.clone() } else { faired },
        report,
        kept,
    })
}
