//! Pole corners split into three quads (\[SV\] §3.4): a three-sided corner patch given as a
//! quad with one side collapsed to a point (a sphere octant, a cone apex) cannot carry a fair G2
//! lead-in next to its pole — a lead-in of constant parameter width shrinks physically to nothing
//! there, and its third derivative across grows without bound. The central split replaces it by
//! three regular quads around a centre point, each with two outer half-sides and two internal
//! curves, which the framework then fairs as a corner group (mesh fairing, per-quad continuity).
//!
//! # Construction
//! With the collapsed side turned to v = 1 and the domain normalized to (x, y) ∈ [0, 1]², the
//! loop is c₀ = side v0 (A → B), c₁ = side u1 (B → pole P), c₂ = side u0 (P → A); M_k is the
//! parametric midpoint of c_k, and the centre C the foot on the patch of the mean of the three
//! midpoints. Quad k has the corner V_k (A, B, P) and follows nside-discrete's convention: side
//! v0 the first half of c_k, side u0 the second half of c_{k−1} reversed, side u1 the internal
//! curve I_k (the patch's image of the domain segment M_k → C) and side v1 the curve I_{k−1}; so
//! I_k is side u1 of quad k and side v1 of quad k + 1. Every side is the image of a domain
//! segment, so its samples lie on the patch exactly. Inside, samples are the Coons patch (in 3D)
//! of the four sides projected onto the patch: smooth across the pole, where the patch's own
//! parametrization is not.
//!
//! Each quad is a bicubic fit on uniform knots: the four side curves first (ends at the corner
//! points, each internal curve fitted once and shared bit for bit by its two quads), then the
//! interior rows with the sides fixed. Spans double (4, 8, 16) until the quads lie within
//! [`FIT_SHARE`] × the G0 tolerance of the patch.

use nurbs_core::{
    BSplineCurve, BSplineSurface, ControlMask, Direction, FitParams, KnotVector, Point3,
    ProjectionParams, Side, SurfaceProjector, fit_curve, fit_surface,
};

use crate::model::{CornerGroup, Link, Model, ModelSurface, Role};

/// Share of the G0 tolerance the split may move the patch: a tenth, so that a side met at G0
/// within its tolerance before the split is still met with nine tenths of the tolerance to
/// spare, and the fairing's deviation budget is spent on fairing, not on the refit.
pub const FIT_SHARE: f64 = 0.1;

/// Knot spans per direction tried in turn (bicubic, uniform): a circular arc of 45° on 4 spans
/// is within 10⁻⁵ of its radius, on 16 within 10⁻⁸ (the error falls as h⁴).
const SPANS: [usize; 3] = [4, 8, 16];

/// Samples per span and direction of the fit (and, doubled, of the check of its error).
const SAMPLES_PER_SPAN: usize = 3;

/// What became of one corner patch with a pole.
#[derive(Debug, Clone, PartialEq)]
pub struct PoleSplit {
    /// the patch's name
    pub surface: String,
    /// what was done
    pub outcome: PoleOutcome,
}

/// Split or kept, and why.
#[derive(Debug, Clone, PartialEq)]
pub enum PoleOutcome {
    /// replaced by three quads, a corner group of the patch's name
    Split {
        /// the quads' names, in cyclic order
        quads: Vec<String>,
        /// control points per direction of each quad
        control_points: usize,
        /// largest distance of a quad from the patch (model units)
        fit_error: f64,
    },
    /// kept as it was
    Kept {
        /// why
        reason: String,
    },
}

/// The model with every corner patch that has exactly one collapsed side split into three
/// quads, and a record of each such patch (split, or kept and why). A patch is kept where it is
/// the master of a link, belongs to a corner group, is trimmed other than by its box, has more
/// than one link on a side, or cannot be fitted within [`FIT_SHARE`] × the G0 tolerance.
pub fn split_pole_corners(model: &Model) -> (Model, Vec<PoleSplit>) {
    let mut splits = Vec::new();
    let mut quads: Vec<Option<Split>> = vec![None; model.surfaces.len()];
    for (k, s) in model.surfaces.iter().enumerate() {
        let Some(pole) = pole_side(s) else { continue };
        let outcome = match splittable(model, k).and_then(|()| split_one(model, k, pole)) {
            Ok((three, control_points, fit_error)) => {
                let names = three.quads.iter().map(|q| q.name.clone()).collect();
                quads[k] = Some(three);
                PoleOutcome::Split {
                    quads: names,
                    control_points,
                    fit_error,
                }
            }
            Err(Why(reason)) => PoleOutcome::Kept { reason },
        };
        splits.push(PoleSplit {
            surface: s.name.clone(),
            outcome,
        });
    }
    (rebuilt(model, quads), splits)
}

