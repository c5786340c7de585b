//! The surface entities as exact NURBS surfaces: 128 (rational B-spline surface), 120 (surface
//! of revolution), 122 (tabulated cylinder), 118 (ruled surface), each moved by its
//! transformation and the model scale, and 140 (offset surface, approximated within
//! [`crate::offset::OFFSET_TOLERANCE_RELATIVE`]) (\[IGES\] §4.24, §4.16, §4.19, §4.14).

use nurbs_core::{BSplineCurve, BSplineSurface, KnotVector, Point3};

use super::IgesSurface;
use super::entities::{Cursor, Reader};
use super::records::{DirEntry, entity_params};
use crate::error::IgesError;

impl Reader<'_> {
    /// The surface read from entity `e` over `param_range`, untrimmed until a 144 claims it.
    fn untrimmed(e: &DirEntry, surface: BSplineSurface, param_range: [f64; 4]) -> IgesSurface {
        IgesSurface {
            de: e.seq,
            name: Self::name(e),
            surface,
            trimmed: false,
            param_range,
            underlying: None,
            trim: Vec::new(),
            holes: Vec::new(),
        }
    }

    /// Entity 128, the rational B-spline surface (\[IGES\] §4.24), its net turned to u-major order.
    pub(super) fn surface(&self, e: &DirEntry, scale: f64) -> Result<IgesSurface, IgesError> {
        let params = entity_params(e, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e,
        };
        let k1 = c.count("K1 (upper index of the u control points)", 1)?;
        let k2 = c.count("K2 (upper index of the v control points)", 1)?;
        let m1 = c.count("M1 (u degree)", 1)?;
        let m2 = c.count("M2 (v degree)", 1)?;
        let _props = c.reals(5)?;
        let (nu, nv) = (k1 + 1, k2 + 1);
        let ku = c.reals(k1 + m1 + 2)?;
        let kv = c.reals(k2 + m2 + 2)?;
        let w = c.reals(nu * nv)?;
        let coords = c.reals(3 * nu * nv)?;
        let range = c.reals(4)?;
        let pts = self.points(e, &coords, scale)?;
        let mut points = vec![Point3::origin(); nu * nv];
        let mut weights = vec![1.0; nu * nv];
        for j in 0..nv {
            for i in 0..nu {
                points[i * nv + j] = pts[i + nu * j];
                weights[i * nv + j] = w[i + nu * j];
            }
        }
        let polynomial = weights.iter().all(|&x| x == weights[0]) && weights[0] > 0.0;
        let g = Self::geometry_err(e);
        let knots_u = KnotVector::new(m1, ku).map_err(|x| g(x.context("u knots")))?;
        let knots_v = KnotVector::new(m2, kv).map_err(|x| g(x.context("v knots")))?;
        let surface =
            BSplineSurface::new(knots_u, knots_v, points, (!polynomial).then_some(weights))
                .map_err(&g)?;
        Ok(Self::untrimmed(
            e,
            surface,
            [range[0], range[1], range[2], range[3]],
        ))
    }

    /// Entity 120, the surface of revolution (\[IGES\] §4.16): the generatrix C turned about the
    /// axis line L from the start angle SA to the terminate angle TA, right-handed about L's
    /// direction (start point to end point), as an exact rational surface
    /// ([`nurbs_core::shapes::revolve_curve`]): u along C, v around the axis.
    pub(super) fn revolution(&self, e: &DirEntry, scale: f64) -> Result<IgesSurface, IgesError> {
        let params = entity_params(e, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e,
        };
        let axis = self.entry(c.int()?, e)?;
        let generatrix = self.entry(c.int()?, e)?;
        let (sa, ta) = (c.real()?, c.real()?);
        if axis.entity_type != 110 {
            return Err(IgesError::Entity {
                de: e.seq,
                entity_type: e.entity_type,
                detail: format!(
                    "the axis is entity {}, expected a line (110)",
                    axis.entity_type
                ),
            });
        }
        // the axis and the generatrix are in the 120's definition space: the surface is built
        // there, then the 120's own transformation and the model scale apply to its net
        let line = self.any_curve(axis, 1.0)?;
        let (o, d) = (
            line.control_points()[0],
            line.control_points()[1] - line.control_points()[0],
        );
        let curve = self.any_curve(generatrix, 1.0)?;
        let g = Self::geometry_err(e);
        let local = nurbs_core::shapes::revolve_curve(&curve, o, d, sa, ta).map_err(&g)?;
        let (t0, t1) = curve.knots().domain();
        self.placed(e, local, scale, [t0, t1, sa, ta])
    }

    /// A surface built in an entity's definition space, moved into model space by the entity's
    /// own transformation and the model scale (exact: an affine map of a rational net).
    pub(super) fn placed(
        &self,
        e: &DirEntry,
        local: BSplineSurface,
        scale: f64,
        param_range: [f64; 4],
    ) -> Result<IgesSurface, IgesError> {
        let coords: Vec<f64> = local
            .control_points()
            .iter()
            .flat_map(|p| [p.x, p.y, p.z])
            .collect();
        let points = self.points(e, &coords, scale)?;
        let surface = BSplineSurface::new(
            local.knots_u().clone(),
            local.knots_v().clone(),
            points,
            local.weights().map(<[f64]>::to_vec),
        )
        .map_err(Self::geometry_err(e))?;
        Ok(Self::untrimmed(e, surface, param_range))
    }

    /// Entity 122, the tabulated cylinder (\[IGES\] §4.19): the directrix C (110, 100 or 126)
    /// moved along the line from its start point C(t0) to the terminate point L,
    /// S(u, v) = C(u) + v (L − C(t0)), v ∈ [0, 1], exactly
    /// ([`nurbs_core::shapes::extrude_curve`]); u keeps the directrix's parameter.
    pub(super) fn tabulated(&self, e: &DirEntry, scale: f64) -> Result<IgesSurface, IgesError> {
        let params = entity_params(e, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e,
        };
        let directrix = self.entry(c.int()?, e)?;
        let l = c.reals(3)?;
        let curve = self.any_curve(directrix, 1.0)?;
        let (t0, t1) = curve.knots().domain();
        let d = Point3::new(l[0], l[1], l[2]) - curve.point(t0);
        let local = nurbs_core::shapes::extrude_curve(&curve, d, (0.0, 1.0))
            .map_err(Self::geometry_err(e))?;
        self.placed(e, local, scale, [t0, t1, 0.0, 1.0])
    }

    /// Entity 118, the ruled surface (\[IGES\] §4.14) between two curves (110, 100 or 126),
    /// S(u, v) = (1 − v) C₁(u) + v C₂(u), DIRFLG 1 joining the first end of C₁ to the last of
    /// C₂, exactly ([`nurbs_core::shapes::ruled_surface`]). Form 1 (equal relative parameter)
    /// is that surface. Form 0 rules points of equal relative arc length: it is read when the
    /// two curves' relative arc lengths agree at their relative parameters within
    /// [`RULED_ARC_LENGTH_RELATIVE`] (lines, arcs of the same sweep, one curve a scaled copy
    /// of the other), and refused otherwise rather than approximated.
    pub(super) fn ruled(&self, e: &DirEntry, scale: f64) -> Result<IgesSurface, IgesError> {
        let params = entity_params(e, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e,
        };
        let first = self.entry(c.int()?, e)?;
        let second = self.entry(c.int()?, e)?;
        let reversed = c.int()? == 1;
        let a = self.any_curve(first, 1.0)?;
        let mut b = self.any_curve(second, 1.0)?;
        if reversed {
            b = b.reversed().map_err(Self::geometry_err(e))?;
        }
        if e.form == 0 {
            let (fa, fb) = (relative_arc_lengths(&a), relative_arc_lengths(&b));
            let off = fa
                .iter()
                .zip(&fb)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            if off > RULED_ARC_LENGTH_RELATIVE {
                return Err(IgesError::Entity {
                    de: e.seq,
                    entity_type: e.entity_type,
                    detail: format!(
                        "form 0 rules points of equal arc length, and the two curves' relative arc lengths differ by up to {off:.3e} at equal parameters: not read exactly"
                    ),
                });
            }
        }
        let local = nurbs_core::shapes::ruled_surface(&a, &b).map_err(Self::geometry_err(e))?;
        self.placed(e, local, scale, [0.0, 1.0, 0.0, 1.0])
    }

    /// An offset surface (\[IGES\], entity 140): S(u, v) + d N(u, v) over the base surface's
    /// domain, N its unit normal, turned to the side of the offset indicator (NX, NY, NZ) where
    /// that is given. An offset is not a NURBS surface in general, so it is approximated: a
    /// polynomial B-spline of degree max(3, the base's) on the base's breakpoints, fitted by least
    /// squares to the exact offset and refined (every span halved) until it lies within
    /// [`crate::offset::OFFSET_TOLERANCE_RELATIVE`] of the base's size at points between the fitted ones, up to
    /// [`crate::offset::OFFSET_MAX_NET`] control points per direction; otherwise, or where the base's normal
    /// is undefined, the entity is refused with the error reached.
    pub(super) fn offset(&self, e: &DirEntry, scale: f64) -> Result<IgesSurface, IgesError> {
        let err = |detail: String| IgesError::Entity {
            de: e.seq,
            entity_type: e.entity_type,
            detail,
        };
        let params = entity_params(e, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e,
        };
        let indicator = c.reals(4)?;
        let base_de = c.int()?;
        if self.transform(e)?.is_some() {
            return Err(err(
                "an offset surface with its own transformation is not read".into(),
            ));
        }
        let base_entry = self.entry(base_de, e)?;
        let base = match base_entry.entity_type {
            128 => self.surface(base_entry, scale)?,
            120 => self.revolution(base_entry, scale)?,
            122 => self.tabulated(base_entry, scale)?,
            118 => self.ruled(base_entry, scale)?,
            other => return Err(err(format!("the offset of entity {other} is not read"))),
        }
        .surface;
        let mut d = indicator[3] / scale;
        let (du, dv) = (base.domain_u(), base.domain_v());
        let mid = base.derivatives(0.5 * (du.0 + du.1), 0.5 * (dv.0 + dv.1));
        let side = nurbs_core::Vector3::new(indicator[0], indicator[1], indicator[2]);
        if let Some(n) = mid.normal()
            && n.dot(&side) < 0.0
        {
            d = -d;
        }
        let surface =
            crate::offset::approximate_offset(&base, d).map_err(|e| err(e.to_string()))?;
        Ok(Self::untrimmed(e, surface, [du.0, du.1, dv.0, dv.1]))
    }
}

