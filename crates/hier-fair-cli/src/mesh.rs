//! `hier-fair fair-mesh MESH.obj -o OUT.obj [--fixed-rings K] [--fixed IDX.json]`
//! (cli-contract.md): discrete thin-plate fairing of a triangle mesh region, and OBJ reading
//! (tobj; polygons are split into triangles, vertex order kept so that indices stay valid).

use std::path::Path;

use anyhow::{Context, Result, anyhow, bail};
use nside_discrete::{DiscreteFairingParams, fair_mesh, fair_mesh_within};
use nurbs_core::TriMesh;

use crate::files::{read_text, refuse_overwrite, write_atomic};

/// Reads an OBJ file as one triangle mesh (vertex order kept, polygons split into fans).
///
/// # Deviation from the design card
/// tobj renumbers vertices in the order faces use them, which would break the vertex indices
/// that `--fixed` and `label` refer to, so the small index-preserving reader of nurbs-core
/// (`TriMesh::from_obj_str`) is used instead.
pub fn read_obj(path: &Path) -> Result<TriMesh> {
    let mesh =
        TriMesh::from_obj_str(&read_text(path)?).map_err(|e| anyhow!("{}: {e}", path.display()))?;
    if mesh.faces.is_empty() {
        bail!("{}: the OBJ holds no faces", path.display());
    }
    Ok(mesh)
}

/// Runs the subcommand; returns a one-line summary.
pub fn run(
    input: &Path,
    output: &Path,
    fixed_rings: usize,
    fixed: Option<&Path>,
    tolerance: Option<f64>,
) -> Result<String> {
    refuse_overwrite(output, &[input])?;
    let mesh = read_obj(input)?;
    let extra: Vec<usize> = match fixed {
        None => Vec::new(),
        Some(path) => serde_json::from_str(&read_text(path)?).with_context(|| {
            format!("{}: expected a JSON list of vertex indices", path.display())
        })?,
    };
    let params = DiscreteFairingParams {
        fixed_rings,
        ..DiscreteFairingParams::default()
    };
    let (faired, report, weight) = match tolerance {
        None => {
            let (m, r) = fair_mesh(&mesh, &extra, &params)
                .map_err(|e| anyhow!("{}: {e}", input.display()))?;
            (m, r, None)
        }
        Some(t) => {
            let (m, r, w) = fair_mesh_within(&mesh, &extra, &params, t)
                .map_err(|e| anyhow!("{}: {e}", input.display()))?;
            (m, r, Some((t, w)))
        }
    };
    let within = weight.map_or(String::new(), |(t, w)| {
        format!(" (tolerance {t:e}: data weight {w:.3e})")
    });
    let mut bytes = Vec::new();
    faired.write_obj(&mut bytes)?;
    write_atomic(output, &bytes)?;
    Ok(format!(
        "faired {} of {} vertices (boundary + {} rings fixed): umbrella energy {:.6e} → {:.6e}, largest move {:.6e}{within}, {:.1} ms; wrote {}",
        report.free_vertices,
        report.vertices,
        fixed_rings,
        report.energy_before,
        report.energy_after,
        report.max_move,
        report.seconds * 1e3,
        output.display()
    ))
}
