//! Pictures of a model, for people who would rather look than read (\[SV\] §6 judges results by
//! isophotes): reflection-line (zebra) stripes and a mean-curvature colour map, rendered from a
//! fixed view so that before and after images line up (the curvature plots along a link and the
//! colour bar are drawn by [`crate::plots`]).
//!
//! # Rendering
//! Every surface is sampled on an n×n grid (points, unit normals, mean curvature H from
//! nurbs-core's differential geometry), projected orthographically along the view direction
//! **d** and rasterized with a z-buffer; normals and H are interpolated linearly inside each
//! triangle (Phong-style), so stripes follow the surface's own normal field, not facets.
//! - *Zebra*: the normal **n** (turned towards the viewer) reflects the view ray,
//!   **r** = **d** − 2(**d**·**n**)**n**; the pixel is black when ⌊k·(**r**·**a**)⌋ is even, **a**
//!   a fixed axis across the view. Stripes are continuous across a G1 join and have no kinks
//!   across a G2 join; a kink in the stripes shows a curvature jump (\[SV\] Fig. 6).
//! - *Mean curvature*: blue (H = −h) through white (0) to red (+h), h fixed per picture pair.
//! - Patch boundaries are drawn over both in orange where they are in front.
//!
//! The view is fixed by [`View::for_points`]: looking down the direction
//! (0.35, −0.55, −0.76) (normalized), up vector +z projected, the model's bounding box fitted
//! into the frame with a margin.

use image::{Rgb, RgbImage};
use nurbs_core::{BSplineSurface, Point3, Vector3};

/// The viewing direction of the first view (from the eye into the scene): from above, half
/// turned, so that the faces of a part seen from its top corner all show.
pub const VIEW_DIRECTION: Vector3 = Vector3::new(0.35, -0.55, -0.76);

/// Samples per direction and surface.
pub(crate) const RENDER_GRID: usize = 64;

/// An orthographic view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// viewing direction (unit, from the eye into the scene)
    pub direction: Vector3,
    /// image x axis (unit)
    pub right: Vector3,
    /// image y axis (unit, up)
    pub up: Vector3,
    /// world point at the image centre
    pub center: Point3,
    /// world units per pixel
    pub scale: f64,
    /// width in pixels
    pub width: u32,
    /// height in pixels
    pub height: u32,
}

impl View {
    /// The fixed view of the module docs, fitting `points` into `width`×`height` pixels.
    pub fn for_points(points: &[Point3], width: u32, height: u32) -> View {
        Self::from_direction(points, VIEW_DIRECTION, width, height)
    }

    /// The second view of the zebra pictures: [`VIEW_DIRECTION`] turned a quarter turn about z,
    /// so that stripes that run along a join in the first view run across it in this one.
    pub fn second_for_points(points: &[Point3], width: u32, height: u32) -> View {
        let d = VIEW_DIRECTION;
        Self::from_direction(points, Vector3::new(-d.y, d.x, d.z), width, height)
    }

    /// A view looking along `direction` (need not be unit; not parallel to z), fitting
    /// `points` into `width`×`height` pixels.
    pub fn from_direction(points: &[Point3], direction: Vector3, width: u32, height: u32) -> View {
        let direction = direction.normalize();
        let z = Vector3::z();
        let right = direction.cross(&z).normalize();
        let up = right.cross(&direction).normalize();
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        let mut c = Vector3::zeros();
        for p in points {
            let q = [p.coords.dot(&right), p.coords.dot(&up)];
            for k in 0..2 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
            c += p.coords;
        }
        if points.is_empty() {
            lo = [-1.0; 2];
            hi = [1.0; 2];
        } else {
            c /= points.len() as f64;
        }
        let along = c.dot(&direction);
        let mid =
            right * (0.5 * (lo[0] + hi[0])) + up * (0.5 * (lo[1] + hi[1])) + direction * along;
        let margin = 1.08;
        let scale = ((hi[0] - lo[0]) / width as f64)
            .max((hi[1] - lo[1]) / height as f64)
            .max(1e-12)
            * margin;
        View {
            direction,
            right,
            up,
            center: Point3::from(mid),
            scale,
            width,
            height,
        }
    }

    fn project(&self, p: &Point3) -> (f64, f64, f64) {
        let d = p - self.center;
        (
            self.width as f64 * 0.5 + d.dot(&self.right) / self.scale,
            self.height as f64 * 0.5 - d.dot(&self.up) / self.scale,
            d.dot(&self.direction),
        )
    }
}

