//! Fairing methods for Python: a built-in method by name or a Python callable as a
//! [`SurfaceFairing`] the framework runs like any other (the research use: prototype a method
//! in Python, run it inside the hierarchy), one surface faired alone ([`fair_surface`]) and one
//! side measured against a master ([`continuity`]).

use numpy::IntoPyArray;
use numpy::ndarray::Array2;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use nurbs_core::{Continuity, Faired, FairingProblem, SurfaceFairing};

use crate::error::{HierFairError, model_err};
use crate::surface::PySurface;

/// A fairing method written in Python: `method(surface, mask, tolerance) -> Surface`, where
/// `mask` is an (n, m) boolean array (True: the control point may move) and `tolerance` the
/// largest move of a control point. The framework checks its result as it checks every
/// method's (fixed points kept, moves within the tolerance).
pub struct PyFairing {
    callable: Py<PyAny>,
    name: String,
}

impl PyFairing {
    /// The method of the Python callable `callable` (named by its `__name__`).
    pub fn new(callable: &Bound<'_, PyAny>) -> PyResult<Self> {
        if !callable.is_callable() {
            return Err(HierFairError::new_err(
                "method: expected a method name or a callable (surface, mask, tolerance) -> Surface",
            ));
        }
        let name = callable
            .getattr("__name__")
            .and_then(|n| n.extract::<String>())
            .unwrap_or_else(|_| "python".to_string());
        Ok(Self {
            callable: callable.clone().unbind(),
            name,
        })
    }
}

impl SurfaceFairing for PyFairing {
    fn name(&self) -> &str {
        &self.name
    }

    fn fair(&self, problem: &FairingProblem<'_>) -> nurbs_core::Result<Faired> {
        let failed = |message: String| nurbs_core::Error::FairingFailed {
            method: self.name.clone(),
            message,
        };
        Python::attach(|py| -> nurbs_core::Result<Faired> {
            let s = problem.surface;
            let (n, m) = (s.num_u(), s.num_v());
            let mask =
                Array2::from_shape_fn((n, m), |(i, j)| problem.mask.is_free(i, j)).into_pyarray(py);
            let surface =
                Py::new(py, PySurface { inner: s.clone() }).map_err(|e| failed(e.to_string()))?;
            let out = self
                .callable
                .call1(py, (surface, mask, problem.tolerance))
                .map_err(|e| failed(e.to_string()))?;
            let out: PyRef<'_, PySurface> = out
                .extract(py)
                .map_err(|_| failed("the method must return a hierfair.Surface".into()))?;
            Ok(Faired::new(out.inner.clone(), 1))
        })
    }
}

/// The method `method` names or is: `None` → `default`; a name of the built-in registry; or a
/// Python callable ([`PyFairing`]).
pub fn method_of(
    method: Option<&Bound<'_, PyAny>>,
    iterations: Option<usize>,
) -> PyResult<Option<Box<dyn SurfaceFairing>>> {
    let Some(m) = method else { return Ok(None) };
    if let Ok(name) = m.extract::<String>() {
        let built = hier_fair::MethodRegistry::builtin()
            .build(&name, iterations)
            .map_err(model_err)?;
        return Ok(Some(built));
    }
    Ok(Some(Box::new(PyFairing::new(m)?)))
}

/// A continuity level by name ("G0", "G1", "G2").
pub fn continuity_of(name: &str) -> PyResult<Continuity> {
    match name {
        "G0" | "g0" => Ok(Continuity::G0),
        "G1" | "g1" => Ok(Continuity::G1),
        "G2" | "g2" => Ok(Continuity::G2),
        _ => Err(HierFairError::new_err(format!(
            "continuity {name:?}: expected \"G0\", \"G1\" or \"G2\""
        ))),
    }
}

/// A JSON value as Python objects (through the `json` module: dicts, lists, floats, None).
pub fn to_python<'py>(py: Python<'py>, v: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (v.to_string(),))
}

