//! The three examples of \[VV18\], rebuilt as synthetic regions, and each of the six admissible
//! configurations.

mod common;

use common::{arc, codes, label, pattern, polygon_region};
use trim_label::CornerKind;

const H: f64 = 0.25;

/// Example 1: a concave notch in the bottom (its three segments fall out, the two bottom parts are
/// concatenated across it), a top side of three segments, a concave rounded cut at the top-left
/// (dropped) so that top and left define a strong virtual corner; four labels, four corners.
#[test]
fn example_1_notch_multi_segment_and_strong_virtual_corner() {
    let pieces = vec![
        vec![[0.0, 0.0], [4.0, 0.0]],         // 0 bottom left
        vec![[4.0, 0.0], [4.0, 2.0]],         // 1 notch wall
        vec![[4.0, 2.0], [6.0, 2.0]],         // 2 notch top
        vec![[6.0, 2.0], [6.0, 0.0]],         // 3 notch wall
        vec![[6.0, 0.0], [10.0, 0.0]],        // 4 bottom right
        vec![[10.0, 0.0], [10.0, 6.0]],       // 5 right
        vec![[10.0, 6.0], [7.0, 6.0]],        // 6 top (three pieces)
        vec![[7.0, 6.0], [4.0, 6.0]],         // 7
        vec![[4.0, 6.0], [1.5, 6.0]],         // 8
        arc([0.0, 6.0], 1.5, 0.0, -90.0, 12), // 9 concave rounded cut
        vec![[0.0, 4.5], [0.0, 0.0]],         // 10 left
    ];
    let (mesh, segs) = polygon_region(&pieces, H);
    let l = label(&mesh, &segs);
    assert_eq!((l.labels, l.corner_count), (4, 4));
    assert_eq!(pattern(&l), "a---abccc-d");
    let virt: Vec<_> = l
        .corners
        .iter()
        .filter(|c| c.kind == CornerKind::Virtual)
        .collect();
    assert_eq!(virt.len(), 1);
    let p = virt[0].position.expect("virtual corner has a position");
    assert!(
        (p.x - 0.0).abs() < 0.05 && (p.y - 6.0).abs() < 0.05,
        "{p:?}"
    );
    assert!(virt[0].strength >= 0.5, "strong: {}", virt[0].strength);
    assert_eq!(
        l.corners
            .iter()
            .filter(|c| c.kind == CornerKind::Real)
            .count(),
        3
    );
}

/// Example 2: a chamfered corner is a label of its own at first (five labels, five corners);
/// removing it leaves a strong virtual corner, removing any other label a weak one.
#[test]
fn example_2_five_labels_remove_the_chamfer() {
    let pieces = vec![
        vec![[12.0, 1.5], [12.0, 4.5]],         // 0 right
        vec![[12.0, 4.5], [9.5, 7.0]],          // 1 chamfer
        vec![[9.5, 7.0], [0.0, 7.0]],           // 2 top
        vec![[0.0, 7.0], [0.0, 0.0]],           // 3 left
        vec![[0.0, 0.0], [4.0, 0.0]],           // 4 bottom left
        vec![[4.0, 0.0], [4.0, 1.5]],           // 5 notch
        vec![[4.0, 1.5], [7.0, 1.5]],           // 6
        vec![[7.0, 1.5], [7.0, 0.0]],           // 7
        vec![[7.0, 0.0], [10.5, 0.0]],          // 8 bottom right
        arc([12.0, 0.0], 1.5, 180.0, 90.0, 12), // 9 concave rounded cut
    ];
    let (mesh, segs) = polygon_region(&pieces, H);
    let l = label(&mesh, &segs);
    assert!(
        l.log
            .iter()
            .any(|s| s.contains("5 labels, 5 corners: not admissible")),
        "the first round has five labels and five corners"
    );
    assert!(
        l.log.iter().any(|s| s.contains("remove label 1,")),
        "the chamfer is removed"
    );
    assert_eq!((l.labels, l.corner_count), (4, 4));
    assert_eq!(pattern(&l), "a-bcd---d-");
    let top_right = l
        .corners
        .iter()
        .find(|c| c.between == [0, 2])
        .expect("corner between right and top");
    assert_eq!(top_right.kind, CornerKind::Virtual);
    let p = top_right.position.expect("position");
    assert!(
        (p.x - 12.0).abs() < 0.05 && (p.y - 7.0).abs() < 0.05,
        "{p:?}"
    );
    assert!(top_right.strength >= 0.5);
}

