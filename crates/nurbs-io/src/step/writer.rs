//! The AP214 writer: B-spline faces (ADVANCED_FACE of a B_SPLINE_SURFACE_WITH_KNOTS, rational
//! where the surface has weights) bounded by their trim loops or their parameter boxes, in one
//! open shell of a SHELL_BASED_SURFACE_MODEL with the product structure a CAD system needs.

use nurbs_core::{BSplineCurve, BSplineSurface, KnotVector, Point3};

use crate::bounds::Face;

/// The distance below which two points of a written file are one point, in the model's unit:
/// the file's `distance_accuracy_value` (UNCERTAINTY_MEASURE_WITH_UNIT, ISO 10303-43), the
/// value Open CASCADE's writer declares too. Corners this close share a vertex and sides this
/// close are one edge ([`StepWriter::box_bound`]).
pub(crate) const DISTANCE_ACCURACY: f64 = 1e-7;

/// Whether two boundary curves are one curve: the same knots and weights, and control points
/// within [`DISTANCE_ACCURACY`] (so, by the convex hull property, the curves too).
pub(super) fn same_curve(a: &BSplineCurve, b: &BSplineCurve) -> bool {
    a.knots().knots() == b.knots().knots()
        && a.weights() == b.weights()
        && a.control_points().len() == b.control_points().len()
        && a.control_points()
            .iter()
            .zip(b.control_points())
            .all(|(p, q)| (p - q).norm() <= DISTANCE_ACCURACY)
}

/// Writes named surfaces as an AP214 STEP file, each a face bounded by its parameter box: as
/// [`write_step_faces`] with no trim.
pub fn write_step(
    surfaces: &[(&str, &BSplineSurface)],
    units: &str,
    name: &str,
) -> Result<String, nurbs_core::Error> {
    let faces: Vec<Face<'_>> = surfaces
        .iter()
        .map(|(label, s)| Face::untrimmed(label, s))
        .collect();
    write_step_faces(&faces, units, name)
}

