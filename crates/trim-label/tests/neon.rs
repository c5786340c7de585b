//! The Neon side panel (`fixtures/third_party/neon_side.obj`, a real car side panel with three openings):
//! labels and fit. Skipped with a message when the file is absent.

use std::time::Instant;

use nurbs_core::TriMesh;
use trim_label::{LabelParams, label_region};

fn neon() -> TriMesh {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/third_party/neon_side.obj"
    );
    let text = std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("{path} is in the repository: {e}"));
    TriMesh::from_obj_str(&text).expect("neon_side.obj parses")
}

#[test]
fn neon_side_labels() {
    let mesh = neon();
    let t = Instant::now();
    let l = label_region(&mesh, None, &LabelParams::default()).expect("labels");
    let secs = t.elapsed().as_secs_f64();
    for line in &l.log {
        eprintln!("{line}");
    }
    eprintln!("labeling took {secs:.3} s");
    assert_eq!(
        l.outer_loop.len(),
        744,
        "the outer outline (data README: loops of 744, 326, 310, 40)"
    );
    assert!(secs <= 1.0, "labeling took {secs} s (goal ≤ 1 s)");
    assert!(matches!(
        (l.labels, l.corner_count),
        (0, 0) | (1, 0) | (2, 0) | (2, 1) | (3, 2) | (4, 4)
    ));
    assert!(
        l.labels >= 2,
        "a panel with long straight sides gets at least two labels"
    );
    // the longest segment (the panel's top edge) is labeled
    let longest = (0..l.segments.len())
        .max_by_key(|&k| l.segments[k].loop_vertices.len())
        .unwrap();
    assert_ne!(l.segments[longest].label, trim_label::Label::Unlabeled);
    if let Ok(dir) = std::env::var("TRIM_LABEL_SVG_DIR") {
        let svg = trim_label::write_svg(&mesh, &l).expect("svg");
        std::fs::write(format!("{dir}/neon.svg"), svg).expect("write svg");
    }
}

#[test]
fn neon_side_fit() {
    let mesh = neon();
    let l = label_region(&mesh, None, &LabelParams::default()).expect("labels");
    let t = Instant::now();
    let (surface, rep) =
        trim_label::fit_labeled(&mesh, &l, &trim_label::LabeledFitParams::default()).expect("fit");
    eprintln!("fit took {:.3} s: {rep:?}", t.elapsed().as_secs_f64());
    eprintln!("rms / size = {:.4} %", 100.0 * rep.rms_distance / rep.size);
    assert_eq!(
        (surface.num_u(), surface.num_v()),
        (rep.control_u, rep.control_v)
    );
}
