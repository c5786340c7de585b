//! One self-contained HTML file a surfacing engineer opens offline to judge a model: a 3D view
//! (turn, zoom, pick) shaded by zebra stripes, mean or Gaussian curvature, or the deviation from
//! the input, with the control nets, knot lines and trims on demand and a before / after
//! toggle; curvature combs across every link (slave and master, normal curvature in the direction
//! n × T, as `check` measures G2) and along a chosen iso-line; the link table and the surface
//! table, sortable, a click focusing the view.
//!
//! The viewer is this crate's own small WebGL program (`assets/html/viewer.js`), embedded with
//! its style sheet and the data ([`data`]) in the page: the file loads nothing from anywhere, so
//! it can be mailed, archived with the model, and opened without a network. The data of the
//! tables are the `report.json` (or `check --json`) values themselves, embedded unchanged.
//!
//! Zebra stripes are the reflection lines of \[SV\] §6: the view ray reflected in the surface
//! normal, striped by its component along a direction across the view; a G1 join keeps them
//! continuous, a G2 join keeps them without kinks.

pub mod data;

use serde_json::{Value, json};

use crate::model::Model;

/// The page's frame: the style sheet, the viewer and the data are put in its slots.
const TEMPLATE: &str = include_str!("../../assets/html/template.html");
/// The page's style sheet.
const STYLE: &str = include_str!("../../assets/html/viewer.css");
/// The viewer (WebGL 1, no library).
const VIEWER: &str = include_str!("../../assets/html/viewer.js");
/// The link and surface tables.
const TABLES: &str = include_str!("../../assets/html/tables.js");

/// What a report shows.
#[derive(Debug, Clone, Copy)]
pub struct HtmlReport<'a> {
    /// the page title (e.g. the command that made it)
    pub title: &'a str,
    /// the model as it came in
    pub model: &'a Model,
    /// the faired model (`fair`), `None` for `check`
    pub faired: Option<&'a Model>,
    /// `fair`'s `report.json` value ([`crate::report_json`]), shown in the tables as it is
    pub report: Option<&'a Value>,
    /// `check --json`'s value ([`crate::check::checks_json`]), for a report of `check`
    pub checks: Option<&'a Value>,
}

/// The whole page as text.
pub fn html_report(r: &HtmlReport) -> String {
    let payload = payload(r).to_string();
    // inside <script> a "</" would end the element: JSON allows "<\/" for it
    let payload = payload.replace("</", "<\\/");
    TEMPLATE
        .replace("{{title}}", &escape(r.title))
        .replace("/*{{style}}*/", STYLE)
        .replace("/*{{tables}}*/", TABLES)
        .replace("/*{{viewer}}*/", VIEWER)
        .replace("{{data}}", &payload)
}

/// `text` with the characters HTML gives meaning escaped.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The data of the page ([`data`] for the geometry; the tables' values as given). The faired
/// model's surfaces and links are matched to the input's by name (a run that merged slivers
/// holds fewer surfaces than its input: those have no "after").
pub fn payload(r: &HtmlReport) -> Value {
    let model = r.model;
    let surfaces = surfaces_json(r);
    let links = links_json(r);
    let t = &model.tolerances;
    json!({
        "title": r.title,
        "generator": concat!("hier-fair ", env!("CARGO_PKG_VERSION")),
        "kind": if r.faired.is_some() { "fair" } else { "check" },
        "unit": model.units.clone().unwrap_or_else(|| "mm".into()),
        "mm_per_unit": model.mm_per_unit(),
        "tolerances": {"g0": t.g0, "g1_deg": t.g1_deg, "g2_rel": t.g2_rel, "deviation": t.deviation},
        "surfaces": surfaces,
        "links": links,
        "report": r.report,
        "checks": r.checks,
    })
}

/// Every input surface with its states, trim and fairness figures ([`payload`]'s `surfaces`).
fn surfaces_json(r: &HtmlReport) -> Vec<Value> {
    let model = r.model;
    let n = data::grid_size(model.surfaces.len());
    let fair_before = crate::fairness::model_fairness(model);
    let fair_after = r.faired.map(crate::fairness::model_fairness);
    // the faired surface of input surface k
    let after_index = |k: usize| {
        let name = &model.surfaces[k].name;
        r.faired
            .and_then(|f| f.surfaces.iter().position(|s| &s.name == name))
    };
    model
        .surfaces
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let a = after_index(k);
            let after = a.and_then(|i| r.faired.map(|f| &f.surfaces[i].surface));
            let fairness = a.and_then(|i| fair_after.as_ref().map(|f| &f[i]));
            json!({
                "name": s.name,
                "role": s.role.name(),
                "n": n,
                "trim": data::trim_json(s, n),
                "before": data::state_json(&s.surface, n, None),
                "after": after.map(|a| data::state_json(a, n, Some(&s.surface))),
                "fairness_before": crate::report::fairness_json(&fair_before[k]),
                "fairness_after": fairness.map(crate::report::fairness_json),
            })
        })
        .collect()
}

