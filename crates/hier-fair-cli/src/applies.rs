//! Options of `fair` that the model does not give them anything to act on are said in one
//! `warning:` line each, never silently ignored (cli-contract.md, "Files"): the link options on a
//! model without links, `--tolerance` where every surface's tolerance comes from elsewhere
//! (its own `deviation`, its role's), `--tolerance-role ROLE` where no surface takes it.

use hier_fair::{Model, ModelSurface, Role};

use crate::options::ModelOptions;

/// The warnings (without `warning: `) for the options of `options` that apply to nothing in
/// `model`, read from `source` (the input's name); empty where every given option applies.
pub fn unused_options(model: &Model, options: &ModelOptions, source: &str) -> Vec<String> {
    let mut out = Vec::new();
    if model.links.is_empty() {
        let mut given = Vec::new();
        if let Some(t) = options.target {
            given.push(format!("--target {t:?}"));
        }
        if options.no_verify {
            given.push("--no-verify".to_string());
        }
        if options.keep_faired {
            given.push("--keep-faired".to_string());
        }
        if !given.is_empty() {
            out.push(format!(
                "{} {} nothing to apply to: {source} has no links (`build` finds a model's links from its geometry)",
                given.join(", "),
                if given.len() == 1 { "has" } else { "have" }
            ));
        }
    }
    // a surface's deviation: its own, else --tolerance-role, else the model's per-role value,
    // else --tolerance (Model::deviation_of)
    for role in [Role::Primary, Role::Connecting, Role::Corner] {
        let takes = |s: &ModelSurface| s.role == role && s.deviation.is_none();
        if options.role_tolerance[role.rank()].is_some() && !model.surfaces.iter().any(takes) {
            out.push(format!(
                "--tolerance-role {0}=… applies to no surface: {source} has no {0} surface without its own deviation",
                role.name()
            ));
        }
    }
    let takes_global = |s: &ModelSurface| {
        let r = s.role.rank();
        s.deviation.is_none()
            && options.role_tolerance[r].is_none()
            && model.tolerances.role_deviation[r].is_none()
    };
    if options.tolerance.is_some() && !model.surfaces.iter().any(takes_global) {
        out.push(format!(
            "--tolerance applies to no surface of {source}: each has its own deviation or its role's (`deviation` in the model, --tolerance-role)"
        ));
    }
    out
}