/// Why a patch is kept as it was (the report's reason).
#[derive(Debug, Clone, PartialEq)]
struct Why(String);

impl From<nurbs_core::Error> for Why {
    fn from(e: nurbs_core::Error) -> Self {
        Why(format!("its split failed: {e}"))
    }
}

/// The one collapsed side of a corner patch (its pole), where it has exactly one: the patches
/// [`split_pole_corners`] splits.
pub fn pole_side(s: &ModelSurface) -> Option<Side> {
    if s.role != Role::Corner {
        return None;
    }
    let collapsed: Vec<Side> = Side::ALL
        .into_iter()
        .filter(|&side| g_continuity::measure::is_collapsed(&s.surface, side))
        .collect();
    (collapsed.len() == 1).then(|| collapsed[0])
}

/// Why patch `k` of `model` cannot be split, if it cannot.
fn splittable(model: &Model, k: usize) -> Result<(), Why> {
    let s = &model.surfaces[k];
    if model.links.iter().any(|l| l.master == k) {
        return Err(Why("it is the master of a link".into()));
    }
    if model.corners.iter().any(|g| g.patches.contains(&k)) {
        return Err(Why("it belongs to a corner group".into()));
    }
    if !s.trim.is_empty() && !nurbs_io::trim_is_box(&s.surface, &s.trim) {
        return Err(Why("it is trimmed inside its parameter box".into()));
    }
    for side in Side::ALL {
        if model
            .links
            .iter()
            .filter(|l| l.slave == k && l.side == side)
            .count()
            > 1
        {
            return Err(Why(format!("its side {side} has more than one master")));
        }
    }
    Ok(())
}

/// How the patch is turned so that its collapsed side is v1: transposed first, then v reversed.
#[derive(Debug, Clone, Copy)]
struct Turn {
    transpose: bool,
    reverse_v: bool,
}

impl Turn {
    fn for_pole(pole: Side) -> Self {
        let (transpose, reverse_v) = match pole {
            Side::V1 => (false, false),
            Side::V0 => (false, true),
            Side::U1 => (true, false),
            Side::U0 => (true, true),
        };
        Self {
            transpose,
            reverse_v,
        }
    }

    /// The side of the turned patch that `side` of the patch becomes.
    fn side(self, side: Side) -> Side {
        let mut s = side;
        if self.transpose {
            s = match s {
                Side::U0 => Side::V0,
                Side::V0 => Side::U0,
                Side::U1 => Side::V1,
                Side::V1 => Side::U1,
            };
        }
        if self.reverse_v {
            s = match s {
                Side::V0 => Side::V1,
                Side::V1 => Side::V0,
                other => other,
            };
        }
        s
    }

    fn apply(self, s: &BSplineSurface) -> nurbs_core::Result<BSplineSurface> {
        let t = if self.transpose {
            s.transposed()?
        } else {
            s.clone()
        };
        if self.reverse_v {
            t.reversed(Direction::V)
        } else {
            Ok(t)
        }
    }
}

/// A point of the turned patch's normalized domain.
type Xy = (f64, f64);

/// The parametric midpoints M₀, M₁, M₂ of the sides c₀ (v0), c₁ (u1), c₂ (u0).
const MIDS: [Xy; 3] = [(0.5, 0.0), (1.0, 0.5), (0.0, 0.5)];

/// The turned patch on its normalized domain.
struct Patch {
    surface: BSplineSurface,
    du: (f64, f64),
    dv: (f64, f64),
}

impl Patch {
    fn params(&self, (x, y): Xy) -> (f64, f64) {
        (
            self.du.0 + x * (self.du.1 - self.du.0),
            self.dv.0 + y * (self.dv.1 - self.dv.0),
        )
    }

    fn at(&self, xy: Xy) -> Point3 {
        let (u, v) = self.params(xy);
        self.surface.point(u, v)
    }
}

