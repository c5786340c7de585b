//! `hierfair.Surface`: a B-spline surface (plain or rational) with numpy arrays in and out —
//! its net, knots and weights as arrays, evaluation, derivatives and curvature vectorised over
//! arrays of parameters.

use numpy::ndarray::{Array2, Array3, ArrayD, IxDyn};
use numpy::{IntoPyArray, PyArray2, PyArray3, PyArrayDyn, PyReadonlyArrayDyn};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PySlice};

use nurbs_core::{BSplineSurface, Direction, KnotVector, Point3};

use crate::error::{HierFairError, core_err};

/// A B-spline surface: degrees (p, q), knot vectors in u and v, an n × m net of control points
/// (and weights for a rational surface).
#[pyclass(module = "hierfair", name = "Surface")]
#[derive(Debug, Clone)]
pub struct PySurface {
    /// the surface
    pub inner: BSplineSurface,
}

/// `x` as a float64 numpy array (a scalar as a 0-d array).
fn as_array<'py>(py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<PyReadonlyArrayDyn<'py, f64>> {
    let np = py.import("numpy")?;
    np.call_method1("asarray", (x, "float64"))?.extract()
}

/// Parameters broadcast to one shape: the shape and the (u, v) pairs in C order.
type Broadcast = (Vec<usize>, Vec<(f64, f64)>);

/// `u` and `v` broadcast to one shape: the shape and the parameter pairs in C order.
fn parameters<'py>(
    py: Python<'py>,
    u: &Bound<'py, PyAny>,
    v: &Bound<'py, PyAny>,
) -> PyResult<Broadcast> {
    let np = py.import("numpy")?;
    let float = |x: &Bound<'py, PyAny>| np.call_method1("asarray", (x, "float64"));
    let both = np.call_method1("broadcast_arrays", (float(u)?, float(v)?))?;
    let (bu, bv): (Bound<'py, PyAny>, Bound<'py, PyAny>) = (both.get_item(0)?, both.get_item(1)?);
    let (au, av) = (as_array(py, &bu)?, as_array(py, &bv)?);
    let (au, av) = (au.as_array(), av.as_array());
    let shape = au.shape().to_vec();
    let pairs = au.iter().zip(av.iter()).map(|(&a, &b)| (a, b)).collect();
    Ok((shape, pairs))
}

/// Parameter pairs per rayon task: enough that a task's evaluator setup is nothing against its
/// points, few enough that both cores share a grid of a few thousand points.
const CHUNK: usize = 4096;

/// `f` at every parameter pair, in order, each task with its own evaluator (the basis buffers
/// of [`nurbs_core::SurfaceEvaluator`]), writing its `width` values per pair into one flat
/// buffer (no copy after: numpy takes the buffer as it is).
fn map_pairs(
    s: &BSplineSurface,
    pairs: &[(f64, f64)],
    width: usize,
    f: impl Fn(&mut nurbs_core::SurfaceEvaluator<'_>, f64, f64, &mut [f64]) + Sync,
) -> Vec<f64> {
    use rayon::prelude::*;
    let mut out = vec![0.0; width * pairs.len()];
    out.par_chunks_mut(width * CHUNK)
        .zip(pairs.par_chunks(CHUNK))
        .for_each(|(block, chunk)| {
            let mut e = s.evaluator();
            for (slot, &(u, v)) in block.chunks_exact_mut(width).zip(chunk) {
                f(&mut e, u, v, slot);
            }
        });
    out
}

/// `flat` (`tail` values per parameter pair) as one array of `shape` + `tail`, and the views
/// `index` picks from it per name (numpy indexing after the parameters' axes: no copies).
fn views<'py>(
    py: Python<'py>,
    shape: &[usize],
    tail: &[usize],
    flat: Vec<f64>,
    picks: &[(&str, Bound<'py, PyAny>)],
) -> PyResult<Bound<'py, PyDict>> {
    let mut full = shape.to_vec();
    full.extend_from_slice(tail);
    let all = ArrayD::from_shape_vec(IxDyn(&full), flat)
        .map_err(|e| HierFairError::new_err(e.to_string()))?
        .into_pyarray(py);
    let out = PyDict::new(py);
    for (name, index) in picks {
        out.set_item(name, all.as_any().get_item(index)?)?;
    }
    Ok(out)
}

/// The direction named `name` ("u" or "v").
fn direction(name: &str) -> PyResult<Direction> {
    match name {
        "u" | "U" => Ok(Direction::U),
        "v" | "V" => Ok(Direction::V),
        _ => Err(HierFairError::new_err(format!(
            "direction {name:?}: expected \"u\" or \"v\""
        ))),
    }
}

/// Vectors (three values per parameter pair, flattened) as an array of `shape` + (3,).
fn vectors<'py>(
    py: Python<'py>,
    shape: &[usize],
    flat: Vec<f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let mut full = shape.to_vec();
    full.push(3);
    let a = ArrayD::from_shape_vec(IxDyn(&full), flat)
        .map_err(|e| HierFairError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py))
}

