//! The IGES writer: a valid IGES 5.3 file with entities 128 (surfaces) and 126 (curves), trimmed
//! faces as 144 over their 128 with 142 curves on surface (their curves 126, or composites 102
//! of 126 pieces between the loop's corners), numbers
//! in full double precision (shortest representation that reads back to the same bits), names in
//! the directory entry labels (8 characters; longer names are cut and numbered by subscript).

use nurbs_core::{BSplineCurve, BSplineSurface, Point3};

use crate::bounds::Face;

use crate::error::IgesError;

/// Data columns of a record (IGES 5.3 §2.1: 1–72, the section letter and sequence follow).
const DATA_COLUMNS: usize = 72;
/// Data columns of a P-section record (IGES 5.3 §2.2.4: 1–64; 65–72 hold the DE pointer).
const P_DATA_COLUMNS: usize = 64;

/// Settings of the Global section.
#[derive(Debug, Clone, PartialEq)]
pub struct IgesWriteParams {
    /// unit flag (2 = millimetres, the default for CAD exchange)
    pub unit_flag: i64,
    /// unit name matching the flag ("MM")
    pub units: String,
    /// file name recorded in the Global section
    pub file_name: String,
    /// date and time of generation, `YYYYMMDD.HHNNSS` (fixed by default so that output is
    /// reproducible; the command line passes the current time)
    pub date: String,
    /// author
    pub author: String,
    /// How far (model units) a trim curve may lie from its loop's points: each loop is then
    /// written as composite curves (102) of cubic pieces between its corners fitted within
    /// this ([`crate::bounds::fitted_edge`]), in model and parameter space; 0 (the default)
    /// writes each loop as one degree-1 curve through its points.
    pub edge_tolerance: f64,
}

impl Default for IgesWriteParams {
    fn default() -> Self {
        Self {
            unit_flag: 2,
            units: "MM".into(),
            file_name: "model.igs".into(),
            date: "20260101.000000".into(),
            author: "hier-fair".into(),
            edge_tolerance: 0.0,
        }
    }
}

/// An IGES real with a decimal point and full precision: Rust's shortest round-trip digits.
fn real(x: f64, what: &str) -> Result<String, IgesError> {
    if !x.is_finite() {
        return Err(IgesError::Write {
            what: what.into(),
            detail: format!("{x} is not finite"),
        });
    }
    let s = format!("{x:?}");
    Ok(match s.split_once('e') {
        Some((m, e)) => {
            let m = if m.contains('.') {
                m.to_string()
            } else {
                format!("{m}.")
            };
            format!("{m}E{e}")
        }
        None if s.contains('.') => s,
        None => format!("{s}."),
    })
}

fn hollerith(s: &str) -> String {
    format!("{}H{s}", s.len())
}

/// Breaks tokens (each with its delimiter) into lines of at most `width` columns.
fn pack(tokens: &[String], width: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let mut cur = String::new();
    for t in tokens {
        if !cur.is_empty() && cur.len() + t.len() > width {
            lines.push(std::mem::take(&mut cur));
        }
        if t.len() > width {
            // only long Hollerith strings in the Global section can get here
            let mut rest = t.as_str();
            while rest.len() > width - cur.len() {
                let cut = width - cur.len();
                cur.push_str(&rest[..cut]);
                lines.push(std::mem::take(&mut cur));
                rest = &rest[cut..];
            }
            cur.push_str(rest);
        } else {
            cur.push_str(t);
        }
    }
    if !cur.is_empty() {
        lines.push(cur);
    }
    lines
}

fn record(data: &str, letter: char, seq: usize) -> String {
    format!("{data:<72}{letter}{seq:>7}")
}

fn tokens(values: Vec<String>) -> Vec<String> {
    let n = values.len();
    values
        .into_iter()
        .enumerate()
        .map(|(k, v)| if k + 1 == n { v + ";" } else { v + "," })
        .collect()
}

