//! One linked side of a slave ([`SideLink`]): which side, onto which master, with what target,
//! over which part and with which vertex zones. Below the continuity steps that read it
//! ([`crate::slave`], [`crate::lead_in`], [`crate::transfer`], [`crate::joint`]).

use nurbs_core::{BSplineSurface, Continuity, Side};

use crate::error::Result;
use crate::measure::{LinkMeasure, MeasureParams};
use crate::sampling::in_zones;

/// One linked side of a slave: which side, onto which master, with what target.
#[derive(Debug, Clone, Copy)]
pub struct SideLink<'a> {
    /// the slave's side
    pub side: Side,
    /// the master surface (never modified)
    pub master: &'a BSplineSurface,
    /// the continuity to reach
    pub target: Continuity,
    /// the part of the side the link holds on, as an interval of the along-side parameter
    /// (`None`: the whole side). A trimmed face's side lies on the surface it meets only up to
    /// the trim; the row equations, measures and refinement then use samples of that part only,
    /// and the control points whose along-side support misses it do not move.
    pub range: Option<(f64, f64)>,
    /// Vertex zones: the lengths, in the along-side parameter, of the stretches at the start
    /// and at the end of the link's part within which its G2 is relaxed (`[0.0; 2]`: none). At
    /// a corner where the neighbouring side's master disagrees in curvature with this one, no
    /// surface is G2 to both at that point (\[SV\] §3.3); the G2 rows of the samples inside a
    /// zone are not set and the G2 figures the decisions take leave them out — they are
    /// reported apart as the vertex figures ([`LinkMeasure::vertex_g2_rel`]). G0 and G1 hold
    /// everywhere.
    pub g2_zones: [f64; 2],
}

impl SideLink<'_> {
    /// The along-side parameter interval the link holds on: its [`SideLink::range`] clipped to
    /// the side's domain, or the whole domain.
    pub fn domain(&self, slave: &BSplineSurface) -> (f64, f64) {
        crate::sampling::side_part(slave, self.side, self.range)
    }

    /// Measures the link on `slave` (over its range).
    pub fn measure(&self, slave: &BSplineSurface, params: &MeasureParams) -> Result<LinkMeasure> {
        crate::measure::measure_link_zoned(
            self.master,
            slave,
            self.side,
            self.range,
            self.g2_zones,
            params,
        )
    }

    /// Whether the along-side parameter `t` lies in one of the link's vertex zones
    /// ([`SideLink::g2_zones`]) on `slave`.
    pub fn in_zone(&self, slave: &BSplineSurface, t: f64) -> bool {
        let (a, b) = self.domain(slave);
        in_zones(t, (a, b), self.g2_zones)
    }
}
