//! The n-sided corner stage of \[SV\] §3.4 in one call: sample the quads of a central split (with
//! the neighbours' wings), fair the mesh with Kobbelt's umbrella² energy (\[K97\]) keeping the
//! patch boundary, the wings and `fixed_rings` rings inside the patch, and refit the quads.
//!
//! [`fill_corner`] starts from the boundary curves instead: it builds the central split first,
//! taking the inward cross-boundary directions at the side midpoints from the neighbours.
//!
//! The fairing runs on the mesh with cotangent weights from its flat layout by default (see
//! [`NsidedParams::weights`]).
//!
//! Ring distances for `fixed_rings` are counted inside the patch from its boundary (wing vertices
//! are not crossed), so ring 1 is the first row of samples inside every quad.

use std::collections::VecDeque;

use nurbs_core::sparse::SpdSolver;
use nurbs_core::{BSplineCurve, BSplineSurface, Direction, Side, Vector3};

use crate::error::{NsideError, Result};
use crate::fairing::{
    DiscreteFairingParams, DiscreteFairingReport, UmbrellaWeights, fair_mesh_with_layout,
};
use crate::refit::{RefitReport, refit_quads};
use crate::sampling::{
    Neighbour, SampledCorner, SamplingParams, VertexOrigin, neighbour_params, sample_quads,
    side_params,
};
use crate::split::{CentralSplitParams, CentralSplitReport, central_split};

/// Settings of the n-sided corner stage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NsidedParams {
    /// central split settings (used by [`fill_corner`] only)
    pub split: CentralSplitParams,
    /// sampling and wing settings
    pub sampling: SamplingParams,
    /// Rings inside the patch, beyond its boundary, that keep their sampled positions. Default 0:
    /// with wings the neighbours' tangent planes enter through the wing rows; without neighbours
    /// use 2 to keep the initial quads' tangent planes and curvature (\[SV\] §3.4, \[K97\] §3).
    pub fixed_rings: usize,
    /// sparse solver of the fairing system (default: faer with AMD)
    pub solver: SpdSolver,
    /// Umbrella weights. Default: the cotangent operator of the mesh projected onto the plane of
    /// the boundary loop ([`SampledCorner::flat_layout`]). The uniform umbrella follows the
    /// quads' parametrization, whose n right angles at the centre make a cone for n ≠ 4 (a 50°
    /// sphere cap with n = 8 sinks by 3 % of the radius with uniform weights, 0.6 % with these);
    /// mean-value weights keep the plane's coordinates too but do not reproduce the paraboloid
    /// (2 % off against 0.2 %: they are not symmetric).
    pub weights: UmbrellaWeights,
    /// Data term of the fairing ([`DiscreteFairingParams::data_weight`]). Default 0.
    pub data_weight: f64,
}

impl Default for NsidedParams {
    fn default() -> Self {
        Self {
            split: CentralSplitParams::default(),
            sampling: SamplingParams::default(),
            fixed_rings: 0,
            solver: SpdSolver::DEFAULT,
            weights: UmbrellaWeights::Cotangent,
            data_weight: 0.0,
        }
    }
}

/// What the corner stage achieved.
#[derive(Debug, Clone, PartialEq)]
pub struct NsidedReport {
    /// the central split, when [`fill_corner`] built it
    pub split: Option<CentralSplitReport>,
    /// mesh vertices (wings included)
    pub mesh_vertices: usize,
    /// vertices kept fixed in the fairing
    pub fixed_vertices: usize,
    /// the discrete fairing
    pub fairing: DiscreteFairingReport,
    /// the refit
    pub refit: RefitReport,
}

