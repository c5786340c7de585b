//! # trim-label
//!
//! Automatic boundary labeling of trimmed mesh regions (\[VV18\]: M. Vaitkus, T. Várady, *A
//! labeling algorithm for trimmed surface fitting*, CAD'18, pp. 86–90) and the labeled
//! parameterization and least-squares fit the labels feed (\[VV17\]: *Parameterizing and
//! extending trimmed regions for tensor-product surface fitting*, CAD 2017).
//!
//! ```
//! use nurbs_core::{Point3, TriMesh, Vector3, shapes::plane_patch};
//! use trim_label::{LabelParams, label_region};
//! // a square region meshed as a 9 × 9 grid of a plane: four straight sides meeting at four
//! // real corners, so four labels
//! let plane = plane_patch(Point3::origin(), Vector3::x(), Vector3::y(), (0.0, 4.0), (0.0, 4.0))
//!     .unwrap();
//! let mesh = TriMesh::from_surface(&plane, 9, 9);
//! let labeling = label_region(&mesh, None, &LabelParams::default()).unwrap();
//! assert_eq!((labeling.labels, labeling.corner_count), (4, 4));
//! ```
//!
//! A region meshed from a surface of your own control points: a bicubic Bézier dome over a
//! 4 × 4 net (i over u) on [0, 3]², its four inner points raised; its four boundary curves
//! still meet at four real corners, so four labels, and the labeled bicubic fit (smoothed, on
//! the labels' parameterization) passes within 1 % of the region's size of every vertex.
//!
//! ```
//! use nurbs_core::{BSplineSurface, KnotVector, Point3, TriMesh};
//! use trim_label::{LabelParams, LabeledFitParams, fit_labeled, label_region};
//! let inner = |i: usize, j: usize| (1..3).contains(&i) && (1..3).contains(&j);
//! let net: Vec<Point3> = (0..16)
//!     .map(|r| (r / 4, r % 4))
//!     .map(|(i, j)| Point3::new(i as f64, j as f64, if inner(i, j) { 0.8 } else { 0.0 }))
//!     .collect();
//! let bezier = KnotVector::bezier(3).unwrap();
//! let dome = BSplineSurface::new(bezier.clone(), bezier, net, None).unwrap();
//! let mesh = TriMesh::from_surface(&dome, 12, 12);
//! let labeling = label_region(&mesh, None, &LabelParams::default()).unwrap();
//! assert_eq!((labeling.labels, labeling.corner_count), (4, 4));
//! let (_fit, report) = fit_labeled(&mesh, &labeling, &LabeledFitParams::default()).unwrap();
//! assert!(report.max_distance < 0.01 * report.size, "{report:?}");
//! ```
//!
//! The same dome read from the JSON format of `docs/model-format.md` (knot vectors left out
//! make a Bézier patch), its labeling written out as JSON ([`Labeling::to_json`]).
//!
//! ```
//! use nurbs_core::TriMesh;
//! use trim_label::{LabelParams, label_region};
//! let json = r#"{"degree_u": 3, "degree_v": 3, "control_points": [
//!     [[0, 0, 0], [0, 1, 0], [0, 2, 0], [0, 3, 0]],
//!     [[1, 0, 0], [1, 1, 0.8], [1, 2, 0.8], [1, 3, 0]],
//!     [[2, 0, 0], [2, 1, 0.8], [2, 2, 0.8], [2, 3, 0]],
//!     [[3, 0, 0], [3, 1, 0], [3, 2, 0], [3, 3, 0]]]}"#;
//! let dome = &nurbs_core::io::surfaces_from_json(json).unwrap()[0];
//! let mesh = TriMesh::from_surface(dome, 12, 12);
//! let labeling = label_region(&mesh, None, &LabelParams::default()).unwrap();
//! assert_eq!((labeling.labels, labeling.corner_count), (4, 4));
//! let out: serde_json::Value = serde_json::from_str(&labeling.to_json()).unwrap();
//! assert_eq!(out["configuration"]["labels"], 4);
//! assert_eq!(out["segments"].as_array().unwrap().len(), 4);
//! ```
//!
//! Pipeline: [`region`] (mesh checks, outer loop, geodesic turning) → [`segments`] (given or
//! automatic) → [`candidates`] (drop concave and complex segments) → [`junction`] (concatenate,
//! real / virtual / no corner, strength) → [`reduce`] (to one of the six admissible (L, C)
//! configurations) → [`labeling`] (sides, output, log); [`svg`] draws the result;
//! [`param`] and [`fit`] parameterize with the labels on their sides of the unit square and fit a
//! bicubic B-spline surface.
//!
//! Entry points: [`label_region`], [`Labeling::to_json`], [`write_svg`], [`fit_labeled`].

pub mod candidates;
pub mod error;
pub mod fit;
pub mod junction;
pub mod labeling;
pub mod param;
pub mod params;
pub mod reduce;
pub mod region;
pub mod segments;
pub mod svg;

pub use error::{LabelError, Result};
pub use fit::{LabeledFitParams, LabeledFitReport, fit_labeled, fit_with_parameters};
pub use junction::CornerKind;
pub use labeling::{Label, LabeledCorner, LabeledSegment, Labeling, label_region};
pub use param::{Parameterization, parameterize};
pub use params::LabelParams;
pub use region::Region;
pub use segments::{SegmentationParams, parse_segments_json};
pub use svg::write_svg;