struct Entity {
    entity_type: i64,
    params: Vec<String>,
    label: String,
    subscript: usize,
    /// the directory status number (columns 65–72 of the first line): "00000000" for an
    /// independent entity, "00010000" for one physically dependent on another (a 144's
    /// surface and boundaries)
    status: &'static str,
}

/// Status of an independent entity.
const INDEPENDENT: &str = "00000000";
/// Status of an entity physically dependent on its parent (a trimmed surface's parts).
const DEPENDENT: &str = "00010000";

fn surface_params(s: &BSplineSurface, what: &str) -> Result<Vec<String>, IgesError> {
    let (nu, nv) = (s.num_u(), s.num_v());
    let mut v = vec![
        "128".to_string(),
        (nu - 1).to_string(),
        (nv - 1).to_string(),
        s.degree_u().to_string(),
        s.degree_v().to_string(),
    ];
    // PROP1 closed in u, PROP2 closed in v, PROP3 polynomial, PROP4/5 periodic: written as 0, 0, 1|0, 0, 0
    v.extend(["0", "0", if s.is_rational() { "0" } else { "1" }, "0", "0"].map(String::from));
    for &k in s.knots_u().knots() {
        v.push(real(k, what)?);
    }
    for &k in s.knots_v().knots() {
        v.push(real(k, what)?);
    }
    for j in 0..nv {
        for i in 0..nu {
            v.push(real(s.weight(i, j), what)?);
        }
    }
    for j in 0..nv {
        for i in 0..nu {
            let p = s.control_point(i, j);
            for c in [p.x, p.y, p.z] {
                v.push(real(c, what)?);
            }
        }
    }
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    for x in [u0, u1, v0, v1] {
        v.push(real(x, what)?);
    }
    Ok(v)
}

fn curve_params(c: &BSplineCurve, what: &str) -> Result<Vec<String>, IgesError> {
    let n = c.control_points().len();
    let mut v = vec![
        "126".to_string(),
        (n - 1).to_string(),
        c.degree().to_string(),
    ];
    // PROP1 planar, PROP2 closed, PROP3 polynomial, PROP4 periodic
    v.extend(["0", "0", if c.is_rational() { "0" } else { "1" }, "0"].map(String::from));
    for &k in c.knots().knots() {
        v.push(real(k, what)?);
    }
    for i in 0..n {
        v.push(real(c.weights().map_or(1.0, |w| w[i]), what)?);
    }
    for p in c.control_points() {
        for x in [p.x, p.y, p.z] {
            v.push(real(x, what)?);
        }
    }
    let (a, b) = c.domain();
    v.extend([
        real(a, what)?,
        real(b, what)?,
        "0.".into(),
        "0.".into(),
        "1.".into(),
    ]);
    Ok(v)
}

/// Labels of at most 8 characters; duplicates (after cutting) are told apart by the subscript.
fn labels(names: &[&str]) -> Vec<(String, usize)> {
    let mut seen: std::collections::HashMap<String, usize> = std::collections::HashMap::new();
    names
        .iter()
        .map(|n| {
            let cut: String = n.chars().filter(|c| c.is_ascii_graphic()).take(8).collect();
            let count = seen.entry(cut.clone()).or_insert(0);
            *count += 1;
            (cut, *count - 1)
        })
        .collect()
}

/// Writes surfaces (entity 128) and curves (entity 126) with their names as an IGES 5.3 file:
/// as [`write_iges_faces`] with no trim.
pub fn write_iges(
    surfaces: &[(&str, &BSplineSurface)],
    curves: &[(&str, &BSplineCurve)],
    params: &IgesWriteParams,
) -> Result<String, IgesError> {
    let faces: Vec<Face<'_>> = surfaces
        .iter()
        .map(|(name, s)| Face::untrimmed(name, s))
        .collect();
    write_iges_faces(&faces, curves, params)
}