/// Writes faces as an AP214 STEP file: each face (ADVANCED_FACE) of its
/// B_SPLINE_SURFACE_WITH_KNOTS (the complex rational instance where it has weights), bounded by
/// its trim loops where it has them — the outer loop a FACE_OUTER_BOUND, the others FACE_BOUNDs,
/// each EDGE_LOOP of ORIENTED_EDGEs of EDGE_CURVEs between VERTEX_POINTs, every edge a degree-1
/// B_SPLINE_CURVE_WITH_KNOTS through its points on the surface ([`crate::bounds::face_bounds`]:
/// the points moved to their feet on the surface, split at the loop's corners, a seam one edge
/// used both ways) — and otherwise by its four boundary curves (exact isocurves, a collapsed side
/// a vertex loop), the faces in one open shell of a SHELL_BASED_SURFACE_MODEL, with the product
/// structure a CAD system needs to open it. `units` is the length unit ("mm", "m", "in", …);
/// `name` the file's name in the header. A unit [`crate::units::mm_per_unit`] does not know is
/// refused: a file in a wrong unit is a part a thousand times too small.
pub fn write_step_faces(
    faces: &[Face<'_>],
    units: &str,
    name: &str,
) -> Result<String, nurbs_core::Error> {
    write_step_faces_within(faces, units, name, 0.0)
}

/// [`write_step_faces`] with each trim edge a cubic B-spline through its points within
/// `edge_tolerance` (model units, at the points; [`crate::bounds::fitted_edge`]) instead of a
/// polyline: an edge of 200 points along a circle becomes a curve of a few dozen control
/// points. 0 keeps the polylines.
pub fn write_step_faces_within(
    faces: &[Face<'_>],
    units: &str,
    name: &str,
    edge_tolerance: f64,
) -> Result<String, nurbs_core::Error> {
    write_step_shell(faces, units, name, edge_tolerance, 0.0, &[])
}

/// [`write_step_faces_within`] with the faces joined into one shell where they meet: vertices
/// within `join_tolerance` (model units) of each other one vertex, edges of two faces along one
/// boundary one EDGE_CURVE used by both (split where a vertex of a third face lies on one), each
/// connected set of faces oriented so that every shared edge is used once each way, and the
/// shell a CLOSED_SHELL where every edge is used twice. The file's distance
/// accuracy is then the join tolerance: the written edge lies on one of its faces and within
/// that of the other. 0 writes every face with its own vertices and edges, as
/// [`write_step_faces_within`]. `parts` gives each face's part of an assembly (empty: one part):
/// faces are joined only within a part.
pub fn write_step_shell(
    faces: &[Face<'_>],
    units: &str,
    name: &str,
    edge_tolerance: f64,
    join_tolerance: f64,
    parts: &[usize],
) -> Result<String, nurbs_core::Error> {
    use std::fmt::Write as _;
    let mut w = StepWriter {
        edge_tolerance,
        ..StepWriter::default()
    };
    let plan = super::shell::ShellPlan::new(faces, join_tolerance, parts)?;
    let ids = w.shell_faces(faces, &plan)?;
    let shells: Vec<usize> = plan
        .shells
        .iter()
        .map(|(members, closed)| {
            let kind = if *closed {
                "CLOSED_SHELL"
            } else {
                "OPEN_SHELL"
            };
            let list: Vec<usize> = members.iter().map(|&f| ids[f]).collect();
            w.add(format!("{kind}('',({}))", refs(&list)))
        })
        .collect();
    let model = w.add(format!("SHELL_BASED_SURFACE_MODEL('',({}))", refs(&shells)));
    let length = w.length_unit(units)?;
    let angle = w.add("( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) )".into());
    let solid = w.add("( NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT() )".into());
    let uncertainty = w.add(format!(
        "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE({}),#{length},'distance_accuracy_value','confusion accuracy')",
        real(DISTANCE_ACCURACY.max(join_tolerance))
    ));
    let context = w.add(format!(
        "( GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#{uncertainty})) GLOBAL_UNIT_ASSIGNED_CONTEXT((#{length},#{angle},#{solid})) REPRESENTATION_CONTEXT('Context #1','3D Context with UNIT and UNCERTAINTY') )"
    ));
    let origin = w.add("CARTESIAN_POINT('',(0.,0.,0.))".into());
    let z = w.add("DIRECTION('',(0.,0.,1.))".into());
    let x = w.add("DIRECTION('',(1.,0.,0.))".into());
    let axes = w.add(format!("AXIS2_PLACEMENT_3D('',#{origin},#{z},#{x})"));
    let rep = w.add(format!(
        "MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#{axes},#{model}),#{context})"
    ));
    let app =
        w.add("APPLICATION_CONTEXT('core data for automotive mechanical design processes')".into());
    w.add(format!(
        "APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',2000,#{app})"
    ));
    let pctx = w.add(format!("PRODUCT_CONTEXT('',#{app},'mechanical')"));
    let product = w.add(format!("PRODUCT('{0}','{0}','',(#{pctx}))", escape(name)));
    let formation = w.add(format!("PRODUCT_DEFINITION_FORMATION('','',#{product})"));
    let dctx = w.add(format!(
        "PRODUCT_DEFINITION_CONTEXT('part definition',#{app},'design')"
    ));
    let def = w.add(format!(
        "PRODUCT_DEFINITION('design','',#{formation},#{dctx})"
    ));
    let shape = w.add(format!("PRODUCT_DEFINITION_SHAPE('','',#{def})"));
    w.add(format!("SHAPE_DEFINITION_REPRESENTATION(#{shape},#{rep})"));
    let mut out = String::new();
    let _ = write!(
        out,
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('hier-fair model'),'2;1');\nFILE_NAME('{}','',(''),(''),'hier-fair','hier-fair','');\nFILE_SCHEMA(('AUTOMOTIVE_DESIGN {{ 1 0 10303 214 1 1 1 1 }}'));\nENDSEC;\nDATA;\n",
        escape(name)
    );
    for (k, line) in w.lines.iter().enumerate() {
        let _ = writeln!(out, "#{} = {line};", k + 1);
    }
    out.push_str("ENDSEC;\nEND-ISO-10303-21;\n");
    Ok(out)
}

#[derive(Default)]
struct StepWriter {
    lines: Vec<String>,
    /// the trim edges' fit tolerance (0: polylines)
    edge_tolerance: f64,
}

fn refs(ids: &[usize]) -> String {
    ids.iter()
        .map(|i| format!("#{i}"))
        .collect::<Vec<_>>()
        .join(",")
}

fn escape(s: &str) -> String {
    s.replace('\'', "''")
}

/// A real as STEP writes it, round-trip exact and always with a decimal point before any
/// exponent (ISO 10303-21 §6.4.4: REAL = [sign] digit {digit} "." {digit} ["E" [sign] digit
/// {digit}]; Rust writes 1e-7 as "1e-7", which is no STEP real).
fn real(x: f64) -> String {
    let s = format!("{x:?}");
    if s.contains("inf") || s.contains("NaN") {
        return s;
    }
    match s.split_once('e') {
        Some((mantissa, exponent)) if mantissa.contains('.') => format!("{mantissa}E{exponent}"),
        Some((mantissa, exponent)) => format!("{mantissa}.E{exponent}"),
        None if s.contains('.') => s,
        None => format!("{s}."),
    }
}

impl StepWriter {
    fn add(&mut self, line: String) -> usize {
        self.lines.push(line);
        self.lines.len()
    }

    /// The LENGTH_UNIT of a model in `units` ([`crate::units`] text, \[ISO41\]): an SI unit
    /// (the metre with its prefix) where it is one, else a CONVERSION_BASED_UNIT defined in
    /// millimetres (INCH, FOOT, or one named by its size).
    fn length_unit(&mut self, units: &str) -> Result<usize, nurbs_core::Error> {
        let mm = crate::units::mm_per_unit(units).ok_or_else(|| nurbs_core::Error::Format {
            detail: format!(
                "model unit {units:?} is not a length unit this writer knows ({}, or \"<factor> mm\")",
                crate::units::UNITS.map(|(n, _)| n).join(", ")
            ),
        })?;
        let si =
            |prefix: &str| format!("( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT({prefix},.METRE.) )");
        let prefix = match crate::units::unit_text(mm).as_str() {
            "mm" => Some(".MILLI."),
            "cm" => Some(".CENTI."),
            "dm" => Some(".DECI."),
            "m" => Some("$"),
            "km" => Some(".KILO."),
            "um" => Some(".MICRO."),
            "nm" => Some(".NANO."),
            _ => None,
        };
        if let Some(prefix) = prefix {
            return Ok(self.add(si(prefix)));
        }
        let name = match crate::units::unit_text(mm).as_str() {
            "in" => "INCH".to_string(),
            "ft" => "FOOT".to_string(),
            "mil" => "MIL".to_string(),
            "mi" => "MILE".to_string(),
            _ => format!("{} MM", real(mm)),
        };
        let base = self.add(si(".MILLI."));
        let measure = self.add(format!(
            "LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE({}),#{base})",
            real(mm)
        ));
        let dims = self.add("DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.)".into());
        Ok(self.add(format!(
            "( CONVERSION_BASED_UNIT('{name}',#{measure}) LENGTH_UNIT() NAMED_UNIT(#{dims}) )"
        )))
    }
    fn point(&mut self, p: &Point3) -> usize {
        self.add(format!(
            "CARTESIAN_POINT('',({},{},{}))",
            real(p.x),
            real(p.y),
            real(p.z)
        ))
    }
    fn knots(kv: &KnotVector) -> (String, String) {
        let mut values: Vec<f64> = Vec::new();
        let mut mults: Vec<usize> = Vec::new();
        for &k in kv.knots() {
            if values.last() == Some(&k) {
                *mults.last_mut().expect("a value has a count") += 1;
            } else {
                values.push(k);
                mults.push(1);
            }
        }
        (
            mults
                .iter()
                .map(|m| m.to_string())
                .collect::<Vec<_>>()
                .join(","),
            values
                .iter()
                .map(|&v| real(v))
                .collect::<Vec<_>>()
                .join(","),
        )
    }
    fn curve(&mut self, c: &BSplineCurve) -> usize {
        let pts: Vec<usize> = c.control_points().iter().map(|p| self.point(p)).collect();
        let (m, k) = Self::knots(c.knots());
        let d = c.knots().degree();
        match c.weights() {
            None => self.add(format!(
                "B_SPLINE_CURVE_WITH_KNOTS('',{d},({}),.UNSPECIFIED.,.F.,.F.,({m}),({k}),.UNSPECIFIED.)",
                refs(&pts)
            )),
            Some(w) => self.add(format!(
                "( BOUNDED_CURVE() B_SPLINE_CURVE({d},({}),.UNSPECIFIED.,.F.,.F.) B_SPLINE_CURVE_WITH_KNOTS(({m}),({k}),.UNSPECIFIED.) CURVE() GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_CURVE(({})) REPRESENTATION_ITEM('') )",
                refs(&pts),
                w.iter().map(|&x| real(x)).collect::<Vec<_>>().join(",")
            )),
        }
    }
    /// The surface entity of `s`.
    fn surface(&mut self, s: &BSplineSurface) -> usize {
        let (nu, nv) = (s.num_u(), s.num_v());
        let mut rows = Vec::new();
        for i in 0..nu {
            let row: Vec<usize> = (0..nv)
                .map(|j| self.point(&s.control_point(i, j)))
                .collect();
            rows.push(format!("({})", refs(&row)));
        }
        let (mu, ku) = Self::knots(s.knots_u());
        let (mv, kv) = Self::knots(s.knots_v());
        let (du, dv) = (s.degree_u(), s.degree_v());
        match s.weights() {
            None => self.add(format!(
                "B_SPLINE_SURFACE_WITH_KNOTS('',{du},{dv},({}),.UNSPECIFIED.,.F.,.F.,.F.,({mu}),({mv}),({ku}),({kv}),.UNSPECIFIED.)",
                rows.join(",")
            )),
            Some(w) => {
                let wrows: Vec<String> = (0..nu)
                    .map(|i| {
                        format!(
                            "({})",
                            (0..nv)
                                .map(|j| real(w[i * nv + j]))
                                .collect::<Vec<_>>()
                                .join(",")
                        )
                    })
                    .collect();
                self.add(format!(
                    "( BOUNDED_SURFACE() B_SPLINE_SURFACE({du},{dv},({}),.UNSPECIFIED.,.F.,.F.,.F.) B_SPLINE_SURFACE_WITH_KNOTS(({mu}),({mv}),({ku}),({kv}),.UNSPECIFIED.) GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_SURFACE(({})) REPRESENTATION_ITEM('') SURFACE() )",
                    rows.join(","),
                    wrows.join(",")
                ))
            }
        }
    }

    /// The faces of `plan` (surfaces from `faces`): its vertices and used edges once each
    /// (an edge its exact curve, else a cubic through its points within the edge tolerance,
    /// [`crate::bounds::fitted_edge`]), then each face with its loops — a face flipped against
    /// its surface's normal written with `same_sense` false and its bounds reversed.
    fn shell_faces(
        &mut self,
        faces: &[Face<'_>],
        plan: &super::shell::ShellPlan,
    ) -> Result<Vec<usize>, nurbs_core::Error> {
        let mut used = vec![false; plan.vertices.len()];
        for e in plan.edges.iter().filter(|e| e.uses > 0) {
            (used[e.start], used[e.end]) = (true, true);
        }
        let vertices: Vec<usize> = plan
            .vertices
            .iter()
            .zip(&used)
            .map(|(p, &u)| {
                if !u {
                    return 0;
                }
                let pt = self.point(p);
                self.add(format!("VERTEX_POINT('',#{pt})"))
            })
            .collect();
        let mut edges = Vec::with_capacity(plan.edges.len());
        for e in &plan.edges {
            if e.uses == 0 {
                edges.push(0);
                continue;
            }
            let curve = match &e.exact {
                Some(c) => c.clone(),
                None => crate::bounds::fitted_edge(&e.points, self.edge_tolerance)?,
            };
            let cid = self.curve(&curve);
            edges.push(self.add(format!(
                "EDGE_CURVE('',#{},#{},#{cid},.T.)",
                vertices[e.start], vertices[e.end]
            )));
        }
        let mut out = Vec::with_capacity(faces.len());
        for (f, pf) in faces.iter().zip(&plan.faces) {
            let surface = self.surface(f.surface);
            let mut bounds = Vec::with_capacity(pf.loops.len());
            for l in &pf.loops {
                let oriented: Vec<usize> = l
                    .edges
                    .iter()
                    .map(|&(k, forward)| {
                        self.add(format!(
                            "ORIENTED_EDGE('',*,*,#{},{})",
                            edges[k],
                            logical(forward)
                        ))
                    })
                    .collect();
                let lp = self.add(format!("EDGE_LOOP('',({}))", refs(&oriented)));
                let kind = if l.outer {
                    "FACE_OUTER_BOUND"
                } else {
                    "FACE_BOUND"
                };
                bounds.push(self.add(format!("{kind}('',#{lp},{})", logical(!pf.flipped))));
            }
            out.push(self.add(format!(
                "ADVANCED_FACE('{}',({}),#{surface},{})",
                escape(f.name),
                refs(&bounds),
                logical(!pf.flipped)
            )));
        }
        Ok(out)
    }
}

/// A STEP logical.
fn logical(b: bool) -> &'static str {
    if b { ".T." } else { ".F." }
}