/// Fairs the n-sided corner given as the quads of a central split (convention of
/// [`crate::split`]) with `neighbours[k]` across side k, and returns the refitted quads.
pub fn fair_corner(
    quads: &[BSplineSurface],
    neighbours: &[Option<Neighbour<'_>>],
    params: &NsidedParams,
) -> Result<(Vec<BSplineSurface>, NsidedReport)> {
    let sampled = sample_quads(quads, neighbours, &params.sampling)?;
    let fixed = fixed_vertices(&sampled, params.fixed_rings);
    let extra: Vec<usize> = (0..fixed.len()).filter(|&v| fixed[v]).collect();
    let fairing_params = DiscreteFairingParams {
        fixed_rings: 0,
        solver: params.solver,
        weights: params.weights,
        data_weight: params.data_weight,
    };
    let layout = sampled.flat_layout();
    let (faired, fairing) = fair_mesh_with_layout(&sampled.mesh, &layout, &extra, &fairing_params)?;
    let (out, refit) = refit_quads(quads, &sampled, &faired.positions, neighbours)?;
    Ok((
        out,
        NsidedReport {
            split: None,
            mesh_vertices: sampled.mesh.positions.len(),
            fixed_vertices: extra.len(),
            fairing,
            refit,
        },
    ))
}

/// Builds the central split of the hole bounded by `boundaries` (inward cross directions from
/// the neighbours where given) and fairs it with [`fair_corner`].
pub fn fill_corner(
    boundaries: &[BSplineCurve],
    neighbours: &[Option<Neighbour<'_>>],
    params: &NsidedParams,
) -> Result<(Vec<BSplineSurface>, NsidedReport)> {
    if neighbours.len() != boundaries.len() {
        return Err(NsideError::CountMismatch {
            what: "neighbours per side",
            expected: boundaries.len(),
            got: neighbours.len(),
        });
    }
    let tangents = cross_tangents(boundaries, neighbours)?;
    let (quads, split) = central_split(boundaries, Some(&tangents), &params.split)?;
    let (out, mut report) = fair_corner(&quads, neighbours, params)?;
    report.split = Some(split);
    Ok((out, report))
}

/// Direction into the hole across side k at its parametric midpoint, from the neighbour's
/// cross-boundary derivative (negated when the neighbour's interior lies at increasing cross
/// parameter); `None` for sides without a neighbour.
pub fn cross_tangents(
    boundaries: &[BSplineCurve],
    neighbours: &[Option<Neighbour<'_>>],
) -> Result<Vec<Option<Vector3>>> {
    boundaries
        .iter()
        .zip(neighbours)
        .map(|(c, nb)| {
            let Some(nb) = nb else { return Ok(None) };
            let (a, b) = c.domain();
            let m = c.point(0.5 * (a + b));
            let t = side_params(nb, std::iter::once(m))?[0];
            let (u, v) = neighbour_params(nb, t, 0.0);
            let d = nb.surface.derivatives(u, v);
            let cross = match nb.side.cross_direction() {
                Direction::U => d.du,
                Direction::V => d.dv,
            };
            // into the neighbour: +cross at U0/V0, −cross at U1/V1; into the hole: the opposite
            Ok(Some(if matches!(nb.side, Side::U0 | Side::V0) {
                -cross
            } else {
                cross
            }))
        })
        .collect()
}

/// Patch boundary, wings and the vertices within `rings` rings inside the patch.
fn fixed_vertices(sampled: &SampledCorner, rings: usize) -> Vec<bool> {
    let mut fixed = sampled.fixed.clone();
    if rings == 0 {
        return fixed;
    }
    let one_rings = sampled.mesh.one_rings();
    let n = fixed.len();
    let mut dist = vec![usize::MAX; n];
    let mut queue = VecDeque::new();
    for v in 0..n {
        if sampled.patch_boundary[v] {
            dist[v] = 0;
            queue.push_back(v);
        }
    }
    while let Some(v) = queue.pop_front() {
        if dist[v] >= rings {
            continue;
        }
        for &w in &one_rings[v] {
            if dist[w] == usize::MAX && matches!(sampled.origins[w], VertexOrigin::Quad { .. }) {
                dist[w] = dist[v] + 1;
                fixed[w] = true;
                queue.push_back(w);
            }
        }
    }
    fixed
}