/// What a picture shows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shading {
    /// reflection-line stripes, `stripes` per unit of r·a
    Zebra {
        /// stripe frequency
        stripes: f64,
    },
    /// mean curvature, blue −range … white 0 … red +range (1/model unit)
    MeanCurvature {
        /// the curvature mapped to full colour
        range: f64,
    },
}

/// One sampled vertex: position, unit normal (if defined), mean curvature (if defined), and
/// its parameters as shares of the domain (for a trim's [`crate::trim::ParameterMask`]).
#[derive(Debug, Clone, Copy)]
struct Sample {
    p: Point3,
    n: Option<Vector3>,
    h: Option<f64>,
    uv: (f64, f64),
}

fn sample(surface: &BSplineSurface, n: usize) -> Vec<Sample> {
    let us = surface.knots_u().uniform_params(n);
    let vs = surface.knots_v().uniform_params(n);
    let share = |k: usize| k as f64 / (n.max(2) - 1) as f64;
    surface
        .eval_grid_derivatives(&us, &vs)
        .into_iter()
        .enumerate()
        .map(|(k, d)| Sample {
            p: d.point,
            n: d.normal(),
            h: d.mean_curvature(),
            uv: (share(k / n), share(k % n)),
        })
        .collect()
}

/// Cells per direction of a trimmed face's parameter mask in a picture: 1 024, finer than a
/// pixel for a face up to a thousand pixels across, so that a trim edge is not a staircase.
pub const TRIM_MASK_RES: usize = 1024;

/// All sample points of `surfaces` (for [`View::for_points`]).
pub fn sample_points(surfaces: &[&BSplineSurface]) -> Vec<Point3> {
    surfaces
        .iter()
        .flat_map(|s| sample(s, 16).into_iter().map(|x| x.p))
        .collect()
}

/// The 95th percentile of |H| over `surfaces` (a robust colour range).
pub fn curvature_range(surfaces: &[&BSplineSurface]) -> f64 {
    let mut hs: Vec<f64> = surfaces
        .iter()
        .flat_map(|s| sample(s, 32).into_iter().filter_map(|x| x.h.map(f64::abs)))
        .collect();
    if hs.is_empty() {
        return 1.0;
    }
    hs.sort_by(f64::total_cmp);
    let r = hs[(hs.len() * 95 / 100).min(hs.len() - 1)];
    if r > 0.0 { r } else { 1.0 }
}

/// Light grey background of the pictures: light enough for the dark patch boundaries, distinct
/// from the white stripes of a zebra.
const BACKGROUND: Rgb<u8> = Rgb([236, 238, 242]);

fn shade(view: &View, shading: Shading, n: Option<Vector3>, h: Option<f64>) -> Rgb<u8> {
    match shading {
        Shading::Zebra { stripes } => {
            let Some(mut n) = n else {
                return Rgb([255, 0, 255]);
            };
            if n.dot(&view.direction) > 0.0 {
                n = -n;
            }
            let r = view.direction - 2.0 * view.direction.dot(&n) * n;
            let s = stripes * r.dot(&view.right);
            let lambert = (-n.dot(&view.direction)).clamp(0.0, 1.0);
            let light = (40.0 + 215.0 * (0.35 + 0.65 * lambert)).min(255.0) as u8;
            if s.floor().rem_euclid(2.0) == 0.0 {
                Rgb([20, 20, 24])
            } else {
                Rgb([light, light, light])
            }
        }
        Shading::MeanCurvature { range } => {
            let Some(h) = h else {
                return Rgb([120, 120, 120]);
            };
            curvature_colour(h / range)
        }
    }
}

/// The colour of the mean-curvature map at t = H / range: blue (t ≤ −1) through white (0) to
/// red (t ≥ 1) — the scale [`crate::plots::with_colour_bar`] draws beside the map.
pub fn curvature_colour(t: f64) -> Rgb<u8> {
    let t = t.clamp(-1.0, 1.0);
    let fade = |x: f64| (255.0 * (1.0 - x.abs())) as u8;
    if t >= 0.0 {
        Rgb([255, fade(t), fade(t)])
    } else {
        Rgb([fade(t), fade(t), 255])
    }
}

/// A face to draw: its surface and its trim loops (points on the surface, outer first; empty:
/// the whole surface is the face, [`crate::model::ModelSurface::trim`]).
#[derive(Debug, Clone, Copy)]
pub struct Face<'a> {
    /// the surface
    pub surface: &'a BSplineSurface,
    /// its trim loops
    pub trim: &'a [Vec<Point3>],
}

/// Renders `surfaces` (whole) with `shading` from `view`.
pub fn render(surfaces: &[&BSplineSurface], view: &View, shading: Shading) -> RgbImage {
    let faces: Vec<Face> = surfaces
        .iter()
        .map(|&surface| Face { surface, trim: &[] })
        .collect();
    render_faces(&faces, view, shading)
}

