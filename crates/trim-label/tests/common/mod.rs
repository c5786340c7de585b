//! Narrow helpers of the integration tests: synthetic planar regions built from boundary pieces
//! (each piece a polyline that becomes one given segment), triangulated by ear clipping, and grid
//! regions with interior vertices for the fit.

#![allow(dead_code)]

use nurbs_core::{Point3, TriMesh};
use trim_label::{Label, LabelParams, Labeling, label_region};

/// A region from boundary pieces (counter-clockwise, piece k ends where piece k+1 starts),
/// resampled at spacing ≤ h; returns the mesh and the pieces as segments of vertex indices.
pub fn polygon_region(pieces: &[Vec<[f64; 2]>], h: f64) -> (TriMesh, Vec<Vec<usize>>) {
    let mut pts: Vec<[f64; 2]> = Vec::new();
    let mut ends = Vec::new();
    for piece in pieces {
        for w in piece.windows(2) {
            let (a, b) = (w[0], w[1]);
            let k = (dist(a, b) / h).ceil().max(1.0) as usize;
            for i in 1..=k {
                let t = i as f64 / k as f64;
                pts.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
            }
        }
        ends.push(pts.len() - 1);
    }
    let n = pts.len();
    let segments = (0..ends.len())
        .map(|k| {
            let start = if k == 0 { n - 1 } else { ends[k - 1] };
            let mut s = vec![start];
            s.extend((start + 1..=start + (ends[k] + n - start) % n).map(|i| i % n));
            s
        })
        .collect();
    let faces = ear_clip(&pts);
    let mesh = TriMesh {
        positions: pts.iter().map(|p| Point3::new(p[0], p[1], 0.0)).collect(),
        normals: vec![],
        faces,
    };
    (mesh, segments)
}

fn cross(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

/// Ear clipping of a simple counter-clockwise polygon (collinear points allowed).
pub fn ear_clip(pts: &[[f64; 2]]) -> Vec<[usize; 3]> {
    let mut idx: Vec<usize> = (0..pts.len()).collect();
    let mut faces = Vec::new();
    let scale = pts
        .iter()
        .fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()));
    let eps = 1e-9 * scale * scale;
    while idx.len() > 3 {
        let m = idx.len();
        let mut best: Option<(usize, f64)> = None;
        for k in 0..m {
            let (a, b, c) = (idx[(k + m - 1) % m], idx[k], idx[(k + 1) % m]);
            let area = cross(pts[a], pts[b], pts[c]);
            if area <= eps {
                continue;
            }
            let blocked = idx.iter().any(|&q| {
                q != a
                    && q != b
                    && q != c
                    && cross(pts[a], pts[b], pts[q]) >= -eps
                    && cross(pts[b], pts[c], pts[q]) >= -eps
                    && cross(pts[c], pts[a], pts[q]) >= -eps
            });
            if blocked {
                continue;
            }
            // prefer the ear with the best shape (largest smallest angle proxy)
            let (ab, bc, ca) = (
                dist(pts[a], pts[b]),
                dist(pts[b], pts[c]),
                dist(pts[c], pts[a]),
            );
            let quality = area / (ab * ab + bc * bc + ca * ca);
            if best.is_none_or(|(_, q)| quality > q) {
                best = Some((k, quality));
            }
        }
        let (k, _) = best.expect("a simple polygon always has an ear");
        let m = idx.len();
        faces.push([idx[(k + m - 1) % m], idx[k], idx[(k + 1) % m]]);
        idx.remove(k);
    }
    faces.push([idx[0], idx[1], idx[2]]);
    faces
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

/// Points of a circular arc (centre, radius, angles in degrees, counter-clockwise if a1 > a0).
pub fn arc(c: [f64; 2], r: f64, a0: f64, a1: f64, n: usize) -> Vec<[f64; 2]> {
    (0..=n)
        .map(|i| {
            let a = (a0 + (a1 - a0) * i as f64 / n as f64).to_radians();
            [c[0] + r * a.cos(), c[1] + r * a.sin()]
        })
        .collect()
}

/// Labels with default params and the given segments.
pub fn label(mesh: &TriMesh, segments: &[Vec<usize>]) -> Labeling {
    let l = label_region(mesh, Some(segments), &LabelParams::default()).expect("labeling");
    for line in &l.log {
        eprintln!("{line}");
    }
    l
}

/// Labels as short strings ("S", "E", "N", "W", "-").
pub fn codes(l: &Labeling) -> String {
    l.segments
        .iter()
        .map(|s| match s.label {
            Label::South => 'S',
            Label::East => 'E',
            Label::North => 'N',
            Label::West => 'W',
            Label::Unlabeled => '-',
        })
        .collect()
}

/// Labels relative to the first labeled segment's side ("a" = that side, then "b", "c", "d" in
/// loop order, "-" unlabeled): the pattern does not depend on which side was chosen as South.
pub fn pattern(l: &Labeling) -> String {
    let index = |lab: Label| Label::SIDES.iter().position(|&s| s == lab);
    let first = l.segments.iter().find_map(|s| index(s.label)).unwrap_or(0);
    l.segments
        .iter()
        .map(|s| match index(s.label) {
            Some(i) => (b'a' + ((i + 4 - first) % 4) as u8) as char,
            None => '-',
        })
        .collect()
}

/// A planar grid region [0, a] × [0, b] of square cells of size h (two triangles each), keeping
/// the cells whose centre passes `keep`, lifted by z = lift(x, y).
pub fn grid_region(
    a: f64,
    b: f64,
    h: f64,
    keep: impl Fn(f64, f64) -> bool,
    lift: impl Fn(f64, f64) -> f64,
) -> TriMesh {
    let (nx, ny) = ((a / h).round() as usize, (b / h).round() as usize);
    let id = |i: usize, j: usize| i * (ny + 1) + j;
    let mut faces = Vec::new();
    for i in 0..nx {
        for j in 0..ny {
            let (cx, cy) = ((i as f64 + 0.5) * h, (j as f64 + 0.5) * h);
            if keep(cx, cy) {
                let (p00, p10, p11, p01) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                faces.push([p00, p10, p11]);
                faces.push([p00, p11, p01]);
            }
        }
    }
    let mut used = vec![usize::MAX; (nx + 1) * (ny + 1)];
    let mut positions = Vec::new();
    for f in &mut faces {
        for v in f.iter_mut() {
            if used[*v] == usize::MAX {
                used[*v] = positions.len();
                let (i, j) = (*v / (ny + 1), *v % (ny + 1));
                let (x, y) = (i as f64 * h, j as f64 * h);
                positions.push(Point3::new(x, y, lift(x, y)));
            }
            *v = used[*v];
        }
    }
    TriMesh {
        positions,
        normals: vec![],
        faces,
    }
}