/// fair_surface(surface, method=None, tolerance=0.05, keep="G2", iterations=None)
///
/// Fairs one surface on its own, as `hier-fair fair` fairs a bare surface file: its boundary
/// frames of `keep` fixed on all four sides (G0: the boundary rows, G1 two rows, G2 three) and
/// its own smooth C0 knot lines kept, every control point within `tolerance` of its place; `method` a built-in name (see `methods()`) or a callable
/// `(surface, mask, tolerance) -> Surface`. Returns the surface (the input where the method
/// raised the thin-plate energy) and a report dict: method, energy_before, energy_after,
/// max_deviation, max_control_move, iterations, seconds, and `kept` where the input was kept.
///
/// >>> import numpy as np, hierfair
/// >>> net = np.array([[[i, j, 0.1 * i * j] for j in range(5)] for i in range(5)], dtype=float)
/// >>> s = hierfair.Surface((3, 3), ([0.0] * 4 + [0.5] + [1.0] * 4, [0.0] * 4 + [0.5] + [1.0] * 4), net)
/// >>> faired, report = hierfair.fair_surface(s, tolerance=0.01, keep="G1")
/// >>> report["method"], report["max_control_move"] <= 0.01
/// ('energy', True)
#[pyfunction]
#[pyo3(signature = (surface, method=None, tolerance=0.05, keep="G2", iterations=None))]
pub fn fair_surface<'py>(
    py: Python<'py>,
    surface: &PySurface,
    method: Option<&Bound<'py, PyAny>>,
    tolerance: f64,
    keep: &str,
    iterations: Option<usize>,
) -> PyResult<(PySurface, Bound<'py, PyDict>)> {
    let keep = continuity_of(keep)?;
    let method = match method_of(method, iterations)? {
        Some(m) => m,
        None => hier_fair::MethodRegistry::builtin()
            .build("energy", iterations)
            .map_err(model_err)?,
    };
    let s = &surface.inner;
    let mask = hier_fair::bare::alone_mask(s, keep).map_err(model_err)?;
    let alone = py
        .detach(|| hier_fair::bare::fair_alone(s, &mask, tolerance, method.as_ref()))
        .map_err(model_err)?;
    let r = &alone.report;
    let report = PyDict::new(py);
    report.set_item("method", &r.method)?;
    report.set_item("energy_before", r.energy_before)?;
    report.set_item(
        "energy_after",
        if alone.kept.is_some() {
            r.energy_before
        } else {
            r.energy_after
        },
    )?;
    report.set_item(
        "max_deviation",
        if alone.kept.is_some() {
            0.0
        } else {
            r.max_deviation
        },
    )?;
    report.set_item("max_control_move", r.max_control_move)?;
    report.set_item("iterations", r.iterations)?;
    report.set_item("seconds", r.seconds)?;
    if let Some(why) = &alone.kept {
        report.set_item("kept", why)?;
    }
    Ok((
        PySurface {
            inner: alone.surface,
        },
        report,
    ))
}

/// continuity(slave, side, master, samples=None)
///
/// The continuity of `slave`'s side `side` ("u0", "u1", "v0", "v1") against `master`, as
/// `hier-fair check --json` measures a link: gap `g0`, normal angle `g1_deg`, relative
/// curvature difference `g2_rel` (along the side's cross direction and across it, n × T), their
/// worst places and the vertex figures.
///
/// >>> import numpy as np, hierfair
/// >>> net = np.array([[[i, j, 0.1 * i * j] for j in range(5)] for i in range(5)], dtype=float)
/// >>> s = hierfair.Surface((3, 3), ([0.0] * 4 + [0.5] + [1.0] * 4, [0.0] * 4 + [0.5] + [1.0] * 4), net)
/// >>> flat = hierfair.Surface(s.degrees, s.knots, net * [1, 1, 0] - [4, 0, 0])
/// >>> c = hierfair.continuity(s, "u0", flat)
/// >>> c["g0"] < 1e-9, c["g1_deg"] > 1.0
/// (True, True)
#[pyfunction]
#[pyo3(signature = (slave, side, master, samples=None))]
pub fn continuity<'py>(
    py: Python<'py>,
    slave: &PySurface,
    side: &str,
    master: &PySurface,
    samples: Option<usize>,
) -> PyResult<Bound<'py, PyAny>> {
    let side = nurbs_core::Side::parse(side).ok_or_else(|| {
        HierFairError::new_err(format!("side {side:?}: expected u0, u1, v0 or v1"))
    })?;
    let params = g_continuity::MeasureParams {
        samples: samples.unwrap_or(g_continuity::MeasureParams::default().samples),
        ..Default::default()
    };
    let m = py
        .detach(|| g_continuity::measure::measure_link(&master.inner, &slave.inner, side, &params))
        .map_err(|e| HierFairError::new_err(e.to_string()))?;
    to_python(py, &hier_fair::check::measure_json(&m))
}

