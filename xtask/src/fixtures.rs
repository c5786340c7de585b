//! The analytic fixture models of `fixtures/models/` (`cargo xtask fixtures` writes them).
//!
//! Every surface is the exact bicubic image of a bilinear map of the unit square lifted by the
//! cubic height function [`height`]: z = f(x, y) of degree 3 composed with a map of bidegree
//! (1, 1) has bidegree (3, 3), so a least-squares fit on enough samples reproduces it up to
//! round-off and surfaces sharing a boundary line share it exactly (C∞ across it). The
//! disturbances are then added to control points away from the boundaries, with a seeded
//! generator, so the models are deterministic:
//! - *noise* on every control point at least two rows from each side keeps the input G1 at
//!   every join (rows 0–1 untouched) and breaks G2 — the situation of \[SV\] Fig. 6 ("stripes not
//!   tangential at the common boundaries (only G1 continuity)");
//! - a smooth *bump* on those points of a corner patch does the same without noise.
//!
//! | model | construction |
//! |---|---|
//! | `x_node` | 3×3 grid of 20 mm squares over [-30, 30]²: four primaries at the corners, four fillets between them, the corner patch in the middle linked G2 to the four fillets; all disturbed beyond their tangent rows (the demo model) |
//! | `five_sided` | a regular pentagon (circumradius 20 mm) split centrally into five quads (one corner group), surrounded by five strips: two primaries, three fillets (\[SV\] Fig. 8) |
//! | `fillet_freeform` | a fillet between two freeform primaries that extend beyond its ends (the master parameters do not match the fillet's) |
//! | `bezier_sphere` | a sphere zone of 2×5 bicubic Bézier patches joined C0 in one surface (interior knots of full multiplicity), one control point pulled out (\[H\] example) |
//! | `noisy_panel` | one 12×12 bicubic panel of 100×60 mm with seeded noise of 0.05 mm |

use anyhow::Result;
use nurbs_core::{BSplineSurface, KnotVector, Point3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

/// The cubic height function of the freeform fixtures (mm): a gentle saddle with cubic terms.
pub fn height(x: f64, y: f64) -> f64 {
    0.004 * x * x - 0.003 * y * y + 5e-5 * x * x * x + 8e-5 * x * y * y + 2e-5 * x * x * y
}

/// Bilinear map of the unit square onto the quad a(0,0) b(1,0) c(1,1) d(0,1), lifted by `f`.
fn lifted(
    a: [f64; 2],
    b: [f64; 2],
    c: [f64; 2],
    d: [f64; 2],
    f: &dyn Fn(f64, f64) -> f64,
) -> impl Fn(f64, f64) -> Point3 + '_ {
    move |s, t| {
        let x = (1.0 - s) * (1.0 - t) * a[0]
            + s * (1.0 - t) * b[0]
            + s * t * c[0]
            + (1.0 - s) * t * d[0];
        let y = (1.0 - s) * (1.0 - t) * a[1]
            + s * (1.0 - t) * b[1]
            + s * t * c[1]
            + (1.0 - s) * t * d[1];
        Point3::new(x, y, f(x, y))
    }
}

/// Least-squares bicubic through samples of `map` (the framework's synthetic-model helper).
pub fn fit_map(map: &dyn Fn(f64, f64) -> Point3, nu: usize, nv: usize) -> Result<BSplineSurface> {
    Ok(hier_fair::synthetic::fit_map(map, nu, nv)?)
}

/// Adds `amplitude`·(uniform noise in [-1, 1]) to z of every control point at least `keep`
/// rows from each side.
pub fn add_noise(s: &mut BSplineSurface, keep: usize, amplitude: f64, rng: &mut ChaCha8Rng) {
    let (nu, nv) = (s.num_u(), s.num_v());
    for i in keep..nu.saturating_sub(keep) {
        for j in keep..nv.saturating_sub(keep) {
            let k = s.index(i, j);
            s.control_points_mut()[k].z += amplitude * rng.random_range(-1.0..=1.0);
        }
    }
}

/// Adds a smooth bump of height `amplitude` (sin² profile) to the control points at least
/// `keep` rows from each side.
pub fn add_bump(s: &mut BSplineSurface, keep: usize, amplitude: f64) {
    let (nu, nv) = (s.num_u(), s.num_v());
    let (lu, lv) = (
        (nu - 1 - 2 * keep + 2) as f64,
        (nv - 1 - 2 * keep + 2) as f64,
    );
    for i in keep..nu - keep {
        for j in keep..nv - keep {
            let a = std::f64::consts::PI * (i + 1 - keep) as f64 / lu;
            let b = std::f64::consts::PI * (j + 1 - keep) as f64 / lv;
            let k = s.index(i, j);
            s.control_points_mut()[k].z += amplitude * a.sin().powi(2) * b.sin().powi(2);
        }
    }
}

fn entry(name: &str, role: &str, s: &BSplineSurface) -> Value {
    let surface: Value =
        serde_json::from_str(&nurbs_core::io::surface_to_json(s)).expect("kernel JSON is valid");
    json!({"name": name, "role": role, "surface": surface})
}

