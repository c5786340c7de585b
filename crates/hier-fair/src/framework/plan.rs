//! The plan of a run: the waves of the hierarchy, masters before slaves ([SV] §1.1).

use super::*;

/// The waves of the hierarchy: wave 0 holds the surfaces without links, a slave is one wave
/// after its latest master; within a wave, file order.
pub fn waves(model: &Model) -> Result<Vec<Vec<usize>>> {
    let order = model.hierarchy_order()?;
    let mut wave_of = vec![0usize; model.surfaces.len()];
    for &k in &order {
        let own = model
            .links_of_slave(k)
            .iter()
            .map(|&l| wave_of[model.links[l].master] + 1)
            .max()
            .unwrap_or(0);
        wave_of[k] = own.max(group_start(model, k, &wave_of));
    }
    let count = wave_of.iter().copied().max().map_or(0, |w| w + 1);
    let mut waves = vec![Vec::new(); count];
    for k in 0..model.surfaces.len() {
        waves[wave_of[k]].push(k);
    }
    Ok(waves)
}

/// The earliest wave of the corner group of surface `k` (0 when it is in none): one after the
/// latest master outside the group of any of its patches, so the whole group can be faired as
/// one mesh before its first patch runs.
fn group_start(model: &Model, k: usize, wave_of: &[usize]) -> usize {
    model
        .corners
        .iter()
        .filter(|g| g.patches.contains(&k))
        .flat_map(|g| {
            g.patches.iter().flat_map(move |&p| {
                model
                    .links_of_slave(p)
                    .into_iter()
                    .map(|l| model.links[l].master)
                    .filter(move |m| !g.patches.contains(m))
            })
        })
        .map(|m| wave_of[m] + 1)
        .max()
        .unwrap_or(0)
}
