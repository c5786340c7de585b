//! Laws: the labeling does not depend on where the region sits in space or on its size.

mod common;

use common::{arc, pattern, polygon_region};
use nalgebra::{Rotation3, Vector3};
use proptest::prelude::*;
use trim_label::{LabelParams, label_region};

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 24,
        rng_seed: proptest::test_runner::RngSeed::Fixed(7),
        ..ProptestConfig::default()
    })]

    /// A rectangle with a rounded concave cut, rotated, scaled and moved in 3D, keeps its
    /// (4, 4) labeling with the same pattern and a virtual corner at the cut-off corner.
    #[test]
    fn labels_are_invariant_under_similarity(
        ax in -3.0f64..3.0, ay in -3.0f64..3.0, az in -3.0f64..3.0,
        scale in 0.01f64..100.0,
        tx in -1e3f64..1e3,
        aspect in 0.4f64..2.5,
    ) {
        let (w, h) = (10.0, 10.0 * aspect);
        let pieces = vec![
            vec![[0.0, 0.0], [w, 0.0]],
            vec![[w, 0.0], [w, h]],
            vec![[w, h], [1.5, h]],
            arc([0.0, h], 1.5, 0.0, -90.0, 12),
            vec![[0.0, h - 1.5], [0.0, 0.0]],
        ];
        let (mut mesh, segs) = polygon_region(&pieces, 0.3);
        let r = Rotation3::from_euler_angles(ax, ay, az);
        for p in &mut mesh.positions {
            *p = r * (*p * scale) + Vector3::new(tx, -tx, 0.5 * tx);
        }
        let l = label_region(&mesh, Some(&segs), &LabelParams::default()).unwrap();
        prop_assert_eq!((l.labels, l.corner_count), (4, 4));
        prop_assert_eq!(pattern(&l), "abc-d");
        let v = l.corners.iter().find(|c| c.kind == trim_label::CornerKind::Virtual).unwrap();
        let expect = r * (nurbs_core::Point3::new(0.0, h, 0.0) * scale) + Vector3::new(tx, -tx, 0.5 * tx);
        prop_assert!((v.position.unwrap() - expect).norm() < 1e-6 * scale * w.max(h));
    }
}
