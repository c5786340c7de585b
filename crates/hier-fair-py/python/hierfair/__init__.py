"""hier-fair from Python: constrained hierarchical fairing of B-spline surfaces.

Surfaces with numpy arrays in and out (:class:`Surface`), models with their hierarchy, CAD
exchange, checks and the fairing framework (:class:`Model`), one surface faired or measured on
its own (:func:`fair_surface`, :func:`connect`, :func:`continuity`), and fairing methods written in Python: any
callable ``method(surface, mask, tolerance) -> Surface`` runs where a built-in method would.

>>> import numpy as np, hierfair
>>> net = np.array([[[i, j, 0.0] for j in range(4)] for i in range(4)])
>>> s = hierfair.Surface((3, 3), ([0.0] * 4 + [1.0] * 4, [0.0] * 4 + [1.0] * 4), net)
>>> s.evaluate(0.5, 0.5).round(6).tolist()
[1.5, 1.5, 0.0]
"""

from ._hierfair import (
    HierFairError,
    Model,
    Surface,
    connect,
    continuity,
    fair_surface,
    methods,
)

__all__ = [
    "HierFairError",
    "Model",
    "Surface",
    "connect",
    "continuity",
    "fair_surface",
    "methods",
]
