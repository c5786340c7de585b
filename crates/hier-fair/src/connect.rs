//! The `connect` driver: continuity setting only (no fairing), slave by slave in hierarchy order
//! ([SV] §3.2 steps 3 and 5, §1.1 order).
//!
//! Surfaces are visited in [`Model::hierarchy_order`]; every surface that is the slave of some
//! links is connected to its masters — which are already final, as they come earlier — by
//! [`g_continuity::connect_slave`] (C0 → G1 → G2, twists, knot insertion). Masters never move.
//! Each link's target is its own continuity, capped by [`ConnectOptions::target`].

use std::time::Instant;

use g_continuity::{ConnectParams, LinkMeasure, SideLink, Tolerances, connect_slave};
use nurbs_core::Continuity;

use crate::check::check_model;
use crate::error::{Error, Result};
use crate::model::{Model, Role};

/// Settings of [`connect`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ConnectOptions {
    /// The highest continuity set (`None`: each link's own target).
    pub target: Option<Continuity>,
    /// Continuity setting; its tolerances are replaced by the model's.
    pub params: ConnectParams,
}

/// What happened to one slave surface.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceConnect {
    /// the surface's index
    pub surface: usize,
    /// its name
    pub name: String,
    /// its role
    pub role: Role,
    /// thin-plate energy before and after
    pub energy_before: f64,
    /// thin-plate energy after
    pub energy_after: f64,
    /// largest sampled distance of the result from the input surface
    pub max_deviation: f64,
    /// largest control point movement (against the input refined the same way)
    pub max_control_movement: f64,
    /// knots inserted
    pub knots_inserted: usize,
    /// rounds of knot insertion
    pub refinements: usize,
    /// twists averaged
    pub twists_averaged: usize,
    /// seconds spent
    pub seconds: f64,
}

/// Before/after of one link.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkConnect {
    /// index into `model.links`
    pub link: usize,
    /// "slave.side -> master"
    pub label: String,
    /// the continuity set (the link's, capped by the option)
    pub target: Continuity,
    /// measured on the input model
    pub before: LinkMeasure,
    /// measured on the result
    pub after: LinkMeasure,
}

/// What [`connect`] did.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ModelConnectReport {
    /// total seconds
    pub seconds_total: f64,
    /// per slave surface, in processing order
    pub surfaces: Vec<SurfaceConnect>,
    /// per link, in model order
    pub links: Vec<LinkConnect>,
}

/// Grid size of the sampled deviation (the same as the fairing reports).
pub const DEVIATION_GRID: usize = 41;

/// Sets continuity on every slave of `model` in hierarchy order; returns the new model and the
/// report. Links that do not touch their masters are errors (see [`check_model`]).
pub fn connect(model: &Model, options: &ConnectOptions) -> Result<(Model, ModelConnectReport)> {
    let start = Instant::now();
    let mut params = options.params;
    let t = &model.tolerances;
    params.tolerances = Tolerances {
        g0: t.g0,
        g1_deg: t.g1_deg,
        g2_rel: t.g2_rel,
    };
    let before = check_model(model, &params.measure)?;
    let target_of = |c: Continuity| options.target.map_or(c, |t| c.min(t));
    let mut out = model.clone();
    let mut surfaces = Vec::new();
    for k in model.hierarchy_order()? {
        let link_ids = model.links_of_slave(k);
        if link_ids.is_empty() {
            continue;
        }
        let t0 = Instant::now();
        let original = &model.surfaces[k].surface;
        let links: Vec<SideLink> = link_ids
            .iter()
            .map(|&i| {
                let l = &model.links[i];
                SideLink {
                    side: l.side,
                    master: &out.surfaces[l.master].surface,
                    target: target_of(l.continuity),
                }
            })
            .collect();
        let (result, report) =
            connect_slave(original, &links, &params).map_err(|source| Error::Continuity {
                place: format!("surface {}", model.surfaces[k].name),
                source,
            })?;
        drop(links);
        surfaces.push(SurfaceConnect {
            surface: k,
            name: model.surfaces[k].name.clone(),
            role: model.surfaces[k].role,
            energy_before: nurbs_core::energy::thin_plate_energy(original),
            energy_after: nurbs_core::energy::thin_plate_energy(&result),
            max_deviation: nurbs_core::energy::max_deviation(original, &result, DEVIATION_GRID),
            max_control_movement: report.max_control_movement,
            knots_inserted: report.knots_inserted,
            refinements: report.refinements,
            twists_averaged: report.twists_averaged,
            seconds: t0.elapsed().as_secs_f64(),
        });
        out.surfaces[k].surface = result;
    }
    let after = check_model(&out, &params.measure)?;
    let links = before
        .into_iter()
        .zip(after)
        .map(|(b, a)| LinkConnect {
            link: b.link,
            label: b.label,
            target: target_of(b.target),
            before: b.measure,
            after: a.measure,
        })
        .collect();
    Ok((
        out,
        ModelConnectReport {
            seconds_total: start.elapsed().as_secs_f64(),
            surfaces,
            links,
        },
    ))
}
