//! Sides, frames and control masks (\[SV\] §3.1).
//!
//! The four boundaries of a surface are its sides: `U0` is u = u_min (control row i = 0), `U1`
//! u = u_max (i = n_u − 1), `V0` v = v_min (column j = 0), `V1` v = v_max (j = n_v − 1). The
//! positional frame of a side is its outermost row, the tangential frame the next row inward,
//! the curvature frame the one after: for a clamped side they alone fix the boundary curve, the
//! cross-boundary first derivative and the second derivative along it. A [`ControlMask`] says
//! which control points a fairing method may move.

use crate::error::{Error, Result};
use crate::ops::Direction;
use crate::surface::BSplineSurface;

/// A boundary of a surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Side {
    /// u = u_min, row i = 0
    U0,
    /// u = u_max, row i = n_u − 1
    U1,
    /// v = v_min, column j = 0
    V0,
    /// v = v_max, column j = n_v − 1
    V1,
}

impl Side {
    /// All four sides.
    pub const ALL: [Side; 4] = [Side::U0, Side::U1, Side::V0, Side::V1];

    /// The place of this side in [`Side::ALL`] and in a [`PerSide`]: `U0` 0, `U1` 1, `V0` 2,
    /// `V1` 3.
    pub const fn index(self) -> usize {
        match self {
            Side::U0 => 0,
            Side::U1 => 1,
            Side::V0 => 2,
            Side::V1 => 3,
        }
    }

    /// The model-format name: "u0", "u1", "v0", "v1".
    pub fn name(self) -> &'static str {
        match self {
            Side::U0 => "u0",
            Side::U1 => "u1",
            Side::V0 => "v0",
            Side::V1 => "v1",
        }
    }

    /// Parses a model-format name.
    pub fn parse(name: &str) -> Option<Side> {
        Side::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The cross-boundary direction: U for `U0`/`U1`, V for `V0`/`V1`.
    pub fn cross_direction(self) -> Direction {
        match self {
            Side::U0 | Side::U1 => Direction::U,
            Side::V0 | Side::V1 => Direction::V,
        }
    }

    /// The direction along the side.
    pub fn along_direction(self) -> Direction {
        match self.cross_direction() {
            Direction::U => Direction::V,
            Direction::V => Direction::U,
        }
    }

    /// The sides at the start and at the end of this side's along direction (for `V0`: `U0`
    /// and `U1`): the neighbours it shares its two corners with.
    pub fn neighbours(self) -> (Side, Side) {
        match self.along_direction() {
            Direction::U => (Side::U0, Side::U1),
            Direction::V => (Side::V0, Side::V1),
        }
    }

    /// The side across the surface from this one (`U0` ↔ `U1`, `V0` ↔ `V1`).
    pub fn opposite(self) -> Side {
        match self {
            Side::U0 => Side::U1,
            Side::U1 => Side::U0,
            Side::V0 => Side::V1,
            Side::V1 => Side::V0,
        }
    }

    /// True for the sides at the start of their cross direction (`U0`, `V0`).
    pub fn is_start(self) -> bool {
        matches!(self, Side::U0 | Side::V0)
    }

    /// Domain of the parameter running along the side.
    pub fn along_domain(self, surface: &BSplineSurface) -> (f64, f64) {
        match self.along_direction() {
            Direction::U => surface.domain_u(),
            Direction::V => surface.domain_v(),
        }
    }

    /// Value of the cross parameter on the side (e.g. u_min for `U0`).
    pub fn boundary_param(self, surface: &BSplineSurface) -> f64 {
        let (a, b) = match self.cross_direction() {
            Direction::U => surface.domain_u(),
            Direction::V => surface.domain_v(),
        };
        if self.is_start() { a } else { b }
    }

    /// Surface parameters (u, v) of the side point with along-parameter `t`.
    pub fn params(self, surface: &BSplineSurface, t: f64) -> (f64, f64) {
        let c = self.boundary_param(surface);
        match self.cross_direction() {
            Direction::U => (c, t),
            Direction::V => (t, c),
        }
    }

    /// Control indices (i, j) of row `k` counted inward from the side (k = 0 positional,
    /// 1 tangential, 2 curvature), in increasing along-index order.
    pub fn row(self, k: usize, nu: usize, nv: usize) -> Vec<(usize, usize)> {
        match self {
            Side::U0 => (0..nv).map(|j| (k, j)).collect(),
            Side::U1 => (0..nv).map(|j| (nu - 1 - k, j)).collect(),
            Side::V0 => (0..nu).map(|i| (i, k)).collect(),
            Side::V1 => (0..nu).map(|i| (i, nv - 1 - k)).collect(),
        }
    }
}

impl std::fmt::Display for Side {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Geometric continuity order of a join.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Continuity {
    /// positional
    G0,
    /// tangent plane
    G1,
    /// curvature
    G2,
}

impl Continuity {
    /// The frame that must stay fixed to keep this continuity.
    pub fn frame(self) -> Frame {
        match self {
            Continuity::G0 => Frame::Positional,
            Continuity::G1 => Frame::Tangential,
            Continuity::G2 => Frame::Curvature,
        }
    }
}

/// The control rows of a side that fix its boundary data (\[SV\] §3.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Frame {
    /// row 0: the boundary curve
    Positional,
    /// rows 0–1: plus the cross-boundary tangent
    Tangential,
    /// rows 0–2: plus the cross-boundary second derivative
    Curvature,
}

impl Frame {
    /// Number of control rows the frame fixes, counted from the side.
    pub fn rows(self) -> usize {
        match self {
            Frame::Positional => 1,
            Frame::Tangential => 2,
            Frame::Curvature => 3,
        }
    }
}

/// Which control points may move (`true` = free).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ControlMask {
    nu: usize,
    nv: usize,
    free: Vec<bool>,
}

