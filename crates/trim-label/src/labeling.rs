//! The labeling driver (\[VV18\], "Algorithm for automatic labeling"): segments → candidates →
//! concatenations and corners → reduction → South/East/North/West, with a log of decisions.
//!
//! Side names follow the boundary orientation: the outer loop runs counter-clockwise around the
//! face normals, as the domain square's sides do in the order South (v = 0, u increasing), East
//! (u = 1), North (v = 1, u decreasing), West (u = 0). Which admissible label becomes South:
//! - (1, 0): the label; (2, 0): the longer label (the other is North);
//! - (2, 1): the label before the corner (the other is East);
//! - (3, 2): the label after the no-corner (then East, North);
//! - (4, 4): the longest label (then East, North, West).

use nurbs_core::{Point3, TriMesh};
use serde::Serialize;

use crate::candidates::{SegmentShape, classify};
use crate::error::Result;
use crate::junction::{CornerKind, Junction, JunctionContext};
use crate::params::LabelParams;
use crate::reduce::{Configuration, Operation, Step, reduce};
use crate::region::{Point2, Region};
use crate::segments::{Segmentation, auto_segments, given_segments};

/// The label of a boundary segment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Label {
    /// v = 0
    South,
    /// u = 1
    East,
    /// v = 1
    North,
    /// u = 0
    West,
    /// free
    Unlabeled,
}

impl Label {
    /// The sides in loop order.
    pub const SIDES: [Label; 4] = [Label::South, Label::East, Label::North, Label::West];

    /// Lower-case name as in the JSON output.
    pub fn name(self) -> &'static str {
        match self {
            Label::South => "south",
            Label::East => "east",
            Label::North => "north",
            Label::West => "west",
            Label::Unlabeled => "unlabeled",
        }
    }
}

/// One segment with its label.
#[derive(Debug, Clone, PartialEq)]
pub struct LabeledSegment {
    /// vertex indices as given (or found), 0-based OBJ order
    pub vertices: Vec<usize>,
    /// its label
    pub label: Label,
    /// the same polyline in loop (counter-clockwise) orientation, end vertices included
    pub loop_vertices: Vec<usize>,
    /// why it was not a candidate (None: it was one)
    pub excluded: Option<String>,
}

/// A junction between consecutive final labels.
#[derive(Debug, Clone, PartialEq)]
pub struct LabeledCorner {
    /// segment indices (caller's order): the last of the first label, the first of the next
    pub between: [usize; 2],
    /// real, virtual or none
    pub kind: CornerKind,
    /// position (None for no corner)
    pub position: Option<Point3>,
    /// strength in [0, 1]
    pub strength: f64,
    /// turning between the labels' tangents (radians)
    pub turning: f64,
    /// position in the best-fit plane (for drawing)
    pub position_2d: Option<Point2>,
    /// plane points where the extensions to a virtual corner start
    pub extension_from: Option<(Point2, Point2)>,
}

/// The result of [`label_region`].
#[derive(Debug, Clone, PartialEq)]
pub struct Labeling {
    /// segments in the caller's order (for automatic segments: loop order)
    pub segments: Vec<LabeledSegment>,
    /// junctions between consecutive labels, in loop order
    pub corners: Vec<LabeledCorner>,
    /// number of labels L
    pub labels: usize,
    /// number of corners C (real + virtual)
    pub corner_count: usize,
    /// the final labels in loop order: side and segment indices (caller's order numbers), each
    /// label's segments in loop order
    pub chains: Vec<(Label, Vec<usize>)>,
    /// the decisions taken, in order
    pub log: Vec<String>,
    /// the outer loop (vertex indices, counter-clockwise)
    pub outer_loop: Vec<usize>,
}

#[derive(Serialize)]
struct SegmentJson<'a> {
    vertices: &'a [usize],
    label: Label,
}

#[derive(Serialize)]
struct CornerJson {
    between: [usize; 2],
    kind: CornerKind,
    position: Option<[f64; 3]>,
    strength: f64,
}