/// Largest difference of relative arc length at equal relative parameters for which a form-0
/// ruled surface (118) is read as the parametric ruling: 1e-9, a thousandth of the kernel's
/// model-size tolerance, so that the points it joins are the same to far below any tolerance.
pub const RULED_ARC_LENGTH_RELATIVE: f64 = 1e-9;

/// Samples of [`relative_arc_lengths`]: 64 spans, each integrated by a 5-point Gauss rule.
const ARC_LENGTH_SPANS: usize = 64;

/// Arc length from the start at the relative parameters k / [`ARC_LENGTH_SPANS`], divided by
/// the whole length (Gauss–Legendre on each piece, \[AS\] 25.4.29).
fn relative_arc_lengths(c: &BSplineCurve) -> Vec<f64> {
    let rule = nurbs_core::quadrature::GaussLegendre::new(5);
    let (t0, t1) = c.knots().domain();
    let at = |k: usize| t0 + (t1 - t0) * k as f64 / ARC_LENGTH_SPANS as f64;
    let mut acc = vec![0.0];
    for k in 0..ARC_LENGTH_SPANS {
        let piece: f64 = rule
            .on(at(k), at(k + 1))
            .map(|(t, w)| w * c.derivatives(t, 1).d[1].norm())
            .sum();
        acc.push(acc[k] + piece);
    }
    let total = acc[ARC_LENGTH_SPANS].max(f64::MIN_POSITIVE);
    acc.iter().map(|x| x / total).collect()
}
