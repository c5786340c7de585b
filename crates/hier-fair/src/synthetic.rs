//! Synthetic models for benchmarks and tests: a grid of filleted blocks, and a sphere corner
//! with a pole between three cylinders.
//!
//! A (2c−1)×(2r−1) grid of 20 mm squares over the cubic height field
//! z = 0.002·x² − 0.0015·y² + 2·10⁻⁶·x³ (mm): the squares at (even, even) grid positions are
//! primaries (block tops), those at (odd, even) and (even, odd) fillets linked G2 to the two
//! primaries beside them, those at (odd, odd) corner patches linked G2 to the four fillets around
//! them — c·r primaries, (c−1)·r + c·(r−1) fillets, (c−1)·(r−1) corners. Each square is the
//! exact 6×6 bicubic image of the height field; every control point two or more rows from the
//! sides gets a deterministic disturbance of up to 0.02 mm (a hash of its indices), so joins are
//! G1 but not G2 and interiors are not fair, as after reverse engineering.

use nurbs_core::{
    BSplineSurface, Continuity, ControlMask, Direction, FitParams, KnotVector, Point3, Side,
    fit_surface, shapes,
};
use serde_json::{Value, json};

use crate::error::{Error, Result};
use crate::model::{Link, Model, Role};

/// Side of one square (mm).
pub(crate) const CELL: f64 = 20.0;

fn height(x: f64, y: f64) -> f64 {
    0.002 * x * x - 0.0015 * y * y + 2e-6 * x * x * x
}

/// A deterministic value in [-1, 1] from three indices (splitmix64 of their combination).
fn hash_noise(a: usize, b: usize, c: usize) -> f64 {
    let mut z = (a as u64)
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add((b as u64).wrapping_mul(0xBF58_476D_1CE4_E5B9))
        .wrapping_add((c as u64).wrapping_mul(0x94D0_49BB_1331_11EB));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
}

/// Least-squares bicubic with `nu`×`nv` uniform control points (clamped knots on [0, 1])
/// through (3·n + 1)² samples of `map` over the unit square — exact when `map` is bicubic.
pub fn fit_map(map: &dyn Fn(f64, f64) -> Point3, nu: usize, nv: usize) -> Result<BSplineSurface> {
    let ku = KnotVector::clamped_uniform(3, nu)?;
    let kv = KnotVector::clamped_uniform(3, nv)?;
    let template = BSplineSurface::new(ku, kv, vec![Point3::origin(); nu * nv], None)?;
    let (su, sv) = (3 * nu + 1, 3 * nv + 1);
    let mut params = Vec::with_capacity(su * sv);
    let mut points = Vec::with_capacity(su * sv);
    for a in 0..su {
        for b in 0..sv {
            let (s, t) = (a as f64 / (su - 1) as f64, b as f64 / (sv - 1) as f64);
            params.push((s, t));
            points.push(map(s, t));
        }
    }
    let mask = ControlMask::for_surface(&template);
    Ok(fit_surface(&template, &mask, &params, &points, &FitParams::default())?.0)
}

fn square(x0: f64, y0: f64, id: usize) -> Result<BSplineSurface> {
    let n = 6;
    let mut s = fit_map(
        &|s, t| {
            let (x, y) = (x0 + CELL * s, y0 + CELL * t);
            Point3::new(x, y, height(x, y))
        },
        n,
        n,
    )?;
    for i in 2..n - 2 {
        for j in 2..n - 2 {
            let idx = s.index(i, j);
            s.control_points_mut()[idx].z += 0.02 * hash_noise(id, i, j);
        }
    }
    Ok(s)
}

