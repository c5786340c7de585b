//! A method registered by an embedding crate is what `--method NAME` runs (the registry of
//! [`hier_fair_cli::cli::main_with`]); an unknown name is one line naming the known ones.
//! (Its own test binary: the registry is set once per process.)

use hier_fair_cli::fair::{FairOptions, fair_surfaces};
use nurbs_core::{Continuity, Faired, FairingProblem, SurfaceFairing};

/// Moves every free control point by half of ε along +z.
struct Lift;

impl SurfaceFairing for Lift {
    fn name(&self) -> &str {
        "lift"
    }
    fn fair(&self, p: &FairingProblem<'_>) -> nurbs_core::Result<Faired> {
        let mut s = p.surface.clone();
        let nv = s.num_v();
        for (i, j) in p.mask.free_indices() {
            s.control_points_mut()[i * nv + j].z += 0.5 * p.tolerance;
        }
        Ok(Faired::new(s, 1))
    }
}

fn options(method: &'static str) -> FairOptions {
    FairOptions {
        method,
        tolerance: 0.02,
        iterations: None,
        keep: Continuity::G0,
    }
}

#[test]
fn a_registered_method_runs_under_its_name_and_an_unknown_one_is_named() {
    let mut methods = hier_fair::MethodRegistry::builtin();
    methods
        .register("lift", "moves free points up by ε/2", false, |_| {
            Box::new(Lift)
        })
        .unwrap();
    assert!(hier_fair_cli::set_methods(methods).is_ok());
    let input = nurbs_core::io::surfaces_from_json(hier_fair_cli::BUNDLED_SURFACE).unwrap();
    // the lift bends the free points against the fixed boundary rows: the bare-surface run
    // keeps a result with a higher thin-plate energy out (reported in `kept`), else takes it
    let (output, report) = fair_surfaces(&input, &options("lift")).unwrap();
    let line = &report.surfaces[0];
    assert_eq!(line.method, "lift");
    let dz: Vec<f64> = input[0]
        .control_points()
        .iter()
        .zip(output[0].control_points())
        .map(|(a, b)| b.z - a.z)
        .collect();
    if line.kept.is_some() {
        assert!(dz.iter().all(|&d| d == 0.0), "{line:?}");
        assert!(line.energy_after <= line.energy_before);
    } else {
        assert!(dz.iter().any(|&d| (d - 0.01).abs() < 1e-12), "{line:?}");
    }
    let e = fair_surfaces(&input, &options("smooth-everything")).unwrap_err();
    let text = format!("{e:#}");
    assert!(
        text.contains("unknown fairing method \"smooth-everything\"") && text.contains("lift"),
        "{text}"
    );
    assert!(!text.contains('\n'));
}
