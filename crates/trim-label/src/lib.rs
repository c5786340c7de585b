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