/// The four sides of a quad as domain segments (start, end), in the order v0, u0, u1, v1 of
/// nside-discrete's convention, for quad `k` of the split with centre `c`.
fn quad_sides(k: usize, c: Xy) -> [(Xy, Xy); 4] {
    let m = MIDS;
    // v0: first half of c_k; u0: second half of c_{k-1} reversed
    let (v0, u0) = match k {
        0 => (((0.0, 0.0), m[0]), ((0.0, 0.0), m[2])),
        1 => (((1.0, 0.0), m[1]), ((1.0, 0.0), m[0])),
        _ => (((0.0, 1.0), m[2]), ((1.0, 1.0), m[1])),
    };
    let internal = |j: usize| (m[j], c);
    [v0, u0, internal(k), internal((k + 2) % 3)]
}

/// `n` points of the segment `(a, b)` of `patch`, uniform in the domain.
fn side_points(patch: &Patch, (a, b): (Xy, Xy), n: usize) -> Vec<Point3> {
    (0..n)
        .map(|i| {
            let t = i as f64 / (n - 1) as f64;
            patch.at((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)))
        })
        .collect()
}

/// A cubic on `knots` fitted to `points` at uniform parameters, its ends `first` and `last`.
fn side_curve(
    knots: &KnotVector,
    points: &[Point3],
    first: Point3,
    last: Point3,
) -> nurbs_core::Result<BSplineCurve> {
    let n = knots.num_basis();
    let mut start = vec![first; n];
    start[n - 1] = last;
    let template = BSplineCurve::new(knots.clone(), start, None)?;
    let mut free = vec![true; n];
    free[0] = false;
    free[n - 1] = false;
    let params = uniform(points.len());
    Ok(fit_curve(&template, &free, &params, points, &FitParams::default())?.0)
}

fn uniform(n: usize) -> Vec<f64> {
    (0..n).map(|i| i as f64 / (n - 1) as f64).collect()
}

/// Splits patch `k` (collapsed side `pole`): the three quads as model surfaces, their control
/// points per direction and the largest distance of a quad from the patch.
fn split_one(model: &Model, k: usize, pole: Side) -> Result<(Split, usize, f64), Why> {
    let parent = &model.surfaces[k];
    let turn = Turn::for_pole(pole);
    let surface = turn.apply(&parent.surface)?;
    let patch = Patch {
        du: surface.domain_u(),
        dv: surface.domain_v(),
        surface,
    };
    let allowed = FIT_SHARE * model.tolerances.g0;
    let mut projector = SurfaceProjector::new(&patch.surface, ProjectionParams::default());
    let centre = centre(&patch, &mut projector);
    let mut last = 0.0;
    for spans in SPANS {
        let quads = fit_quads(&patch, &mut projector, centre, spans)?;
        let error = quads
            .iter()
            .map(|q| distance_to(&mut projector, q, 2 * SAMPLES_PER_SPAN * spans))
            .fold(0.0, f64::max);
        if error <= allowed {
            let surfaces = model_quads(model, k, quads, &parent.surface)?;
            return Ok((surfaces, spans + 3, error));
        }
        last = error;
    }
    Err(Why(format!(
        "its quads stay {last:.3e} from it on {} spans, above {FIT_SHARE} × the G0 tolerance",
        SPANS[SPANS.len() - 1]
    )))
}

/// The centre of the split in the normalized domain: the foot of the mean of the side
/// midpoints.
fn centre(patch: &Patch, projector: &mut SurfaceProjector<'_>) -> Xy {
    let mids = MIDS.map(|m| patch.at(m).coords);
    let mean = Point3::from((mids[0] + mids[1] + mids[2]) / 3.0);
    let foot = projector.project(&mean);
    (
        (foot.u - patch.du.0) / (patch.du.1 - patch.du.0),
        (foot.v - patch.dv.0) / (patch.dv.1 - patch.dv.0),
    )
}

