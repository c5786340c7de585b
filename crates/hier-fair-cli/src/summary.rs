//! A readable summary of a surface: shape of the net, domain, extent, curvature ranges, energy.
//! `hier-fair demo` prints it for the bundled surface; `xtask` snapshots it (rounded) for the
//! fixtures.

use std::fmt::Write as _;

use nurbs_core::energy::thin_plate_energy;
use nurbs_core::{BSplineSurface, GridOrder};
use serde::Serialize;

/// Samples per direction of the summary's curvature scan.
pub(crate) const SUMMARY_GRID: usize = 201;

/// Figures describing a surface.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct SurfaceSummary {
    /// degrees (u, v)
    pub degrees: [usize; 2],
    /// control net (n_u, n_v)
    pub control_net: [usize; 2],
    /// rational or not
    pub rational: bool,
    /// domain [[u0, u1], [v0, v1]]
    pub domain: [[f64; 2]; 2],
    /// distinct interior knots (u, v)
    pub interior_knots: [usize; 2],
    /// bounding box of the sampled surface [min, max]
    pub bounding_box: [[f64; 3]; 2],
    /// smallest and largest k2, k1 over the samples
    pub k_range: [f64; 2],
    /// smallest and largest mean curvature
    pub mean_range: [f64; 2],
    /// smallest and largest Gaussian curvature
    pub gauss_range: [f64; 2],
    /// samples without a normal (singular points)
    pub singular_samples: usize,
    /// samples taken
    pub samples: usize,
    /// thin-plate energy
    pub thin_plate_energy: f64,
}

fn range(it: impl Iterator<Item = f64>) -> [f64; 2] {
    it.fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], x| {
        [lo.min(x), hi.max(x)]
    })
}

/// Samples `surface` on a `SUMMARY_GRID²` grid and collects the figures.
pub fn summarize(surface: &BSplineSurface) -> SurfaceSummary {
    let us = surface.knots_u().uniform_params(SUMMARY_GRID);
    let vs = surface.knots_v().uniform_params(SUMMARY_GRID);
    let samples = surface.par_eval_grid_with(&us, &vs, GridOrder::Second, |d| {
        (d.point, d.curvature_values())
    });
    let curv: Vec<_> = samples.iter().filter_map(|(_, c)| *c).collect();
    let mut bbox = [[f64::INFINITY; 3], [f64::NEG_INFINITY; 3]];
    for (p, _) in &samples {
        for c in 0..3 {
            bbox[0][c] = bbox[0][c].min(p[c]);
            bbox[1][c] = bbox[1][c].max(p[c]);
        }
    }
    let k2 = range(curv.iter().map(|c| c.k2));
    let k1 = range(curv.iter().map(|c| c.k1));
    SurfaceSummary {
        degrees: [surface.degree_u(), surface.degree_v()],
        control_net: [surface.num_u(), surface.num_v()],
        rational: surface.is_rational(),
        domain: [surface.domain_u().into(), surface.domain_v().into()],
        interior_knots: [
            surface.knots_u().interior_knots().len(),
            surface.knots_v().interior_knots().len(),
        ],
        bounding_box: bbox,
        k_range: [k2[0], k1[1]],
        mean_range: range(curv.iter().map(|c| c.mean)),
        gauss_range: range(curv.iter().map(|c| c.gauss)),
        singular_samples: samples.len() - curv.len(),
        samples: samples.len(),
        thin_plate_energy: thin_plate_energy(surface),
    }
}

/// The summary as aligned text for people.
pub fn render(name: &str, s: &SurfaceSummary, seconds: f64) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "surface            {name}");
    let _ = writeln!(
        out,
        "degrees (u, v)     {} × {}{}",
        s.degrees[0],
        s.degrees[1],
        if s.rational {
            " (rational)"
        } else {
            " (polynomial)"
        }
    );
    let _ = writeln!(
        out,
        "control net        {} × {}",
        s.control_net[0], s.control_net[1]
    );
    let _ = writeln!(
        out,
        "interior knots     {} in u, {} in v",
        s.interior_knots[0], s.interior_knots[1]
    );
    let _ = writeln!(
        out,
        "domain             u ∈ [{}, {}], v ∈ [{}, {}]",
        s.domain[0][0], s.domain[0][1], s.domain[1][0], s.domain[1][1]
    );
    let b = &s.bounding_box;
    let _ = writeln!(
        out,
        "bounding box       [{:.3}, {:.3}, {:.3}] – [{:.3}, {:.3}, {:.3}]",
        b[0][0], b[0][1], b[0][2], b[1][0], b[1][1], b[1][2]
    );
    let _ = writeln!(
        out,
        "principal k        {:+.6e} … {:+.6e}",
        s.k_range[0], s.k_range[1]
    );
    let _ = writeln!(
        out,
        "mean curvature H   {:+.6e} … {:+.6e}",
        s.mean_range[0], s.mean_range[1]
    );
    let _ = writeln!(
        out,
        "Gauss curvature K  {:+.6e} … {:+.6e}",
        s.gauss_range[0], s.gauss_range[1]
    );
    let _ = writeln!(
        out,
        "singular samples   {} of {}",
        s.singular_samples, s.samples
    );
    let _ = writeln!(out, "thin-plate energy  {:.6e}", s.thin_plate_energy);
    let _ = writeln!(
        out,
        "evaluation         {} points with derivatives and curvatures in {:.1} ms",
        s.samples,
        seconds * 1e3
    );
    out
}
