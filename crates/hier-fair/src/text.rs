//! Text drawn into the pictures with its glyphs where the font puts them: each glyph at its pen
//! position plus its own left bearing, anti-aliased by coverage. (plotters' `ab_glyph` text
//! leaves the bearing out, so that every glyph after a narrow one — ".", "-", "_" — stands a
//! gap apart: "+6. 23e-3".)
//!
//! The font is the embedded DejaVu Sans Mono of [`crate::plots`] (Bitstream Vera licence,
//! `assets/DejaVu-LICENSE.txt`).

use ab_glyph::{Font, FontRef, GlyphId, PxScale, ScaleFont, point};
use image::{Rgb, RgbImage};

/// The embedded font (the same file plotters registers for the plots' axes).
fn font() -> FontRef<'static> {
    FontRef::try_from_slice(include_bytes!("../assets/DejaVuSansMono.ttf"))
        .expect("the embedded font parses (tested)")
}

/// Where the anchor point of [`draw`] lies on the text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Anchor {
    /// the anchor is the left end of the text's middle line
    Left,
    /// the anchor is the middle of the text
    Centre,
    /// the anchor is the right end of the text's middle line
    Right,
}

/// The glyphs of `text` at `size` pixels with their pen positions from 0 (kerning included),
/// and the pen's end: the text's advance.
fn layout(font: &FontRef, text: &str, size: f32) -> (Vec<(GlyphId, f32)>, f32) {
    let scaled = font.as_scaled(PxScale::from(size));
    let (mut pen, mut prev, mut glyphs) = (0.0, None, Vec::new());
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = prev {
            pen += scaled.kern(p, id);
        }
        glyphs.push((id, pen));
        pen += scaled.h_advance(id);
        prev = Some(id);
    }
    (glyphs, pen)
}

/// Width of `text` at `size` pixels (its pen advance, kerning included).
pub fn width(text: &str, size: f32) -> f32 {
    layout(&font(), text, size).1
}

/// Draws `text` at `size` pixels in `colour` into `img`, `anchor` at `(x, y)` (y the middle of
/// the text's height); pixels outside the image are left out.
pub fn draw(
    img: &mut RgbImage,
    text: &str,
    (x, y): (f32, f32),
    size: f32,
    colour: Rgb<u8>,
    anchor: Anchor,
) {
    let f = font();
    let scaled = f.as_scaled(PxScale::from(size));
    let (glyphs, w) = layout(&f, text, size);
    let left = match anchor {
        Anchor::Left => x,
        Anchor::Centre => x - 0.5 * w,
        Anchor::Right => x - w,
    };
    // the baseline such that the text's cap height is centred on y
    let baseline = y + 0.5 * (scaled.ascent() + scaled.descent());
    for (id, pen) in glyphs {
        let glyph = id.with_scale_and_position(PxScale::from(size), point(left + pen, baseline));
        if let Some(outline) = f.outline_glyph(glyph) {
            let b = outline.px_bounds();
            outline.draw(|gx, gy, coverage| {
                let px = b.min.x as i64 + i64::from(gx);
                let py = b.min.y as i64 + i64::from(gy);
                blend(img, (px, py), colour, coverage);
            });
        }
    }
}

/// Mixes `colour` with coverage `a` (0 to 1) into pixel `(px, py)` of `img`, where it lies
/// inside.
fn blend(img: &mut RgbImage, (px, py): (i64, i64), colour: Rgb<u8>, a: f32) {
    if px < 0 || py < 0 || px >= i64::from(img.width()) || py >= i64::from(img.height()) {
        return;
    }
    let a = a.clamp(0.0, 1.0);
    let under = img.get_pixel(px as u32, py as u32).0;
    let mix =
        |k: usize| (f32::from(under[k]) * (1.0 - a) + f32::from(colour.0[k]) * a).round() as u8;
    img.put_pixel(px as u32, py as u32, Rgb([mix(0), mix(1), mix(2)]));
}

