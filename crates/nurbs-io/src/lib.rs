//! # nurbs-io
//!
//! IGES 5.3 exchange (\[IGES\] US PRO/IPO-100-1996) of B-spline geometry: rational B-spline
//! surfaces (entity 128), curves (126), surfaces of revolution (120), tabulated cylinders (122)
//! and ruled surfaces (118) as exact NURBS surfaces, planes (108) bounded by the trimmed surface
//! (144) over them, trimmed B-spline surfaces cut to their face's parameter box, and
//! transformation matrices (124, applied where referenced). Other entities are counted and
//! skipped. The reader checks the fixed 80-column layout and reports errors by line;
//! the writer produces files that pass the same checks ([`check_structure`]).
//!
//! ```
//! use nurbs_io::{IgesWriteParams, read_iges, write_iges};
//! use nurbs_core::shapes::cylinder;
//! // an exact rational quarter cylinder written as IGES entity 128 and read back
//! let s = cylinder(5.0, 20.0).unwrap();
//! let text = write_iges(&[("CYL", &s)], &[], &IgesWriteParams::default()).unwrap();
//! let file = read_iges(text.as_bytes()).unwrap();
//! let back = &file.surfaces[0].surface;
//! assert!((back.point(0.4, 0.6) - s.point(0.4, 0.6)).norm() < 1e-9);
//! ```
//!
//! A surface from your own control points written as STEP and read back: a biquadratic Bézier
//! patch over a 3 × 3 net (i over u) with its middle point raised, one face in millimetres.
//!
//! ```
//! use nurbs_core::{BSplineSurface, KnotVector, Point3};
//! use nurbs_io::{read_step, write_step};
//! let net: Vec<Point3> = (0..9)
//!     .map(|r| Point3::new((r / 3) as f64, (r % 3) as f64, if r == 4 { 1.0 } else { 0.0 }))
//!     .collect();
//! let bezier = KnotVector::bezier(2).unwrap();
//! let s = BSplineSurface::new(bezier.clone(), bezier, net, None).unwrap();
//! let text = write_step(&[("BUMP", &s)], "mm", "bump.step").unwrap();
//! assert!(text.starts_with("ISO-10303-21;"));
//! let file = read_step(&text).unwrap();
//! assert_eq!((file.faces.len(), file.units.as_str()), (1, "mm"));
//! let back = &file.faces[0].surface;
//! // the raised middle point lifts the centre by a quarter of its height
//! assert!((back.point(0.5, 0.5) - Point3::new(1.0, 1.0, 0.25)).norm() < 1e-12);
//! ```
//!
//! A surface read from the JSON format of `docs/model-format.md` and exported as IGES: the
//! control points and knots come back as they were written.
//!
//! ```
//! use nurbs_io::{IgesWriteParams, read_iges, write_iges};
//! let json = r#"{"degree_u": 2, "degree_v": 1,
//!     "knots_u": [0, 0, 0, 0.5, 1, 1, 1],
//!     "control_points": [[[0, 0, 0], [0, 2, 0]], [[1, 0, 0.5], [1, 2, 0.5]],
//!                        [[2, 0, -0.5], [2, 2, -0.5]], [[3, 0, 0], [3, 2, 0]]]}"#;
//! let s = &nurbs_core::io::surfaces_from_json(json).unwrap()[0];
//! let text = write_iges(&[("JSON", s)], &[], &IgesWriteParams::default()).unwrap();
//! let back = &read_iges(text.as_bytes()).unwrap().surfaces[0].surface;
//! assert_eq!(back.knots_u().knots(), s.knots_u().knots());
//! assert!(back.control_points().iter().zip(s.control_points()).all(|(p, q)| (p - q).norm() < 1e-12));
//! ```
//!
//! STEP (ISO 10303-21) faces are read by [`read_step`]: elementary and B-spline surfaces over
//! their faces' parameter boxes (module [`step`]).
//!
//! Both writers bound a face by its trim loops where it has them ([`write_step_faces`],
//! [`write_iges_faces`]; the loops made ready on the written surface by module [`bounds`]).
//! [`write_step_shell`] joins the faces of a STEP file into shells where they meet: shared
//! vertices and edges, each connected set oriented, closed where every edge is used twice.

pub mod bounds;
mod edge_fit;
pub mod error;
pub mod offset;
pub mod params;
pub mod reader;
mod seam;
pub mod step;
pub mod structure;
pub mod units;
pub mod writer;

pub use bounds::{Face, FaceBounds, face_bounds};
pub use error::IgesError;
pub use reader::{IgesCurve, IgesFile, IgesSurface, read_iges};
pub use seam::trim_is_box;
pub use step::{
    StepError, StepFace, StepFile, read_step, write_step, write_step_faces,
    write_step_faces_within, write_step_shell,
};
pub use structure::{StructureReport, check_structure};
pub use writer::{IgesWriteParams, write_iges, write_iges_faces};
