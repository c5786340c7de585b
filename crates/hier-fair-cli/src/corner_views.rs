//! Pictures zoomed on each corner patch: zebra stripes and the mean-curvature map of the corner
//! with the surfaces around it, before and after, looking down onto the corner — a vertex blend
//! of a 26-face box is a few pixels in the whole-model pictures, and its pole, its lead-ins and
//! the stripes across its joins are what a surfacer checks (\[SV\] §3.3, §6).

use std::path::{Path, PathBuf};

use anyhow::Result;
use hier_fair::render::{self, Shading, View};
use hier_fair::{Model, Role};
use nurbs_core::{BSplineSurface, Vector3};

/// Picture size of a corner view (pixels): square, the corner fills its middle.
pub const CORNER_IMAGE_SIZE: u32 = 640;

/// How much wider than the corner itself a corner view is: 1.8, so that a band of the surfaces
/// around it about 40 % of the corner's size shows on each side — the stripes must be seen to
/// run on across the joins.
pub const CORNER_VIEW_MARGIN: f64 = 1.8;

/// The mean-curvature colour range of a corner view, as a multiple of the 95th percentile of
/// the corner's |H| before: 2, so that the input's curvature shows at half strength and a
/// result up to twice it (beyond the 1.6× peak bound of [`hier_fair::fairness::PEAK_FACTOR`])
/// still reads; a spike beyond saturates.
pub const CORNER_RANGE_FACTOR: f64 = 2.0;

/// The view direction of a corner: into its middle normal, tilted off the vertical by this
/// much of a unit when the normal is vertical ([`View::from_direction`] needs a direction that
/// is not parallel to z).
const VERTICAL_TILT: f64 = 0.2;

/// Writes, for every corner patch of `original` (role corner), `corner_<name>_zebra_<before|
/// after>.png` and `corner_<name>_mean_curvature_<before|after>.png` into `dir`: the corner and
/// the surfaces it hangs on, seen along the corner's middle normal, zoomed on the corner, with
/// one colour range for both mean-curvature maps ([`CORNER_RANGE_FACTOR`] × the 95th
/// percentile of the corner's |H| before). Returns the files.
pub fn write_corner_views(
    dir: &Path,
    original: &Model,
    faired: &Model,
    unit: &str,
    png: &dyn Fn(&Path, &image::RgbImage) -> Result<()>,
    stripes: f64,
) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    for (k, entry) in original.surfaces.iter().enumerate() {
        if entry.role != Role::Corner || k >= faired.surfaces.len() {
            continue;
        }
        let around: Vec<usize> = std::iter::once(k)
            .chain(
                original
                    .links
                    .iter()
                    .filter(|l| l.slave == k)
                    .map(|l| l.master),
            )
            .collect();
        let Some(view) = corner_view(&entry.surface) else {
            continue;
        };
        let range = CORNER_RANGE_FACTOR * render::curvature_range(&[&entry.surface]);
        let name = entry
            .name
            .replace(|c: char| !c.is_ascii_alphanumeric() && c != '_', "_");
        for (when, model) in [("before", original), ("after", faired)] {
            // (a model whose run merged slivers may hold fewer surfaces than the input)
            let surfaces: Vec<&BSplineSurface> = around
                .iter()
                .filter_map(|&i| model.surfaces.get(i).map(|s| &s.surface))
                .collect();
            let path = dir.join(format!("corner_{name}_zebra_{when}.png"));
            png(
                &path,
                &render::render(&surfaces, &view, Shading::Zebra { stripes }),
            )?;
            written.push(path);
            let map = mean_curvature_map(&surfaces, &view, range, unit)?;
            let path = dir.join(format!("corner_{name}_mean_curvature_{when}.png"));
            png(&path, &map)?;
            written.push(path);
        }
    }
    Ok(written)
}

/// The mean-curvature map of `surfaces` seen through `view`, blue – white – red over ±`range`
/// (1/`unit`), with its colour bar at the right.
pub(crate) fn mean_curvature_map(
    surfaces: &[&BSplineSurface],
    view: &View,
    range: f64,
    unit: &str,
) -> Result<image::RgbImage> {
    let map = render::render(surfaces, view, Shading::MeanCurvature { range });
    hier_fair::plots::with_colour_bar(
        &map,
        range,
        &format!("H (1/{unit})"),
        render::curvature_colour,
    )
    .map_err(|e| anyhow::anyhow!(e))
}

/// The view of a corner: along its normal at the middle of its domain (into the surface),
/// fitted to its own points and widened by [`CORNER_VIEW_MARGIN`]; `None` where the surface has
/// no normal there.
fn corner_view(s: &BSplineSurface) -> Option<View> {
    let (u0, u1) = s.domain_u();
    let (v0, v1) = s.domain_v();
    let n = s.derivatives(0.5 * (u0 + u1), 0.5 * (v0 + v1)).normal()?;
    let mut d = -n;
    if d.cross(&Vector3::z()).norm() < 1e-6 {
        d += Vector3::new(VERTICAL_TILT, 0.0, 0.0);
    }
    let points = render::sample_points(&[s]);
    let mut view = View::from_direction(&points, d, CORNER_IMAGE_SIZE, CORNER_IMAGE_SIZE);
    view.scale *= CORNER_VIEW_MARGIN;
    Some(view)
}
