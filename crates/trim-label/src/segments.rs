//! Boundary segments: oriented polylines that tile the outer loop, either given (JSON lists of
//! vertex indices) or found by splitting the loop at corners and at strong changes of geodesic
//! curvature (\[VV18\]: "its perimeter boundary loop segmented into a sequence of oriented
//! polylines").
//!
//! Automatic segmentation, with τ_i the discrete geodesic turning of [`crate::region`] and s the
//! arc length along the loop:
//! - corner at vertex i when the windowed turning T(i) = Σ_{|s_j − s_i| ≤ w_c/2} τ_j has
//!   |T(i)| ≥ [`SegmentationParams::corner_angle_deg`] and |τ_i| is the largest in that window;
//! - curvature break at i when the mean curvatures of the arcs of length w_k before and after i,
//!   κ± = (Σ τ_j)/w_k, differ by |κ₊ − κ₋|·D ≥ [`SegmentationParams::curvature_change`] (D the
//!   region size, so the test is dimensionless) and the jump is a local maximum; breaks closer
//!   than [`SegmentationParams::min_segment_rel`]·perimeter to a kept split are skipped.
//!
//! Given segments may share their end vertices with their neighbours (polylines) or partition the
//! loop's vertices (each segment starts after the previous one's last vertex); they may run with
//! the loop or all against it. Internally every segment is a run of loop edges in the loop's
//! (counter-clockwise) orientation.

use serde::Deserialize;

use crate::error::{LabelError, Result};
use crate::region::Region;

/// Settings of the automatic segmentation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentationParams {
    /// Windowed turning (degrees) above which the loop has a corner (default 30°: a sharp corner
    /// of a CAD trim; smooth G1 joins turn by a few degrees over the window).
    pub corner_angle_deg: f64,
    /// Window w_c for corners, relative to the region size D (default 0.02: corner fillets up to
    /// ~1 % of the region count as corners).
    pub corner_window_rel: f64,
    /// Jump of geodesic curvature, |κ₊ − κ₋|·D, that splits a smooth run (dimensionless, default
    /// 8: e.g. a straight line meeting an arc of radius D/8).
    pub curvature_change: f64,
    /// Window w_k for the curvature means, relative to D (default 0.05).
    pub curvature_window_rel: f64,
    /// Shortest segment created by a curvature break, relative to the perimeter (default 0.02).
    pub min_segment_rel: f64,
}

impl Default for SegmentationParams {
    fn default() -> Self {
        Self {
            corner_angle_deg: 30.0,
            corner_window_rel: 0.02,
            curvature_change: 8.0,
            curvature_window_rel: 0.05,
            min_segment_rel: 0.02,
        }
    }
}

/// One boundary segment.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    /// vertex indices as given (or as found), 0-based OBJ order
    pub vertices: Vec<usize>,
    /// loop position of the first vertex, in loop orientation
    pub start: usize,
    /// number of loop edges it covers (≥ 1)
    pub edges: usize,
}

impl Segment {
    /// Loop position of its last vertex (not reduced modulo the loop length).
    pub fn end(&self) -> usize {
        self.start + self.edges
    }
}

/// The segments of the outer loop, in loop order.
#[derive(Debug, Clone, PartialEq)]
pub struct Segmentation {
    /// segments in loop (counter-clockwise) order
    pub segments: Vec<Segment>,
    /// true when the given segments ran against the loop: `segments[k]` is then input segment
    /// `n − 1 − k`
    pub reversed_input: bool,
}

impl Segmentation {
    /// Index in the caller's order of internal segment `k`.
    pub fn input_index(&self, k: usize) -> usize {
        if self.reversed_input {
            self.segments.len() - 1 - k
        } else {
            k
        }
    }
}

#[derive(Deserialize)]
#[serde(untagged)]
enum SegmentEntry {
    Plain(Vec<usize>),
    Record { vertices: Vec<usize> },
}

#[derive(Deserialize)]
#[serde(untagged)]
enum SegmentFile {
    Wrapped { segments: Vec<SegmentEntry> },
    Bare(Vec<SegmentEntry>),
}