impl ControlMask {
    /// Every point free.
    pub fn all_free(nu: usize, nv: usize) -> Self {
        Self {
            nu,
            nv,
            free: vec![true; nu * nv],
        }
    }
    /// Every point fixed.
    pub fn all_fixed(nu: usize, nv: usize) -> Self {
        Self {
            nu,
            nv,
            free: vec![false; nu * nv],
        }
    }
    /// A mask of the shape of `surface`, every point free.
    pub fn for_surface(surface: &BSplineSurface) -> Self {
        Self::all_free(surface.num_u(), surface.num_v())
    }
    /// A mask that fixes `frame` on all four sides.
    pub fn with_boundary_frame(surface: &BSplineSurface, frame: Frame) -> Self {
        let mut m = Self::for_surface(surface);
        for side in Side::ALL {
            m.fix_frame(side, frame);
        }
        m
    }
    /// Number of control points in u.
    pub fn num_u(&self) -> usize {
        self.nu
    }
    /// Number of control points in v.
    pub fn num_v(&self) -> usize {
        self.nv
    }
    /// Fixes the rows of `frame` on `side`.
    pub fn fix_frame(&mut self, side: Side, frame: Frame) {
        for k in 0..frame.rows().min(self.rows_across(side)) {
            for (i, j) in side.row(k, self.nu, self.nv) {
                self.free[i * self.nv + j] = false;
            }
        }
    }
    fn rows_across(&self, side: Side) -> usize {
        match side.cross_direction() {
            Direction::U => self.nu,
            Direction::V => self.nv,
        }
    }
    /// Whether (i, j) may move.
    #[inline]
    pub fn is_free(&self, i: usize, j: usize) -> bool {
        self.free[i * self.nv + j]
    }
    /// Sets whether (i, j) may move.
    pub fn set_free(&mut self, i: usize, j: usize, free: bool) {
        self.free[i * self.nv + j] = free;
    }
    /// The flat free flags (index i·n_v + j).
    pub fn as_slice(&self) -> &[bool] {
        &self.free
    }
    /// Number of free points.
    pub fn free_count(&self) -> usize {
        self.free.iter().filter(|&&f| f).count()
    }
    /// Free points (i, j) in storage order.
    pub fn free_indices(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        let nv = self.nv;
        self.free
            .iter()
            .enumerate()
            .filter(|(_, f)| **f)
            .map(move |(k, _)| (k / nv, k % nv))
    }
    /// Checks that the mask has the shape of `surface`.
    pub fn check_shape(&self, surface: &BSplineSurface) -> Result<()> {
        if (self.nu, self.nv) != (surface.num_u(), surface.num_v()) {
            return Err(Error::ControlNetShape {
                detail: format!(
                    "mask is {}×{} but the surface has {}×{} control points",
                    self.nu,
                    self.nv,
                    surface.num_u(),
                    surface.num_v()
                ),
            });
        }
        Ok(())
    }
}

/// One value per side of a surface, indexed by [`Side`] (`per_side[Side::V0]`): what a surface
/// keeps, is linked or owes at each of its four sides, without a side's place in an array
/// spelled out where it is used.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct PerSide<T>(pub [T; 4]);

impl<T> PerSide<T> {
    /// The value of each side from `f`.
    pub fn from_fn(f: impl FnMut(Side) -> T) -> Self {
        PerSide(Side::ALL.map(f))
    }

    /// The sides with their values, in the order of [`Side::ALL`].
    pub fn iter(&self) -> impl Iterator<Item = (Side, &T)> {
        Side::ALL.into_iter().zip(self.0.iter())
    }

    /// Each value mapped by `f`.
    pub fn map<U>(self, f: impl FnMut(T) -> U) -> PerSide<U> {
        PerSide(self.0.map(f))
    }
}

impl<T> std::ops::Index<Side> for PerSide<T> {
    type Output = T;
    fn index(&self, side: Side) -> &T {
        &self.0[side.index()]
    }
}

impl<T> std::ops::IndexMut<Side> for PerSide<T> {
    fn index_mut(&mut self, side: Side) -> &mut T {
        &mut self.0[side.index()]
    }
}

impl<'a, T> IntoIterator for &'a PerSide<T> {
    type Item = &'a T;
    type IntoIter = std::slice::Iter<'a, T>;
    /// The values in the order of [`Side::ALL`] (as an array's).
    fn into_iter(self) -> Self::IntoIter {
        self.0.iter()
    }
}

impl<T> From<[T; 4]> for PerSide<T> {
    fn from(values: [T; 4]) -> Self {
        PerSide(values)
    }
}

#[cfg(test)]
mod tests {
    use super::{PerSide, Side};

    /// A side's index is its place in `Side::ALL`, and a `PerSide` reads and writes by side.
    #[test]
    fn per_side_values_are_found_by_side() {
        for (k, side) in Side::ALL.into_iter().enumerate() {
            assert_eq!(side.index(), k, "{side:?}");
        }
        let mut p = PerSide::from_fn(|s| s.name());
        assert_eq!(p[Side::V0], "v0");
        assert_eq!(p[Side::U1], "u1");
        p[Side::V1] = "top";
        assert_eq!(p.0, ["u0", "u1", "v0", "top"]);
        let lens = p.map(str::len);
        assert_eq!(lens, PerSide::from([2, 2, 2, 3]));
        let named: Vec<(Side, usize)> = lens.iter().map(|(s, &n)| (s, n)).collect();
        assert_eq!(named[3], (Side::V1, 3));
        assert_eq!(PerSide::<bool>::default().0, [false; 4]);
        let some = PerSide::from([Some(1), None, Some(3), None]);
        assert_eq!((&some).into_iter().flatten().sum::<i32>(), 4);
    }
}