/// Draws `text` turned a quarter turn counter-clockwise (read from bottom to top, as a y axis's
/// description), centred on `(x, y)`.
pub fn draw_vertical(
    img: &mut RgbImage,
    text: &str,
    (x, y): (f32, f32),
    size: f32,
    colour: Rgb<u8>,
) {
    let w = width(text, size).ceil() as u32 + 4;
    let h = (size * 1.4).ceil() as u32;
    // drawn on white, then each dark pixel copied turned: the text's own anti-aliasing kept
    let mut tile = RgbImage::from_pixel(w, h, Rgb([255, 255, 255]));
    draw(
        &mut tile,
        text,
        (w as f32 / 2.0, h as f32 / 2.0),
        size,
        Rgb([0, 0, 0]),
        Anchor::Centre,
    );
    let turned = image::imageops::rotate270(&tile);
    let (x0, y0) = (
        x - turned.width() as f32 / 2.0,
        y - turned.height() as f32 / 2.0,
    );
    for (tx, ty, p) in turned.enumerate_pixels() {
        let a = 1.0 - f32::from(p.0[0]) / 255.0;
        if a <= 0.0 {
            continue;
        }
        let (px, py) = ((x0 + tx as f32) as i64, (y0 + ty as f32) as i64);
        blend(img, (px, py), colour, a);
    }
}

/// A number as a reader wants it on an axis or a colour bar: plain with three significant digits
/// from 0.01 to 10 000, else `6.23e-3`; "0" for zero.
pub fn number(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let a = x.abs();
    if (0.01..10_000.0).contains(&a) {
        let digits = (2 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{x:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{x:.2e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Columns holding ink in `img`'s row band `y0..y1`.
    fn inked_columns(img: &RgbImage, y0: u32, y1: u32) -> Vec<bool> {
        (0..img.width())
            .map(|x| (y0..y1).any(|y| img.get_pixel(x, y).0[0] < 160))
            .collect()
    }

    /// In a monospace font every glyph has the same advance: the gap between the ink of "6." and
    /// of "23" is no wider than the gap between "2" and "3" plus the dot's own narrowness — no
    /// blank column run as wide as a glyph.
    #[test]
    fn no_gap_after_a_point() {
        let mut img = RgbImage::from_pixel(200, 40, Rgb([255, 255, 255]));
        draw(
            &mut img,
            "+6.23e-3",
            (10.0, 20.0),
            16.0,
            Rgb([0, 0, 0]),
            Anchor::Left,
        );
        let ink = inked_columns(&img, 0, 40);
        let first = ink.iter().position(|&x| x).expect("ink");
        let last = ink.iter().rposition(|&x| x).expect("ink");
        let mut longest = 0;
        let mut run = 0;
        for &i in &ink[first..=last] {
            run = if i { 0 } else { run + 1 };
            longest = longest.max(run);
        }
        let advance = width("0", 16.0);
        assert!(
            (longest as f32) < 0.6 * advance,
            "a gap of {longest} px (advance {advance})"
        );
        // eight glyphs of one advance each
        assert!(
            ((last - first) as f32 - 8.0 * advance).abs() < advance,
            "{first}..{last}"
        );
    }

    #[test]
    fn numbers_read() {
        assert_eq!(number(0.0), "0");
        assert_eq!(number(6.23e-3), "6.23e-3");
        assert_eq!(number(-0.2), "-0.2");
        assert_eq!(number(0.333), "0.333");
        assert_eq!(number(12.5), "12.5");
        assert_eq!(number(1234.0), "1234");
        assert_eq!(number(2.5e5), "2.50e5");
    }

    #[test]
    fn vertical_text_is_taller_than_wide() {
        let mut img = RgbImage::from_pixel(60, 200, Rgb([255, 255, 255]));
        draw_vertical(
            &mut img,
            "curvature (1/mm)",
            (30.0, 100.0),
            14.0,
            Rgb([0, 0, 0]),
        );
        let (mut xs, mut ys) = (Vec::new(), Vec::new());
        for (x, y, p) in img.enumerate_pixels() {
            if p.0[0] < 128 {
                xs.push(x);
                ys.push(y);
            }
        }
        let span = |v: &[u32]| v.iter().max().unwrap() - v.iter().min().unwrap();
        assert!(span(&ys) > 3 * span(&xs), "{} × {}", span(&xs), span(&ys));
    }
}
