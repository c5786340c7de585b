//! Labeled parameterization: the labeled segments are constrained to their sides of the domain
//! rectangle, the rest of the mesh (unlabeled boundary, holes, interior) is placed by minimizing
//! a distortion energy (\[VV17\] §3; \[VV18\], "Labeled parameterization").
//!
//! Energy: the conformal (LSCM) energy E_C = E_D(u) + E_D(v) − A(u, v), with the cotangent
//! Dirichlet energy E_D(u) = ½ uᵀLu, L_ij = −½(cot α_ij + cot β_ij), and A the signed area of the
//! image (Σ over faces of ½ Σ_cyc (u_i v_j − u_j v_i)). Per triangle E_C = ½∫|∇u − J∇v|² ≥ 0, so
//! the quadratic form is positive semi-definite; it is zero exactly for conformal maps.
//!
//! Constraints (linear, eliminated before the sparse Cholesky solve):
//! - West u = 0, East u = 1 when both are labeled, otherwise East u = 0;
//! - South v = 0, North v = V when all four sides are labeled (V is one more unknown, so the
//!   aspect ratio is free), North v = 1 when South and North are labeled without both West and
//!   East, otherwise North v = 0;
//! - gauge: a coordinate that no label fixes is pinned at one vertex; when no constraint sets
//!   the scale (configurations (0, 0), (1, 0), (2, 1)) a second pin does — the guiding frame of
//!   partial configurations, reduced to what fixes the similarity transform.
//!
//! The result is scaled per axis to [0, 1]²: a labeled side keeps its value, an unlabeled one is
//! the extreme of the parameters; parameters beyond a labeled side are clamped (and counted).
//!
//! # Deviation from the paper
//! \[VV17\] minimizes ARAP under these constraints inside a guiding frame extrapolated from the
//! labels; we minimize the linear conformal energy (one sparse solve, no iterations) and replace
//! the frame by the gauge pins. Free boundaries of LSCM behave well, so the labels alone orient
//! and stretch the parameterization.

use nalgebra::DMatrix;
use nurbs_core::TriMesh;
use nurbs_core::sparse::{SparseSpd, SpdSolver};

use crate::error::{LabelError, Result};
use crate::labeling::{Label, Labeling};

/// A parameterization of the mesh vertices on [0, 1]².
#[derive(Debug, Clone, PartialEq)]
pub struct Parameterization {
    /// (u, v) per mesh vertex (NaN for vertices no face uses)
    pub uv: Vec<(f64, f64)>,
    /// vertices whose parameters were clamped into the square
    pub clamped: usize,
    /// world-units extent ratio of the domain, (u extent)/(v extent) before scaling
    pub aspect: f64,
}

/// A coordinate of a vertex: unknown number i or a fixed value.
#[derive(Clone, Copy, PartialEq)]
enum Slot {
    Free(usize),
    Fixed(f64),
}

/// Parameterizes `mesh` with the labels of `labeling` (see the module docs).
pub fn parameterize(mesh: &TriMesh, labeling: &Labeling) -> Result<Parameterization> {
    let nv = mesh.positions.len();
    let mut used = vec![false; nv];
    for f in &mesh.faces {
        for &v in f {
            used[v] = true;
        }
    }
    let sides = Sides::of(labeling);
    // slot 2·v = u of vertex v, 2·v + 1 = v of vertex v; unknown V (if any) comes last
    let (mut slot, pinned) = label_slots(labeling, sides, nv);
    pin_gauge(labeling, sides, &mut slot, pinned)?;
    let (map, count, shared) = number_slots(&slot, &used, sides.big_v());
    let x = solve_conformal(mesh, &map, count)?;
    let value = |sl: Slot| match sl {
        Slot::Free(i) => x[(i, 0)],
        Slot::Fixed(c) => c,
    };
    let raw: Vec<(f64, f64)> = (0..nv)
        .map(|v| {
            if used[v] {
                (value(map[2 * v]), value(map[2 * v + 1]))
            } else {
                (f64::NAN, f64::NAN)
            }
        })
        .collect();
    scale_to_square(&raw, sides, shared.map(|i| x[(i, 0)]))
}

/// Which sides have a label.
#[derive(Clone, Copy)]
struct Sides {
    s: bool,
    e: bool,
    n: bool,
    w: bool,
}