#[derive(Serialize)]
struct ConfigurationJson {
    labels: usize,
    corners: usize,
}

#[derive(Serialize)]
struct LabelingJson<'a> {
    segments: Vec<SegmentJson<'a>>,
    corners: Vec<CornerJson>,
    configuration: ConfigurationJson,
}

impl Labeling {
    /// The `label` JSON of the CLI contract:
    /// `{"segments": [{"vertices", "label"}], "corners": [{"between", "kind", "position",
    /// "strength"}], "configuration": {"labels", "corners"}}` (pretty-printed).
    pub fn to_json(&self) -> String {
        let doc = LabelingJson {
            segments: self
                .segments
                .iter()
                .map(|s| SegmentJson {
                    vertices: &s.vertices,
                    label: s.label,
                })
                .collect(),
            corners: self
                .corners
                .iter()
                .map(|c| CornerJson {
                    between: c.between,
                    kind: c.kind,
                    position: c.position.map(|p| [p.x, p.y, p.z]),
                    strength: c.strength,
                })
                .collect(),
            configuration: ConfigurationJson {
                labels: self.labels,
                corners: self.corner_count,
            },
        };
        serde_json::to_string_pretty(&doc).expect("plain data always serializes")
    }

    /// Labels in the caller's segment order.
    pub fn segment_labels(&self) -> Vec<Label> {
        self.segments.iter().map(|s| s.label).collect()
    }
}

fn names(seg: &Segmentation, ids: &[usize]) -> String {
    ids.iter()
        .map(|&k| seg.input_index(k).to_string())
        .collect::<Vec<_>>()
        .join("-")
}

fn describe(j: &Junction, strong: f64) -> String {
    match j {
        Junction::Concatenate { quality } => format!("a smooth connection (quality {quality:.2})"),
        Junction::Corner(c) => match c.kind {
            CornerKind::None => format!("no corner (turning {:.1}°)", c.turning.to_degrees()),
            kind => format!(
                "a {} {} corner (strength {:.2}, turning {:.1}°, distance {:.3})",
                if c.strength >= strong {
                    "strong"
                } else {
                    "weak"
                },
                if kind == CornerKind::Real {
                    "real"
                } else {
                    "virtual"
                },
                c.strength,
                c.turning.to_degrees(),
                c.distance
            ),
        },
    }
}

/// Labels the outer boundary of a trimmed region.
///
/// `segments`: the outer loop's segments as lists of vertex indices (see
/// [`crate::segments::given_segments`]); `None` segments the loop automatically. Errors: the
/// mesh checks of [`Region::new`], segments that do not tile the outer loop, invalid params.
pub fn label_region(
    mesh: &TriMesh,
    segments: Option<&[Vec<usize>]>,
    params: &LabelParams,
) -> Result<Labeling> {
    params.validate()?;
    let region = Region::new(mesh)?;
    let seg = match segments {
        Some(s) => given_segments(&region, s)?,
        None => auto_segments(&region, &params.segmentation),
    };
    Ok(label_segmentation(&region, &seg, params))
}

/// Labels a validated region with a checked segmentation.
pub fn label_segmentation(
    region: &Region<'_>,
    seg: &Segmentation,
    params: &LabelParams,
) -> Labeling {
    let mut log = Vec::new();
    let segments = &seg.segments;
    log.push(format!(
        "{} segments on an outer loop of {} vertices ({} holes), region size {:.4}",
        segments.len(),
        region.loop_len(),
        region.holes.len(),
        region.size
    ));
    let shapes: Vec<SegmentShape> = segments
        .iter()
        .map(|s| SegmentShape::new(region, s, params))
        .collect();
    let exclusions = classify(region, segments, &shapes, params);
    for (k, e) in exclusions.iter().enumerate() {
        let name = seg.input_index(k);
        match e {
            Some(e) => log.push(format!("segment {name}: dropped: it {e}")),
            None => log.push(format!(
                "segment {name}: label candidate (length {:.4}, turning {:.1}°)",
                shapes[k].length,
                shapes[k].total_turning.to_degrees()
            )),
        }
    }
    let ctx = JunctionContext {
        region,
        segments,
        shapes: &shapes,
        params,
    };
    let mut config = Configuration {
        labels: (0..segments.len())
            .filter(|&k| exclusions[k].is_none())
            .map(|k| vec![k])
            .collect(),
    };
    for (a, b) in config.merge_concatenations(&ctx) {
        log.push(format!(
            "segments {} and {}: concatenated into a multi-segment label",
            seg.input_index(a),
            seg.input_index(b)
        ));
    }
    let (config, steps) = reduce(config, &ctx);
    for (round, step) in steps.iter().enumerate() {
        log_round(round + 1, step, seg, &ctx, &mut log);
    }
    log.push(format!(
        "{} labels, {} corners: admissible",
        config.len(),
        Configuration::corner_count(&config.junctions(&ctx))
    ));
    finish(region, seg, &ctx, &config, &exclusions, log)
}