/// Renders `faces` with `shading` from `view`: a trimmed face pixel by pixel inside its trim
/// ([`crate::trim::ParameterMask`] at [`TRIM_MASK_RES`]) and bounded by its trim loops, so that
/// a cap plane does not hide the body it bounds; a face whose loops cross a seam is drawn whole,
/// its loops over it.
pub fn render_faces(faces: &[Face], view: &View, shading: Shading) -> RgbImage {
    let (w, h) = (view.width as usize, view.height as usize);
    let mut img = RgbImage::from_pixel(view.width, view.height, BACKGROUND);
    let mut depth = vec![f64::INFINITY; w * h];
    let n = RENDER_GRID;
    let masks: Vec<Option<crate::trim::ParameterMask>> = faces
        .iter()
        .map(|f| crate::trim::ParameterMask::new(f.surface, f.trim, TRIM_MASK_RES))
        .collect();
    for (f, mask) in faces.iter().zip(&masks) {
        let samples = sample(f.surface, n);
        let proj: Vec<(f64, f64, f64)> = samples.iter().map(|x| view.project(&x.p)).collect();
        for a in 0..n - 1 {
            for b in 0..n - 1 {
                let quad = [
                    a * n + b,
                    (a + 1) * n + b,
                    (a + 1) * n + b + 1,
                    a * n + b + 1,
                ];
                for tri in [[quad[0], quad[1], quad[2]], [quad[0], quad[2], quad[3]]] {
                    let target = Target {
                        img: &mut img,
                        depth: &mut depth,
                        view,
                        mask: mask.as_ref(),
                    };
                    raster(target, shading, &samples, &proj, tri);
                }
            }
        }
    }
    for (f, mask) in faces.iter().zip(&masks) {
        if mask.is_none() {
            draw_boundary(&mut img, &depth, view, f.surface);
        }
        for l in f.trim {
            let mut pts: Vec<(f64, f64, f64)> = l.iter().map(|p| view.project(p)).collect();
            pts.extend(pts.first().copied());
            draw_polyline(&mut img, &depth, view, &pts);
        }
    }
    img
}

/// Stripes per unit of r·a ([`Shading::Zebra`]) that make a stripe about [`STRIPE_PIXELS`]
/// wide on the curved faces of `faces` seen through `view`: the reflected ray turns twice as
/// fast as the normal, so across a face of curvature κ a stripe of s stripes per unit is
/// 1 / (2 κ s) long, 1 / (2 κ s · scale) pixels. κ is the 75th percentile of |H| over the
/// curved samples (a plane reflects one direction and shows one shade at any density; a
/// curvature under 10⁻⁹ per pixel — a normal that turns less than 10⁻⁶ rad across a thousand
/// pixels — is a plane's rounding, not a curve).
pub fn zebra_stripes(faces: &[Face], view: &View) -> f64 {
    let mut hs: Vec<f64> = faces
        .iter()
        .flat_map(|f| {
            sample(f.surface, 24)
                .into_iter()
                .filter_map(|x| x.h.map(f64::abs))
        })
        .filter(|h| h.is_finite() && *h > 1e-9 / view.scale)
        .collect();
    if hs.is_empty() {
        return MIN_STRIPES;
    }
    hs.sort_by(f64::total_cmp);
    let kappa = hs[(hs.len() * 3 / 4).min(hs.len() - 1)];
    (1.0 / (2.0 * kappa * view.scale * STRIPE_PIXELS)).clamp(MIN_STRIPES, MAX_STRIPES)
}

/// Width of a zebra stripe on a typical curved face (pixels): wide enough to follow by eye at
/// the pictures' size, narrow enough that a kink across a join bends several stripes.
pub const STRIPE_PIXELS: f64 = 14.0;

/// Fewest stripes per unit of r·a: two stripes across the whole reflected hemisphere would
/// say nothing.
pub(crate) const MIN_STRIPES: f64 = 4.0;

/// Most stripes per unit of r·a: beyond this a nearly flat face turns to moiré at its edges.
pub(crate) const MAX_STRIPES: f64 = 400.0;

/// Colour of the patch boundaries drawn over every picture.
pub(crate) const BOUNDARY_COLOUR: Rgb<u8> = Rgb([255, 140, 0]);