/// Reads segments from JSON: `[[i, ...], ...]`, `{"segments": [[i, ...], ...]}` or the `label`
/// output itself (`{"segments": [{"vertices": [...]}, ...]}`).
pub fn parse_segments_json(text: &str) -> Result<Vec<Vec<usize>>> {
    let file: SegmentFile = serde_json::from_str(text).map_err(|e| LabelError::SegmentFormat {
        detail: e.to_string(),
    })?;
    let entries = match file {
        SegmentFile::Wrapped { segments } => segments,
        SegmentFile::Bare(s) => s,
    };
    Ok(entries
        .into_iter()
        .map(|e| match e {
            SegmentEntry::Plain(v) => v,
            SegmentEntry::Record { vertices } => vertices,
        })
        .collect())
}

/// Checks given segments against the outer loop and orders them with the loop.
pub fn given_segments(region: &Region<'_>, input: &[Vec<usize>]) -> Result<Segmentation> {
    check_on_loop(region, input)?;
    let reversed = input_orientation(region, input)?;
    let n = region.loop_len();
    let pos = |v: usize| region.loop_position[v];
    let count = input.len();
    let mut segments: Vec<Segment> = (0..count)
        .map(|k| {
            let idx = if reversed { count - 1 - k } else { k };
            let s = &input[idx];
            let first = if reversed { s[s.len() - 1] } else { s[0] };
            Segment {
                vertices: s.clone(),
                start: pos(first),
                edges: s.len() - 1,
            }
        })
        .collect();
    chain_segments(region, &mut segments, reversed)?;
    let total: usize = segments.iter().map(|s| s.edges).sum();
    if total != n {
        return Err(LabelError::SegmentsDoNotCoverLoop {
            detail: format!("the segments cover {total} edges, but the outer loop has {n}"),
        });
    }
    Ok(Segmentation {
        segments,
        reversed_input: reversed,
    })
}

/// Errors unless some segments are given, each of at least two vertices, all on the outer
/// loop.
fn check_on_loop(region: &Region<'_>, input: &[Vec<usize>]) -> Result<()> {
    if input.is_empty() {
        return Err(LabelError::SegmentsDoNotCoverLoop {
            detail: "no segments given".into(),
        });
    }
    for (segment, s) in input.iter().enumerate() {
        if s.len() < 2 {
            return Err(LabelError::SegmentTooShort {
                segment,
                count: s.len(),
            });
        }
        if let Some(&vertex) = s
            .iter()
            .find(|&&v| region.loop_position.get(v).is_none_or(|&p| p == usize::MAX))
        {
            return Err(LabelError::SegmentOffBoundary { segment, vertex });
        }
    }
    Ok(())
}

/// Whether the segments run against the loop (their first edge says), checking that every
/// edge of every segment is an edge of the loop in that direction.
fn input_orientation(region: &Region<'_>, input: &[Vec<usize>]) -> Result<bool> {
    let n = region.loop_len();
    let pos = |v: usize| region.loop_position[v];
    let (a, b) = (pos(input[0][0]), pos(input[0][1]));
    let reversed = if (a + 1) % n == b {
        false
    } else if (b + 1) % n == a {
        true
    } else {
        return Err(LabelError::SegmentNotContiguous {
            segment: 0,
            from: input[0][0],
            to: input[0][1],
        });
    };
    for (segment, s) in input.iter().enumerate() {
        for w in s.windows(2) {
            let (p, q) = (pos(w[0]), pos(w[1]));
            let ok = if reversed {
                (q + 1) % n == p
            } else {
                (p + 1) % n == q
            };
            if !ok {
                return Err(LabelError::SegmentNotContiguous {
                    segment,
                    from: w[0],
                    to: w[1],
                });
            }
        }
    }
    Ok(reversed)
}

/// Chains the loop-ordered `segments`: each ends where the next starts, or one edge before
/// (partition style: the edge between goes to the first); an error names a gap or overlap in
/// the caller's numbering.
fn chain_segments(region: &Region<'_>, segments: &mut [Segment], reversed: bool) -> Result<()> {
    let (n, count) = (region.loop_len(), segments.len());
    for k in 0..count {
        let next_start = segments[(k + 1) % count].start;
        let end = segments[k].end() % n;
        if next_start == (end + 1) % n && next_start != end {
            segments[k].edges += 1;
        } else if next_start != end {
            let (a, b) = (k, (k + 1) % count);
            return Err(LabelError::SegmentsDoNotCoverLoop {
                detail: format!(
                    "segment {} ends at vertex {} but the next segment ({}) starts at vertex {}",
                    if reversed { count - 1 - a } else { a },
                    region.outer[end],
                    if reversed { count - 1 - b } else { b },
                    region.outer[next_start]
                ),
            });
        }
    }
    Ok(())
}

