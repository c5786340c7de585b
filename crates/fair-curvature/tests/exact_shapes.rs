//! Acceptance: exact shapes stay put — a sphere patch or a cylinder faired with either method
//! moves by ≤ 1e-6 of its size.

mod common;

use common::*;
use fair_curvature::{GreinerFairing, GreinerParams, GreinerTarget, TargetCurvatureFairing};
use nurbs_core::{BSplineSurface, ControlMask, Frame, SurfaceFairing};

fn methods() -> Vec<Box<dyn SurfaceFairing>> {
    vec![
        Box::new(TargetCurvatureFairing::default()),
        Box::new(GreinerFairing::default()),
        Box::new(GreinerFairing {
            params: GreinerParams {
                target: GreinerTarget::MeanCurvature,
                ..GreinerParams::default()
            },
        }),
    ]
}

fn stays_put(s: &BSplineSurface, what: &str) {
    let size = s.size();
    for method in methods() {
        for mask in [
            ControlMask::for_surface(s),
            ControlMask::with_boundary_frame(s, Frame::Tangential),
        ] {
            let (out, report) = run(method.as_ref(), s, &mask, 0.01 * size);
            let moved = nurbs_core::max_displacement(s.control_points(), out.control_points());
            println!(
                "{what} {}: move {:.2e} of size",
                method.name(),
                moved / size
            );
            assert!(moved <= 1e-6 * size, "{what} {}: {moved:e}", method.name());
            assert!(report.max_deviation <= 1e-6 * size);
        }
    }
}

#[test]
fn sphere_patch_stays_put() {
    stays_put(&sphere(3.0, 6), "sphere");
}

#[test]
fn cylinder_stays_put() {
    stays_put(&cylinder(2.0, 5.0, 6), "cylinder");
}
