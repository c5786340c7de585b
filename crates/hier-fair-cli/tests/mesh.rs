//! `hier-fair fair-mesh`: OBJ in, faired OBJ out, boundary kept, bad meshes rejected.

use std::process::Command;

use nurbs_core::TriMesh;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_hier-fair"))
}

fn noisy_obj(dir: &tempfile::TempDir) -> (std::path::PathBuf, TriMesh) {
    let s = nurbs_core::shapes::paraboloid_bicubic(&[]).unwrap();
    let mut m = TriMesh::from_surface(&s, 21, 21);
    for (k, p) in m.positions.iter_mut().enumerate() {
        p.z += 0.01 * ((k * 7919 % 13) as f64 - 6.0);
    }
    let path = dir.path().join("in.obj");
    let mut bytes = Vec::new();
    m.write_obj(&mut bytes).unwrap();
    std::fs::write(&path, bytes).unwrap();
    (path, m)
}

fn positions(text: &str) -> Vec<[f64; 3]> {
    text.lines()
        .filter(|l| l.starts_with("v "))
        .map(|l| {
            let c: Vec<f64> = l
                .split_whitespace()
                .skip(1)
                .map(|x| x.parse().unwrap())
                .collect();
            [c[0], c[1], c[2]]
        })
        .collect()
}

#[test]
fn fair_mesh_keeps_the_boundary_and_smooths_the_inside() {
    let dir = tempfile::tempdir().unwrap();
    let (input, mesh) = noisy_obj(&dir);
    let out = dir.path().join("out.obj");
    let o = bin()
        .args([
            "fair-mesh",
            input.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--fixed-rings",
            "2",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let faired = positions(&std::fs::read_to_string(&out).unwrap());
    assert_eq!(faired.len(), mesh.positions.len());
    for k in 0..21 {
        // first grid row (a boundary) is unchanged to the printed precision
        let p = mesh.positions[k];
        assert_eq!(faired[k], [p.x, p.y, p.z]);
    }
    assert!(String::from_utf8_lossy(&o.stdout).contains("faired"));
    // --fixed pins extra vertices
    let fixed = dir.path().join("fixed.json");
    std::fs::write(&fixed, "[220]").unwrap();
    let out2 = dir.path().join("out2.obj");
    let o = bin()
        .args([
            "fair-mesh",
            input.to_str().unwrap(),
            "-o",
            out2.to_str().unwrap(),
            "--fixed",
            fixed.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success());
    let p = mesh.positions[220];
    assert_eq!(
        positions(&std::fs::read_to_string(&out2).unwrap())[220],
        [p.x, p.y, p.z]
    );
}

#[test]
fn bad_meshes_and_overwrites_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.obj");
    std::fs::write(
        &bad,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n",
    )
    .unwrap();
    let o = bin()
        .args([
            "fair-mesh",
            bad.to_str().unwrap(),
            "-o",
            dir.path().join("o.obj").to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("not a manifold"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let (input, _) = noisy_obj(&dir);
    let o = bin()
        .args([
            "fair-mesh",
            input.to_str().unwrap(),
            "-o",
            input.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
}

/// `--tolerance MM`: no vertex moves more than MM, and the mesh still gets fairer (the data
/// term keeps it near the input, the smallest weight that fits is used); pure fairing moves
/// more than that here, so the bound is what decides.
#[test]
fn fair_mesh_within_a_tolerance() {
    let dir = tempfile::tempdir().unwrap();
    let (input, mesh) = noisy_obj(&dir);
    let free = dir.path().join("free.obj");
    let o = bin()
        .args([
            "fair-mesh",
            input.to_str().unwrap(),
            "-o",
            free.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success());
    let largest = |path: &std::path::Path| {
        positions(&std::fs::read_to_string(path).unwrap())
            .iter()
            .zip(&mesh.positions)
            .map(|(a, p)| {
                ((a[0] - p.x).powi(2) + (a[1] - p.y).powi(2) + (a[2] - p.z).powi(2)).sqrt()
            })
            .fold(0.0, f64::max)
    };
    let unbounded = largest(&free);
    let tol = unbounded / 4.0;
    let out = dir.path().join("within.obj");
    let o = bin()
        .args([
            "fair-mesh",
            input.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--tolerance",
            &tol.to_string(),
        ])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // the written coordinates are rounded to the OBJ's printed digits
    assert!(
        largest(&out) <= tol * (1.0 + 1e-6),
        "{} > {tol}",
        largest(&out)
    );
    assert!(text.contains("data weight"), "{text}");
    let energies: Vec<f64> = text
        .split("umbrella energy ")
        .nth(1)
        .unwrap()
        .split(',')
        .next()
        .unwrap()
        .split(" → ")
        .map(|x| x.trim().parse().unwrap())
        .collect();
    assert!(energies[1] < energies[0], "{text}");
    // a tolerance that is not a length is one line
    let o = bin()
        .args([
            "fair-mesh",
            input.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--tolerance",
            "-1",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(String::from_utf8_lossy(&o.stderr).lines().count(), 1);
}