/// Writes faces and curves (entity 126) with their names as an IGES 5.3 file. A face without
/// trim is its surface (entity 128); a face with trim loops is a trimmed surface (144) over its
/// 128 whose boundaries are curves on the surface (142, parameter space preferred), each loop's
/// curves through its points on the surface ([`crate::bounds::face_bounds`]: moved to their
/// feet on the surface, turned, densified) — one closed degree-1 126, or with
/// [`IgesWriteParams::edge_tolerance`] composites (102) of fitted pieces — the outer loop the
/// outer boundary and the others inner boundaries.
pub fn write_iges_faces(
    faces: &[Face<'_>],
    curves: &[(&str, &BSplineCurve)],
    params: &IgesWriteParams,
) -> Result<String, IgesError> {
    let names: Vec<&str> = faces
        .iter()
        .map(|f| f.name)
        .chain(curves.iter().map(|c| c.0))
        .collect();
    let labels = labels(&names);
    let mut entities = Vec::new();
    for (k, f) in faces.iter().enumerate() {
        push_face(&mut entities, f, &labels[k], params.edge_tolerance)?;
    }
    for (k, (name, c)) in curves.iter().enumerate() {
        let l = &labels[faces.len() + k];
        entities.push(Entity {
            entity_type: 126,
            params: curve_params(c, &format!("curve {name}"))?,
            label: l.0.clone(),
            subscript: l.1,
            status: INDEPENDENT,
        });
    }
    let max_coord = faces
        .iter()
        .flat_map(|f| f.surface.control_points())
        .chain(curves.iter().flat_map(|c| c.1.control_points()))
        .flat_map(|p| [p.x.abs(), p.y.abs(), p.z.abs()])
        .fold(0.0, f64::max);
    file_text(&entities, params, max_coord)
}

/// Pushes the entities of face `f` labelled `label`: its 128, and where it has trim loops, each
/// loop's 126 and 142 and the 144 over them (every entity after those it points to).
fn push_face(
    entities: &mut Vec<Entity>,
    f: &Face<'_>,
    label: &(String, usize),
    edge_tolerance: f64,
) -> Result<(), IgesError> {
    let what = format!("surface {}", f.name);
    // a trim that is the parameter box is the untrimmed surface ([`crate::seam::trim_is_box`])
    let boxed = crate::seam::trim_is_box(f.surface, f.trim);
    let bounds = crate::bounds::face_bounds(f.surface, if boxed { &[] } else { f.trim });
    let trimmed = !bounds.loops.is_empty();
    entities.push(Entity {
        entity_type: 128,
        params: surface_params(f.surface, &what)?,
        label: label.0.clone(),
        subscript: label.1,
        status: if trimmed { DEPENDENT } else { INDEPENDENT },
    });
    if !trimmed {
        return Ok(());
    }
    // directory sequence number of the entity pushed next
    let de = |entities: &Vec<Entity>| 2 * entities.len() + 1;
    let surface = de(entities) - 2;
    let mut boundaries = Vec::new();
    let loops = loops_with_params(f.surface, &bounds);
    let params: Vec<Vec<Point3>> = loops.iter().map(|l| l.1.clone()).collect();
    let seam = crate::seam::close_winding_loops(f.surface, &params);
    // the seam boundary first (the outer one), then every loop it does not replace
    let order: Vec<Option<usize>> = match &seam {
        Some(b) => std::iter::once(None)
            .chain((0..loops.len()).filter(|k| !b.loops.contains(k)).map(Some))
            .collect(),
        None => (0..loops.len()).map(Some).collect(),
    };
    for k in order {
        let pieces = match (k, &seam) {
            (Some(k), _) => {
                let (pts, uv) = &loops[k];
                loop_curves(f.surface, &bounds, pts, uv, edge_tolerance)
            }
            (None, Some(b)) => seam_pieces(f.surface, &b.uv, &b.cuts, edge_tolerance),
            (None, None) => continue,
        };
        let (model, parametric) = pieces.map_err(|source| IgesError::Write {
            what: what.clone(),
            detail: format!("trim loop {k:?}: {source}"),
        })?;
        let c = push_curve(entities, &model, &what)?;
        let b = push_curve(entities, &parametric, &what)?;
        boundaries.push(de(entities));
        // CRTN 0 (unspecified), the surface, the parameter-space curve, the model-space curve,
        // PREF 1 (parameter space: the kernel need not project onto a closed surface's seam)
        let p = [142, 0, surface as i64, b as i64, c as i64, 1].map(|x| x.to_string());
        entities.push(part(142, p.to_vec()));
    }
    // the surface, N1 = 1 (the outer boundary is the first 142), N2 inner boundaries, PTO, PTI…
    let mut p = vec![
        "144".to_string(),
        surface.to_string(),
        "1".into(),
        (boundaries.len() - 1).to_string(),
    ];
    p.extend(boundaries.iter().map(|b| b.to_string()));
    entities.push(Entity {
        entity_type: 144,
        params: p,
        label: label.0.clone(),
        subscript: label.1,
        status: INDEPENDENT,
    });
    Ok(())
}

/// Pushes a trim curve made of `pieces` in order: the one 126, or each piece's 126 and the
/// composite (102, \[IGES\] §4.4) over them; returns the directory number of the curve.
fn push_curve(
    entities: &mut Vec<Entity>,
    pieces: &[BSplineCurve],
    what: &str,
) -> Result<usize, IgesError> {
    let mut members = Vec::with_capacity(pieces.len());
    for c in pieces {
        members.push(2 * entities.len() + 1);
        entities.push(part(126, curve_params(c, what)?));
    }
    if members.len() == 1 {
        return Ok(members[0]);
    }
    let mut p = vec!["102".to_string(), members.len().to_string()];
    p.extend(members.iter().map(|m| m.to_string()));
    entities.push(part(102, p));
    Ok(2 * entities.len() - 1)
}

/// A closed loop's pieces in model and in parameter space, each fitted within `tolerance`
/// ([`crate::bounds::fitted_edge`]): the loop's points `pts` (on the surface, in order) split
/// at the face's vertices, and its parameters `uv` (closed: the last the first) split at the
/// vertices' images, at the ends of a run along a collapsed side (a pole: two parameters, one
/// point) and at the ends of a jump across a seam ([`crate::bounds::is_seam_jump`]), fitted
/// within `tolerance` over √2 times the largest first derivative of the surface at the loop's
/// points (a parameter error (δu, δv) moves the point by at most |S_u| |δu| + |S_v| |δv|).
fn loop_pieces(
    surface: &BSplineSurface,
    bounds: &crate::bounds::FaceBounds,
    pts: &[Point3],
    uv: &[Point3],
    tolerance: f64,
) -> Result<(Vec<BSplineCurve>, Vec<BSplineCurve>), nurbs_core::Error> {
    let same = crate::bounds::SAME_POINT_RELATIVE * surface.size().max(f64::MIN_POSITIVE);
    let at_vertex = |p: &Point3| bounds.vertices.iter().any(|v| (v - p).norm() <= same);
    let mut closed = pts.to_vec();
    closed.push(pts[0]);
    let cuts: Vec<usize> = (0..closed.len())
        .filter(|&i| i == 0 || i + 1 == closed.len() || at_vertex(&closed[i]))
        .collect();
    let model = fitted_runs(&closed, &cuts, tolerance)?;
    let (images, tol_uv) = images_and_uv_tolerance(surface, uv, tolerance);
    let n = uv.len();
    let jump = |i: usize, j: usize| {
        crate::bounds::is_seam_jump(surface, (uv[i].x, uv[i].y), (uv[j].x, uv[j].y))
    };
    let mut cuts = vec![0];
    for i in 1..n - 1 {
        let pole = (images[i + 1] - images[i]).norm() <= same
            || (images[i] - images[i - 1]).norm() <= same;
        if at_vertex(&images[i]) || pole || jump(i - 1, i) || jump(i, i + 1) {
            cuts.push(i);
        }
    }
    cuts.push(n - 1);
    cuts.dedup();
    Ok((model, fitted_runs(uv, &cuts, tol_uv)?))
}

/// The images of the parameters `uv` on `surface`, and the parameter-space tolerance that keeps
/// them within `tolerance`: over √2 times the largest first derivative there (a parameter error
/// (δu, δv) moves the point by at most |S_u| |δu| + |S_v| |δv|).
fn images_and_uv_tolerance(
    surface: &BSplineSurface,
    uv: &[Point3],
    tolerance: f64,
) -> (Vec<Point3>, f64) {
    let mut eval = surface.evaluator();
    let mut speed: f64 = 0.0;
    let images = uv
        .iter()
        .map(|q| {
            let d = eval.derivatives(q.x, q.y);
            speed = speed.max(d.du.norm()).max(d.dv.norm());
            d.point
        })
        .collect();
    let tol_uv = tolerance / (std::f64::consts::SQRT_2 * speed.max(f64::MIN_POSITIVE));
    (images, tol_uv)
}

/// The runs of `points` between consecutive `cuts` (both ends included), each fitted within
/// `tolerance` ([`crate::bounds::fitted_edge`]; a polyline where it is 0).
fn fitted_runs(
    points: &[Point3],
    cuts: &[usize],
    tolerance: f64,
) -> Result<Vec<BSplineCurve>, nurbs_core::Error> {
    cuts.windows(2)
        .map(|w| crate::bounds::fitted_edge(&points[w[0]..=w[1]], tolerance))
        .collect()
}

/// Each loop of `bounds` as its points in order and their parameters on `surface` (u, v, 0),
/// closed: the last parameter the first.
fn loops_with_params(
    surface: &BSplineSurface,
    bounds: &crate::bounds::FaceBounds,
) -> Vec<(Vec<Point3>, Vec<Point3>)> {
    (0..bounds.loops.len())
        .map(|k| {
            let pts = bounds.loop_points(k);
            let mut uv: Vec<Point3> = crate::bounds::loop_params(surface, &pts)
                .into_iter()
                .map(|(u, v)| Point3::new(u, v, 0.0))
                .collect();
            uv.push(uv[0]);
            (pts, uv)
        })
        .collect()
}

/// The model-space and parameter-space curves of one loop: its points `pts` and parameters
/// `uv` (closed) as [`loop_pieces`] fits them, or each one degree-1 curve where `tolerance` is 0.
fn loop_curves(
    surface: &BSplineSurface,
    bounds: &crate::bounds::FaceBounds,
    pts: &[Point3],
    uv: &[Point3],
    tolerance: f64,
) -> Result<(Vec<BSplineCurve>, Vec<BSplineCurve>), nurbs_core::Error> {
    if tolerance > 0.0 {
        return loop_pieces(surface, bounds, pts, uv, tolerance);
    }
    let mut closed = pts.to_vec();
    closed.push(pts[0]);
    Ok((
        vec![crate::bounds::polyline(&closed)?],
        vec![crate::bounds::polyline(uv)?],
    ))
}

/// The pieces of a seam boundary ([`crate::seam`]): its parameters `uv` cut at `cuts`, each
/// run in parameter space and its image in model space fitted within `tolerance` as
/// [`loop_pieces`] fits them (polylines where it is 0).
fn seam_pieces(
    surface: &BSplineSurface,
    uv: &[Point3],
    cuts: &[usize],
    tolerance: f64,
) -> Result<(Vec<BSplineCurve>, Vec<BSplineCurve>), nurbs_core::Error> {
    let same = crate::bounds::SAME_POINT_RELATIVE * surface.size().max(f64::MIN_POSITIVE);
    let (images, tol_uv) = images_and_uv_tolerance(surface, uv, tolerance);
    let parametric = fitted_runs(uv, cuts, tol_uv)?;
    let mut model = Vec::with_capacity(cuts.len());
    for w in cuts.windows(2) {
        let mut run: Vec<Point3> = Vec::with_capacity(w[1] - w[0] + 1);
        for p in &images[w[0]..=w[1]] {
            if run.last().is_none_or(|q| (q - p).norm() > same) {
                run.push(*p);
            }
        }
        if run.len() >= 2 {
            model.push(crate::bounds::fitted_edge(&run, tolerance)?);
        }
    }
    Ok((model, parametric))
}

/// A trimmed surface's part (126, 142): dependent, unlabelled.
fn part(entity_type: i64, params: Vec<String>) -> Entity {
    Entity {
        entity_type,
        params,
        label: String::new(),
        subscript: 0,
        status: DEPENDENT,
    }
}

/// The file: Start, Global, Directory, Parameter Data and Terminate sections of `entities`.
fn file_text(
    entities: &[Entity],
    params: &IgesWriteParams,
    max_coord: f64,
) -> Result<String, IgesError> {
    let mut out: Vec<String> = Vec::new();
    let start = "hier-fair IGES 5.3 export: B-spline surfaces (128) and curves (126)";
    out.push(record(start, 'S', 1));
    let g_lines = pack(&tokens(global_params(params, max_coord)?), DATA_COLUMNS);
    for (k, l) in g_lines.iter().enumerate() {
        out.push(record(l, 'G', k + 1));
    }
    let (d_lines, p_lines) = directory_and_data(entities);
    let terminate = format!(
        "S{:>7}G{:>7}D{:>7}P{:>7}",
        1,
        g_lines.len(),
        d_lines.len(),
        p_lines.len()
    );
    out.extend(d_lines);
    out.extend(p_lines);
    out.push(record(&terminate, 'T', 1));
    Ok(out.join("\n") + "\n")
}

/// The Global section's parameters.
fn global_params(params: &IgesWriteParams, max_coord: f64) -> Result<Vec<String>, IgesError> {
    Ok(vec![
        "1H,".to_string(),
        "1H;".to_string(),
        hollerith("hier-fair model"),
        hollerith(&params.file_name),
        hollerith("hier-fair"),
        hollerith(env!("CARGO_PKG_VERSION")),
        "32".into(),
        "308".into(),
        "15".into(),
        "308".into(),
        "15".into(),
        hollerith("hier-fair model"),
        "1.".into(),
        params.unit_flag.to_string(),
        hollerith(&params.units),
        "1".into(),
        "1.".into(),
        hollerith(&params.date),
        "1.E-10".into(),
        real(max_coord.max(1.0), "global max coordinate")?,
        hollerith(&params.author),
        hollerith(""),
        "11".into(),
        "0".into(),
        hollerith(&params.date),
    ])
}

/// The Directory and Parameter Data records of `entities` (entity k at directory line 2k + 1).
fn directory_and_data(entities: &[Entity]) -> (Vec<String>, Vec<String>) {
    let mut d_lines = Vec::new();
    let mut p_lines = Vec::new();
    for (k, e) in entities.iter().enumerate() {
        let de = 2 * k + 1;
        let lines = pack(&tokens(e.params.clone()), P_DATA_COLUMNS);
        let pointer = p_lines.len() + 1;
        for l in &lines {
            let seq = p_lines.len() + 1;
            p_lines.push(format!("{l:<64}{de:>8}P{seq:>7}"));
        }
        d_lines.push(record(
            &format!(
                "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
                e.entity_type, pointer, 0, 0, 0, 0, 0, 0, e.status
            ),
            'D',
            de,
        ));
        d_lines.push(record(
            &format!(
                "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
                e.entity_type,
                0,
                0,
                lines.len(),
                0,
                "",
                "",
                e.label,
                e.subscript
            ),
            'D',
            de + 1,
        ));
    }
    (d_lines, p_lines)
}
