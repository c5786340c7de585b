//! Pictures zoomed on each corner patch and on each link left unmet: zebra stripes and the
//! mean-curvature map of the surface with the surfaces around it, before and after, looking down
//! onto it — a vertex blend of a 26-face box is a few pixels in the whole-model pictures, and
//! its pole, its lead-ins and the stripes across its joins are what a surfacer checks (\[SV\]
//! §3.3, §6); an unmet link is where the reader looks first. Each picture is titled and labelled
//! before or after, its zebra stripes as dense as its zoom needs
//! ([`render::zebra_stripes`]), trimmed faces drawn by their trims.

use std::path::{Path, PathBuf};

use anyhow::Result;
use hier_fair::render::{self, Shading, View};
use hier_fair::{Model, Role};
use nurbs_core::{BSplineSurface, Vector3};

/// Picture size of a corner view (pixels): square, the corner fills its middle.
pub(crate) const CORNER_IMAGE_SIZE: u32 = 640;

/// How much wider than the corner itself a corner view is: 1.8, so that a band of the surfaces
/// around it about 40 % of the corner's size shows on each side — the stripes must be seen to
/// run on across the joins.
pub(crate) const CORNER_VIEW_MARGIN: f64 = 1.8;

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
/// after>.png` and `corner_<name>_mean_curvature_<before|after>.png` into `dir`, and for every
/// link of `unmet` (indices into `original.links`) `link_<slave>_<side>_zebra_<when>.png` and
/// `link_<slave>_<side>_mean_curvature_<when>.png`: the surface and those it hangs on (a link:
/// its slave and master), seen along the surface's middle normal, zoomed on it, with one colour
/// range for both mean-curvature maps ([`CORNER_RANGE_FACTOR`] × the 95th percentile of the
/// surface's |H| before). Returns the files.
pub fn write_corner_views(
    dir: &Path,
    original: &Model,
    faired: &Model,
    unmet: &[usize],
    unit: &str,
    png: &dyn Fn(&Path, &image::RgbImage) -> Result<()>,
) -> Result<Vec<PathBuf>> {
    let clean = |name: &str| name.replace(|c: char| !c.is_ascii_alphanumeric() && c != '_', "_");
    let mut focus: Vec<(usize, Vec<usize>, String, String)> = Vec::new();
    for (k, entry) in original.surfaces.iter().enumerate() {
        if entry.role != Role::Corner || k >= faired.surfaces.len() {
            continue;
        }
        let masters = original
            .links
            .iter()
            .filter(|l| l.slave == k)
            .map(|l| l.master);
        let around = std::iter::once(k).chain(masters).collect();
        let title = format!("corner {}", entry.name);
        focus.push((k, around, format!("corner_{}", clean(&entry.name)), title));
    }
    for &li in unmet {
        let l = &original.links[li];
        let stem = format!(
            "link_{}_{}",
            clean(&original.surfaces[l.slave].name),
            l.side
        );
        let title = format!("unmet link {}", original.link_label(li));
        focus.push((l.slave, vec![l.slave, l.master], stem, title));
    }
    let mut written = Vec::new();
    for (k, around, stem, title) in focus {
        let entry = &original.surfaces[k];
        let Some(view) = corner_view(&entry.surface) else {
            continue;
        };
        let range = CORNER_RANGE_FACTOR * render::curvature_range(&[&entry.surface]);
        let faces_of = |model: &Model| -> Vec<(BSplineSurface, Vec<Vec<nurbs_core::Point3>>)> {
            // (a model whose run merged slivers may hold fewer surfaces than the input)
            around
                .iter()
                .filter_map(|&i| {
                    model
                        .surfaces
                        .get(i)
                        .map(|s| (s.surface.clone(), s.trim.clone()))
                })
                .collect()
        };
        let before = faces_of(original);
        let stripes = render::zebra_stripes(&faces(&before), &view);
        for (when, model) in [("before", original), ("after", faired)] {
            let owned = faces_of(model);
            let faces = faces(&owned);
            let zebra = render::render_faces(&faces, &view, Shading::Zebra { stripes });
            let path = dir.join(format!("{stem}_zebra_{when}.png"));
            png(
                &path,
                &hier_fair::plots::titled(&zebra, &format!("{title}: zebra"), when),
            )?;
            written.push(path);
            let map = mean_curvature_map(&faces, &view, range, unit)?;
            let path = dir.join(format!("{stem}_mean_curvature_{when}.png"));
            let map_title = format!("{title}: mean curvature");
            png(&path, &hier_fair::plots::titled(&map, &map_title, when))?;
            written.push(path);
        }
    }
    Ok(written)
}

/// Borrowed faces of owned (surface, trim) pairs.
pub(crate) fn faces(
    owned: &[(BSplineSurface, Vec<Vec<nurbs_core::Point3>>)],
) -> Vec<render::Face<'_>> {
    owned
        .iter()
        .map(|(surface, trim)| render::Face { surface, trim })
        .collect()
}

/// The mean-curvature map of `faces` seen through `view`, blue – white – red over ±`range`
/// (1/`unit`), with its colour bar at the right.
pub(crate) fn mean_curvature_map(
    faces: &[render::Face],
    view: &View,
    range: f64,
    unit: &str,
) -> Result<image::RgbImage> {
    let map = render::render_faces(faces, view, Shading::MeanCurvature { range });
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