/// Sums of τ over cyclic arc windows.
struct LoopWindows<'r, 'a> {
    region: &'r Region<'a>,
}

impl LoopWindows<'_, '_> {
    /// Arc length from loop position i forward to position j (cyclic).
    fn forward(&self, i: usize, j: usize) -> f64 {
        let r = self.region;
        let (n, p) = (r.loop_len(), r.perimeter());
        let d = r.arc[j % n] - r.arc[i % n];
        if d < 0.0 { d + p } else { d }
    }
    /// Positions strictly after i (direction +1) or before (−1) within arc `w`, capped at half
    /// the loop.
    fn run(&self, i: usize, forward: bool, w: f64) -> Vec<usize> {
        let n = self.region.loop_len();
        let mut out = Vec::new();
        for step in 1..n / 2 {
            let j = if forward {
                (i + step) % n
            } else {
                (i + n - step) % n
            };
            let d = if forward {
                self.forward(i, j)
            } else {
                self.forward(j, i)
            };
            if d > w {
                break;
            }
            out.push(j);
        }
        out
    }
}

/// Splits the outer loop automatically (see the module docs).
pub fn auto_segments(region: &Region<'_>, params: &SegmentationParams) -> Segmentation {
    let n = region.loop_len();
    let tau = &region.turning;
    let win = LoopWindows { region };
    let d = region.size;
    let wc = params.corner_window_rel * d;
    let corner = params.corner_angle_deg.to_radians();
    let mut splits: Vec<usize> = Vec::new();
    for i in 0..n {
        let (before, after) = (win.run(i, false, wc / 2.0), win.run(i, true, wc / 2.0));
        let total: f64 = tau[i] + before.iter().chain(&after).map(|&j| tau[j]).sum::<f64>();
        let is_max = before
            .iter()
            .chain(&after)
            .all(|&j| tau[j].abs() < tau[i].abs() || (tau[j].abs() == tau[i].abs() && j > i));
        if total.abs() >= corner && is_max {
            splits.push(i);
        }
    }
    let wk = params.curvature_window_rel * d;
    let min_len = params.min_segment_rel * region.perimeter();
    let jump: Vec<f64> = (0..n)
        .map(|i| {
            let b: f64 = win.run(i, false, wk).iter().map(|&j| tau[j]).sum();
            let a: f64 = win.run(i, true, wk).iter().map(|&j| tau[j]).sum();
            ((a - b) / wk.max(f64::MIN_POSITIVE)).abs() * d
        })
        .collect();
    let near_corner = |i: usize| {
        splits
            .iter()
            .any(|&c| win.forward(c, i).min(win.forward(i, c)) < wk.max(min_len))
    };
    let mut breaks: Vec<usize> = (0..n)
        .filter(|&i| jump[i] >= params.curvature_change)
        .filter(|&i| {
            let around = win.run(i, false, wk / 2.0);
            let ahead = win.run(i, true, wk / 2.0);
            around
                .iter()
                .chain(&ahead)
                .all(|&j| jump[j] < jump[i] || (jump[j] == jump[i] && j > i))
        })
        .filter(|&i| !near_corner(i))
        .collect();
    breaks.sort_by(|&a, &b| jump[b].total_cmp(&jump[a]));
    for b in breaks {
        if splits
            .iter()
            .all(|&s| win.forward(s, b).min(win.forward(b, s)) >= min_len)
        {
            splits.push(b);
        }
    }
    splits.sort_unstable();
    if splits.is_empty() {
        splits.push(0);
    }
    let m = splits.len();
    let segments = (0..m)
        .map(|k| {
            let start = splits[k];
            let end = if m == 1 {
                start + n
            } else {
                splits[(k + 1) % m]
            };
            let edges = (end + n - start - 1) % n + 1;
            Segment {
                vertices: (0..=edges).map(|e| region.outer[(start + e) % n]).collect(),
                start,
                edges,
            }
        })
        .collect();
    Segmentation {
        segments,
        reversed_input: false,
    }
}