/// Draws the four boundary curves of `s` (sampled [`BOUNDARY_SAMPLES`] times each) where they
/// are in front: a boundary point counts as visible when it lies within
/// [`BOUNDARY_DEPTH_PIXELS`] pixels of depth of the nearest surface at its pixel.
fn draw_boundary(img: &mut RgbImage, depth: &[f64], view: &View, s: &BSplineSurface) {
    let (u0, u1) = s.domain_u();
    let (v0, v1) = s.domain_v();
    let n = BOUNDARY_SAMPLES;
    let at = |k: usize, a: f64, b: f64| a + (b - a) * k as f64 / n as f64;
    // the k-th sample of side u0, u1, v0, v1
    let param = |side: usize, k: usize| match side {
        0 => (u0, at(k, v0, v1)),
        1 => (u1, at(k, v0, v1)),
        2 => (at(k, u0, u1), v0),
        _ => (at(k, u0, u1), v1),
    };
    for side in 0..4 {
        let pts: Vec<(f64, f64, f64)> = (0..=n)
            .map(|k| {
                let (u, v) = param(side, k);
                view.project(&s.point(u, v))
            })
            .collect();
        draw_polyline(img, depth, view, &pts);
    }
}

/// Draws the projected polyline `pts` in [`BOUNDARY_COLOUR`] where it is in front (within
/// [`BOUNDARY_DEPTH_PIXELS`] of the nearest surface at each pixel).
fn draw_polyline(img: &mut RgbImage, depth: &[f64], view: &View, pts: &[(f64, f64, f64)]) {
    let tolerance = BOUNDARY_DEPTH_PIXELS * view.scale;
    for pair in pts.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let steps = ((b.0 - a.0).abs().max((b.1 - a.1).abs()).ceil() as usize).clamp(1, 100_000);
        for k in 0..=steps {
            let t = k as f64 / steps as f64;
            let (x, y, z) = (
                a.0 + t * (b.0 - a.0),
                a.1 + t * (b.1 - a.1),
                a.2 + t * (b.2 - a.2),
            );
            let (px, py) = (x.floor(), y.floor());
            if !(px >= 0.0
                && py >= 0.0
                && px < f64::from(view.width)
                && py < f64::from(view.height))
            {
                continue;
            }
            let idx = py as usize * view.width as usize + px as usize;
            if z <= depth[idx] + tolerance {
                img.put_pixel(px as u32, py as u32, BOUNDARY_COLOUR);
            }
        }
    }
}

/// Samples per boundary curve of `draw_boundary`.
pub const BOUNDARY_SAMPLES: usize = 200;

/// Depth tolerance of a visible boundary point, in pixels of the view's scale: the rendered
/// triangles lie within a fraction of a pixel of the surface at [`RENDER_GRID`] samples, so a
/// few pixels separate a boundary in front from one hidden behind another sheet.
pub(crate) const BOUNDARY_DEPTH_PIXELS: f64 = 3.0;

/// Where [`raster`] draws: the image, its depth buffer, the view, and the face's trim mask
/// (a pixel outside it is not drawn).
struct Target<'a> {
    img: &'a mut RgbImage,
    depth: &'a mut [f64],
    view: &'a View,
    mask: Option<&'a crate::trim::ParameterMask>,
}

