//! The module's exception: every error of hier-fair reaches Python as a `HierFairError` (a
//! `ValueError`) carrying its one-line message.

use pyo3::PyErr;

pyo3::create_exception!(
    hierfair,
    HierFairError,
    pyo3::exceptions::PyValueError,
    "An error of hier-fair: bad input (naming the surface, link or field) or a failed computation."
);

/// A nurbs-core error of `what` as the module's exception.
pub fn core_err(what: &str, e: nurbs_core::Error) -> PyErr {
    HierFairError::new_err(format!("{what}: {e}"))
}

/// A hier-fair error as the module's exception.
pub fn model_err(e: hier_fair::Error) -> PyErr {
    HierFairError::new_err(e.to_string())
}