fn xyz(v: &nurbs_core::Vector3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

#[pymethods]
impl PySurface {
    /// Surface(degrees, knots, points, weights=None)
    ///
    /// `degrees` (p, q); `knots` (knots_u, knots_v), full (clamped or not) knot vectors;
    /// `points` an (n, m, 3) array of control points, n along u; `weights` an (n, m) array for
    /// a rational surface.
    ///
    /// >>> import numpy as np, hierfair
    /// >>> net = np.array([[[i, j, 0.0] for j in range(2)] for i in range(2)])
    /// >>> s = hierfair.Surface((1, 1), ([0, 0, 1, 1], [0, 0, 1, 1]), net)
    /// >>> s.evaluate(0.5, 0.5).tolist()
    /// [0.5, 0.5, 0.0]
    #[new]
    #[pyo3(signature = (degrees, knots, points, weights=None))]
    fn new(
        py: Python<'_>,
        degrees: (usize, usize),
        knots: (Vec<f64>, Vec<f64>),
        points: &Bound<'_, PyAny>,
        weights: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let pts = as_array(py, points)?;
        let pts = pts.as_array();
        let [n, m, 3] = pts.shape() else {
            return Err(HierFairError::new_err(format!(
                "points: expected an (n, m, 3) array, got shape {:?}",
                pts.shape()
            )));
        };
        let (n, m) = (*n, *m);
        let mut net = Vec::with_capacity(n * m);
        for i in 0..n {
            for j in 0..m {
                net.push(Point3::new(pts[[i, j, 0]], pts[[i, j, 1]], pts[[i, j, 2]]));
            }
        }
        let w = match weights {
            None => None,
            Some(w) => {
                let w = as_array(py, w)?;
                let w = w.as_array();
                if w.shape() != [n, m] {
                    return Err(HierFairError::new_err(format!(
                        "weights: expected an ({n}, {m}) array, got shape {:?}",
                        w.shape()
                    )));
                }
                Some(w.iter().copied().collect())
            }
        };
        let ku = KnotVector::new(degrees.0, knots.0).map_err(|e| core_err("knots_u", e))?;
        let kv = KnotVector::new(degrees.1, knots.1).map_err(|e| core_err("knots_v", e))?;
        let inner = BSplineSurface::new(ku, kv, net, w).map_err(|e| core_err("surface", e))?;
        Ok(Self { inner })
    }

    /// The surface from its JSON record (the model format's `surface` object).
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Self> {
        let mut all = nurbs_core::io::surfaces_from_json(text).map_err(|e| core_err("json", e))?;
        if all.len() != 1 {
            return Err(HierFairError::new_err(format!(
                "json: {} surfaces where one was expected",
                all.len()
            )));
        }
        Ok(Self {
            inner: all.remove(0),
        })
    }

    /// The surface as its JSON record.
    fn to_json(&self) -> String {
        nurbs_core::io::surface_to_json(&self.inner)
    }

    /// (p, q): the degrees in u and v.
    #[getter]
    fn degrees(&self) -> (usize, usize) {
        (self.inner.degree_u(), self.inner.degree_v())
    }

    /// (knots_u, knots_v) as float64 arrays.
    #[getter]
    fn knots<'py>(
        &self,
        py: Python<'py>,
    ) -> (
        Bound<'py, numpy::PyArray1<f64>>,
        Bound<'py, numpy::PyArray1<f64>>,
    ) {
        (
            self.inner.knots_u().knots().to_vec().into_pyarray(py),
            self.inner.knots_v().knots().to_vec().into_pyarray(py),
        )
    }

    /// The (n, m, 3) array of control points.
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f64>> {
        let (n, m) = (self.inner.num_u(), self.inner.num_v());
        Array3::from_shape_fn((n, m, 3), |(i, j, k)| self.inner.control_point(i, j)[k])
            .into_pyarray(py)
    }

    /// The (n, m) array of weights; `None` for a polynomial surface.
    #[getter]
    fn weights<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray2<f64>>> {
        let (n, m) = (self.inner.num_u(), self.inner.num_v());
        self.inner
            .weights()
            .map(|w| Array2::from_shape_fn((n, m), |(i, j)| w[i * m + j]).into_pyarray(py))
    }

    /// ((u0, u1), (v0, v1)): the parameter domain.
    #[getter]
    fn domain(&self) -> ((f64, f64), (f64, f64)) {
        (self.inner.domain_u(), self.inner.domain_v())
    }

    /// Points S(u, v): `u` and `v` scalars or arrays (broadcast); an array of their shape + (3,).
    ///
    /// >>> import numpy as np, hierfair
    /// >>> net = np.array([[[i, j, i * j] for j in range(2)] for i in range(2)], dtype=float)
    /// >>> s = hierfair.Surface((1, 1), ([0, 0, 1, 1], [0, 0, 1, 1]), net)
    /// >>> s.evaluate([0.0, 0.5], 0.5).tolist()
    /// [[0.0, 0.5, 0.0], [0.5, 0.5, 0.25]]
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        u: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let (shape, pairs) = parameters(py, u, v)?;
        let s = &self.inner;
        let flat = py.detach(|| {
            map_pairs(s, &pairs, 3, |e, a, b, out| {
                out.copy_from_slice(&xyz(&e.point(a, b).coords))
            })
        });
        vectors(py, &shape, flat)
    }

    /// Partial derivatives at (u, v) up to `order` (1 or 2): a dict of arrays of the
    /// parameters' shape + (3,), keys "point", "du", "dv" and, for order 2, "duu", "duv", "dvv".
    ///
    /// >>> import numpy as np, hierfair
    /// >>> net = np.array([[[i, j, i * j] for j in range(2)] for i in range(2)], dtype=float)
    /// >>> s = hierfair.Surface((1, 1), ([0, 0, 1, 1], [0, 0, 1, 1]), net)
    /// >>> d = s.derivatives(0.5, 0.5)
    /// >>> d["du"].tolist(), d["duv"].tolist()
    /// ([1.0, 0.0, 0.5], [0.0, 0.0, 1.0])
    #[pyo3(signature = (u, v, order=2))]
    fn derivatives<'py>(
        &self,
        py: Python<'py>,
        u: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        order: usize,
    ) -> PyResult<Bound<'py, PyDict>> {
        if !(1..=2).contains(&order) {
            return Err(HierFairError::new_err(format!(
                "order {order}: expected 1 or 2"
            )));
        }
        let (shape, pairs) = parameters(py, u, v)?;
        let s = &self.inner;
        let rows = if order == 2 { 6 } else { 3 };
        let flat = py.detach(|| {
            map_pairs(s, &pairs, 3 * rows, |e, a, b, out| {
                let d = e.evaluate(a, b, order);
                let all = [d.point.coords, d.du, d.dv, d.duu, d.duv, d.dvv];
                for (slot, w) in out.chunks_exact_mut(3).zip(&all) {
                    slot.copy_from_slice(&xyz(w));
                }
            })
        });
        let names = ["point", "du", "dv", "duu", "duv", "dvv"];
        let ellipsis = py.Ellipsis().into_bound(py);
        let picks: Vec<(&str, Bound<'py, PyAny>)> = names
            .iter()
            .take(rows)
            .enumerate()
            .map(|(k, &name)| {
                let index = (ellipsis.clone(), k, PySlice::full(py)).into_pyobject(py)?;
                Ok((name, index.into_any()))
            })
            .collect::<PyResult<_>>()?;
        views(py, &shape, &[rows, 3], flat, &picks)
    }

    /// Curvature at (u, v): a dict of arrays — "normal" (shape + (3,), the unit normal
    /// S_u × S_v), "k1" ≥ "k2" (principal curvatures, signed against the normal), "mean",
    /// "gauss"; NaN where the surface is singular (a pole).
    ///
    /// >>> import numpy as np, hierfair
    /// >>> net = np.array([[[i, j, i * j] for j in range(2)] for i in range(2)], dtype=float)
    /// >>> s = hierfair.Surface((1, 1), ([0, 0, 1, 1], [0, 0, 1, 1]), net)
    /// >>> c = s.curvature(0.0, 0.0)
    /// >>> round(float(c["gauss"]), 6), round(float(c["mean"]), 6)
    /// (-1.0, 0.0)
    fn curvature<'py>(
        &self,
        py: Python<'py>,
        u: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (shape, pairs) = parameters(py, u, v)?;
        let s = &self.inner;
        // normal (3), k1, k2, mean, gauss per pair; NaN where the surface is singular
        let flat = py.detach(|| {
            map_pairs(s, &pairs, 7, |e, a, b, out| {
                match e.evaluate(a, b, 2).curvature_values() {
                    Some(c) => {
                        out[..3].copy_from_slice(&xyz(&c.normal));
                        out[3..].copy_from_slice(&[c.k1, c.k2, c.mean, c.gauss]);
                    }
                    None => out.fill(f64::NAN),
                }
            })
        });
        let ellipsis = py.Ellipsis().into_bound(py);
        let mut picks = vec![(
            "normal",
            (ellipsis.clone(), PySlice::new(py, 0, 3, 1))
                .into_pyobject(py)?
                .into_any(),
        )];
        for (k, name) in ["k1", "k2", "mean", "gauss"].into_iter().enumerate() {
            picks.push((
                name,
                (ellipsis.clone(), 3 + k).into_pyobject(py)?.into_any(),
            ));
        }
        views(py, &shape, &[7], flat, &picks)
    }

    /// Points on an nu × nv grid of uniform parameters over the domain: an (nu, nv, 3) array.
    ///
    /// >>> import numpy as np, hierfair
    /// >>> net = np.array([[[i, j, i * j] for j in range(2)] for i in range(2)], dtype=float)
    /// >>> s = hierfair.Surface((1, 1), ([0, 0, 1, 1], [0, 0, 1, 1]), net)
    /// >>> s.grid(3, 2).shape
    /// (3, 2, 3)
    fn grid<'py>(
        &self,
        py: Python<'py>,
        nu: usize,
        nv: usize,
    ) -> PyResult<Bound<'py, PyArray3<f64>>> {
        if nu < 2 || nv < 2 {
            return Err(HierFairError::new_err(format!(
                "grid {nu} × {nv}: at least 2 × 2"
            )));
        }
        let us = self.inner.knots_u().uniform_params(nu);
        let vs = self.inner.knots_v().uniform_params(nv);
        let s = &self.inner;
        // the tensor-product grid (the basis of each row and column once), blocks of rows on
        // rayon tasks written straight into the array's buffer
        let flat: Vec<f64> = py.detach(|| {
            use rayon::prelude::*;
            let rows = CHUNK.div_ceil(nv).max(1);
            let mut out = vec![0.0; 3 * nu * nv];
            out.par_chunks_mut(3 * nv * rows)
                .zip(us.par_chunks(rows))
                .for_each(|(block, us)| {
                    for (slot, p) in block.chunks_exact_mut(3).zip(s.eval_grid_points(us, &vs)) {
                        slot.copy_from_slice(&xyz(&p.coords));
                    }
                });
            out
        });
        let a = Array3::from_shape_vec((nu, nv, 3), flat)
            .map_err(|e| HierFairError::new_err(e.to_string()))?;
        Ok(a.into_pyarray(py))
    }

    /// The same surface with knot `t` inserted `times` times in `direction` ("u" or "v").
    ///
    /// >>> import numpy as np, hierfair
    /// >>> net = np.array([[[i, j, i * j] for j in range(2)] for i in range(2)], dtype=float)
    /// >>> s = hierfair.Surface((1, 1), ([0, 0, 1, 1], [0, 0, 1, 1]), net)
    /// >>> t = s.insert_knot("u", 0.5)
    /// >>> t.points.shape, bool(np.allclose(t.evaluate(0.3, 0.7), s.evaluate(0.3, 0.7)))
    /// ((3, 2, 3), True)
    #[pyo3(signature = (direction, t, times=1))]
    fn insert_knot(&self, direction: &str, t: f64, times: usize) -> PyResult<Self> {
        let inner = self
            .inner
            .insert_knot(self::direction(direction)?, t, times)
            .map_err(|e| core_err("insert_knot", e))?;
        Ok(Self { inner })
    }

    /// The same surface with its degree in `direction` raised by `by`.
    ///
    /// >>> import numpy as np, hierfair
    /// >>> net = np.array([[[i, j, i * j] for j in range(2)] for i in range(2)], dtype=float)
    /// >>> s = hierfair.Surface((1, 1), ([0, 0, 1, 1], [0, 0, 1, 1]), net)
    /// >>> s.elevate("v").degrees
    /// (1, 2)
    #[pyo3(signature = (direction, by=1))]
    fn elevate(&self, direction: &str, by: usize) -> PyResult<Self> {
        let inner = self
            .inner
            .elevate_degree(self::direction(direction)?, by)
            .map_err(|e| core_err("elevate", e))?;
        Ok(Self { inner })
    }

    /// The thin-plate energy ∫∫ |S_uu|² + 2|S_uv|² + |S_vv|² du dv.
    fn thin_plate_energy(&self) -> f64 {
        nurbs_core::energy::thin_plate_energy(&self.inner)
    }

    fn __repr__(&self) -> String {
        format!(
            "Surface(degrees=({}, {}), net={}×{}, rational={})",
            self.inner.degree_u(),
            self.inner.degree_v(),
            self.inner.num_u(),
            self.inner.num_v(),
            if self.inner.is_rational() {
                "True"
            } else {
                "False"
            }
        )
    }
}
