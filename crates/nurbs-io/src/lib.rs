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
//! STEP (ISO 10303-21) faces are read by [`read_step`]: elementary and B-spline surfaces over
//! their faces' parameter boxes (module [`step`]).
//!
//! Both writers bound a face by its trim loops where it has them ([`write_step_faces`],
//! [`write_iges_faces`]; the loops made ready on the written surface by module [`bounds`]).

pub mod bounds;
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
pub use step::{
    StepError, StepFace, StepFile, read_step, write_step, write_step_faces, write_step_faces_within,
};
pub use structure::{StructureReport, check_structure};
pub use writer::{IgesWriteParams, write_iges, write_iges_faces};