/// Example 3: six labels with six corners at first; the chamfer goes (its neighbours make a
/// strong virtual corner), then both segments of the pointed left end go together (either alone
/// would leave a weak virtual corner): three labels, two corners.
#[test]
fn example_3_ends_with_three_labels_and_two_corners() {
    let pieces = vec![
        vec![[3.0, 0.0], [18.0, 0.0]],  // 0 bottom
        vec![[18.0, 0.0], [20.0, 2.0]], // 1 chamfer
        vec![[20.0, 2.0], [20.0, 5.0]], // 2 right
        vec![[20.0, 5.0], [11.0, 5.0]], // 3 top right part
        vec![[11.0, 5.0], [11.0, 4.6]], // 4 small notch
        vec![[11.0, 4.6], [10.0, 4.6]], // 5
        vec![[10.0, 4.6], [10.0, 5.0]], // 6
        vec![[10.0, 5.0], [3.0, 5.7]],  // 7 top left part, slightly tilted
        vec![[3.0, 5.7], [0.0, 2.5]],   // 8 pointed end
        vec![[0.0, 2.5], [3.0, 0.0]],   // 9
    ];
    let (mesh, segs) = polygon_region(&pieces, H);
    let l = label(&mesh, &segs);
    assert!(
        l.log
            .iter()
            .any(|s| s.contains("6 labels, 6 corners: not admissible"))
    );
    assert!(l.log.iter().any(|s| s.contains("remove labels 8 and 9")));
    assert_eq!((l.labels, l.corner_count), (3, 2));
    assert_eq!(codes(&l), "S-EN---N--");
    let kinds: Vec<CornerKind> = l.corners.iter().map(|c| c.kind).collect();
    assert_eq!(kinds.iter().filter(|&&k| k == CornerKind::None).count(), 1);
    assert!(kinds.contains(&CornerKind::Virtual) && kinds.contains(&CornerKind::Real));
}

/// (0, 0): a disk is one smooth closed segment turning 360°: no candidate.
#[test]
fn configuration_0_0_disk() {
    let pieces = vec![arc([0.0, 0.0], 3.0, 0.0, 360.0, 96)];
    let (mesh, _) = polygon_region(&pieces, H);
    let l = trim_label::label_region(&mesh, None, &trim_label::LabelParams::default()).unwrap();
    assert_eq!(l.segments.len(), 1);
    assert_eq!((l.labels, l.corner_count), (0, 0));
    assert_eq!(codes(&l), "-");
    assert!(l.corners.is_empty());
}

/// (1, 0): a half disk: the diameter is the only candidate (the arc turns 180°).
#[test]
fn configuration_1_0_half_disk() {
    let pieces = vec![
        vec![[-5.0, 0.0], [5.0, 0.0]],
        arc([0.0, 0.0], 5.0, 0.0, 180.0, 64),
    ];
    let (mesh, segs) = polygon_region(&pieces, H);
    let l = label(&mesh, &segs);
    assert_eq!((l.labels, l.corner_count), (1, 0));
    assert_eq!(codes(&l), "S-");
    assert_eq!(l.corners.len(), 1);
    assert_eq!(l.corners[0].kind, CornerKind::None);
}

/// (2, 0): a stadium: two opposite sides, no corner between them.
#[test]
fn configuration_2_0_stadium() {
    let pieces = vec![
        vec![[0.0, 0.0], [10.0, 0.0]],
        arc([10.0, 2.0], 2.0, -90.0, 90.0, 32),
        vec![[10.0, 4.0], [0.0, 4.0]],
        arc([0.0, 2.0], 2.0, 90.0, 270.0, 32),
    ];
    let (mesh, segs) = polygon_region(&pieces, H);
    let l = label(&mesh, &segs);
    assert_eq!((l.labels, l.corner_count), (2, 0));
    assert_eq!(codes(&l), "S-N-");
}

/// (2, 1): two sides at a right angle; the third side is an S-shaped curve (complex geometry).
#[test]
fn configuration_2_1_wavy_hypotenuse() {
    let wave: Vec<[f64; 2]> = (0..=64)
        .map(|i| {
            let t = i as f64 / 64.0;
            let off = (2.0 * std::f64::consts::PI * t).sin() / std::f64::consts::SQRT_2;
            [8.0 - 8.0 * t + off, 8.0 * t + off]
        })
        .collect();
    let pieces = vec![
        vec![[0.0, 0.0], [8.0, 0.0]],
        wave,
        vec![[0.0, 8.0], [0.0, 0.0]],
    ];
    let (mesh, segs) = polygon_region(&pieces, H);
    let l = label(&mesh, &segs);
    assert!(
        l.segments[1]
            .excluded
            .as_deref()
            .unwrap_or("")
            .contains("complex")
    );
    assert_eq!((l.labels, l.corner_count), (2, 1));
    assert_eq!(codes(&l), "E-S");
    let real = l
        .corners
        .iter()
        .find(|c| c.kind == CornerKind::Real)
        .unwrap();
    assert!(real.position.unwrap().coords.norm() < 1e-9);
}

