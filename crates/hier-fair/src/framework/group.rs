//! The n-sided stage of a corner group (\[SV\] §3.4): the group's patches faired as one mesh and
//! refitted, used only when fairer and within the group's share of the tolerance.

use nurbs_core::energy::{max_deviation, thin_plate_energy};

use super::{FairModelReport, FairParams, Problem, ProblemKind};
use crate::model::Model;

pub(super) fn group_stage(
    model: &Model,
    out: &mut Model,
    group: &crate::model::CornerGroup,
    tolerance: f64,
    params: &FairParams,
    report: &mut FairModelReport,
) {
    let first = group
        .patches
        .first()
        .map_or_else(String::new, |&k| model.surfaces[k].name.clone());
    let (quads, nsided) = match crate::corners::fair_group(model, out, group) {
        Ok(r) => r,
        Err(message) => {
            report.problems.push(Problem {
                kind: ProblemKind::Limited,
                surface: first,
                link: None,
                message: format!("{message}; the patches are faired one by one instead"),
                amount: None,
            });
            return;
        }
    };
    let worst = group
        .patches
        .iter()
        .zip(&quads)
        .map(|(&k, q)| max_deviation(&model.surfaces[k].surface, q, params.deviation_grid))
        .fold(0.0, f64::max);
    // the mesh fairing is for fairness: a refit that raises a patch's thin-plate energy above
    // its start is not used, nor one that moves the patches beyond the group's share
    let raised = group.patches.iter().zip(&quads).find_map(|(&k, q)| {
        let (before, after) = (
            thin_plate_energy(&model.surfaces[k].surface),
            thin_plate_energy(q),
        );
        (after > before).then(|| (model.surfaces[k].name.clone(), before, after))
    });
    let refused = match raised {
        Some((name, before, after)) => Some((
            format!(
                "corner group {}: the refitted patch {name} would have thin-plate energy {after:.4} above its {before:.4}; the patches are faired one by one instead",
                group.name
            ),
            after / before,
        )),
        None if worst > params.budget.group(tolerance) => Some((
            format!(
                "corner group {}: the n-sided mesh fairing moves the patches {worst:.4} from the original, above {} × the tolerance; the patches are faired one by one instead",
                group.name, params.budget.group_share
            ),
            worst,
        )),
        None => None,
    };
    report.groups.push(GroupFair {
        name: group.name.clone(),
        applied: refused.is_none(),
        max_deviation: worst,
        mesh_vertices: nsided.mesh_vertices,
        refit_max_error: nsided.refit.max_error,
        internal_angle_deg: nsided.refit.max_internal_angle_deg,
    });
    match refused {
        None => {
            for (&k, q) in group.patches.iter().zip(quads) {
                out.surfaces[k].surface = q;
            }
        }
        Some((message, amount)) => report.problems.push(Problem {
            kind: ProblemKind::Limited,
            surface: first,
            link: None,
            message,
            amount: Some(amount),
        }),
    }
}

/// What the n-sided stage did to one corner group.
#[derive(Debug, Clone, PartialEq)]
pub struct GroupFair {
    /// the group's name
    pub name: String,
    /// whether the refitted patches were used
    pub applied: bool,
    /// largest sampled deviation of a refitted patch from its original
    pub max_deviation: f64,
    /// vertices of the faired mesh (wings included)
    pub mesh_vertices: usize,
    /// largest refit error against the faired mesh
    pub refit_max_error: f64,
    /// largest normal angle between adjacent patches along the internal curves (degrees)
    pub internal_angle_deg: f64,
}
