//! Trims through export: every kernel model of `fixtures/occt` imported from STEP and from IGES
//! (each face's bounds kept as trim loops), exported to the same format and read back with this
//! crate's readers gives every face its loops back (a face whose trim is its parameter box is
//! written as its box and reads back untrimmed or bounded by its box, [`nurbs_io::trim_is_box`]) — as many as the model has (IGES: the outer
//! boundary the reader keeps) — with every point within the model's G0 tolerance (STEP: half of
//! it plus the loop's own chord sag, its edges being cubics fitted to the loop's points) of the
//! written loop (a closed polyline: the model's loop on the written surface, densified where
//! its chords leave the surface, [`nurbs_io::face_bounds`]) and of the read-back face's
//! surface. The written loops lie within the model's loops' own sag of them (plus the G0
//! tolerance): the written loop follows the surface between the model's points, and a model
//! loop's chord is as far off its true edge as the import's sampling left it (2° steps on a
//! 25 mm arc: 4e-3; a long chord at a sphere's pole in an IGES import: 0.8) — so the bound is
//! that sag, measured on the model's own surface at seven points inside each chord, with G0 for
//! what the sampling of the chord misses and for the feet of the model's points.

use std::path::Path;

use nurbs_core::{BSplineSurface, Point3, ProjectionParams, SurfaceProjector};
use nurbs_io::bounds::distance_to_polyline;

/// The kernel models of `fixtures/occt` (their index).
fn kernel_models() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/occt");
    let index: Vec<serde_json::Value> =
        serde_json::from_str(&std::fs::read_to_string(dir.join("index.json")).unwrap()).unwrap();
    assert!(index.len() >= 6);
    index
        .iter()
        .map(|e| e["name"].as_str().expect("a name").to_string())
        .collect()
}

/// The faces read back from `text` (a file of format `ext`): surface and trim loops each.
fn read_back(text: &str, ext: &str) -> Vec<(BSplineSurface, Vec<Vec<Point3>>)> {
    if ext == "step" {
        nurbs_io::read_step(text)
            .unwrap()
            .faces
            .into_iter()
            .map(|f| (f.surface, f.trim))
            .collect()
    } else {
        nurbs_io::read_iges(text.as_bytes())
            .unwrap()
            .surfaces
            .into_iter()
            .map(|s| {
                let loops = s.trim_loops();
                (s.surface, loops)
            })
            .collect()
    }
}

