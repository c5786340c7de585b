//! The IGES writer: a valid IGES 5.3 file with entities 128 (surfaces) and 126 (curves), numbers
//! in full double precision (shortest representation that reads back to the same bits), names in
//! the directory entry labels (8 characters; longer names are cut and numbered by subscript).

use nurbs_core::{BSplineCurve, BSplineSurface};

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
}

impl Default for IgesWriteParams {
    fn default() -> Self {
        Self {
            unit_flag: 2,
            units: "MM".into(),
            file_name: "model.igs".into(),
            date: "20260101.000000".into(),
            author: "hier-fair".into(),
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
}

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

/// Writes surfaces (entity 128) and curves (entity 126) with their names as an IGES 5.3 file.
pub fn write_iges(
    surfaces: &[(&str, &BSplineSurface)],
    curves: &[(&str, &BSplineCurve)],
    params: &IgesWriteParams,
) -> Result<String, IgesError> {
    let names: Vec<&str> = surfaces
        .iter()
        .map(|s| s.0)
        .chain(curves.iter().map(|c| c.0))
        .collect();
    let labels = labels(&names);
    let mut entities = Vec::new();
    let mut max_coord: f64 = 0.0;
    for (k, (name, s)) in surfaces.iter().enumerate() {
        max_coord = s
            .control_points()
            .iter()
            .flat_map(|p| [p.x.abs(), p.y.abs(), p.z.abs()])
            .fold(max_coord, f64::max);
        entities.push(Entity {
            entity_type: 128,
            params: surface_params(s, &format!("surface {name}"))?,
            label: labels[k].0.clone(),
            subscript: labels[k].1,
        });
    }
    for (k, (name, c)) in curves.iter().enumerate() {
        max_coord = c
            .control_points()
            .iter()
            .flat_map(|p| [p.x.abs(), p.y.abs(), p.z.abs()])
            .fold(max_coord, f64::max);
        let l = &labels[surfaces.len() + k];
        entities.push(Entity {
            entity_type: 126,
            params: curve_params(c, &format!("curve {name}"))?,
            label: l.0.clone(),
            subscript: l.1,
        });
    }
    let mut out: Vec<String> = Vec::new();
    let start = "hier-fair IGES 5.3 export: B-spline surfaces (128) and curves (126)";
    out.push(record(start, 'S', 1));
    let global = vec![
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
    ];
    let g_lines = pack(&tokens(global), DATA_COLUMNS);
    for (k, l) in g_lines.iter().enumerate() {
        out.push(record(l, 'G', k + 1));
    }
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
                e.entity_type, pointer, 0, 0, 0, 0, 0, 0, "00000000"
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
