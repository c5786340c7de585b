//! An SVG drawing of a labeling, for checking labels by eye: the region projected to its
//! best-fit plane (y up), holes in grey, the outer loop's segments colored by label (South red,
//! East green, North blue, West orange, unlabeled grey dashed) with their indices, real corners
//! as filled dots, virtual corners as rings with their dashed tangent extensions.

use std::fmt::Write;

use nurbs_core::TriMesh;

use crate::error::Result;
use crate::junction::CornerKind;
use crate::labeling::{Label, LabeledCorner, Labeling};
use crate::region::{Point2, Region};

/// Width of the drawing in pixels (the height follows the region's aspect ratio).
const WIDTH_PX: f64 = 1000.0;
/// Margin around the region in pixels.
const MARGIN_PX: f64 = 40.0;

/// The stroke color of `label`.
fn color(label: Label) -> &'static str {
    match label {
        Label::South => "#d62728",
        Label::East => "#2ca02c",
        Label::North => "#1f77b4",
        Label::West => "#ff7f0e",
        Label::Unlabeled => "#999999",
    }
}

/// Draws `labeling` of `mesh` (the mesh it was computed from) as an SVG document.
pub fn write_svg(mesh: &TriMesh, labeling: &Labeling) -> Result<String> {
    let region = Region::new(mesh)?;
    let frame = region.frame;
    let p2 = |v: usize| frame.project(&mesh.positions[v]);
    let mut pts: Vec<Point2> = region.outer_2d.clone();
    for c in &labeling.corners {
        pts.extend(c.position_2d);
    }
    let canvas = Canvas::around(&pts);
    let height = canvas.height;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH_PX}" height="{height:.0}" viewBox="0 0 {WIDTH_PX} {height:.0}">"#
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let outer: Vec<Point2> = region.outer_2d.clone();
    let _ = writeln!(
        s,
        r##"<polygon points="{}" fill="#f3f3f3" stroke="none"/>"##,
        canvas.path(&outer)
    );
    for hole in &region.holes {
        let h: Vec<Point2> = hole.iter().map(|&v| p2(v)).collect();
        let _ = writeln!(
            s,
            r##"<polygon points="{}" fill="white" stroke="#777777" stroke-width="1"/>"##,
            canvas.path(&h)
        );
    }
    for (k, seg) in labeling.segments.iter().enumerate() {
        let poly: Vec<Point2> = seg.loop_vertices.iter().map(|&v| p2(v)).collect();
        draw_segment(&mut s, &canvas, k, seg.label, &poly);
    }
    for c in &labeling.corners {
        draw_corner(&mut s, &canvas, c);
    }
    let _ = writeln!(
        s,
        r##"<text x="{MARGIN_PX}" y="{:.0}" font-family="sans-serif" font-size="14"><tspan fill="#d62728">south</tspan> <tspan fill="#2ca02c">east</tspan> <tspan fill="#1f77b4">north</tspan> <tspan fill="#ff7f0e">west</tspan> <tspan fill="#999999">unlabeled</tspan> · ● real corner ○ virtual corner · {} labels, {} corners</text>"##,
        height - 12.0,
        labeling.labels,
        labeling.corner_count
    );
    s.push_str("</svg>\n");
    Ok(s)
}

/// The drawing area: plane coordinates (y up) mapped to pixels (y down) with a margin.
struct Canvas {
    /// lower-left of the points' box (plane coordinates)
    lo: Point2,
    /// upper-right of the points' box
    hi: Point2,
    /// pixels per plane unit
    scale: f64,
    /// height of the drawing (pixels)
    height: f64,
}

impl Canvas {
    /// The canvas [`WIDTH_PX`] wide that holds `pts`.
    fn around(pts: &[Point2]) -> Self {
        let (mut lo, mut hi) = (Point2::repeat(f64::MAX), Point2::repeat(f64::MIN));
        for p in pts {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        let span = (hi - lo).max().max(f64::MIN_POSITIVE);
        let scale = (WIDTH_PX - 2.0 * MARGIN_PX) / (hi.x - lo.x).max(span * 1e-3);
        let height = (hi.y - lo.y) * scale + 2.0 * MARGIN_PX + 30.0;
        Self {
            lo,
            hi,
            scale,
            height,
        }
    }

    /// Pixel coordinates of the plane point `p`.
    fn map(&self, p: &Point2) -> (f64, f64) {
        (
            MARGIN_PX + (p.x - self.lo.x) * self.scale,
            MARGIN_PX + (self.hi.y - p.y) * self.scale,
        )
    }

    /// The `points` attribute of a polyline through `pts`.
    fn path(&self, pts: &[Point2]) -> String {
        pts.iter()
            .map(|p| {
                let (x, y) = self.map(p);
                format!("{x:.2},{y:.2}")
            })
            .collect::<Vec<_>>()
            .join(" ")
    }
}

/// Segment `k` with `label` along `poly`: its polyline, end dots and index.
fn draw_segment(s: &mut String, canvas: &Canvas, k: usize, label: Label, poly: &[Point2]) {
    let (width, dash) = if label == Label::Unlabeled {
        (1.5, r#" stroke-dasharray="6,4""#)
    } else {
        (4.0, "")
    };
    let _ = writeln!(
        s,
        r#"<polyline points="{}" fill="none" stroke="{}" stroke-width="{width}"{dash}><title>segment {k}: {}</title></polyline>"#,
        canvas.path(poly),
        color(label),
        label.name()
    );
    for end in [poly[0], poly[poly.len() - 1]] {
        let (x, y) = canvas.map(&end);
        let _ = writeln!(
            s,
            r#"<circle cx="{x:.2}" cy="{y:.2}" r="2.5" fill="black"/>"#
        );
    }
    let (x, y) = canvas.map(&poly[poly.len() / 2]);
    let _ = writeln!(
        s,
        r#"<text x="{x:.2}" y="{:.2}" font-family="sans-serif" font-size="12" fill="black">{k}</text>"#,
        y - 6.0
    );
}

/// A real corner as a dot, a virtual one as a ring with its dashed extensions.
fn draw_corner(s: &mut String, canvas: &Canvas, c: &LabeledCorner) {
    let Some(q) = c.position_2d else { return };
    let (x, y) = canvas.map(&q);
    match c.kind {
        CornerKind::Real => {
            let _ = writeln!(
                s,
                r#"<circle cx="{x:.2}" cy="{y:.2}" r="6" fill="black"><title>real corner, strength {:.2}</title></circle>"#,
                c.strength
            );
        }
        CornerKind::Virtual => {
            if let Some((a, b)) = c.extension_from {
                for from in [a, b] {
                    let (fx, fy) = canvas.map(&from);
                    let _ = writeln!(
                        s,
                        r#"<line x1="{fx:.2}" y1="{fy:.2}" x2="{x:.2}" y2="{y:.2}" stroke="black" stroke-width="1" stroke-dasharray="4,3"/>"#
                    );
                }
            }
            let _ = writeln!(
                s,
                r#"<circle cx="{x:.2}" cy="{y:.2}" r="6" fill="white" stroke="black" stroke-width="2"><title>virtual corner, strength {:.2}</title></circle>"#,
                c.strength
            );
        }
        CornerKind::None => {}
    }
}
