//! `hier-fair` with `--method shrink`: each free point halfway to its neighbours' mean, within ε.
use nurbs_core::{Faired, FairingProblem, SurfaceFairing};

struct Shrink;
impl SurfaceFairing for Shrink {
    fn name(&self) -> &str {
        "shrink"
    }
    fn fair(&self, p: &FairingProblem<'_>) -> nurbs_core::Result<Faired> {
        let (mut surface, nu, nv) = (p.surface.clone(), p.surface.num_u(), p.surface.num_v());
        let at = |i: usize, j: usize| p.surface.control_points()[i * nv + j].coords;
        let inner = |&(i, j): &(usize, usize)| i > 0 && j > 0 && i + 1 < nu && j + 1 < nv;
        for (i, j) in p.mask.free_indices().filter(inner) {
            let mean = (at(i - 1, j) + at(i + 1, j) + at(i, j - 1) + at(i, j + 1)) / 4.0;
            let step = (mean - at(i, j)) * 0.5;
            surface.control_points_mut()[i * nv + j] += step * (p.tolerance / step.norm()).min(1.0);
        }
        Ok(Faired::new(surface, 1))
    }
}

fn main() -> std::process::ExitCode {
    let mut methods = hier_fair::MethodRegistry::builtin();
    let added = methods.register("shrink", "halfway to the mean", false, |_| Box::new(Shrink));
    added.expect("a new name");
    hier_fair_cli::cli::main_with(methods)
}
