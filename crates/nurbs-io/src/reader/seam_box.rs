//! A face's parameter box on a surface closed in a direction (a torus, a cylinder closed in
//! its angle): the box of its boundary moved by whole periods into the surface's domain, and
//! where it then runs across the seam, the surface's piece after the seam joined to its piece
//! before it ([`nurbs_core::BSplineSurface::joined`]), so that the face has an ordinary box
//! (\[IGES\] §4.34: a trimmed surface's parameter-space boundary may name any period of a
//! closed surface's parameters).

use nurbs_core::{BSplineSurface, Direction};

use super::BOX_RELATIVE;

/// A face's range in one direction of its surface.
#[derive(Debug, Clone, Copy)]
pub(super) enum SeamRange {
    /// within the domain (clamped to it)
    Inside(f64, f64),
    /// across the seam of a closed direction: from `lo` in the domain on past its end to
    /// `hi` (the end plus the part before the seam)
    Across(f64, f64),
}

impl SeamRange {
    /// Whether the range holds no parameter of the domain (a boundary beside the surface).
    pub(super) fn is_empty(self) -> bool {
        match self {
            SeamRange::Inside(a, b) => !(b > a),
            SeamRange::Across(..) => false,
        }
    }

    /// The range on `carrier`'s domain `d` in its direction: an inside range as it is, one
    /// across the seam as the joined surface's domain where the join was made (its domain then
    /// ends at `hi`), else the whole domain.
    pub(super) fn on(self, d: (f64, f64)) -> (f64, f64) {
        match self {
            SeamRange::Inside(a, b) => (a, b),
            SeamRange::Across(a, hi) if (d.1 - hi).abs() <= BOX_RELATIVE * (hi - a) => (a, hi),
            SeamRange::Across(..) => d,
        }
    }
}

/// The range `(lo, hi)` of a face's boundary in a direction with domain `d`: clamped to the
/// domain, or in a closed direction moved by whole periods to start inside it — and where it
/// then runs past the domain's end, across the seam (the whole domain where it spans a full
/// period: a face that winds round).
pub(super) fn seam_range((lo, hi): (f64, f64), d: (f64, f64), closed: bool) -> SeamRange {
    let period = d.1 - d.0;
    if !closed || (lo >= d.0 && hi <= d.1) || !(period > 0.0) {
        return SeamRange::Inside(lo.max(d.0), hi.min(d.1));
    }
    let snap = BOX_RELATIVE * period;
    let k = ((lo - d.0 + snap) / period).floor();
    let (lo, hi) = (lo - k * period, hi - k * period);
    if hi <= d.1 + snap {
        SeamRange::Inside(lo.max(d.0), hi.min(d.1))
    } else if hi - lo >= period - snap {
        SeamRange::Inside(d.0, d.1)
    } else {
        SeamRange::Across(lo, hi)
    }
}

/// `surface` over the face's ranges `ru`, `rv` ([`seam_range`]), or `None` where that is the
/// whole surface. A range across the seam of a closed direction takes the piece after the seam
/// joined to the piece before it ([`across_seam`]), so the face has an ordinary box; where the
/// two pieces do not join (weights along the seam that differ), the whole closed direction
/// stays, and the face is its trim on it.
pub(super) fn cut_to_box(
    surface: &BSplineSurface,
    ru: SeamRange,
    rv: SeamRange,
) -> nurbs_core::Result<Option<BSplineSurface>> {
    let mut carrier = surface.clone();
    for (dir, range) in [(Direction::U, ru), (Direction::V, rv)] {
        if let SeamRange::Across(lo, hi) = range
            && let Ok(joined) = across_seam(&carrier, dir, lo, hi)
        {
            carrier = joined;
        }
    }
    let (cu, cv) = (carrier.domain_u(), carrier.domain_v());
    let (u0, u1) = ru.on(cu);
    let (v0, v1) = rv.on(cv);
    let tiny = |a: f64, b: f64, d: (f64, f64)| (a - b).abs() <= BOX_RELATIVE * (d.1 - d.0);
    if tiny(u0, cu.0, cu) && tiny(u1, cu.1, cu) && tiny(v0, cv.0, cv) && tiny(v1, cv.1, cv) {
        return Ok((carrier != *surface).then_some(carrier));
    }
    carrier.extract((u0, u1), (v0, v1)).map(Some)
}

/// `s` (closed in `dir`) over `[lo, hi]` with `lo` inside its domain and `hi` past its end:
/// the piece from `lo` to the seam joined to the piece from the domain's start to `hi` less the
/// period, shifted by the period ([`BSplineSurface::joined`]).
fn across_seam(
    s: &BSplineSurface,
    dir: Direction,
    lo: f64,
    hi: f64,
) -> nurbs_core::Result<BSplineSurface> {
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let (a, b) = match dir {
        Direction::U => (u0, u1),
        Direction::V => (v0, v1),
    };
    let period = b - a;
    let piece = |from: f64, to: f64| match dir {
        Direction::U => s.extract((from, to), (v0, v1)),
        Direction::V => s.extract((u0, u1), (from, to)),
    };
    let before = piece(lo, b)?;
    let after = piece(a, hi - period)?.shifted(dir, period)?;
    before.joined(dir, &after)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A boundary's range on a closed direction of period 2π: inside as it is; named by
    /// another period, moved into the domain; past the seam, across it; a whole period, the
    /// domain; on an open direction, clamped.
    #[test]
    fn a_range_on_a_closed_direction_is_moved_by_periods_or_runs_across_the_seam() {
        use std::f64::consts::{PI, TAU};
        let d = (0.0, TAU);
        let near = |r: SeamRange, a: f64, b: f64| match r {
            SeamRange::Inside(x, y) => (x - a).abs() < 1e-12 && (y - b).abs() < 1e-12,
            SeamRange::Across(..) => false,
        };
        assert!(near(seam_range((1.0, 2.0), d, true), 1.0, 2.0));
        assert!(near(seam_range((1.0 + TAU, 2.0 + TAU), d, true), 1.0, 2.0));
        assert!(near(seam_range((-PI, -1.0), d, true), PI, TAU - 1.0));
        match seam_range((-PI / 2.0, PI / 2.0), d, true) {
            SeamRange::Across(lo, hi) => {
                assert!((lo - 1.5 * PI).abs() < 1e-12 && (hi - 2.5 * PI).abs() < 1e-12);
            }
            r => panic!("{r:?}"),
        }
        assert!(near(seam_range((-1.0, TAU - 1.0), d, true), 0.0, TAU));
        assert!(near(
            seam_range((-PI / 2.0, PI / 2.0), d, false),
            0.0,
            PI / 2.0
        ));
        assert!(seam_range((7.0, 8.0), (0.0, 1.0), false).is_empty());
        // the joined carrier's domain ends where the range does: the range is all of it
        let across = SeamRange::Across(1.5 * PI, 2.5 * PI);
        assert_eq!(across.on((1.5 * PI, 2.5 * PI)), (1.5 * PI, 2.5 * PI));
        assert_eq!(across.on(d), d, "not joined: the whole closed direction");
    }
}
