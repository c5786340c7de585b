//! `hierfair.Model`: a model (surfaces with names and roles, links, tolerances) loaded from its
//! JSON or imported from STEP/IGES with its hierarchy found, measured as `check` measures it,
//! faired by the framework as `fair` fairs it, and written back (JSON, STEP, IGES).

use std::path::Path;

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use hier_fair::exchange::{CadFormat, cad_text, read_cad};
use hier_fair::{BuiltMethods, FairParams, Fairers, Model, RoleMethods};

use crate::error::{HierFairError, model_err};
use crate::method::{continuity_of, method_of, to_python};
use crate::surface::PySurface;

/// A model: surfaces with names and roles (primary, connecting, corner), the links between
/// them and the model's tolerances.
#[pyclass(module = "hierfair", name = "Model")]
#[derive(Debug, Clone)]
pub struct PyModel {
    /// the model
    pub inner: Model,
    /// what the import found (CAD files only)
    summary: Option<String>,
}

/// The file at `path`, or an error naming it.
fn read(path: &str) -> PyResult<Vec<u8>> {
    std::fs::read(path).map_err(|e| HierFairError::new_err(format!("{path}: {e}")))
}

/// The exchange format an output path names by its extension (`None`: JSON).
fn format_of(path: &str) -> Option<CadFormat> {
    let ext = Path::new(path)
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("step" | "stp") => Some(CadFormat::Step),
        Some("igs" | "iges") => Some(CadFormat::Iges),
        _ => None,
    }
}

impl PyModel {
    fn index(&self, name: &str) -> PyResult<usize> {
        self.inner
            .find(name)
            .ok_or_else(|| HierFairError::new_err(format!("no surface named {name:?}")))
    }
}

#[pymethods]
impl PyModel {
    /// The model in the JSON model file at `path`.
    ///
    /// >>> import hierfair
    /// >>> m = hierfair.Model.load("fixtures/occt/occt_plate_boss.json")
    /// >>> m
    /// Model(10 surfaces, 4 links)
    #[staticmethod]
    fn load(path: &str) -> PyResult<Self> {
        let bytes = read(path)?;
        let text = String::from_utf8_lossy(&bytes);
        let inner =
            Model::from_json(&text).map_err(|e| HierFairError::new_err(format!("{path}: {e}")))?;
        Ok(Self {
            inner,
            summary: None,
        })
    }

    /// The model of JSON text in the model format.
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Self> {
        let inner = Model::from_json(text).map_err(model_err)?;
        Ok(Self {
            inner,
            summary: None,
        })
    }

    /// The model of the STEP or IGES file at `path` (known by its content), its hierarchy
    /// found as `hier-fair import` finds it; `summary` says what was read.
    #[staticmethod]
    fn import_cad(py: Python<'_>, path: &str) -> PyResult<Self> {
        let bytes = read(path)?;
        let imported = py
            .detach(|| read_cad(&bytes))
            .map_err(|e| HierFairError::new_err(format!("{path}: {e}")))?;
        Ok(Self {
            inner: imported.model,
            summary: Some(imported.summary),
        })
    }

    /// The model as JSON text (the model format).
    fn to_json(&self) -> String {
        self.inner.to_json()
    }

    /// Writes the model to `path`: STEP (.step, .stp) or IGES (.igs, .iges) by the extension,
    /// else its JSON.
    fn save(&self, path: &str) -> PyResult<()> {
        let text = match format_of(path) {
            Some(format) => {
                let name = Path::new(path)
                    .file_name()
                    .map_or_else(|| path.to_string(), |n| n.to_string_lossy().into_owned());
                cad_text(&self.inner, format, &name).map_err(model_err)?
            }
            None => self.inner.to_json(),
        };
        std::fs::write(path, text).map_err(|e| HierFairError::new_err(format!("{path}: {e}")))
    }

    /// Writes the model as STEP or IGES (by the extension of `path`).
    fn export(&self, path: &str) -> PyResult<()> {
        if format_of(path).is_none() {
            return Err(HierFairError::new_err(format!(
                "{path}: export writes .step, .stp, .igs or .iges (save() writes JSON)"
            )));
        }
        self.save(path)
    }

    /// What the CAD import read and found (`None` for a model loaded from JSON).
    #[getter]
    fn summary(&self) -> Option<String> {
        self.summary.clone()
    }

    /// The surfaces' names, in the model's order.
    #[getter]
    fn names(&self) -> Vec<String> {
        self.inner.surfaces.iter().map(|s| s.name.clone()).collect()
    }

