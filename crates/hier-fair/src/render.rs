//! Pictures of a model, for people who would rather look than read ([SV] §6 judges results by
//! isophotes): reflection-line (zebra) stripes and a mean-curvature colour map, rendered from a
//! fixed view so that before and after images line up, and curvature plots along a link.
//!
//! # Rendering
//! Every surface is sampled on an n×n grid (points, unit normals, mean curvature H from
//! nurbs-core's differential geometry), projected orthographically along the view direction
//! **d** and rasterized with a z-buffer; normals and H are interpolated linearly inside each
//! triangle (Phong-style), so stripes follow the surface's own normal field, not facets.
//! - *Zebra*: the normal **n** (turned towards the viewer) reflects the view ray,
//!   **r** = **d** − 2(**d**·**n**)**n**; the pixel is black when ⌊k·(**r**·**a**)⌋ is even, **a**
//!   a fixed axis across the view. Stripes are continuous across a G1 join and have no kinks
//!   across a G2 join; a kink in the stripes shows a curvature jump ([SV] Fig. 6).
//! - *Mean curvature*: blue (H = −h) through white (0) to red (+h), h fixed per picture pair.
//!
//! The view is fixed by [`View::for_points`]: looking down the direction
//! (0.35, −0.55, −0.76) (normalized), up vector +z projected, the model's bounding box fitted
//! into the frame with a margin.

use image::{Rgb, RgbImage};
use nurbs_core::{BSplineSurface, Point3, Vector3};

/// Samples per direction and surface.
pub const RENDER_GRID: usize = 64;

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
        let direction = Vector3::new(0.35, -0.55, -0.76).normalize();
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

/// One sampled vertex: position, unit normal (if defined), mean curvature (if defined).
#[derive(Debug, Clone, Copy)]
struct Sample {
    p: Point3,
    n: Option<Vector3>,
    h: Option<f64>,
}

fn sample(surface: &BSplineSurface, n: usize) -> Vec<Sample> {
    let us = surface.knots_u().uniform_params(n);
    let vs = surface.knots_v().uniform_params(n);
    surface
        .eval_grid_derivatives(&us, &vs)
        .into_iter()
        .map(|d| Sample {
            p: d.point,
            n: d.normal(),
            h: d.mean_curvature(),
        })
        .collect()
}

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
            let t = (h / range).clamp(-1.0, 1.0);
            let fade = |x: f64| (255.0 * (1.0 - x.abs())) as u8;
            if t >= 0.0 {
                Rgb([255, fade(t), fade(t)])
            } else {
                Rgb([fade(t), fade(t), 255])
            }
        }
    }
}

/// Renders `surfaces` with `shading` from `view`.
pub fn render(surfaces: &[&BSplineSurface], view: &View, shading: Shading) -> RgbImage {
    let (w, h) = (view.width as usize, view.height as usize);
    let mut img = RgbImage::from_pixel(view.width, view.height, BACKGROUND);
    let mut depth = vec![f64::INFINITY; w * h];
    let n = RENDER_GRID;
    for s in surfaces {
        let samples = sample(s, n);
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
                    raster(&mut img, &mut depth, view, shading, &samples, &proj, tri);
                }
            }
        }
    }
    img
}

fn raster(
    img: &mut RgbImage,
    depth: &mut [f64],
    view: &View,
    shading: Shading,
    samples: &[Sample],
    proj: &[(f64, f64, f64)],
    tri: [usize; 3],
) {
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
            depth[k] = z;
            let [s0, s1, s2] = tri.map(|k| samples[k]);
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

/// Colours of the curvature plots: slave before, master before, slave after, master after.
pub const PLOT_COLOURS: [Rgb<u8>; 4] = [
    Rgb([230, 140, 140]),
    Rgb([140, 160, 230]),
    Rgb([200, 20, 20]),
    Rgb([20, 50, 200]),
];

/// A line plot of curves `(t, value)` over t ∈ [0, 1] on one common value axis (zero line grey),
/// drawn in the order given with [`PLOT_COLOURS`].
pub fn plot_curves(curves: &[Vec<(f64, f64)>], width: u32, height: u32) -> RgbImage {
    let mut img = RgbImage::from_pixel(width, height, Rgb([255, 255, 255]));
    let values = curves.iter().flatten().map(|&(_, v)| v);
    let (mut lo, mut hi) = values.fold((0.0f64, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    if hi - lo < 1e-12 {
        lo -= 1.0;
        hi += 1.0;
    }
    let pad = 0.08 * (hi - lo);
    let (lo, hi) = (lo - pad, hi + pad);
    let m = 10.0;
    let to_px = |t: f64, v: f64| {
        (
            m + t * (width as f64 - 2.0 * m),
            m + (hi - v) / (hi - lo) * (height as f64 - 2.0 * m),
        )
    };
    let grey = Rgb([170, 170, 170]);
    let (x0, y0) = to_px(0.0, 0.0);
    let (x1, _) = to_px(1.0, 0.0);
    line(&mut img, (x0, y0), (x1, y0), grey);
    let (_, ya) = to_px(0.0, lo);
    let (_, yb) = to_px(0.0, hi);
    line(&mut img, (x0, ya), (x0, yb), grey);
    for (c, curve) in curves.iter().enumerate() {
        let colour = PLOT_COLOURS[c % PLOT_COLOURS.len()];
        for pair in curve.windows(2) {
            let a = to_px(pair[0].0, pair[0].1);
            let b = to_px(pair[1].0, pair[1].1);
            line(&mut img, a, b, colour);
        }
    }
    img
}

fn line(img: &mut RgbImage, a: (f64, f64), b: (f64, f64), colour: Rgb<u8>) {
    let steps = ((b.0 - a.0).abs().max((b.1 - a.1).abs()).ceil() as usize).max(1);
    for k in 0..=steps {
        let t = k as f64 / steps as f64;
        let (x, y) = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
        for (dx, dy) in [(0.0, 0.0), (0.0, 1.0)] {
            let (px, py) = ((x + dx).round(), (y + dy).round());
            if px >= 0.0 && py >= 0.0 && (px as u32) < img.width() && (py as u32) < img.height() {
                img.put_pixel(px as u32, py as u32, colour);
            }
        }
    }
}