/// Logs reduction round `round`: the junctions of the configuration before it, the operation
/// with the junction it leaves, and the concatenations that follow.
fn log_round(
    round: usize,
    step: &Step,
    seg: &Segmentation,
    ctx: &JunctionContext<'_, '_>,
    log: &mut Vec<String>,
) {
    let strong = ctx.params.strong_strength;
    let before = &step.before;
    let l = before.len();
    let junctions = before.junctions(ctx);
    let c = Configuration::corner_count(&junctions);
    let summary: Vec<String> = (0..l)
        .map(|k| {
            format!(
                "{} → {}: {}",
                names(seg, &before.labels[k]),
                names(seg, &before.labels[(k + 1) % l]),
                describe(&junctions[k], strong)
            )
        })
        .collect();
    log.push(format!(
        "round {round}: {l} labels, {c} corners: not admissible [{}]",
        summary.join("; ")
    ));
    let mut after = before.clone();
    after.apply(step.op);
    let (text, at) = describe_operation(step.op, before, seg);
    let left = at
        .and_then(|prev| {
            let prev_label = &before.labels[prev];
            let idx = after.labels.iter().position(|x| x == prev_label)?;
            Some(format!(
                ", leaving {}",
                describe(&after.junction(ctx, idx), strong)
            ))
        })
        .unwrap_or_default();
    log.push(format!("round {round}: {text}{left}"));
    for (a, b) in after.merge_concatenations(ctx) {
        log.push(format!(
            "round {round}: segments {} and {} concatenated",
            seg.input_index(a),
            seg.input_index(b)
        ));
    }
}

/// The text of operation `op` on `before`, and the label before the removed ones (whose
/// junction the removal changes).
fn describe_operation(
    op: Operation,
    before: &Configuration,
    seg: &Segmentation,
) -> (String, Option<usize>) {
    let l = before.len();
    match op {
        Operation::KillCorner(j) => (
            format!(
                "kill the weak corner {} → {} (concatenate)",
                names(seg, &before.labels[j]),
                names(seg, &before.labels[(j + 1) % l])
            ),
            None,
        ),
        Operation::RemoveLabel(k) => (
            format!("remove label {}", names(seg, &before.labels[k])),
            Some((k + l - 1) % l),
        ),
        Operation::RemovePair(k) => (
            format!(
                "remove labels {} and {}",
                names(seg, &before.labels[k]),
                names(seg, &before.labels[(k + 1) % l])
            ),
            Some((k + l - 1) % l),
        ),
    }
}