    /// The model's length unit ("mm" where it names none).
    #[getter]
    fn units(&self) -> String {
        self.inner.units.clone().unwrap_or_else(|| "mm".into())
    }

    /// The surface named `name`.
    fn surface(&self, name: &str) -> PyResult<PySurface> {
        let k = self.index(name)?;
        Ok(PySurface {
            inner: self.inner.surfaces[k].surface.clone(),
        })
    }

    /// The role of the surface named `name`: "primary", "connecting" or "corner".
    fn role(&self, name: &str) -> PyResult<&'static str> {
        Ok(self.inner.surfaces[self.index(name)?].role.name())
    }

    /// {name: role} for every surface.
    ///
    /// >>> import hierfair
    /// >>> m = hierfair.Model.load("fixtures/occt/occt_plate_boss.json")
    /// >>> m.roles["F02_torus"]
    /// 'connecting'
    #[getter]
    fn roles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for s in &self.inner.surfaces {
            d.set_item(&s.name, s.role.name())?;
        }
        Ok(d)
    }

    /// The links: a list of dicts with `slave`, `side`, `master` and `target`.
    ///
    /// >>> import hierfair
    /// >>> m = hierfair.Model.load("fixtures/occt/occt_plate_boss.json")
    /// >>> m.links[0]
    /// {'slave': 'F02_torus', 'side': 'v0', 'master': 'P01_plane', 'target': 'G2'}
    #[getter]
    fn links<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let out = PyList::empty(py);
        for l in &self.inner.links {
            let d = PyDict::new(py);
            d.set_item("slave", &self.inner.surfaces[l.slave].name)?;
            d.set_item("side", l.side.name())?;
            d.set_item("master", &self.inner.surfaces[l.master].name)?;
            d.set_item("target", hier_fair::check::continuity_name(l.continuity))?;
            out.append(d)?;
        }
        Ok(out)
    }

    /// check(samples=None) → one dict per link with the fields of `hier-fair check --json`:
    /// slave, side, master, target, g0, g1_deg, g2_rel (and across the boundary, n × T), the
    /// worst places, the vertex figures.
    ///
    /// >>> import hierfair
    /// >>> m = hierfair.Model.load("fixtures/occt/occt_plate_boss.json")
    /// >>> link = m.check()[0]
    /// >>> link["slave"], link["g1_deg"] < 0.01, link["g2_rel"]
    /// ('F02_torus', True, 1.0)
    #[pyo3(signature = (samples=None))]
    fn check<'py>(&self, py: Python<'py>, samples: Option<usize>) -> PyResult<Bound<'py, PyAny>> {
        let params = g_continuity::MeasureParams {
            samples: samples.unwrap_or(g_continuity::MeasureParams::default().samples),
            ..Default::default()
        };
        let model = &self.inner;
        let checks = py
            .detach(|| hier_fair::measure_model(model, &params))
            .map_err(model_err)?;
        let v = hier_fair::check::checks_json(model, &checks, None);
        to_python(py, &v["links"])
    }

    /// fair(method=None, tolerance=None, tolerance_role=None, target=None, iterations=None,
    /// verify=True, keep_faired=False) → (Model, report)
    ///
    /// Fairs the model as `hier-fair fair` does: each surface in the hierarchy's order, its
    /// continuity to its masters set and faired in the alternation. `method` a built-in name
    /// for every role, or a Python callable `(surface, mask, tolerance) -> Surface` (None: the
    /// default per role); `tolerance` the deviation in millimetres, `tolerance_role` a dict
    /// {"primary"|"connecting"|"corner": mm}; `target` the highest continuity ("G0", "G1",
    /// "G2"); the report is the dict of `fair --report`.
    ///
    /// >>> import hierfair
    /// >>> m = hierfair.Model.load("fixtures/occt/occt_plate_boss.json")
    /// >>> faired, report = m.fair()
    /// >>> all(link["met"] for link in report["links"])
    /// True
    #[pyo3(signature = (method=None, tolerance=None, tolerance_role=None, target=None, iterations=None, verify=true, keep_faired=false))]
    fn fair<'py>(
        &self,
        py: Python<'py>,
        method: Option<&Bound<'py, PyAny>>,
        tolerance: Option<f64>,
        tolerance_role: Option<std::collections::HashMap<String, f64>>,
        target: Option<&str>,
        iterations: Option<usize>,
        verify: bool,
        keep_faired: bool,
    ) -> PyResult<(PyModel, Bound<'py, PyAny>)> {
        let model = &self.inner;
        // the lengths a user gives are millimetres; the framework takes the model's unit
        let in_units = |mm: f64| mm / model.mm_per_unit();
        let mut role_tolerance = [None; 3];
        for (role, mm) in tolerance_role.unwrap_or_default() {
            let k = match role.as_str() {
                "primary" => 0,
                "connecting" => 1,
                "corner" => 2,
                _ => {
                    return Err(HierFairError::new_err(format!(
                        "tolerance_role: unknown role {role:?} (primary, connecting or corner)"
                    )));
                }
            };
            role_tolerance[k] = Some(in_units(mm));
        }
        if let Some(t) = tolerance
            && !(t.is_finite() && t > 0.0)
        {
            return Err(HierFairError::new_err(format!(
                "tolerance must be a finite length > 0, got {t}"
            )));
        }
        let params = FairParams {
            target: target.map(continuity_of).transpose()?,
            tolerance: tolerance.map(in_units),
            role_tolerance,
            verify_unmet: verify,
            prefer_fairer: !keep_faired,
            ..FairParams::default()
        };
        let custom = method_of(method, iterations)?;
        let built = BuiltMethods::new(&RoleMethods::default(), iterations);
        let fairers = match &custom {
            Some(m) => Fairers {
                primary: m.as_ref(),
                connecting: m.as_ref(),
                corner: m.as_ref(),
            },
            None => built.fairers(),
        };
        let (faired, report) = py
            .detach(|| hier_fair::fair_model_with(model, fairers, &params, &|_| {}))
            .map_err(model_err)?;
        let report = to_python(py, &hier_fair::report_json(&report))?;
        Ok((
            PyModel {
                inner: faired,
                summary: None,
            },
            report,
        ))
    }

    /// html_report(faired=None, report=None, title="hierfair") → str
    ///
    /// The quality report page of `hier-fair fair --html` (with `faired` and the `report` dict
    /// that `fair` returned: before / after, deviation, the report's tables) or of `hier-fair
    /// check --html` (without: this model's links measured): one self-contained HTML file with
    /// a 3D viewer, zebra and curvature shading, curvature combs and sortable tables. Write it
    /// to a `.html` file and open it in a browser.
    ///
    /// >>> import hierfair
    /// >>> m = hierfair.Model.load("fixtures/models/x_node.json")
    /// >>> faired, report = m.fair()
    /// >>> page = m.html_report(faired, report, title="the X-node")
    /// >>> page.startswith("<!DOCTYPE html>"), "<title>the X-node</title>" in page
    /// (True, True)
    #[pyo3(signature = (faired=None, report=None, title="hierfair"))]
    fn html_report(
        &self,
        py: Python<'_>,
        faired: Option<PyRef<'_, PyModel>>,
        report: Option<&Bound<'_, PyAny>>,
        title: &str,
    ) -> PyResult<String> {
        let report: Option<serde_json::Value> = match report {
            Some(r) => {
                let text: String = py.import("json")?.call_method1("dumps", (r,))?.extract()?;
                Some(serde_json::from_str(&text).map_err(|e| {
                    HierFairError::new_err(format!("report: not the dict fair returned: {e}"))
                })?)
            }
            None => None,
        };
        let model = &self.inner;
        let faired = faired.as_ref().map(|f| &f.inner);
        if let Some(f) = faired
            && f.surfaces.len() != model.surfaces.len()
        {
            return Err(HierFairError::new_err(format!(
                "faired: {} surfaces, this model {}: not its faired model",
                f.surfaces.len(),
                model.surfaces.len()
            )));
        }
        py.detach(|| -> hier_fair::Result<String> {
            let checks = match faired {
                Some(_) => None,
                None => {
                    let params = g_continuity::MeasureParams::default();
                    let checks = hier_fair::measure_model(model, &params)?;
                    Some(hier_fair::check::checks_json(model, &checks, None))
                }
            };
            Ok(hier_fair::html::html_report(&hier_fair::html::HtmlReport {
                title,
                model,
                faired,
                report: report.as_ref(),
                checks: checks.as_ref(),
            }))
        })
        .map_err(model_err)
    }

    fn __repr__(&self) -> String {
        format!(
            "Model({} surfaces, {} links)",
            self.inner.surfaces.len(),
            self.inner.links.len()
        )
    }
}