impl Sides {
    /// The labeled sides of `labeling`.
    fn of(labeling: &Labeling) -> Self {
        let has = |side: Label| labeling.segments.iter().any(|s| s.label == side);
        Self {
            s: has(Label::South),
            e: has(Label::East),
            n: has(Label::North),
            w: has(Label::West),
        }
    }

    /// Whether all four are labeled: North is then at v = V, one more unknown.
    fn big_v(&self) -> bool {
        self.w && self.e && self.s && self.n
    }
}

/// The slots the labels constrain (see the module docs; the shared V as `Free(usize::MAX)`),
/// and whether some label fixes u and v.
fn label_slots(labeling: &Labeling, sides: Sides, nv: usize) -> (Vec<Option<Slot>>, (bool, bool)) {
    let mut slot: Vec<Option<Slot>> = vec![None; 2 * nv];
    let (mut pinned_u, mut pinned_v) = (false, false);
    let big_v = sides.big_v();
    for seg in &labeling.segments {
        let (coord, value) = match seg.label {
            Label::South => (1, Some(0.0)),
            Label::North if big_v => (1, None),
            Label::North => (1, Some(if sides.s { 1.0 } else { 0.0 })),
            Label::West => (0, Some(0.0)),
            Label::East => (0, Some(if sides.w { 1.0 } else { 0.0 })),
            Label::Unlabeled => continue,
        };
        for &v in &seg.loop_vertices {
            slot[2 * v + coord] = Some(match value {
                Some(x) => Slot::Fixed(x),
                None => Slot::Free(usize::MAX), // the shared V, numbered below
            });
            if coord == 0 {
                pinned_u = true;
            } else {
                pinned_v = true;
            }
        }
    }
    (slot, (pinned_u, pinned_v))
}

/// The gauge pins of the module docs: where no label sets the scale, pins along South (or two
/// pins on the outer loop), then a pin for each coordinate no constraint fixes yet.
fn pin_gauge(
    labeling: &Labeling,
    sides: Sides,
    slot: &mut [Option<Slot>],
    (mut pinned_u, mut pinned_v): (bool, bool),
) -> Result<()> {
    let chain = |side: Label| -> Option<Vec<usize>> {
        let (_, segs) = labeling.chains.iter().find(|(l, _)| *l == side)?;
        Some(
            segs.iter()
                .flat_map(|&k| labeling.segments[k].loop_vertices.iter().copied())
                .collect(),
        )
    };
    let outer = &labeling.outer_loop;
    let scaled = (sides.w && sides.e) || (sides.s && sides.n);
    if !scaled {
        if let Some(south) = chain(Label::South) {
            // (1, 0) or (2, 1): pin along South
            let a = south[0];
            let b = *south.last().unwrap_or(&a);
            if sides.e {
                let free = south
                    .iter()
                    .copied()
                    .find(|&v| slot[2 * v].is_none())
                    .ok_or_else(|| LabelError::ParameterizationFailed {
                        detail: "no free vertex on the south side to fix the scale".into(),
                    })?;
                slot[2 * free] = Some(Slot::Fixed(-1.0));
            } else {
                slot[2 * a] = Some(Slot::Fixed(0.0));
                slot[2 * b] = Some(Slot::Fixed(1.0));
                pinned_u = true;
            }
        } else {
            // (0, 0): two pins
            let (a, b) = (outer[0], outer[outer.len() / 2]);
            slot[2 * a] = Some(Slot::Fixed(0.0));
            slot[2 * a + 1] = Some(Slot::Fixed(0.0));
            slot[2 * b] = Some(Slot::Fixed(1.0));
            slot[2 * b + 1] = Some(Slot::Fixed(0.0));
            pinned_u = true;
            pinned_v = true;
        }
    }
    if !pinned_u {
        let a = outer[0];
        slot[2 * a] = Some(Slot::Fixed(0.0));
    }
    if !pinned_v {
        let a = outer[0];
        slot[2 * a + 1] = Some(Slot::Fixed(0.0));
    }
    Ok(())
}

