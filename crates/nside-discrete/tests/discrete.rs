//! Discrete fairing against closed-form truth: planes stay planes, the paraboloid is in the
//! solution space, a sphere hole comes back close to the sphere.

use nside_discrete::{DiscreteFairingParams, MeshTopology, NsideError, fair_mesh, ring_distance};
use nurbs_core::shapes::{paraboloid_bicubic, sphere_patch};
use nurbs_core::testing::rng;
use nurbs_core::{Point3, TriMesh, Vector3};
use rand::Rng;

/// A planar regular n-gon of radius 1, `rings` rings of n·k vertices, fan-free triangulation.
fn ngon(n: usize, rings: usize) -> TriMesh {
    let mut positions = vec![Point3::origin()];
    let mut faces = Vec::new();
    let mut ring_start = vec![0usize];
    for k in 1..=rings {
        ring_start.push(positions.len());
        let count = n * k;
        for s in 0..count {
            // along the polygon's edges: corner c, fraction t
            let c = s / k;
            let t = (s % k) as f64 / k as f64;
            let a = 2.0 * std::f64::consts::PI * c as f64 / n as f64;
            let b = 2.0 * std::f64::consts::PI * (c + 1) as f64 / n as f64;
            let r = k as f64 / rings as f64;
            positions.push(Point3::new(
                r * ((1.0 - t) * a.cos() + t * b.cos()),
                r * ((1.0 - t) * a.sin() + t * b.sin()),
                0.0,
            ));
        }
    }
    // triangulate between ring k−1 and ring k, side by side
    for k in 1..=rings {
        for c in 0..n {
            for s in 0..k {
                let outer = |m: usize| ring_start[k] + (c * k + m) % (n * k);
                let inner = |m: usize| {
                    if k == 1 {
                        0
                    } else {
                        ring_start[k - 1] + (c * (k - 1) + m) % (n * (k - 1))
                    }
                };
                faces.push([inner(s), outer(s), outer(s + 1)]);
                if s + 1 < k {
                    faces.push([inner(s), outer(s + 1), inner(s + 1)]);
                }
            }
        }
    }
    TriMesh {
        positions,
        normals: Vec::new(),
        faces,
    }
}

#[test]
fn planar_ngons_stay_planar() {
    for n in 3..=8 {
        let mesh = ngon(n, 8);
        let topo = MeshTopology::new(&mesh).unwrap();
        assert_eq!(mesh.boundary_loops().len(), 1, "n = {n}");
        let dist = ring_distance(&topo);
        // lift the free interior out of the plane; the fixed rings stay planar
        let mut noisy = mesh.clone();
        let mut r = rng(n as u64);
        for (p, &d) in noisy.positions.iter_mut().zip(&dist) {
            if d > 2 {
                p.z += r.random_range(-0.2..0.2);
                p.x += r.random_range(-0.01..0.01);
            }
        }
        let (faired, report) = fair_mesh(&noisy, &[], &DiscreteFairingParams::default()).unwrap();
        assert!(report.free_vertices > 0);
        assert!(report.energy_after < report.energy_before);
        let worst = faired
            .positions
            .iter()
            .map(|p| p.z.abs())
            .fold(0.0, f64::max);
        assert!(worst <= 1e-9, "n = {n}: |z| up to {worst}");
    }
}

#[test]
fn paraboloid_hole_is_reproduced_exactly() {
    let s = paraboloid_bicubic(&[0.3, 0.6]).unwrap();
    let exact = TriMesh::from_surface(&s, 41, 41);
    let topo = MeshTopology::new(&exact).unwrap();
    let dist = ring_distance(&topo);
    let mut noisy = exact.clone();
    let mut r = rng(11);
    for (p, &d) in noisy.positions.iter_mut().zip(&dist) {
        if d > 2 {
            *p += Vector3::new(
                r.random_range(-0.02..0.02),
                r.random_range(-0.02..0.02),
                r.random_range(-0.1..0.1),
            );
        }
    }
    let (faired, _) = fair_mesh(&noisy, &[], &DiscreteFairingParams::default()).unwrap();
    let size = 2.0 * 2f64.sqrt();
    for (a, b) in faired.positions.iter().zip(&exact.positions) {
        assert!((a - b).norm() <= 1e-6 * size, "{a:?} vs {b:?}");
    }
}

