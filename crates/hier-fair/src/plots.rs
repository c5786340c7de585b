//! Plots a surface engineer can read: axes with ticks, numbers and units, a title and a legend
//! (plotters, drawn into the same RGB images as [`crate::render`]), and the colour bar of a
//! mean-curvature map with its range.
//!
//! Text is drawn with DejaVu Sans Mono (`assets/`, Bitstream Vera licence, see
//! `assets/DejaVu-LICENSE.txt`), embedded so that no system font is needed.

use image::{Rgb, RgbImage};
use plotters::prelude::*;
use plotters::style::FontStyle;

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

/// A line plot: `title`, axis descriptions with units, ticks and numbers (y in scientific
/// notation), a legend; x over [0, 1]. An error names what plotters could not draw.
pub fn line_plot(
    title: &str,
    x_desc: &str,
    y_desc: &str,
    series: &[Series],
    width: u32,
    height: u32,
) -> Result<RgbImage, String> {
    register();
    let values = series.iter().flat_map(|s| s.points.iter().map(|p| p.1));
    let (mut lo, mut hi) = values.fold((0.0f64, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    if hi - lo < 1e-12 {
        lo -= 1.0;
        hi += 1.0;
    }
    let pad = 0.08 * (hi - lo);
    let (lo, hi) = (lo - pad, hi + pad);
    let mut buffer = vec![255u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (width, height)).into_drawing_area();
        let e = |e: &dyn std::fmt::Display| format!("plot {title}: {e}");
        root.fill(&WHITE).map_err(|x| e(&x))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, (FAMILY, 16))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(80)
            .build_cartesian_2d(0f64..1f64, lo..hi)
            .map_err(|x| e(&x))?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc(y_desc)
            .label_style((FAMILY, 12))
            .y_label_formatter(&|v| format!("{v:.2e}"))
            .x_label_formatter(&|v| format!("{v:.1}"))
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
            let drawn = if s.dashed {
                chart.draw_series(DashedLineSeries::new(points, 8, 6, style))
            } else {
                chart.draw_series(LineSeries::new(points, style))
            }
            .map_err(|x| e(&x))?;
            drawn
                .label(s.label.as_str())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], style));
        }
        chart
            .configure_series_labels()
            .label_font((FAMILY, 12))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(|x| e(&x))?;
        root.present().map_err(|x| e(&x))?;
    }
    RgbImage::from_raw(width, height, buffer).ok_or_else(|| format!("plot {title}: buffer size"))
}

/// Width of the colour bar panel [`with_colour_bar`] adds (pixels).
pub const COLOUR_BAR_WIDTH: u32 = 150;

/// `map` with a colour bar on its right: the colour scale of `colour(t)` for t ∈ [−1, 1] from
/// −`range` to +`range`, its end values and zero written beside it, and `label` (the quantity
/// and its unit) above.
pub fn with_colour_bar(
    map: &RgbImage,
    range: f64,
    label: &str,
    colour: impl Fn(f64) -> Rgb<u8>,
) -> Result<RgbImage, String> {
    register();
    let (w, h) = (map.width() + COLOUR_BAR_WIDTH, map.height());
    let mut out = RgbImage::from_pixel(w, h, Rgb([255, 255, 255]));
    image::imageops::replace(&mut out, map, 0, 0);
    let (x0, bar_w) = (map.width() + 16, 22u32);
    let (top, bottom) = (40u32, h.saturating_sub(30));
    for y in top..bottom {
        // +range at the top
        let t = 1.0 - 2.0 * f64::from(y - top) / f64::from((bottom - top).max(1));
        let c = colour(t);
        for x in x0..x0 + bar_w {
            out.put_pixel(x, y, c);
        }
    }
    let mut buffer = out.into_raw();
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area();
        let e = |e: &dyn std::fmt::Display| format!("colour bar: {e}");
        let font = (FAMILY, 12).into_font().color(&BLACK);
        let tx = (x0 + bar_w + 6) as i32;
        root.draw(&Rectangle::new(
            [
                (x0 as i32, top as i32),
                ((x0 + bar_w) as i32, bottom as i32),
            ],
            BLACK.stroke_width(1),
        ))
        .map_err(|x| e(&x))?;
        for (value, y) in [
            (range, top),
            (0.0, (top + bottom) / 2),
            (-range, bottom.saturating_sub(1)),
        ] {
            root.draw(&Text::new(
                format!("{value:+.2e}"),
                (tx, y as i32 - 6),
                font.clone(),
            ))
            .map_err(|x| e(&x))?;
        }
        root.draw(&Text::new(label.to_string(), (x0 as i32 - 6, 12), font))
            .map_err(|x| e(&x))?;
        root.present().map_err(|x| e(&x))?;
    }
    RgbImage::from_raw(w, h, buffer).ok_or_else(|| "colour bar: buffer size".to_string())
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
