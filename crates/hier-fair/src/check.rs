//! Measuring every link of a model (the analyzer users run first) and the presets of the
//! `--fail-above` option.
//!
//! Each link is measured by [`g_continuity::measure_link`] (gap, normal angle, relative and
//! absolute normal-curvature difference, the worst sample of each), its curvature figures
//! outside the vertex zones of [`crate::zones`] (those are reported as the vertex figures). A link whose largest gap is
//! above [`TOUCH_FACTOR`] × the model's g0 tolerance does not touch its master: that is bad input,
//! reported as an error naming the link and the gap.

use g_continuity::{LinkMeasure, MeasureParams};
use nurbs_core::Continuity;
use rayon::prelude::*;
use serde_json::{Value, json};

use crate::error::{Error, Result};
use crate::model::Model;

/// A link side farther than this many g0 tolerances from its master does not touch it.
pub const TOUCH_FACTOR: f64 = 100.0;

/// The measurement of one link.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkCheck {
    /// index into `model.links`
    pub link: usize,
    /// "slave.side -> master"
    pub label: String,
    /// the link's target
    pub target: Continuity,
    /// what was measured
    pub measure: LinkMeasure,
}

/// Continuity limits a link must not exceed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Preset {
    /// largest gap (model units; the named presets' in millimetres, which `check` converts)
    pub g0: f64,
    /// largest normal angle (degrees)
    pub g1_deg: f64,
    /// largest relative curvature difference; `None`: not checked
    pub g2_rel: Option<f64>,
}

impl Preset {
    /// The named presets of the CLI contract: class-a 0.001 / 0.01° / 0.02, standard 0.01 / 0.1° /
    /// 0.05, exchange 0.01 / 0.5° / none; the gaps in millimetres.
    pub fn named(name: &str) -> Option<Preset> {
        match name {
            "class-a" => Some(Preset {
                g0: 1e-3,
                g1_deg: 1e-2,
                g2_rel: Some(2e-2),
            }),
            "standard" => Some(Preset {
                g0: 1e-2,
                g1_deg: 1e-1,
                g2_rel: Some(5e-2),
            }),
            "exchange" => Some(Preset {
                g0: 1e-2,
                g1_deg: 0.5,
                g2_rel: None,
            }),
            _ => None,
        }
    }

    /// Names of the presets.
    pub const NAMES: [&'static str; 3] = ["class-a", "standard", "exchange"];

    /// Whether `check` exceeds the preset up to its link's target continuity (a G1 link is not
    /// judged on curvature). Undefined values (collapsed sides, poles) do not count.
    pub fn exceeded_by(&self, check: &LinkCheck) -> bool {
        let m = &check.measure;
        let g0 = m.g0 > self.g0;
        let g1 = check.target >= Continuity::G1 && m.g1_deg.is_some_and(|a| a > self.g1_deg);
        let g2 = check.target >= Continuity::G2
            && matches!((m.g2_rel, self.g2_rel), (Some(r), Some(limit)) if r > limit);
        g0 || g1 || g2
    }
}

/// Measures every link of `model` (in parallel); errors on a link that does not touch its master.
pub fn check_model(model: &Model, params: &MeasureParams) -> Result<Vec<LinkCheck>> {
    let checks = measure_model(model, params)?;
    if let Some(c) = checks.iter().find(|c| !c.touches(model)) {
        return Err(Error::LinkNotTouching {
            link: c.label.clone(),
            gap: c.measure.g0,
            limit: TOUCH_FACTOR * model.tolerances.g0,
        });
    }
    Ok(checks)
}

impl LinkCheck {
    /// Whether the link's side touches its master: its largest gap is within [`TOUCH_FACTOR`]
    /// × the model's g0 tolerance.
    pub fn touches(&self, model: &Model) -> bool {
        self.measure.g0 <= TOUCH_FACTOR * model.tolerances.g0
    }
}

/// Measures every link of `model` (in parallel), touching or not: what `hier-fair check`
/// reports (a link that does not touch shows its gap).
pub fn measure_model(model: &Model, params: &MeasureParams) -> Result<Vec<LinkCheck>> {
    // the vertex zones are found on the model as `fair` works on it: with the shared edges no
    // link covers linked too ([`crate::edges::link_edges`]), so that a corner a found link makes
    // a conflict is judged the same way here
    let (work, _, ranges) = crate::edges::link_edges(model, &crate::edges::shared_edges(model));
    let tol = model.tolerances.continuity();
    let checks: Vec<LinkCheck> = (0..model.links.len())
        .into_par_iter()
        .map(|k| {
            let l = &model.links[k];
            let label = model.link_label(k);
            // the vertex zones where the slave's masters disagree at a corner ([`crate::zones`])
            let zones = crate::zones::link_zones(&work, &ranges, k, &tol);
            let measure = g_continuity::measure::measure_link_zoned(
                &model.surfaces[l.master].surface,
                &model.surfaces[l.slave].surface,
                l.side,
                None,
                zones,
                params,
            )
            .map_err(|source| Error::Continuity {
                place: format!("link {label}"),
                source,
            })?;
            Ok(LinkCheck {
                link: k,
                label,
                target: l.continuity,
                measure,
            })
        })
        .collect::<Result<_>>()?;
    Ok(checks)
}

/// The C⁰ knot lines inside one surface ([`nurbs_core::creases`]) and how far the normal turns
/// across them: a join between a kernel's rational arcs, or a crease a method made. `check`
/// reports them beside the links, so a surface that is no longer tangent continuous inside
/// shows even where every link is met.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceJoins {
    /// index into `model.surfaces`
    pub surface: usize,
    /// its name
    pub name: String,
    /// number of C⁰ knot lines
    pub lines: usize,
    /// the largest normal jump across them (degrees); `None` where no sample has normals on
    /// both sides
    pub crease_deg: Option<f64>,
}