/// connect(slave, masters, target="G2")
///
/// Sets `slave`'s continuity to its masters as the framework's continuity steps do (degree
/// raised, knots inserted where the rows need room, the G0, G1 and G2 rows fitted by least
/// squares): `masters` a list of (side, master) or (side, master, target) tuples, the side
/// "u0", "u1", "v0" or "v1", the target "G0", "G1" or "G2" (`target` by default). Returns the
/// surface and a list of dicts per side: side, target, met, before and after (the measures of
/// `continuity`).
#[pyfunction]
#[pyo3(signature = (slave, masters, target="G2"))]
pub fn connect<'py>(
    py: Python<'py>,
    slave: &PySurface,
    masters: Vec<Bound<'py, PyAny>>,
    target: &str,
) -> PyResult<(PySurface, Bound<'py, PyList>)> {
    let default = continuity_of(target)?;
    let mut given: Vec<(nurbs_core::Side, PySurface, Continuity)> =
        Vec::with_capacity(masters.len());
    for m in &masters {
        let (side, master, level): (String, PySurface, Option<String>) =
            if let Ok((a, b, c)) = m.extract::<(String, PyRef<'_, PySurface>, String)>() {
                (a, b.clone(), Some(c))
            } else {
                let (a, b) = m.extract::<(String, PyRef<'_, PySurface>)>().map_err(|_| {
                    HierFairError::new_err(
                        "masters: expected (side, Surface) or (side, Surface, target) tuples",
                    )
                })?;
                (a, b.clone(), None)
            };
        let side = nurbs_core::Side::parse(&side).ok_or_else(|| {
            HierFairError::new_err(format!("side {side:?}: expected u0, u1, v0 or v1"))
        })?;
        let level = level.map_or(Ok(default), |l| continuity_of(&l))?;
        given.push((side, master, level));
    }
    let links: Vec<g_continuity::SideLink<'_>> = given
        .iter()
        .map(|(side, master, level)| g_continuity::SideLink {
            side: *side,
            master: &master.inner,
            target: *level,
            range: None,
            g2_zones: [0.0; 2],
        })
        .collect();
    let params = g_continuity::ConnectParams::default();
    let (out, report) = py
        .detach(|| g_continuity::connect_slave(&slave.inner, &links, &params))
        .map_err(|e| HierFairError::new_err(e.to_string()))?;
    let sides = PyList::empty(py);
    for r in &report.sides {
        let d = PyDict::new(py);
        d.set_item("side", r.side.name())?;
        d.set_item("target", hier_fair::check::continuity_name(r.target))?;
        d.set_item("met", r.met)?;
        d.set_item(
            "before",
            to_python(py, &hier_fair::check::measure_json(&r.before))?,
        )?;
        d.set_item(
            "after",
            to_python(py, &hier_fair::check::measure_json(&r.after))?,
        )?;
        sides.append(d)?;
    }
    Ok((PySurface { inner: out }, sides))
}

/// methods() → the built-in fairing methods: a list of dicts with `name`, `summary` and
/// `takes_iterations`.
///
/// >>> import hierfair
/// >>> names = [m["name"] for m in hierfair.methods()]
/// >>> names[0], "krr" in names
/// ('energy', True)
#[pyfunction]
pub fn methods(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let out = PyList::empty(py);
    for e in hier_fair::MethodRegistry::builtin().entries() {
        let d = PyDict::new(py);
        d.set_item("name", e.name)?;
        d.set_item("summary", e.summary)?;
        d.set_item("takes_iterations", e.takes_iterations)?;
        out.append(d)?;
    }
    Ok(out)
}
