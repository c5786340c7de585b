//! hier-fair from Python: the extension module behind the `hierfair` package — surfaces with
//! numpy arrays in and out ([`surface`]), models with their hierarchy, CAD exchange, checks and
//! the fairing framework ([`model`]), one surface faired or measured on its own, and fairing
//! methods written in Python ([`method`]). Long calls release the GIL; every error is a
//! `hierfair.HierFairError` with its one-line message. Built as an abi3 wheel by maturin
//! (`pip install ./crates/hier-fair-py`); its tests are `tests/test_hierfair.py` (pytest).

// the doc comments of the Python-facing items are Python docstrings: their doctest lines index
// lists and dicts (`m.links[0]`), which rustdoc would take for intra-doc links
#![allow(rustdoc::broken_intra_doc_links)]

pub mod error;
pub mod method;
pub mod model;
pub mod surface;

use pyo3::prelude::*;

/// The extension module `hierfair._hierfair` (the package `hierfair` re-exports it).
#[pymodule]
fn _hierfair(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<surface::PySurface>()?;
    m.add_class::<model::PyModel>()?;
    m.add("HierFairError", m.py().get_type::<error::HierFairError>())?;
    m.add_function(wrap_pyfunction!(method::fair_surface, m)?)?;
    m.add_function(wrap_pyfunction!(method::continuity, m)?)?;
    m.add_function(wrap_pyfunction!(method::connect, m)?)?;
    m.add_function(wrap_pyfunction!(method::methods, m)?)?;
    Ok(())
}