fn link(slave: &str, side: &str, master: &str, continuity: &str) -> Value {
    json!({"slave": slave, "side": side, "master": master, "continuity": continuity})
}

/// The X-node of the demo (\[SV\] Fig. 6).
pub fn x_node() -> Result<Value> {
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let f = &height;
    let sq = |x0: f64, y0: f64| {
        let (x1, y1) = (x0 + 20.0, y0 + 20.0);
        lifted([x0, y0], [x1, y0], [x1, y1], [x0, y1], f)
    };
    let mut surfaces = Vec::new();
    // primaries at the four corners of the grid
    for (name, x0, y0) in [
        ("primary_sw", -30.0, -30.0),
        ("primary_se", 10.0, -30.0),
        ("primary_nw", -30.0, 10.0),
        ("primary_ne", 10.0, 10.0),
    ] {
        let mut s = fit_map(&sq(x0, y0), 8, 8)?;
        add_noise(&mut s, 2, 0.03, &mut rng);
        surfaces.push(entry(name, "primary", &s));
    }
    // fillets: u runs along x, v along y
    for (name, x0, y0) in [
        ("fillet_s", -10.0, -30.0),
        ("fillet_n", -10.0, 10.0),
        ("fillet_w", -30.0, -10.0),
        ("fillet_e", 10.0, -10.0),
    ] {
        let mut s = fit_map(&sq(x0, y0), 7, 7)?;
        add_noise(&mut s, 2, 0.02, &mut rng);
        surfaces.push(entry(name, "connecting", &s));
    }
    let mut corner = fit_map(&sq(-10.0, -10.0), 7, 7)?;
    add_bump(&mut corner, 2, 0.25);
    surfaces.push(entry("corner", "corner", &corner));
    let links = vec![
        link("fillet_s", "u0", "primary_sw", "G2"),
        link("fillet_s", "u1", "primary_se", "G2"),
        link("fillet_n", "u0", "primary_nw", "G2"),
        link("fillet_n", "u1", "primary_ne", "G2"),
        link("fillet_w", "v0", "primary_sw", "G2"),
        link("fillet_w", "v1", "primary_nw", "G2"),
        link("fillet_e", "v0", "primary_se", "G2"),
        link("fillet_e", "v1", "primary_ne", "G2"),
        link("corner", "u0", "fillet_w", "G2"),
        link("corner", "u1", "fillet_e", "G2"),
        link("corner", "v0", "fillet_s", "G2"),
        link("corner", "v1", "fillet_n", "G2"),
    ];
    Ok(json!({
        "units": "mm",
        "surfaces": surfaces,
        "links": links,
        "tolerances": {"deviation": 0.1, "g0": 0.001, "g1_deg": 0.01, "g2_rel": 0.005}
    }))
}

/// The five-sided corner of \[SV\] Fig. 8.
pub fn five_sided() -> Result<Value> {
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let f = &height;
    let r = 20.0;
    let vertex = |k: usize| {
        let a = std::f64::consts::TAU * (k % 5) as f64 / 5.0 + std::f64::consts::FRAC_PI_2;
        [r * a.cos(), r * a.sin()]
    };
    let mid = |k: usize| {
        let (a, b) = (vertex(k), vertex(k + 1));
        [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]
    };
    // outward offsets along the vertex directions: adjacent strips share these lines
    let out = |k: usize, d: f64| {
        let v = vertex(k);
        [v[0] * (1.0 + d / r), v[1] * (1.0 + d / r)]
    };
    let roles = [
        "primary",
        "connecting",
        "primary",
        "connecting",
        "connecting",
    ];
    let mut surfaces = Vec::new();
    for k in 0..5 {
        let map = lifted(vertex(k), vertex(k + 1), out(k + 1, 12.0), out(k, 12.0), f);
        let mut s = fit_map(&map, 7, 6)?;
        add_noise(&mut s, 2, 0.02, &mut rng);
        surfaces.push(entry(&format!("strip{k}"), roles[k], &s));
    }
    let c = [0.0, 0.0];
    for i in 0..5 {
        // quad i: C, M_i, V_{i+1}, M_{i+1}
        let map = lifted(c, mid(i), vertex(i + 1), mid(i + 1), f);
        let mut s = fit_map(&map, 7, 7)?;
        add_noise(&mut s, 2, 0.03, &mut rng);
        surfaces.push(entry(&format!("q{i}"), "corner", &s));
    }
    let mut links = vec![
        // fillets on the primaries (strips share the lines out of the pentagon's vertices)
        link("strip1", "u0", "strip0", "G2"),
        link("strip1", "u1", "strip2", "G2"),
        link("strip3", "u0", "strip2", "G2"),
        link("strip3", "u1", "strip4", "G1"),
        link("strip4", "u1", "strip0", "G2"),
    ];
    for i in 0..5 {
        let q = format!("q{i}");
        links.push(link(&q, "u1", &format!("strip{i}"), "G2"));
        links.push(link(&q, "v1", &format!("strip{}", (i + 1) % 5), "G2"));
    }
    // internal curves: q_i.v0 is q_{i-1}.u0; a chain without cycles, q4 closes on q0
    for i in 1..5 {
        links.push(link(&format!("q{i}"), "v0", &format!("q{}", i - 1), "G2"));
    }
    links.push(link("q4", "u0", "q0", "G2"));
    Ok(json!({
        "units": "mm",
        "surfaces": surfaces,
        "links": links,
        "corners": [{"name": "c5", "patches": ["q0", "q1", "q2", "q3", "q4"]}],
        "tolerances": {"deviation": 0.1, "g0": 0.001, "g1_deg": 0.01, "g2_rel": 0.005}
    }))
}