/// (3, 2): a rectangle with a round end.
#[test]
fn configuration_3_2_round_end() {
    let pieces = vec![
        vec![[0.0, 0.0], [10.0, 0.0]],
        vec![[10.0, 0.0], [10.0, 4.0]],
        vec![[10.0, 4.0], [0.0, 4.0]],
        arc([0.0, 2.0], 2.0, 90.0, 270.0, 32),
    ];
    let (mesh, segs) = polygon_region(&pieces, H);
    let l = label(&mesh, &segs);
    assert_eq!((l.labels, l.corner_count), (3, 2));
    assert_eq!(codes(&l), "SEN-");
}

/// Automatic segmentation splits Example 1 at its polygon corners and gives the same labels.
#[test]
fn automatic_segments_of_example_1() {
    let pieces = vec![
        vec![
            [0.0, 0.0],
            [4.0, 0.0],
            [4.0, 2.0],
            [6.0, 2.0],
            [6.0, 0.0],
            [10.0, 0.0],
        ],
        vec![[10.0, 0.0], [10.0, 6.0], [1.5, 6.0]],
        arc([0.0, 6.0], 1.5, 0.0, -90.0, 12),
        vec![[0.0, 4.5], [0.0, 0.0]],
    ];
    let (mesh, _) = polygon_region(&pieces, H);
    let l = trim_label::label_region(&mesh, None, &trim_label::LabelParams::default()).unwrap();
    for line in &l.log {
        eprintln!("{line}");
    }
    assert_eq!(
        l.segments.len(),
        9,
        "8 polygon corners + the rounded cut's two ends"
    );
    assert_eq!((l.labels, l.corner_count), (4, 4));
    let labeled = l
        .segments
        .iter()
        .filter(|s| s.label != trim_label::Label::Unlabeled)
        .count();
    assert_eq!(labeled, 5, "bottom (2 parts), right, top, left");
}

/// The `label` JSON of the CLI contract, field by field, and the SVG drawing.
#[test]
fn json_and_svg_of_example_1() {
    let pieces = vec![
        vec![[0.0, 0.0], [10.0, 0.0]],
        vec![[10.0, 0.0], [10.0, 6.0]],
        vec![[10.0, 6.0], [1.5, 6.0]],
        arc([0.0, 6.0], 1.5, 0.0, -90.0, 12),
        vec![[0.0, 4.5], [0.0, 0.0]],
    ];
    let (mesh, segs) = polygon_region(&pieces, H);
    let l = label(&mesh, &segs);
    let v: serde_json::Value = serde_json::from_str(&l.to_json()).unwrap();
    let keys: Vec<&String> = v.as_object().unwrap().keys().collect();
    assert_eq!(keys, ["configuration", "corners", "segments"]);
    assert_eq!(
        v["configuration"],
        serde_json::json!({"labels": 4, "corners": 4})
    );
    let s = v["segments"].as_array().unwrap();
    assert_eq!(s.len(), 5);
    assert_eq!(s[0]["vertices"], serde_json::json!(segs[0]));
    assert_eq!(s[3]["label"], "unlabeled");
    let labels: Vec<&str> = s.iter().map(|x| x["label"].as_str().unwrap()).collect();
    for side in ["south", "east", "north", "west"] {
        assert_eq!(
            labels.iter().filter(|&&x| x == side).count(),
            1,
            "{labels:?}"
        );
    }
    let corners = v["corners"].as_array().unwrap();
    assert_eq!(corners.len(), 4);
    let virt = corners.iter().find(|c| c["kind"] == "virtual").unwrap();
    assert_eq!(virt["between"], serde_json::json!([2, 4]));
    let pos = virt["position"].as_array().unwrap();
    assert!(
        (pos[0].as_f64().unwrap()).abs() < 0.05 && (pos[1].as_f64().unwrap() - 6.0).abs() < 0.05
    );
    assert!(corners.iter().all(|c| c.as_object().unwrap().len() == 4));
    let svg = trim_label::write_svg(&mesh, &l).unwrap();
    assert!(svg.starts_with("<svg"));
    assert_eq!(svg.matches("<polyline").count(), 5);
    assert_eq!(svg.matches("virtual corner, strength").count(), 1);
    assert_eq!(svg.matches("real corner, strength").count(), 3);
    assert_eq!(
        svg.matches("stroke-dasharray=\"4,3\"").count(),
        2,
        "two extension lines"
    );
}