/// The three quads on `spans` uniform bicubic spans (turned patch's orientation).
fn fit_quads(
    patch: &Patch,
    projector: &mut SurfaceProjector<'_>,
    c: Xy,
    spans: usize,
) -> nurbs_core::Result<Vec<BSplineSurface>> {
    let knots = KnotVector::clamped_uniform(3, spans + 3)?;
    let n = SAMPLES_PER_SPAN * spans + 1;
    let centre = patch.at(c);
    let mids = MIDS.map(|m| patch.at(m));
    // each side sampled once: its curve is fitted to the samples, the Coons interior built
    // from them (an internal curve serves two quads)
    let fitted = |samples: Vec<Point3>, first: Point3, last: Point3| {
        side_curve(&knots, &samples, first, last).map(|curve| (curve, samples))
    };
    let internal: Vec<(BSplineCurve, Vec<Point3>)> = (0..3)
        .map(|j| fitted(side_points(patch, (MIDS[j], c), n), mids[j], centre))
        .collect::<nurbs_core::Result<_>>()?;
    let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)].map(|v| patch.at(v));
    (0..3)
        .map(|k| {
            let sides = quad_sides(k, c);
            let prev = (k + 2) % 3;
            let v0 = fitted(side_points(patch, sides[0], n), corners[k], mids[k])?;
            let u0 = fitted(side_points(patch, sides[1], n), corners[k], mids[prev])?;
            quad_fit(
                projector,
                &knots,
                [&v0, &u0, &internal[k], &internal[prev]],
                n,
            )
        })
        .collect()
}

/// One quad fitted with its side curves (v0, u0, u1, v1, each with its `n` samples) fixed and
/// its interior fitted to the Coons patch of the side samples projected onto the patch.
fn quad_fit(
    projector: &mut SurfaceProjector<'_>,
    knots: &KnotVector,
    sides: [&(BSplineCurve, Vec<Point3>); 4],
    n: usize,
) -> nurbs_core::Result<BSplineSurface> {
    let [v0, u0, u1, v1] = sides.map(|s| &s.0);
    let m = knots.num_basis();
    let mut net = vec![Point3::origin(); m * m];
    let mut mask = ControlMask::all_free(m, m);
    for t in 0..m {
        for (i, j, p) in [
            (t, 0, v0.control_points()[t]),
            (t, m - 1, v1.control_points()[t]),
            (0, t, u0.control_points()[t]),
            (m - 1, t, u1.control_points()[t]),
        ] {
            net[i * m + j] = p;
            mask.set_free(i, j, false);
        }
    }
    let template = BSplineSurface::new(knots.clone(), knots.clone(), net, None)?;
    let s = sides.map(|side| &side.1);
    let (a, b, c, d) = (s[0][0], s[0][n - 1], s[1][n - 1], s[2][n - 1]);
    let t = uniform(n);
    let (mut params, mut points) = (Vec::new(), Vec::new());
    for (i, &x) in t.iter().enumerate() {
        for (j, &y) in t.iter().enumerate() {
            let coons = (1.0 - y) * s[0][i].coords
                + y * s[3][i].coords
                + (1.0 - x) * s[1][j].coords
                + x * s[2][j].coords
                - ((1.0 - x) * (1.0 - y) * a.coords
                    + x * (1.0 - y) * b.coords
                    + (1.0 - x) * y * c.coords
                    + x * y * d.coords);
            params.push((x, y));
            points.push(projector.project(&Point3::from(coons)).point);
        }
    }
    Ok(fit_surface(&template, &mask, &params, &points, &FitParams::default())?.0)
}

/// The largest distance from `q` (on an `n` × `n` grid) to the projector's surface.
fn distance_to(projector: &mut SurfaceProjector<'_>, q: &BSplineSurface, n: usize) -> f64 {
    let t = uniform(n + 1);
    let mut worst = 0.0f64;
    for &x in &t {
        for &y in &t {
            worst = worst.max(projector.project(&q.point(x, y)).distance);
        }
    }
    worst
}

/// The quads as model surfaces named `<patch>.q0` … `.q2`, oriented as the patch (a quad
/// whose normal opposes the patch's at its middle is transposed), with the patch's role,
/// deviation and part.
fn model_quads(
    model: &Model,
    k: usize,
    quads: Vec<BSplineSurface>,
    original: &BSplineSurface,
) -> Result<Split, Why> {
    let parent = &model.surfaces[k];
    let mut projector = SurfaceProjector::new(original, ProjectionParams::default());
    let mut transposed = [false; 3];
    let out: Vec<ModelSurface> = quads
        .into_iter()
        .enumerate()
        .map(|(j, q)| {
            let d = q.derivatives(0.5, 0.5);
            let foot = projector.project(&d.point);
            let o = original.derivatives(foot.u, foot.v);
            let agrees = d.du.cross(&d.dv).dot(&o.du.cross(&o.dv)) >= 0.0;
            transposed[j] = !agrees;
            let surface = if agrees { q } else { q.transposed()? };
            Ok(ModelSurface {
                name: format!("{}.q{j}", parent.name),
                role: Role::Corner,
                surface,
                deviation: parent.deviation,
                trim: Vec::new(),
                part: parent.part.clone(),
            })
        })
        .collect::<Result<_, Why>>()?;
    let quads = out
        .try_into()
        .map_err(|_| Why("the split gave other than three quads".into()))?;
    Ok(Split { quads, transposed })
}