fn raster(
    target: Target,
    shading: Shading,
    samples: &[Sample],
    proj: &[(f64, f64, f64)],
    tri: [usize; 3],
) {
    let Target {
        img,
        depth,
        view,
        mask,
    } = target;
    let (w, h) = (view.width as i64, view.height as i64);
    let [p0, p1, p2] = tri.map(|k| proj[k]);
    let area = (p1.0 - p0.0) * (p2.1 - p0.1) - (p2.0 - p0.0) * (p1.1 - p0.1);
    if area.abs() < 1e-12 {
        return;
    }
    let x0 = (p0.0.min(p1.0).min(p2.0).floor() as i64).max(0);
    let x1 = (p0.0.max(p1.0).max(p2.0).ceil() as i64).min(w - 1);
    let y0 = (p0.1.min(p1.1).min(p2.1).floor() as i64).max(0);
    let y1 = (p0.1.max(p1.1).max(p2.1).ceil() as i64).min(h - 1);
    for y in y0..=y1 {
        for x in x0..=x1 {
            let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
            let l1 = ((px - p0.0) * (p2.1 - p0.1) - (p2.0 - p0.0) * (py - p0.1)) / area;
            let l2 = ((p1.0 - p0.0) * (py - p0.1) - (px - p0.0) * (p1.1 - p0.1)) / area;
            let l0 = 1.0 - l1 - l2;
            if l0 < -1e-9 || l1 < -1e-9 || l2 < -1e-9 {
                continue;
            }
            let z = l0 * p0.2 + l1 * p1.2 + l2 * p2.2;
            let k = y as usize * view.width as usize + x as usize;
            if z >= depth[k] {
                continue;
            }
            let [s0, s1, s2] = tri.map(|k| samples[k]);
            if let Some(m) = mask {
                let uv = (
                    l0 * s0.uv.0 + l1 * s1.uv.0 + l2 * s2.uv.0,
                    l0 * s0.uv.1 + l1 * s1.uv.1 + l2 * s2.uv.1,
                );
                if !m.contains(uv) {
                    continue;
                }
            }
            depth[k] = z;
            let normal = match (s0.n, s1.n, s2.n) {
                (Some(a), Some(b), Some(c)) => (a * l0 + b * l1 + c * l2).try_normalize(1e-12),
                _ => None,
            };
            let hh = match (s0.h, s1.h, s2.h) {
                (Some(a), Some(b), Some(c)) => Some(a * l0 + b * l1 + c * l2),
                _ => None,
            };
            img.put_pixel(x as u32, y as u32, shade(view, shading, normal, hh));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs_core::shapes;

    fn plane() -> BSplineSurface {
        shapes::plane_patch(
            Point3::origin(),
            Vector3::x(),
            Vector3::y(),
            (0.0, 4.0),
            (0.0, 4.0),
        )
        .expect("plane")
    }

    fn is_background(img: &RgbImage, x: f64, y: f64) -> bool {
        *img.get_pixel(x as u32, y as u32) == BACKGROUND
    }

    /// A plane trimmed to its middle square is drawn inside the square only: its corners stay
    /// background, its middle is shaded, and the trim loop is drawn as its boundary.
    #[test]
    fn a_trimmed_face_is_drawn_within_its_trim() {
        let s = plane();
        let square = vec![
            Point3::new(1.0, 1.0, 0.0),
            Point3::new(3.0, 1.0, 0.0),
            Point3::new(3.0, 3.0, 0.0),
            Point3::new(1.0, 3.0, 0.0),
        ];
        let trim = [square];
        let view = View::from_direction(
            &sample_points(&[&s]),
            Vector3::new(0.01, 0.02, -1.0),
            200,
            200,
        );
        let shading = Shading::MeanCurvature { range: 1.0 };
        let whole = render_faces(
            &[Face {
                surface: &s,
                trim: &[],
            }],
            &view,
            shading,
        );
        let cut = render_faces(
            &[Face {
                surface: &s,
                trim: &trim,
            }],
            &view,
            shading,
        );
        let at = |x: f64, y: f64| view.project(&Point3::new(x, y, 0.0));
        let (cx, cy, _) = at(0.3, 0.3);
        assert!(
            !is_background(&whole, cx, cy),
            "the whole plane covers its corner"
        );
        assert!(
            is_background(&cut, cx, cy),
            "the trimmed plane leaves its corner out"
        );
        let (mx, my, _) = at(2.0, 2.0);
        assert!(
            !is_background(&cut, mx, my) && *cut.get_pixel(mx as u32, my as u32) != BOUNDARY_COLOUR
        );
        let (ex, ey, _) = at(1.0, 2.0);
        let edge =
            (-1..=1).any(|d| *cut.get_pixel((ex as i64 + d) as u32, ey as u32) == BOUNDARY_COLOUR);
        assert!(edge, "the trim loop is drawn");
    }

    /// A cylinder of radius r seen square-on at `scale` units per pixel: a stripe is
    /// [`STRIPE_PIXELS`] wide where its mean curvature 1/(2r) is the typical one, i.e.
    /// stripes = r / (scale · STRIPE_PIXELS); a plane alone gets the fewest stripes.
    #[test]
    fn zebra_density_follows_curvature_and_zoom() {
        let r = 3.0;
        let cyl = shapes::cylinder(r, 10.0).expect("cylinder");
        let faces = [Face {
            surface: &cyl,
            trim: &[],
        }];
        let view = View::from_direction(
            &sample_points(&[&cyl]),
            Vector3::new(-1.0, -1.0, -0.2),
            400,
            400,
        );
        let stripes = zebra_stripes(&faces, &view);
        let want = r / (view.scale * STRIPE_PIXELS);
        assert!(
            (stripes - want.clamp(MIN_STRIPES, MAX_STRIPES)).abs() < 1e-6 * want,
            "{stripes} vs {want}"
        );
        let mut zoomed = view;
        zoomed.scale *= 0.25;
        assert!((zebra_stripes(&faces, &zoomed) - 4.0 * stripes).abs() < 1e-6 * stripes);
        let p = plane();
        assert_eq!(
            zebra_stripes(
                &[Face {
                    surface: &p,
                    trim: &[]
                }],
                &view
            ),
            MIN_STRIPES
        );
    }
}
