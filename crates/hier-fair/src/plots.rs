//! Plots a surface engineer can read: axes with ticks, numbers and units, a title and a legend
//! (plotters, drawn into the same RGB images as [`crate::render`]), and the colour bar of a
//! mean-curvature map with its range.
//!
//! Text is drawn with DejaVu Sans Mono (`assets/`, Bitstream Vera licence, see
//! `assets/DejaVu-LICENSE.txt`), embedded so that no system font is needed.

use image::{Rgb, RgbImage};
use plotters::coord::ranged1d::{BoldPoints, Ranged};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::text::{self, Anchor};

/// The font of every plot's text, embedded so that a plot reads the same on any machine
/// (DejaVu Sans Mono, free licence, in `assets/`).
const FONT: &[u8] = include_bytes!("../assets/DejaVuSansMono.ttf");
/// The family name the embedded font is registered under with plotters.
const FAMILY: &str = "sans-serif";

fn register() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // the embedded font parses (tested); a failure would leave plots without text only
        let _ = plotters::style::register_font(FAMILY, FontStyle::Normal, FONT);
    });
}

/// What a plot could not draw.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlotError {
    /// plotters failed to draw part of a line plot (its error, generic over the backend, as
    /// text)
    #[error("plot {title}: {detail}")]
    Draw {
        /// the plot's title
        title: String,
        /// what plotters said
        detail: String,
    },
    /// the map beside which a colour bar goes is too low to hold one
    #[error("colour bar: the map is {height} pixels high, too low for a bar")]
    TooLow {
        /// the map's height (pixels)
        height: u32,
    },
}

impl PlotError {
    /// plotters' error `detail` while drawing the plot `title`.
    fn draw(title: &str, detail: &dyn std::fmt::Display) -> Self {
        PlotError::Draw {
            title: title.to_string(),
            detail: detail.to_string(),
        }
    }
}

/// One curve of a line plot.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// legend text
    pub label: String,
    /// (x, y) points
    pub points: Vec<(f64, f64)>,
    /// colour
    pub colour: Rgb<u8>,
    /// dashed (drawn over a solid curve it coincides with, both stay visible)
    pub dashed: bool,
}

/// Width of the legend column right of a line plot's axes: the legend never covers a curve.
pub(crate) const LEGEND_WIDTH: u32 = 170;

/// Ticks with numbers on the x axis (0, 0.1, …, 1) and about as many on the y axis.
const X_TICKS: usize = 11;
/// See [`X_TICKS`].
const Y_TICKS: usize = 9;

/// Text sizes (pixels): the title, and axis numbers, descriptions and legend.
const TITLE_SIZE: f32 = 15.0;
/// See [`TITLE_SIZE`].
const LABEL_SIZE: f32 = 12.0;