/// The three quads of a split patch, and which of them were transposed to follow its
/// orientation (their sides u and v swapped against nside-discrete's convention).
#[derive(Debug, Clone)]
struct Split {
    quads: [ModelSurface; 3],
    transposed: [bool; 3],
}

impl Split {
    /// Side `side` (in the convention) of quad `j` as the model has it.
    fn side(&self, j: usize, side: Side) -> Side {
        if !self.transposed[j] {
            return side;
        }
        match side {
            Side::U0 => Side::V0,
            Side::V0 => Side::U0,
            Side::U1 => Side::V1,
            Side::V1 => Side::U1,
        }
    }
}

/// `model` with each split patch replaced by its quads (in its place, in cyclic order), the
/// links and groups renumbered, each split patch's links carried to the quads' outer sides and
/// the internal links and a corner group added.
fn rebuilt(model: &Model, quads: Vec<Option<Split>>) -> Model {
    let mut out = model.clone();
    out.surfaces.clear();
    out.links.clear();
    out.corners.clear();
    let mut index = vec![0; model.surfaces.len()];
    for (k, s) in model.surfaces.iter().enumerate() {
        index[k] = out.surfaces.len();
        match &quads[k] {
            Some(three) => out.surfaces.extend(three.quads.iter().cloned()),
            None => out.surfaces.push(s.clone()),
        }
    }
    for l in &model.links {
        if quads[l.slave].is_none() {
            out.links.push(Link {
                slave: index[l.slave],
                master: index[l.master],
                ..*l
            });
        }
    }
    for g in &model.corners {
        out.corners.push(CornerGroup {
            name: g.name.clone(),
            patches: g.patches.iter().map(|&p| index[p]).collect(),
        });
    }
    for (k, three) in quads.iter().enumerate() {
        if let Some(three) = three {
            split_links(model, k, &index, three, &mut out);
        }
    }
    out
}

/// The links and the corner group of split patch `k`, whose quads start at `index[k]` of `out`
/// (`index`: each surface's first index in `out`): quad j's side v0 lies on the patch's side c_j and its side u0 on c_{j−1}, each linked
/// as that side was; the internal curves I₀, I₁, I₂ are linked G2 as nside-discrete's corner
/// groups are (each quad to the one before it, the last to the first too).
fn split_links(model: &Model, k: usize, index: &[usize], split: &Split, out: &mut Model) {
    let (parent, first) = (&model.surfaces[k], index[k]);
    let turn = Turn::for_pole(pole_side(parent).unwrap_or(Side::V1));
    // the patch's sides c0, c1, c2 in the turned patch
    let loop_sides = [Side::V0, Side::U1, Side::U0];
    let master_of = |c: usize| {
        model
            .links
            .iter()
            .find(|l| l.slave == k && turn.side(l.side) == loop_sides[c])
    };
    for j in 0..3 {
        for (side, c) in [(Side::V0, j), (Side::U0, (j + 2) % 3)] {
            if let Some(l) = master_of(c) {
                out.links.push(Link {
                    slave: first + j,
                    side: split.side(j, side),
                    master: index[l.master],
                    continuity: l.continuity,
                });
            }
        }
    }
    for (slave, side, master) in [(1, Side::V1, 0), (2, Side::V1, 1), (2, Side::U1, 0)] {
        out.links.push(Link {
            slave: first + slave,
            side: split.side(slave, side),
            master: first + master,
            continuity: nurbs_core::Continuity::G2,
        });
    }
    out.corners.push(CornerGroup {
        name: parent.name.clone(),
        patches: vec![first, first + 1, first + 2],
    });
}