/// The surfaces of `model` that have C⁰ knot lines, with the largest normal jump across them
/// (in parallel).
pub fn surface_joins(model: &Model) -> Vec<SurfaceJoins> {
    (0..model.surfaces.len())
        .into_par_iter()
        .filter_map(|k| {
            let s = &model.surfaces[k].surface;
            let lines = nurbs_core::creases::knot_lines(s);
            if lines.is_empty() {
                return None;
            }
            let crease_deg = lines
                .iter()
                .filter_map(|l| nurbs_core::creases::crease_deg(s, l))
                .fold(None, |a: Option<f64>, d| Some(a.map_or(d, |a| a.max(d))));
            Some(SurfaceJoins {
                surface: k,
                name: model.surfaces[k].name.clone(),
                lines: lines.len(),
                crease_deg,
            })
        })
        .collect()
}

/// `x` as JSON, `null` where absent.
pub fn optional_json(x: Option<f64>) -> Value {
    x.map_or(Value::Null, |v| json!(v))
}

/// The measurements as a JSON object (the fields of a `check --json` link entry).
pub fn measure_json(m: &LinkMeasure) -> Value {
    json!({
        "samples": m.samples,
        "g0": m.g0,
        "g1_deg": optional_json(m.g1_deg),
        "g2_rel": optional_json(m.g2_rel),
        "g2_abs": optional_json(m.g2_abs),
        "worst_g0": {"t": m.worst_g0_t},
        "worst_g1": {"t": optional_json(m.worst_g1_t)},
        "worst_g2": {"t": optional_json(m.worst_g2_t)},
        "g2_rel_across": optional_json(m.g2_rel_across),
        "g2_abs_across": optional_json(m.g2_abs_across),
        "worst_g2_across": {"t": optional_json(m.worst_g2_across_t)},
        "g1_deg_vertex": optional_json(m.vertex_g1_deg),
        "g2_rel_vertex": optional_json(m.vertex_g2_rel),
        "vertex_zones": m.vertex_zones,
        "collapsed": m.collapsed,
        "undefined_normals": m.undefined_normals,
        "undefined_curvatures": m.undefined_curvatures,
    })
}

/// Continuity name as in the model format.
pub fn continuity_name(c: nurbs_core::Continuity) -> &'static str {
    match c {
        nurbs_core::Continuity::G0 => "G0",
        nurbs_core::Continuity::G1 => "G1",
        nurbs_core::Continuity::G2 => "G2",
    }
}

/// The links of `check --json`: each link's measures ([`measure_json`]) with its slave, side,
/// master and target; `exceeded` where `flags` (a preset's verdict per check) are given, and
/// `touches: false` for a link whose slave does not touch its master.
pub fn checks_json(model: &Model, checks: &[LinkCheck], flags: Option<&[bool]>) -> Value {
    let links: Vec<Value> = checks
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let l = &model.links[c.link];
            let mut v = measure_json(&c.measure);
            let o = v.as_object_mut().expect("object");
            o.insert("slave".into(), json!(model.surfaces[l.slave].name));
            o.insert("side".into(), json!(l.side.name()));
            o.insert("master".into(), json!(model.surfaces[l.master].name));
            o.insert("target".into(), json!(continuity_name(l.continuity)));
            if let Some(f) = flags {
                o.insert("exceeded".into(), json!(f[k]));
            }
            if !c.touches(model) {
                o.insert("touches".into(), json!(false));
            }
            v
        })
        .collect();
    json!({ "links": links })
}