/// Numbers the unknowns: the shared V first (when `big_v`), then every unconstrained slot of
/// the `used` vertices; returns each slot's value or unknown, the unknowns' count and V's
/// index.
fn number_slots(
    slot: &[Option<Slot>],
    used: &[bool],
    big_v: bool,
) -> (Vec<Slot>, usize, Option<usize>) {
    let mut count = 0usize;
    let shared = if big_v {
        count += 1;
        Some(0usize)
    } else {
        None
    };
    let mut map = vec![Slot::Fixed(f64::NAN); slot.len()];
    for v in 0..used.len() {
        if !used[v] {
            continue;
        }
        for c in 0..2 {
            map[2 * v + c] = match slot[2 * v + c] {
                Some(Slot::Fixed(x)) => Slot::Fixed(x),
                Some(Slot::Free(_)) => Slot::Free(shared.unwrap_or(0)),
                None => {
                    count += 1;
                    Slot::Free(count - 1)
                }
            };
        }
    }
    (map, count, shared)
}

/// Minimizes the conformal energy E_D(u) + E_D(v) − A(u, v) over the `count` unknowns of
/// `map` by a sparse Cholesky solve.
fn solve_conformal(mesh: &TriMesh, map: &[Slot], count: usize) -> Result<DMatrix<f64>> {
    let mut triplets: Vec<(usize, usize, f64)> = Vec::with_capacity(mesh.faces.len() * 36);
    let mut rhs = DMatrix::<f64>::zeros(count, 1);
    let mut add = |a: usize, b: usize, h: f64| match (map[a], map[b]) {
        (Slot::Free(i), Slot::Free(j)) => triplets.push((i, j, h)),
        (Slot::Free(i), Slot::Fixed(c)) => rhs[(i, 0)] -= h * c,
        _ => {}
    };
    for f in &mesh.faces {
        for k in 0..3 {
            let (i, j, o) = (f[k], f[(k + 1) % 3], f[(k + 2) % 3]);
            let (a, b) = (
                mesh.positions[i] - mesh.positions[o],
                mesh.positions[j] - mesh.positions[o],
            );
            let cot = a.dot(&b) / a.cross(&b).norm();
            let c = 0.5 * cot;
            for coord in 0..2 {
                let (si, sj) = (2 * i + coord, 2 * j + coord);
                add(si, si, c);
                add(sj, sj, c);
                add(si, sj, -c);
                add(sj, si, -c);
            }
            // −A: the directed edge i → j contributes −½(u_i v_j − u_j v_i)
            add(2 * i, 2 * j + 1, -0.5);
            add(2 * j + 1, 2 * i, -0.5);
            add(2 * j, 2 * i + 1, 0.5);
            add(2 * i + 1, 2 * j, 0.5);
        }
    }
    let matrix = SparseSpd::from_triplets(count, &triplets)?;
    Ok(matrix.solve(&rhs, SpdSolver::DEFAULT)?)
}

/// Scales the `raw` parameters per axis to [0, 1]²: a labeled side keeps its value (North the
/// solved V, `big_v_value`, when all four are labeled), an unlabeled one is the extreme of the
/// parameters; parameters beyond are clamped and counted.
fn scale_to_square(
    raw: &[(f64, f64)],
    sides: Sides,
    big_v_value: Option<f64>,
) -> Result<Parameterization> {
    let finite = raw.iter().filter(|p| p.0.is_finite());
    let (mut umin, mut umax, mut vmin, mut vmax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for p in finite {
        umin = umin.min(p.0);
        umax = umax.max(p.0);
        vmin = vmin.min(p.1);
        vmax = vmax.max(p.1);
    }
    if sides.w {
        umin = 0.0;
    }
    if sides.e {
        umax = if sides.w { 1.0 } else { 0.0 };
    }
    if sides.s {
        vmin = 0.0;
    }
    if sides.n {
        vmax = big_v_value.unwrap_or(if sides.s { 1.0 } else { 0.0 });
    }
    let (du, dv) = (umax - umin, vmax - vmin);
    if !(du > 0.0 && dv > 0.0 && du.is_finite() && dv.is_finite()) {
        return Err(LabelError::ParameterizationFailed {
            detail: format!("the domain collapsed: extents {du:e} × {dv:e}"),
        });
    }
    let mut clamped = 0;
    let uv = raw
        .iter()
        .map(|&(u, v)| {
            if !u.is_finite() {
                return (f64::NAN, f64::NAN);
            }
            let (a, b) = ((u - umin) / du, (v - vmin) / dv);
            let (ca, cb) = (a.clamp(0.0, 1.0), b.clamp(0.0, 1.0));
            if ca != a || cb != b {
                clamped += 1;
            }
            (ca, cb)
        })
        .collect();
    Ok(Parameterization {
        uv,
        clamped,
        aspect: du / dv,
    })
}
