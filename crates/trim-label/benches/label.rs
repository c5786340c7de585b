//! Labeling (goal ≤ 1 s) and the labeled fit of the Neon side panel
//! (`fixtures/third_party/neon_side.obj`, 15,896 vertices, 30,376 triangles); a synthetic grid region
//! stands in when the file is absent. Run: `cargo bench -p trim-label -j 1`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use nurbs_core::{Point3, TriMesh};
use trim_label::{LabelParams, LabeledFitParams, fit_labeled, label_region, parameterize};

fn grid(n: usize) -> TriMesh {
    let id = |i: usize, j: usize| i * (n + 1) + j;
    let positions = (0..=n)
        .flat_map(|i| (0..=n).map(move |j| (i, j)))
        .map(|(i, j)| {
            let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
            Point3::new(x, y, 0.2 * (3.0 * x).sin() * y)
        })
        .collect();
    let mut faces = Vec::new();
    for i in 0..n {
        for j in 0..n {
            faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            faces.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    TriMesh {
        positions,
        normals: vec![],
        faces,
    }
}

fn mesh() -> (&'static str, TriMesh) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/third_party/neon_side.obj"
    );
    match std::fs::read_to_string(path)
        .ok()
        .and_then(|t| TriMesh::from_obj_str(&t).ok())
    {
        Some(m) => ("neon_side", m),
        None => {
            eprintln!("{path} not found: benchmarking a 126×126 grid instead");
            ("grid_126", grid(126))
        }
    }
}

fn bench(c: &mut Criterion) {
    let (name, mesh) = mesh();
    let params = LabelParams::default();
    let labels = label_region(&mesh, None, &params).expect("labels");
    let mut g = c.benchmark_group("trim_label");
    g.sample_size(10);
    g.bench_function(format!("label/{name}"), |b| {
        b.iter(|| label_region(black_box(&mesh), None, &params).expect("labels"))
    });
    g.bench_function(format!("parameterize/{name}"), |b| {
        b.iter(|| parameterize(black_box(&mesh), &labels).expect("parameterization"))
    });
    g.bench_function(format!("fit/{name}"), |b| {
        b.iter(|| {
            fit_labeled(black_box(&mesh), &labels, &LabeledFitParams::default()).expect("fit")
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