/// Every input link with its combs before and after ([`payload`]'s `links`).
fn links_json(r: &HtmlReport) -> Vec<Value> {
    let model = r.model;
    let combs = |m: &Model| {
        let measures = data::link_measures(m);
        (measures.len() == m.links.len()).then_some(measures)
    };
    let (combs_before, combs_after) = (combs(model), r.faired.and_then(combs));
    let label = |m: &Model, l: &crate::model::Link| {
        (
            m.surfaces[l.slave].name.clone(),
            l.side,
            m.surfaces[l.master].name.clone(),
        )
    };
    model
        .links
        .iter()
        .enumerate()
        .map(|(k, l)| {
            let before = combs_before
                .as_ref()
                .map(|ms| data::comb_json(&model.surfaces[l.slave].surface, l.side, &ms[k]));
            let after = r.faired.zip(combs_after.as_ref()).and_then(|(f, ms)| {
                let want = label(model, l);
                let j = f.links.iter().position(|fl| label(f, fl) == want)?;
                let fl = &f.links[j];
                Some(data::comb_json(
                    &f.surfaces[fl.slave].surface,
                    fl.side,
                    &ms[j],
                ))
            });
            json!({
                "label": model.link_label(k),
                "slave": l.slave,
                "master": l.master,
                "side": l.side.name(),
                "target": crate::check::continuity_name(l.continuity),
                "comb_before": before,
                "comb_after": after,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs_core::{KnotVector, Point3};

    /// A bicubic patch with an `n` × `n` net over the unit square at `(x, y)`, gently curved.
    fn patch(x: f64, y: f64, n: usize) -> nurbs_core::BSplineSurface {
        let knots = KnotVector::clamped_uniform(3, n).expect("knots");
        let pts = (0..n * n)
            .map(|k| {
                let (a, b) = (
                    (k / n) as f64 / (n - 1) as f64,
                    (k % n) as f64 / (n - 1) as f64,
                );
                Point3::new(x + a, y + b, 0.1 * (a * a - b * b))
            })
            .collect();
        nurbs_core::BSplineSurface::new(knots.clone(), knots, pts, None).expect("patch")
    }

    /// A 100-surface model whose faired nets have grown to 40 × 40 (as corner blends grow)
    /// gives a page under 10 MB, before and after.
    #[test]
    fn a_hundred_surfaces_stay_under_ten_megabytes() {
        let model = Model::from_primaries(
            (0..100)
                .map(|k| patch((k % 10) as f64, (k / 10) as f64, 8))
                .collect(),
        );
        let faired = Model::from_primaries(
            (0..100)
                .map(|k| patch((k % 10) as f64, (k / 10) as f64, 40))
                .collect(),
        );
        let page = html_report(&HtmlReport {
            title: "a hundred patches",
            model: &model,
            faired: Some(&faired),
            report: None,
            checks: None,
        });
        assert!(page.len() < 10_000_000, "{} bytes", page.len());
        assert!(
            page.len() > 1_000_000,
            "{} bytes: the grids are missing",
            page.len()
        );
    }

    /// A faired model that holds fewer surfaces than its input (slivers merged) is matched by
    /// name: the surface it lost has no "after", the others theirs.
    #[test]
    fn faired_surfaces_are_matched_by_name() {
        let model = Model::from_primaries(vec![patch(0.0, 0.0, 4), patch(1.0, 0.0, 4)]);
        let mut faired = model.clone();
        faired.surfaces.remove(0);
        let data = payload(&HtmlReport {
            title: "merged",
            model: &model,
            faired: Some(&faired),
            report: None,
            checks: None,
        });
        assert_eq!(data["surfaces"][0]["after"], Value::Null);
        assert!(data["surfaces"][1]["after"]["grid"].is_object());
        assert!(data["surfaces"][1]["fairness_after"].is_object());
    }

    /// The page embeds the tables' JSON unchanged, escapes what would end its script element,
    /// and loads nothing from the network.
    #[test]
    fn page_embeds_the_values_and_nothing_external() {
        let model = Model::from_primaries(vec![patch(0.0, 0.0, 4)]);
        let checks = json!({"links": [], "note": "</script><script>alert(1)</script>"});
        let page = html_report(&HtmlReport {
            title: "<b>check</b>",
            model: &model,
            faired: None,
            report: None,
            checks: Some(&checks),
        });
        assert!(!page.contains("http://") && !page.contains("https://"));
        assert!(page.contains("<title>&lt;b&gt;check&lt;/b&gt;</title>"));
        assert_eq!(
            page.matches("</script>").count(),
            2,
            "the data and the viewer elements only"
        );
        let start = page.find(r#"id="hf-data">"#).expect("data") + r#"id="hf-data">"#.len();
        let end = start + page[start..].find("</script>").expect("end");
        let data: Value = serde_json::from_str(&page[start..end]).expect("parses");
        assert_eq!(data["checks"], checks);
        assert_eq!(data["kind"], "check");
        assert_eq!(data["surfaces"][0]["after"], Value::Null);
        assert!(!page.contains("/*{{"), "every slot filled");
    }
}