/// A line plot: `title`, axis descriptions with units, ticks with numbers that read (0.1,
/// 6.23e-3: [`text::number`]), a legend in its own column right of the axes; x over [0, 1].
/// The text is drawn by [`crate::text`]. An error names what plotters could not draw.
pub fn line_plot(
    title: &str,
    x_desc: &str,
    y_desc: &str,
    series: &[Series],
    width: u32,
    height: u32,
) -> Result<RgbImage, PlotError> {
    register();
    let values = series.iter().flat_map(|s| s.points.iter().map(|p| p.1));
    let (mut lo, mut hi) = values.fold((0.0f64, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    if hi - lo < 1e-12 {
        lo -= 1.0;
        hi += 1.0;
    }
    let pad = 0.08 * (hi - lo);
    let (lo, hi) = (lo - pad, hi + pad);
    let plot_w = width.saturating_sub(LEGEND_WIDTH).max(100);
    let mut buffer = vec![255u8; width as usize * height as usize * 3];
    let e = |x: &dyn std::fmt::Display| PlotError::draw(title, x);
    let (xs, ys) = {
        let root = BitMapBackend::with_buffer(&mut buffer, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(|x| e(&x))?;
        let (area, _legend) = root.split_horizontally(plot_w);
        let mut chart = ChartBuilder::on(&area)
            .margin_top(34)
            .margin_right(14)
            .margin_left(8)
            .x_label_area_size(44)
            .y_label_area_size(84)
            .build_cartesian_2d(0f64..1f64, lo..hi)
            .map_err(|x| e(&x))?;
        chart
            .configure_mesh()
            .x_labels(X_TICKS)
            .y_labels(Y_TICKS)
            .x_label_formatter(&|_| String::new())
            .y_label_formatter(&|_| String::new())
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(|x| e(&x))?;
        for s in series {
            let Rgb([r, g, b]) = s.colour;
            let style = ShapeStyle {
                color: RGBColor(r, g, b).to_rgba(),
                filled: false,
                stroke_width: 2,
            };
            let points = s.points.clone();
            if s.dashed {
                chart.draw_series(DashedLineSeries::new(points, 8, 6, style))
            } else {
                chart.draw_series(LineSeries::new(points, style))
            }
            .map_err(|x| e(&x))?;
        }
        // where the mesh put its bold lines: the same key points plotters draws them at
        let xs: Vec<(f64, (i32, i32))> = RangedCoordf64::from(0f64..1f64)
            .key_points(BoldPoints(X_TICKS))
            .into_iter()
            .map(|x| (x, chart.backend_coord(&(x, lo))))
            .collect();
        let ys: Vec<(f64, (i32, i32))> = RangedCoordf64::from(lo..hi)
            .key_points(BoldPoints(Y_TICKS))
            .into_iter()
            .map(|y| (y, chart.backend_coord(&(0.0, y))))
            .collect();
        root.present().map_err(|x| e(&x))?;
        (xs, ys)
    };
    let mut img = RgbImage::from_raw(width, height, buffer).ok_or_else(|| e(&"buffer size"))?;
    let ticks = Ticks {
        xs,
        ys,
        span: hi - lo,
    };
    axes_text(&mut img, (title, x_desc, y_desc), &ticks, plot_w);
    legend(&mut img, series, plot_w + 6, 40);
    Ok(img)
}

/// Where a plot's ticks are: each value with its pixel, and the y range's length (a tick within
/// 1e-9 of it of zero reads 0).
struct Ticks {
    xs: Vec<(f64, (i32, i32))>,
    ys: Vec<(f64, (i32, i32))>,
    span: f64,
}

/// A plot's title, tick numbers and axis descriptions (title, x, y), drawn by [`crate::text`]
/// into the plot `img` whose axes take the left `plot_w` pixels.
fn axes_text(
    img: &mut RgbImage,
    (title, x_desc, y_desc): (&str, &str, &str),
    t: &Ticks,
    plot_w: u32,
) {
    let height = img.height();
    let ink = Rgb([20, 20, 20]);
    text::draw(
        img,
        title,
        (plot_w as f32 / 2.0, 16.0),
        TITLE_SIZE,
        ink,
        Anchor::Centre,
    );
    for (x, (px, py)) in &t.xs {
        let at = (*px as f32, *py as f32 + 12.0);
        text::draw(img, &text::number(*x), at, LABEL_SIZE, ink, Anchor::Centre);
    }
    for (y, (px, py)) in &t.ys {
        let at = (*px as f32 - 6.0, *py as f32);
        // a tick at zero computed as −5.55e-17 reads 0
        let y = if y.abs() < 1e-9 * t.span { 0.0 } else { *y };
        text::draw(img, &text::number(y), at, LABEL_SIZE, ink, Anchor::Right);
    }
    let mid_x =
        t.xs.first()
            .zip(t.xs.last())
            .map_or(plot_w as f32 / 2.0, |(a, b)| (a.1.0 + b.1.0) as f32 / 2.0);
    let mid_y =
        t.ys.first()
            .zip(t.ys.last())
            .map_or(height as f32 / 2.0, |(a, b)| (a.1.1 + b.1.1) as f32 / 2.0);
    text::draw(
        img,
        x_desc,
        (mid_x, height as f32 - 12.0),
        LABEL_SIZE,
        ink,
        Anchor::Centre,
    );
    text::draw_vertical(img, y_desc, (12.0, mid_y), LABEL_SIZE, ink);
}

/// The legend: per series a sample of its line (dashed where it is) and its label, one row each
/// from `top`, in the column from `x0`.
fn legend(img: &mut RgbImage, series: &[Series], x0: u32, top: u32) {
    for (k, s) in series.iter().enumerate() {
        let y = top + 22 * k as u32;
        for dx in 0..26u32 {
            if s.dashed && (dx / 5) % 2 == 1 {
                continue;
            }
            for dy in 0..2u32 {
                let (px, py) = (x0 + dx, y + dy);
                if px < img.width() && py < img.height() {
                    img.put_pixel(px, py, s.colour);
                }
            }
        }
        let at = ((x0 + 32) as f32, y as f32 + 1.0);
        text::draw(
            img,
            &s.label,
            at,
            LABEL_SIZE,
            Rgb([20, 20, 20]),
            Anchor::Left,
        );
    }
}

/// Width of the colour bar panel [`with_colour_bar`] adds (pixels).
pub(crate) const COLOUR_BAR_WIDTH: u32 = 150;

/// `map` with a colour bar on its right: the colour scale of `colour(t)` for t ∈ [−1, 1] from
/// −`range` to +`range`, its end values and zero written beside it (numbers that read:
/// [`text::number`]), and `label` (the quantity and its unit) above.
pub fn with_colour_bar(
    map: &RgbImage,
    range: f64,
    label: &str,
    colour: impl Fn(f64) -> Rgb<u8>,
) -> Result<RgbImage, PlotError> {
    let (w, h) = (map.width() + COLOUR_BAR_WIDTH, map.height());
    let mut out = RgbImage::from_pixel(w, h, Rgb([255, 255, 255]));
    image::imageops::replace(&mut out, map, 0, 0);
    let (x0, bar_w) = (map.width() + 16, 22u32);
    let (top, bottom) = (40u32, h.saturating_sub(30));
    if bottom <= top + 2 {
        return Err(PlotError::TooLow { height: h });
    }
    let ink = Rgb([20, 20, 20]);
    for y in top..bottom {
        // +range at the top
        let t = 1.0 - 2.0 * f64::from(y - top) / f64::from(bottom - top);
        let c = colour(t);
        for x in x0..x0 + bar_w {
            out.put_pixel(x, y, c);
        }
    }
    for x in x0..x0 + bar_w {
        out.put_pixel(x, top, ink);
        out.put_pixel(x, bottom - 1, ink);
    }
    for y in top..bottom {
        out.put_pixel(x0, y, ink);
        out.put_pixel(x0 + bar_w - 1, y, ink);
    }
    let tx = (x0 + bar_w + 6) as f32;
    for (value, y) in [
        (range, top),
        (0.0, (top + bottom) / 2),
        (-range, bottom - 1),
    ] {
        let t = if value > 0.0 {
            format!("+{}", text::number(value))
        } else {
            text::number(value)
        };
        text::draw(&mut out, &t, (tx, y as f32), LABEL_SIZE, ink, Anchor::Left);
    }
    text::draw(
        &mut out,
        label,
        (x0 as f32 - 6.0, 14.0),
        LABEL_SIZE,
        ink,
        Anchor::Left,
    );
    Ok(out)
}

/// `img` under a title band: `title` on the left, `label` (e.g. "before", "after") on the
/// right in a box, so that a picture says what it shows wherever it is shown.
pub fn titled(img: &RgbImage, title: &str, label: &str) -> RgbImage {
    let band = 30u32;
    let mut out = RgbImage::from_pixel(img.width(), img.height() + band, Rgb([255, 255, 255]));
    image::imageops::replace(&mut out, img, 0, i64::from(band));
    let ink = Rgb([20, 20, 20]);
    text::draw(
        &mut out,
        title,
        (10.0, band as f32 / 2.0),
        TITLE_SIZE,
        ink,
        Anchor::Left,
    );
    if !label.is_empty() {
        let w = text::width(label, TITLE_SIZE).ceil() as u32 + 14;
        let x1 = img.width().saturating_sub(8);
        let x0 = x1.saturating_sub(w);
        let fill = if label == "after" {
            Rgb([214, 234, 214])
        } else {
            Rgb([236, 226, 206])
        };
        for x in x0..x1 {
            for y in 4..band - 4 {
                out.put_pixel(x, y, fill);
            }
        }
        let at = ((x0 + x1) as f32 / 2.0, band as f32 / 2.0);
        text::draw(&mut out, label, at, TITLE_SIZE, ink, Anchor::Centre);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dark(img: &RgbImage, x0: u32, x1: u32, y0: u32, y1: u32) -> usize {
        let mut n = 0;
        for x in x0..x1.min(img.width()) {
            for y in y0..y1.min(img.height()) {
                let Rgb([r, g, b]) = *img.get_pixel(x, y);
                if u32::from(r) + u32::from(g) + u32::from(b) < 200 {
                    n += 1;
                }
            }
        }
        n
    }

    /// The plot has text (title band, tick numbers left of the axis) and the two curves; a
    /// dashed curve over a solid one leaves the solid one visible between its dashes.
    #[test]
    fn line_plot_draws_axes_text_and_curves() {
        let points: Vec<(f64, f64)> = (0..=50)
            .map(|k| (k as f64 / 50.0, (k as f64 / 8.0).sin() * 1e-3))
            .collect();
        let series = [
            Series {
                label: "slave".into(),
                points: points.clone(),
                colour: Rgb([200, 20, 20]),
                dashed: false,
            },
            Series {
                label: "master".into(),
                points,
                colour: Rgb([20, 50, 200]),
                dashed: true,
            },
        ];
        let img = line_plot("a title", "t", "k (1/mm)", &series, 640, 300).unwrap();
        assert!(dark(&img, 200, 440, 0, 30) > 20, "no title");
        assert!(dark(&img, 0, 90, 40, 260) > 50, "no tick numbers");
        let (mut red, mut blue) = (0, 0);
        for p in img.pixels() {
            match p.0 {
                [200, 20, 20] => red += 1,
                [20, 50, 200] => blue += 1,
                _ => {}
            }
        }
        assert!(red > 100 && blue > 100, "red {red} blue {blue}");
    }

    /// The bar shows the colours from +range (top) to −range (bottom) and its numbers.
    #[test]
    fn colour_bar_shows_the_scale_and_its_range() {
        let map = RgbImage::from_pixel(200, 200, Rgb([128, 128, 128]));
        let colour = |t: f64| {
            if t > 0.0 {
                Rgb([255, 0, 0])
            } else {
                Rgb([0, 0, 255])
            }
        };
        let img = with_colour_bar(&map, 0.25, "H (1/mm)", colour).unwrap();
        assert_eq!(img.width(), 200 + COLOUR_BAR_WIDTH);
        assert_eq!(img.get_pixel(225, 50).0, [255, 0, 0]);
        assert_eq!(img.get_pixel(225, 160).0, [0, 0, 255]);
        assert!(dark(&img, 245, 350, 30, 200) > 30, "no numbers");
        assert_eq!(img.get_pixel(10, 10).0, [128, 128, 128]);
    }
}