/// A fillet between two freeform primaries that extend past its ends.
pub fn fillet_freeform() -> Result<Value> {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let f = &height;
    let left = lifted(
        [-40.0, -30.0],
        [-8.0, -30.0],
        [-8.0, 30.0],
        [-40.0, 30.0],
        f,
    );
    let right = lifted([8.0, -30.0], [40.0, -30.0], [40.0, 30.0], [8.0, 30.0], f);
    let fillet = lifted([-8.0, -20.0], [8.0, -20.0], [8.0, 20.0], [-8.0, 20.0], f);
    let mut a = fit_map(&left, 9, 12)?;
    let mut b = fit_map(&right, 9, 12)?;
    let mut c = fit_map(&fillet, 6, 9)?;
    add_noise(&mut a, 2, 0.03, &mut rng);
    add_noise(&mut b, 2, 0.03, &mut rng);
    add_noise(&mut c, 2, 0.03, &mut rng);
    Ok(json!({
        "units": "mm",
        "surfaces": [entry("left", "primary", &a), entry("right", "primary", &b), entry("fillet", "connecting", &c)],
        "links": [link("fillet", "u0", "left", "G2"), link("fillet", "u1", "right", "G2")],
        "tolerances": {"deviation": 0.1, "g0": 0.001, "g1_deg": 0.01, "g2_rel": 0.005}
    }))
}

/// A sphere zone (latitude ±60°, longitude 0–180°, radius 50 mm) as 2×5 bicubic Bézier patches
/// in one C0-joined surface, one interior control point pulled out by 2 mm.
pub fn bezier_sphere() -> Result<Value> {
    let r = 50.0;
    let (lat, lon) = (60f64.to_radians(), std::f64::consts::PI);
    let (bu, bv) = (2usize, 5usize);
    let mut patches = Vec::new();
    // fit every patch as a Bézier patch, then join them into one surface
    for a in 0..bu {
        for b in 0..bv {
            let map = move |s: f64, t: f64| {
                let th = -lat + 2.0 * lat * (a as f64 + s) / bu as f64;
                let ph = lon * (b as f64 + t) / bv as f64;
                Point3::new(
                    r * th.cos() * ph.cos(),
                    r * th.cos() * ph.sin(),
                    r * th.sin(),
                )
            };
            patches.push(fit_map(&map, 4, 4)?);
        }
    }
    let (nu, nv) = (3 * bu + 1, 3 * bv + 1);
    let mut points = vec![Point3::origin(); nu * nv];
    for a in 0..bu {
        for b in 0..bv {
            let p = &patches[a * bv + b];
            for i in 0..4 {
                for j in 0..4 {
                    points[(3 * a + i) * nv + 3 * b + j] = p.control_point(i, j);
                }
            }
        }
    }
    let knots = |n: usize| {
        let mut k = vec![0.0; 4];
        for s in 1..n {
            k.extend([s as f64 / n as f64; 3]);
        }
        k.extend([1.0; 4]);
        k
    };
    let ku = KnotVector::new(3, knots(bu))?;
    let kv = KnotVector::new(3, knots(bv))?;
    let mut s = BSplineSurface::new(ku, kv, points, None)?;
    let k = s.index(2, 7);
    let p = s.control_points()[k];
    let n = p.coords.normalize();
    s.control_points_mut()[k] = p + 2.0 * n;
    Ok(json!({
        "units": "mm",
        "surfaces": [entry("sphere_zone", "primary", &s)],
        "links": [],
        "tolerances": {"deviation": 2.5}
    }))
}

/// A noisy freeform panel.
pub fn noisy_panel() -> Result<Value> {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let f = &height;
    let map = lifted(
        [-50.0, -30.0],
        [50.0, -30.0],
        [50.0, 30.0],
        [-50.0, 30.0],
        f,
    );
    let mut s = fit_map(&map, 12, 12)?;
    add_noise(&mut s, 1, 0.05, &mut rng);
    Ok(json!({
        "units": "mm",
        "surfaces": [entry("panel", "primary", &s)],
        "links": [],
        "tolerances": {"deviation": 0.1}
    }))
}

/// All fixture models, by file stem.
pub fn all() -> Result<Vec<(&'static str, Value)>> {
    Ok(vec![
        ("x_node", x_node()?),
        ("five_sided", five_sided()?),
        ("fillet_freeform", fillet_freeform()?),
        ("bezier_sphere", bezier_sphere()?),
        ("noisy_panel", noisy_panel()?),
    ])
}
