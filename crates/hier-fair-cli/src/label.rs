//! `hier-fair label MESH.obj [--segments SEG.json] -o LABELS.json [--svg PIC.svg] [--fit SURFACE.json]`
//! (cli-contract.md): boundary labeling of a trimmed mesh region (trim-label, \[VV18\]) and,
//! optionally, the labeled bicubic fit.

use std::path::Path;

use anyhow::{Result, anyhow};
use trim_label::{
    LabelParams, LabeledFitParams, fit_labeled, label_region, parse_segments_json, write_svg,
};

use crate::files::{read_text, refuse_overwrite, write_atomic};
use crate::mesh::read_obj;

/// Output files of `label`.
#[derive(Debug, Clone, Copy)]
pub struct LabelOutputs<'a> {
    /// the labels JSON
    pub labels: &'a Path,
    /// the SVG drawing
    pub svg: Option<&'a Path>,
    /// the fitted surface
    pub fit: Option<&'a Path>,
}

/// Runs the subcommand; returns the readable summary (configuration, labels, decisions, fit).
pub fn run(input: &Path, segments: Option<&Path>, out: LabelOutputs<'_>) -> Result<String> {
    let inputs: Vec<&Path> = [Some(input), segments].into_iter().flatten().collect();
    for o in [Some(out.labels), out.svg, out.fit].into_iter().flatten() {
        refuse_overwrite(o, &inputs)?;
    }
    let mesh = read_obj(input)?;
    let segs = match segments {
        Some(path) => Some(
            parse_segments_json(&read_text(path)?)
                .map_err(|e| anyhow!("{}: {e}", path.display()))?,
        ),
        None => None,
    };
    let start = std::time::Instant::now();
    let labeling = label_region(&mesh, segs.as_deref(), &LabelParams::default())
        .map_err(|e| anyhow!("{}: {e}", input.display()))?;
    let seconds = start.elapsed().as_secs_f64();
    write_atomic(out.labels, (labeling.to_json() + "\n").as_bytes())?;
    let mut text = format!(
        "{}: {} segments, configuration {} labels / {} corners (labeled in {:.3} s)\n",
        input.display(),
        labeling.segments.len(),
        labeling.labels,
        labeling.corner_count,
        seconds
    );
    for (label, segs) in &labeling.chains {
        text.push_str(&format!("  {label:?}: segments {segs:?}\n"));
    }
    for line in &labeling.log {
        text.push_str(&format!("  · {line}\n"));
    }
    if let Some(svg) = out.svg {
        let drawing = write_svg(&mesh, &labeling).map_err(|e| anyhow!("{e}"))?;
        write_atomic(svg, drawing.as_bytes())?;
    }
    if let Some(fit) = out.fit {
        let (surface, r) = fit_labeled(&mesh, &labeling, &LabeledFitParams::default())
            .map_err(|e| anyhow!("fitting {}: {e}", input.display()))?;
        write_atomic(fit, nurbs_core::io::surface_to_json(&surface).as_bytes())?;
        text.push_str(&format!(
            "fitted {}×{} bicubic: distance to the mesh RMS {:.4e} ({:.3} % of the size {:.4e}), max {:.4e}\n",
            r.control_u,
            r.control_v,
            r.rms_distance,
            100.0 * r.rms_distance / r.size,
            r.size,
            r.max_distance
        ));
    }
    Ok(text)
}