/// Imports `NAME.ext`, exports it to `ext`, reads it back and checks the loops (module docs);
/// returns the points read back and the largest distances from the loops and the surfaces.
fn trims_round_trip(name: &str, ext: &str) -> (usize, f64, f64) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/occt");
    let (model, _, _) =
        hier_fair_cli::exchange::model_from_cad(&dir.join(format!("{name}.{ext}"))).unwrap();
    let text = hier_fair_cli::exchange::cad_text(&model, Path::new(&format!("out.{ext}"))).unwrap();
    let back = read_back(&text, ext);
    assert_eq!(back.len(), model.surfaces.len(), "{name}.{ext}");
    let g0 = model.tolerances.g0;
    let (mut count, mut off_loop, mut off_surface, mut off_model) = (0, 0.0f64, 0.0f64, 0.0f64);
    let (mut sag, mut own_sag) = (0.0f64, 0.0f64);
    for (s, (surface, loops)) in model.surfaces.iter().zip(&back) {
        // a trim that is the parameter box is written as the box ([`nurbs_io::trim_is_box`]):
        // it reads back untrimmed (IGES) or bounded by its box again (STEP)
        if nurbs_io::trim_is_box(&s.surface, &s.trim) {
            assert!(
                loops.is_empty() || nurbs_io::trim_is_box(surface, loops),
                "{name}.{ext}: {}",
                s.name
            );
            count += 1;
            continue;
        }
        assert_eq!(loops.len(), s.trim.len(), "{name}.{ext}: {}", s.name);
        let written = nurbs_io::face_bounds(&s.surface, &s.trim);
        let mut projector = SurfaceProjector::new(surface, ProjectionParams::default());
        for (k, (l, given)) in loops.iter().zip(&s.trim).enumerate() {
            let closed = |pts: &[Point3]| [pts, &pts[..1]].concat();
            let (polyline, model_loop) = (closed(&written.loop_points(k)), closed(given));
            // each point from the sampled starts and from the previous foot (the sampled starts
            // alone can stall at a pole, where every sample of the collapsed row is one point)
            let mut previous: Option<(f64, f64)> = None;
            for p in l {
                off_loop = off_loop.max(distance_to_polyline(p, &polyline));
                let mut f = projector.project(p);
                if let Some(start) = previous {
                    let warm = projector.project_from(p, start);
                    if warm.distance < f.distance {
                        f = warm;
                    }
                }
                if f.distance > g0 {
                    // Newton from a spread of starts: one of them reaches a point by a pole
                    let ((u0, u1), (v0, v1)) = (surface.domain_u(), surface.domain_v());
                    for (a, b) in (1..8).flat_map(|a| (1..8).map(move |b| (a, b))) {
                        let start = (
                            u0 + (u1 - u0) * f64::from(a) / 8.0,
                            v0 + (v1 - v0) * f64::from(b) / 8.0,
                        );
                        let g = projector.project_from(p, start);
                        if g.distance < f.distance {
                            f = g;
                        }
                    }
                }
                previous = Some((f.u, f.v));
                off_surface = off_surface.max(f.distance);
            }
            for p in &polyline {
                off_model = off_model.max(distance_to_polyline(p, &model_loop));
            }
            own_sag = own_sag.max(polyline_sag(&polyline));
            let mut model_projector =
                SurfaceProjector::new(&s.surface, ProjectionParams::default());
            sag = sag.max(chord_sag(&model_loop, &mut model_projector));
            count += l.len();
        }
    }
    eprintln!(
        "{name}.{ext}: {count} trim points back, at most {off_loop:.2e} from the written loops and {off_surface:.2e} from their surfaces; written loops at most {off_model:.2e} from the model's, whose chords leave their surfaces by up to {sag:.2e} (G0 {g0:.0e})"
    );
    // STEP writes each edge as a cubic within EDGE_FIT_SHARE of G0 of the loop's points, which
    // follows the true edge between them where the polyline cuts across: a point read back lies
    // within that share plus the polyline's own chord sag of it; IGES writes the polyline
    let bound = if ext == "step" {
        hier_fair::exchange::EDGE_FIT_SHARE * g0 + own_sag
    } else {
        g0
    };
    assert!(
        off_loop <= bound,
        "{name}.{ext}: {off_loop:.3e} off the loops (bound {bound:.3e})"
    );
    assert!(
        off_model <= sag + g0,
        "{name}.{ext}: written loops {off_model:.3e} from the model's, whose chords sag {sag:.3e}"
    );
    assert!(
        off_surface <= g0,
        "{name}.{ext}: {off_surface:.3e} off the surfaces"
    );
    (count, off_loop, off_surface)
}

/// The sag of the closed polyline `closed`'s chords from the smooth curve through its points,
/// estimated at each point from its distance to the chord of its two neighbours: on a circle
/// through points h apart that distance is h²/(2R) and a chord's sag h²/(8R), a quarter of it.
fn polyline_sag(closed: &[Point3]) -> f64 {
    closed
        .windows(3)
        .map(|w| distance_to_polyline(&w[1], &[w[0], w[2]]) / 4.0)
        .fold(0.0, f64::max)
}

/// The largest distance from `surface` of the model loop `closed` (first point repeated at the
/// end): at its points and at seven points inside each chord.
fn chord_sag(closed: &[Point3], projector: &mut SurfaceProjector) -> f64 {
    let mut sag = 0.0f64;
    for w in closed.windows(2) {
        for k in 0..8 {
            let p = w[0] + (w[1] - w[0]) * (f64::from(k) / 8.0);
            sag = sag.max(projector.project(&p).distance);
        }
    }
    sag
}

#[test]
fn step_exports_read_back_with_their_trims() {
    for name in kernel_models() {
        let (count, _, _) = trims_round_trip(&name, "step");
        assert!(count > 0, "{name}");
    }
}

#[test]
fn iges_exports_read_back_with_their_trims() {
    for name in kernel_models() {
        let (count, _, _) = trims_round_trip(&name, "igs");
        assert!(count > 0, "{name}");
    }
}