/// The [`Labeling`] of the admissible `config`: sides assigned as the module docs say.
fn finish(
    region: &Region<'_>,
    seg: &Segmentation,
    ctx: &JunctionContext<'_, '_>,
    config: &Configuration,
    exclusions: &[Option<crate::candidates::Exclusion>],
    mut log: Vec<String>,
) -> Labeling {
    let l = config.len();
    let junctions = config.junctions(ctx);
    let c = junctions.iter().filter(|j| is_corner(j)).count();
    let side = assign_sides(ctx, config, &junctions, c);
    let n = region.loop_len();
    let mut labels_internal = vec![Label::Unlabeled; seg.segments.len()];
    for (k, ids) in config.labels.iter().enumerate() {
        for &s in ids {
            labels_internal[s] = side[k];
        }
    }
    let mut segments: Vec<LabeledSegment> = vec![];
    for out in 0..seg.segments.len() {
        let k = seg.input_index(out);
        let s = &seg.segments[k];
        segments.push(LabeledSegment {
            vertices: s.vertices.clone(),
            label: labels_internal[k],
            loop_vertices: (0..=s.edges)
                .map(|e| region.outer[(s.start + e) % n])
                .collect(),
            excluded: exclusions[k].map(|e| e.to_string()),
        });
    }
    let corners = labeled_corners(seg, config, &junctions);
    let assigned: Vec<String> = (0..l)
        .map(|k| format!("{} = {}", names(seg, &config.labels[k]), side[k].name()))
        .collect();
    log.push(format!(
        "result: {l} labels, {c} corners: {}",
        assigned.join(", ")
    ));
    let chains = (0..l)
        .map(|k| {
            (
                side[k],
                config.labels[k]
                    .iter()
                    .map(|&s| seg.input_index(s))
                    .collect(),
            )
        })
        .collect();
    Labeling {
        segments,
        corners,
        labels: l,
        corner_count: c,
        chains,
        log,
        outer_loop: region.outer.clone(),
    }
}

/// Whether junction `j` is a (real or virtual) corner.
fn is_corner(j: &Junction) -> bool {
    matches!(j, Junction::Corner(c) if c.is_corner())
}

/// The side of each label of `config` (with `junctions`, `c` of them corners), as the module
/// docs say.
fn assign_sides(
    ctx: &JunctionContext<'_, '_>,
    config: &Configuration,
    junctions: &[Junction],
    c: usize,
) -> Vec<Label> {
    let l = config.len();
    let lengths: Vec<f64> = (0..l).map(|k| config.length(ctx, k)).collect();
    let longest = (0..l)
        .max_by(|&a, &b| lengths[a].total_cmp(&lengths[b]).then(b.cmp(&a)))
        .unwrap_or(0);
    let mut side = vec![Label::Unlabeled; l];
    let mut put = |first: usize, sides: &[Label]| {
        for (i, s) in sides.iter().enumerate() {
            side[(first + i) % l] = *s;
        }
    };
    match (l, c) {
        (1, _) => put(0, &[Label::South]),
        (2, 0) => put(longest, &[Label::South, Label::North]),
        (2, _) => {
            let k = junctions.iter().position(is_corner).unwrap_or(0);
            put(k, &[Label::South, Label::East]);
        }
        (3, _) => {
            let j = junctions.iter().position(|j| !is_corner(j)).unwrap_or(0);
            put(j + 1, &[Label::South, Label::East, Label::North]);
        }
        (4, _) => put(longest, &Label::SIDES),
        _ => {}
    }
    side
}

/// The corner between each label of `config` and the next, from `junctions`.
fn labeled_corners(
    seg: &Segmentation,
    config: &Configuration,
    junctions: &[Junction],
) -> Vec<LabeledCorner> {
    let l = config.len();
    (0..l)
        .map(|k| {
            let a = *config.labels[k].last().expect("non-empty");
            let b = config.labels[(k + 1) % l][0];
            let between = [seg.input_index(a), seg.input_index(b)];
            match &junctions[k] {
                Junction::Corner(cn) => LabeledCorner {
                    between,
                    kind: cn.kind,
                    position: cn.position,
                    strength: cn.strength,
                    turning: cn.turning,
                    position_2d: cn.position_2d,
                    extension_from: cn.extension_from,
                },
                Junction::Concatenate { .. } => LabeledCorner {
                    between,
                    kind: CornerKind::None,
                    position: None,
                    strength: 0.0,
                    turning: 0.0,
                    position_2d: None,
                    extension_from: None,
                },
            }
        })
        .collect()
}