#[test]
fn sphere_hole_comes_back_near_the_sphere() {
    let radius = 10.0;
    let s = sphere_patch(radius).unwrap();
    let mesh = TriMesh::from_surface(&s, 41, 41);
    // the hole: grid cells 12..=28 in both directions; everything else is fixed
    let inside = |k: usize| {
        let (a, b) = (k / 41, k % 41);
        (12..=28).contains(&a) && (12..=28).contains(&b)
    };
    let fixed: Vec<usize> = (0..mesh.positions.len()).filter(|&k| !inside(k)).collect();
    let mut flat = mesh.clone();
    for (k, p) in flat.positions.iter_mut().enumerate() {
        if inside(k) {
            *p = Point3::from(p.coords * 0.97); // sink the hole by 3 % of the radius
        }
    }
    let (faired, report) = fair_mesh(
        &flat,
        &fixed,
        &DiscreteFairingParams {
            fixed_rings: 0,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(report.free_vertices, 17 * 17);
    let worst = faired
        .positions
        .iter()
        .map(|p| (p.coords.norm() - radius).abs())
        .fold(0.0, f64::max);
    assert!(
        worst <= 0.01 * radius,
        "deviation {worst} of radius {radius}"
    );
}

#[test]
fn bad_meshes_are_errors() {
    let mut m = ngon(4, 3);
    m.faces.push([0, 1, 2]); // a directed edge used twice
    assert!(matches!(
        fair_mesh(&m, &[], &DiscreteFairingParams::default()),
        Err(NsideError::NotManifold { .. })
    ));
    let mut m = ngon(4, 3);
    m.faces.push([0, 1, 999]);
    assert!(matches!(
        fair_mesh(&m, &[], &DiscreteFairingParams::default()),
        Err(NsideError::BadFace { .. })
    ));
    let mut m = ngon(5, 3);
    m.positions[3].y = f64::NAN;
    assert!(matches!(
        fair_mesh(&m, &[], &DiscreteFairingParams::default()),
        Err(NsideError::NonFinite { index: 3 })
    ));
    let m = ngon(5, 3);
    assert!(matches!(
        fair_mesh(&m, &[10_000], &DiscreteFairingParams::default()),
        Err(NsideError::FixedIndex { .. })
    ));
    // a closed tetrahedron has no boundary: nothing is fixed
    let tet = TriMesh {
        positions: vec![
            Point3::new(0., 0., 0.),
            Point3::new(1., 0., 0.),
            Point3::new(0., 1., 0.),
            Point3::new(0., 0., 1.),
        ],
        normals: vec![],
        faces: vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
    };
    assert!(matches!(
        fair_mesh(&tet, &[], &DiscreteFairingParams::default()),
        Err(NsideError::NothingFixed)
    ));
}

/// The data term: a noisy planar hexagon faired with a positive data weight moves less (in the
/// sum of squared moves, which Tikhonov regularization makes monotone in the weight) than with
/// pure fairing and less the larger the weight, while its umbrella energy still drops; with a
/// huge weight the mesh stays put.
#[test]
fn data_term_keeps_the_mesh_near_its_input() {
    let mut mesh = ngon(6, 8);
    let mut r = rng(21);
    let boundary_start = mesh.positions.len() - 6 * 8;
    for p in mesh.positions[..boundary_start].iter_mut() {
        p.z += r.random_range(-0.05..0.05);
    }
    let mut moves = Vec::new();
    for w in [0.0, 0.01, 1.0, 1e6] {
        let (out, report) = fair_mesh(
            &mesh,
            &[],
            &DiscreteFairingParams {
                fixed_rings: 0,
                data_weight: w,
                ..Default::default()
            },
        )
        .unwrap();
        assert!(
            report.energy_after < report.energy_before,
            "w {w}: {} -> {}",
            report.energy_before,
            report.energy_after
        );
        let squared: f64 = out
            .positions
            .iter()
            .zip(&mesh.positions)
            .map(|(a, b)| (a - b).norm_squared())
            .sum();
        moves.push(squared);
    }
    assert!(moves.windows(2).all(|m| m[1] < m[0]), "{moves:?}");
    assert!(moves[3] < 1e-8 * moves[0], "{moves:?}");
}