/// The grid of filleted blocks with `c`×`r` primaries (c, r ≥ 1); (2c−1)(2r−1) surfaces.
pub fn block_grid(c: usize, r: usize) -> Result<Model> {
    if c == 0 || r == 0 {
        return Err(Error::Format {
            detail: format!("a block grid needs at least one block, got {c}×{r}"),
        });
    }
    let (nx, ny) = (2 * c - 1, 2 * r - 1);
    let name = |i: usize, j: usize| -> String {
        match (i % 2, j % 2) {
            (0, 0) => format!("p{i}_{j}"),
            (1, 1) => format!("c{i}_{j}"),
            _ => format!("f{i}_{j}"),
        }
    };
    let mut surfaces = Vec::new();
    let mut links = Vec::new();
    for i in 0..nx {
        for j in 0..ny {
            let s = square(CELL * i as f64, CELL * j as f64, i * ny + j)?;
            let role = match (i % 2, j % 2) {
                (0, 0) => "primary",
                (1, 1) => "corner",
                _ => "connecting",
            };
            let surface: Value = serde_json::from_str(&nurbs_core::io::surface_to_json(&s))
                .map_err(|e| Error::Format {
                    detail: e.to_string(),
                })?;
            surfaces.push(json!({"name": name(i, j), "role": role, "surface": surface}));
            // u runs along x (i), v along y (j)
            let mut link = |side: &str, mi: usize, mj: usize| {
                links.push(json!({"slave": name(i, j), "side": side, "master": name(mi, mj), "continuity": "G2"}));
            };
            match (i % 2, j % 2) {
                (1, 0) => {
                    link("u0", i - 1, j);
                    link("u1", i + 1, j);
                }
                (0, 1) => {
                    link("v0", i, j - 1);
                    link("v1", i, j + 1);
                }
                (1, 1) => {
                    link("u0", i - 1, j);
                    link("u1", i + 1, j);
                    link("v0", i, j - 1);
                    link("v1", i, j + 1);
                }
                _ => {}
            }
        }
    }
    let doc = json!({
        "units": "mm",
        "surfaces": surfaces,
        "links": links,
        "tolerances": {"deviation": 0.1, "g0": 0.001, "g1_deg": 0.01, "g2_rel": 0.005}
    });
    Model::from_json(&doc.to_string())
}

/// The exact sphere octant of radius `r` (nurbs-core's `shapes::sphere_octant`: its pole the
/// side u0, collapsed to a point) as a corner patch named "pole", turned by `turn` (0: as built,
/// 1: u reversed, 2: transposed, 3: transposed and v reversed — the pole on u0, u1, v0, v1),
/// linked G2 to the three quarter cylinders of radius `r` tangent to it along its sides: about
/// the z axis under its equator ("cyl_z", z ≤ 0), about the y axis beside its meridian y = 0
/// ("cyl_y", y ≤ 0) and about the x axis beside its meridian x = 0 ("cyl_x", x ≤ 0) — a box
/// corner rounded with one radius, as kernels build it: G1 across each side (the cylinders are
/// straight along their axes, the sphere is not).
pub fn sphere_corner(r: f64, turn: usize) -> Result<Model> {
    let geometry = |e: nurbs_core::Error| Error::Surface {
        name: "pole".into(),
        source: e,
    };
    let octant = shapes::sphere_octant(r).map_err(geometry)?;
    let corner = match turn {
        0 => octant,
        1 => octant.reversed(Direction::U).map_err(geometry)?,
        2 => octant.transposed().map_err(geometry)?,
        _ => octant
            .transposed()
            .and_then(|t| t.reversed(Direction::V))
            .map_err(geometry)?,
    };
    let height = 0.4 * r;
    // the quarter cylinder about z (x, y ≥ 0, z ∈ [0, h]) moved by `place`
    let cylinder = |place: &dyn Fn(Point3) -> Point3| {
        let mut c = shapes::cylinder(r, height).map_err(geometry)?;
        for p in c.control_points_mut() {
            *p = place(*p);
        }
        Ok::<_, Error>(c)
    };
    let mut model = Model::from_primaries(vec![
        cylinder(&|p| Point3::new(p.x, p.y, p.z - height))?,
        cylinder(&|p| Point3::new(p.x, -p.z, p.y))?,
        cylinder(&|p| Point3::new(-p.z, p.x, p.y))?,
        corner.clone(),
    ]);
    for (k, name) in ["cyl_z", "cyl_y", "cyl_x", "pole"].into_iter().enumerate() {
        model.surfaces[k].name = name.into();
    }
    model.surfaces[3].role = Role::Corner;
    let near = 1e-9 * r;
    for side in Side::ALL {
        let (a, b) = side.along_domain(&corner);
        let (u, v) = side.params(&corner, 0.5 * (a + b));
        let m = corner.point(u, v);
        let master = if m.z.abs() < near {
            0
        } else if m.y.abs() < near && m.x > near {
            1
        } else if m.x.abs() < near && m.y > near {
            2
        } else {
            continue;
        };
        model.links.push(Link {
            slave: 3,
            side,
            master,
            continuity: Continuity::G2,
        });
    }
    Ok(model)
}
