//! Fairness of the kernel models' results, measured as a surfacer reads it (hier-fair's
//! `fairness` module): peak curvature against the input's, the comb's extrema across a fillet,
//! and the choice of the fairer of the faired result and the continuity setting alone.

mod common;
use common::{model, models};

use hier_fair::fairness::{PEAK_FACTOR, model_fairness, surface_fairness};
use hier_fair::{FairModelReport, FairParams, Model, RoleMethods, fair_model};

/// Per-role deviation (\[SV\] §1.1: primaries 0.05 mm, connecting and corner surfaces 0.5 mm).
fn per_role(name: &str) -> (Model, Model, FairModelReport) {
    per_role_with(name, FairParams::default())
}

/// [`per_role`] from the settings `base` (their per-role tolerances replaced).
fn per_role_with(name: &str, base: FairParams) -> (Model, Model, FairModelReport) {
    let m = model(name).unwrap();
    let params = FairParams {
        role_tolerance: [Some(0.05), Some(0.5), Some(0.5)],
        ..base
    };
    let (out, report) = fair_model(&m, &RoleMethods::default(), None, &params).unwrap();
    (m, out, report)
}

/// `m` faired by default (0.05 mm everywhere): its report.
fn by_default(m: &Model) -> FairModelReport {
    fair_model(m, &RoleMethods::default(), None, &FairParams::default())
        .unwrap()
        .1
}

fn surface<'a>(report: &'a FairModelReport, name: &str) -> &'a hier_fair::SurfaceFair {
    report
        .surfaces
        .iter()
        .find(|s| s.name == name)
        .unwrap_or_else(|| panic!("no surface {name}"))
}

/// The size of the normal curvature across `surface` on the iso-line at the fraction `at` of
/// its other direction, 201 samples along `along` ([`nurbs_core::fairness::cross_profile`]),
/// and its largest value.
fn abs_profile(
    surface: &nurbs_core::BSplineSurface,
    along: nurbs_core::Direction,
    at: f64,
) -> (Vec<f64>, f64) {
    let p: Vec<f64> = nurbs_core::fairness::cross_profile(surface, along, at, 201)
        .into_iter()
        .map(|k| k.unwrap().abs())
        .collect();
    let peak = p.iter().cloned().fold(0.0, f64::max);
    (p, peak)
}

/// The input's figures are closed-form: a torus fillet of tube radius r reads 1/r as its peak,
/// with no extremum across (its cross section is a circular arc).
#[test]
fn input_fillets_read_their_radius() {
    let m = model("occt_plate_boss").unwrap();
    for (name, r) in [("F02_torus", 5.0), ("F09_torus", 3.0)] {
        let k = m.surfaces.iter().position(|s| s.name == name).unwrap();
        let f = surface_fairness(&m, k, &m.surfaces[k].surface);
        assert!(
            (f.peak_curvature - 1.0 / r).abs() < 1e-9 / r,
            "{name}: {f:?}"
        );
        assert_eq!(f.cross_extrema, Some(0), "{name}: {f:?}");
    }
    // the sphere corner of box12_r5 (radius 5, one side a pole): 1/5 next to the pole too
    let m = model("occt_box12_r5").unwrap();
    let k = m
        .surfaces
        .iter()
        .position(|s| s.name == "C06_sphere")
        .unwrap();
    let f = surface_fairness(&m, k, &m.surfaces[k].surface);
    assert!((f.peak_curvature - 0.2).abs() < 1e-9, "{f:?}");
    assert!((f.max_curvature - 0.2).abs() < 1e-9, "{f:?}");
}

/// A kernel's rolling-ball fillet has a circular section (or, on a variable radius, one of
/// monotone radius): the comb across it never turns, on every connecting surface of every
/// kernel model, and its peak is its largest section curvature — finite and positive.
#[test]
fn kernel_fillets_come_in_without_a_wiggle() {
    for name in models() {
        let m = model(&name).unwrap();
        let all = model_fairness(&m);
        for (s, f) in m.surfaces.iter().zip(&all) {
            if s.role != hier_fair::Role::Connecting {
                continue;
            }
            assert_eq!(f.cross_extrema, Some(0), "{name} {}: {f:?}", s.name);
            assert!(
                f.peak_curvature > 0.0 && f.peak_curvature.is_finite(),
                "{name} {}",
                s.name
            );
        }
    }
}

/// With per-role deviation the energy fairing of the G2 stages lowered a fillet's thin-plate
/// energy while raising its peak curvature (plate_boss's torus fillet r 3: 0.333 → 0.871 /mm,
/// 2.6×; pipe_tee's freeform fillet 0.200 → 1.62, 8.1×). The framework now keeps the fairer of
/// the faired result and the continuity setting: both fillets stay within [`PEAK_FACTOR`] of
/// their input, every link still met, and the report says why fairing was dropped.
#[test]
fn fillets_keep_their_peak_curvature_with_per_role_deviation() {
    for (name, fillets) in [
        ("occt_plate_boss", &["F02_torus", "F09_torus"][..]),
        ("occt_pipe_tee", &["F02_bspline", "F05_bspline"][..]),
    ] {
        let (_, out, report) = per_role(name);
        assert!(report.links.iter().all(|l| l.met), "{name}");
        for &f in fillets {
            let s = surface(&report, f);
            let v = s.fairness_verdict();
            assert!(v.peak_ratio <= PEAK_FACTOR, "{name} {f}: {v:?}");
            assert!(
                v.energy_ratio <= hier_fair::fairness::ENERGY_FACTOR,
                "{name} {f}: {v:?}"
            );
            // the figures in the report are those of the written surface
            let k = out.surfaces.iter().position(|x| x.name == f).unwrap();
            let again = surface_fairness(&out, k, &out.surfaces[k].surface);
            assert_eq!(
                again.peak_curvature, s.fairness.1.peak_curvature,
                "{name} {f}"
            );
        }
        assert!(
            report
                .problems
                .iter()
                .any(|p| p.message.contains("it is fairer")),
            "{name}: {:?}",
            report.problems
        );
    }
}

/// The torus fillets of plate_boss (tube radii 5 and 3) per role: their sections replaced by
/// the one-hump profile ([`g_continuity::section`]) — curvature 0 at both contact lines, one
/// rise to a plateau about 1.3× the input's 1/r, one fall — every link still met and each
/// fillet fair by every criterion. Before the section, the G2 lead-in left five curvature
/// extrema across each (a bump and a dip beside each side: 0.333 → 0.379 0.430 0.357 0.315 …).
#[test]
fn torus_fillets_get_one_hump_per_role() {
    let (_, out, report) = per_role("occt_plate_boss");
    assert!(report.links.iter().all(|l| l.met));
    for (f, r) in [("F02_torus", 5.0), ("F09_torus", 3.0)] {
        let s = surface(&report, f);
        let v = s.fairness_verdict();
        assert!(v.fair(), "{f}: {v:?}");
        // the report says the section was replaced, and how wide its ramps are
        let ramp = s.stages[0].section_ramp.expect("section replaced");
        assert!(
            ramp > 0.0 && ramp <= g_continuity::MAX_RAMP,
            "{f}: ramp {ramp}"
        );
        let k = out.surfaces.iter().position(|x| x.name == f).unwrap();
        let surface = &out.surfaces[k].surface;
        for at in [0.1, 0.5, 0.9] {
            let (p, peak) = abs_profile(surface, nurbs_core::Direction::V, at);
            assert_eq!(
                nurbs_core::fairness::count_extrema(&p, 0.005 * peak),
                1,
                "{f} at {at}: {p:?}"
            );
            assert!(peak > 1.0 / r && peak < PEAK_FACTOR / r, "{f}: peak {peak}");
            // zero at both contact lines (the planes'), as G2 to a plane needs
            assert!(
                p[0] < 1e-3 / r && p[200] < 1e-3 / r,
                "{f}: ends {} {}",
                p[0],
                p[200]
            );
        }
    }
}

/// The pipe tee's two fillet halves are freeform: their section changes around the junction,
/// so the middle section carried through every column's frame deviates 0.20 mm from them at any
/// ramp, beyond the budget. Taken section by section ([`g_continuity::section`]) it comes
/// within it: per role both halves take one-hump sections, one rise and one fall across at
/// three places along, within 1.6× their input's peak (measured 1.19×; with the lead-in alone
/// five extrema at 1.35×, and before the lead-in's fairness was judged 9× peaks).
#[test]
fn freeform_fillets_get_one_hump_section_by_section() {
    let (_, out, report) = per_role("occt_pipe_tee");
    assert!(report.links.iter().all(|l| l.met));
    for f in ["F02_bspline", "F05_bspline"] {
        let s = surface(&report, f);
        let v = s.fairness_verdict();
        assert!(v.fair(), "{f}: {v:?}");
        assert!(s.max_deviation <= s.tolerance, "{f}");
        let k = out.surfaces.iter().position(|x| x.name == f).unwrap();
        let surface = &out.surfaces[k].surface;
        // the fillets run along v: their sections lie across u. Each ramp starts from its
        // pipe's curvature across (1 % of the plateau at the ends, up to 18 %, the pipe's
        // 1/25 mm, where a section crosses the pipe's circle), which bends against the fillet:
        // the section turns through 0 beside the contact line, so its curvature's size dips
        // by at most the contact value there. Extrema are counted above the larger contact
        // value and the 0.5 % at which a G2 join's curvatures differ
        for at in [0.1, 0.5, 0.9] {
            let (p, peak) = abs_profile(surface, nurbs_core::Direction::U, at);
            let dip = p[0].max(p[200]);
            assert_eq!(
                nurbs_core::fairness::count_extrema(&p, dip + 0.005 * peak),
                1,
                "{f} at {at}: {p:?}"
            );
        }
    }
}

/// By default (0.05 mm, of which the lead-in may take half) plate_boss's torus fillets are no
/// masters and take one-hump sections with ramps as wide as that budget allows: with the
/// linear ramp ([`g_continuity::RampShape`]) the r 5 fillet's about 1/34 of its section (the
/// flat ramp's deficit allowed only 1/72, below the 1/64 a master's ramp keeps), one rise and
/// one fall across within 1.6× (measured 1.01×; before any section, the lead-in's five extrema
/// at 1.30×).
#[test]
fn torus_fillets_get_one_hump_by_default() {
    let report = by_default(&model("occt_plate_boss").unwrap());
    assert!(report.links.iter().all(|l| l.met));
    for f in ["F02_torus", "F09_torus"] {
        let s = surface(&report, f);
        let v = s.fairness_verdict();
        assert!(v.fair(), "{f}: {v:?}");
        let ramp = s.stages[0].section_ramp.expect("section replaced");
        assert!(
            ramp >= hier_fair::framework::MIN_FREE_RAMP,
            "{f}: ramp {ramp}"
        );
        assert!(s.max_deviation <= s.tolerance, "{f}");
    }
    let ramp = surface(&report, "F02_torus").stages[0]
        .section_ramp
        .unwrap();
    assert!(
        ramp > 1.5 * hier_fair::framework::MIN_RAMP,
        "F02_torus: ramp {ramp}"
    );
    // every stage carries its wall time, and together they stay within the surface's own
    for s in &report.surfaces {
        let staged: f64 = s.stages.iter().map(|st| st.seconds).sum();
        assert!(s.stages.iter().all(|st| st.seconds >= 0.0), "{}", s.name);
        assert!(
            staged <= s.seconds + 1e-9,
            "{}: {staged} > {}",
            s.name,
            s.seconds
        );
    }
}

/// box12_r5's sphere corners are vertex blends with a pole (a side collapsed to a point) where
/// two fillets meet. The fillets reach the plane with G2, so they are flat at that point, and
/// the corner's sides are set to their (zero) curvature across; the pole step sets the pole's
/// own ring to the same curvature, so that every ray through the pole has it. Before, the ring
/// kept the sphere's 1/R = 0.2 /mm between the sides set to 0, and the corner peaked 8.5× its
/// input's next to the pole.
///
/// Per role the twelve cylinder fillets, masters of the corners, take their one-hump sections
/// (one rise and one fall across, fair by every figure; before: five extrema at 1.30×), and
/// the corners follow the changed end curves with their whole interior (the C0 move spread,
/// `SetParams::spread_boundary_move`): every link met, every corner's peak below twice its
/// input's (measured 1.81–1.88×; 6.0× before, with the fillets' lead-ins squeezed at the pole,
/// and 11× with the sections but the move kept in a strip beside each side).
#[test]
fn sphere_corner_poles_take_their_masters_curvature() {
    let (_, out, report) = per_role("occt_box12_r5");
    assert!(report.links.iter().all(|l| l.met));
    for s in report.surfaces.iter() {
        let v = s.fairness_verdict();
        if s.name.ends_with("_cylinder") {
            assert!(s.stages[0].section_ramp.is_some(), "{}: no section", s.name);
            assert!(v.fair(), "{}: {v:?}", s.name);
        }
        if s.name.ends_with("_sphere") {
            assert!(v.peak_ratio < 2.0, "{}: {v:?}", s.name);
        }
    }
    let mut poles = 0;
    for ms in out.surfaces.iter().filter(|s| s.name.ends_with("_sphere")) {
        let s = &ms.surface;
        let Some(side) = nurbs_core::Side::ALL
            .into_iter()
            .find(|&side| g_continuity::measure::is_collapsed(s, side))
        else {
            continue;
        };
        poles += 1;
        // the pole's normal from its tangent row (the fan of row 1 around the pole point)
        let (nu, nv) = (s.num_u(), s.num_v());
        let at = |(i, j): (usize, usize)| s.control_points()[s.index(i, j)];
        let p = at(side.row(0, nu, nv)[0]);
        let ring: Vec<_> = side
            .row(1, nu, nv)
            .into_iter()
            .map(|ij| at(ij) - p)
            .collect();
        let fan: nurbs_core::Vector3 = ring.windows(2).map(|w| w[0].cross(&w[1])).sum();
        let n = fan.normalize();
        let (t0, t1) = side.along_domain(s);
        for k in 0..=20 {
            let (u, v) = side.params(s, t0 + (t1 - t0) * k as f64 / 20.0);
            let d = s.derivatives(u, v);
            let (a, b) = match side.cross_direction() {
                nurbs_core::Direction::U => (d.du, d.duu),
                nurbs_core::Direction::V => (d.dv, d.dvv),
            };
            let kappa = n.dot(&b) / a.norm_squared();
            assert!(
                kappa.abs() < 0.01 * 0.2,
                "{}: ray {k} through the pole has curvature {kappa}",
                ms.name
            );
        }
    }
    assert_eq!(poles, 8, "box12_r5 has eight sphere corners with a pole");
}

/// box12_variable's B-spline corner C07 with the fillets and planes it hangs on, by default
/// (0.05 mm): its cylinder fillets take one-hump sections, which the corner cannot follow on
/// every side (a link missed); the run is made again with those sections withdrawn (the fillets
/// keep their input's section), every link is met, and the report names each withdrawn section.
#[test]
fn sections_a_corner_cannot_follow_are_withdrawn() {
    let report = by_default(&hanging(
        &model("occt_box12_variable").unwrap(),
        "C07_bspline",
    ));
    assert!(report.links.iter().all(|l| l.met));
    let withdrawn: Vec<&str> = report
        .problems
        .iter()
        .filter(|p| p.message.contains("one-hump section was withdrawn"))
        .map(|p| p.surface.as_str())
        .collect();
    assert!(!withdrawn.is_empty(), "{:?}", report.problems);
    for name in withdrawn {
        assert!(name.ends_with("_cylinder"), "{name}");
        assert!(
            surface(&report, name).stages[0].section_ramp.is_none(),
            "{name}"
        );
    }
}

/// The part of `model` that surface `name` hangs on: it, its masters, theirs, … with the links
/// among them.
fn hanging(model: &Model, name: &str) -> Model {
    let mut keep = vec![model.find(name).unwrap()];
    let mut k = 0;
    while k < keep.len() {
        let slave = keep[k];
        for l in model.links.iter().filter(|l| l.slave == slave) {
            if !keep.contains(&l.master) {
                keep.push(l.master);
            }
        }
        k += 1;
    }
    keep.sort_unstable();
    let mut out = model.clone();
    out.surfaces = keep.iter().map(|&k| model.surfaces[k].clone()).collect();
    out.corners.clear();
    let at = |k: usize| keep.iter().position(|&j| j == k);
    out.links = model
        .links
        .iter()
        .filter_map(|l| {
            Some(hier_fair::Link {
                slave: at(l.slave)?,
                master: at(l.master)?,
                ..*l
            })
        })
        .collect();
    out
}

/// box12_r5's sphere corner C06 (radius 5: 0.2 /mm everywhere) with its three cylinder fillets
/// and their planes, faired with the default deviation (0.05 mm). As one patch with a pole it
/// meets every link and keeps its input's peak curvature (measured 1.02×: its continuity
/// setting against fillets with linear-ramp sections, kept where it is fairer than its faired
/// result; 5.3× when its lead-ins narrowed to nothing at the pole, 2.5× with the faired result
/// kept); split into three quads it has no pole, every link is still met, and no quad peaks
/// beyond 2× (measured 1.67×; 1.55–2.0× in the whole model, where the quad next to the two
/// fillets that meet at a corner of the sphere carries the vertex conflict there).
#[test]
fn a_split_sphere_corner_has_no_spike_at_its_pole() {
    let model = hanging(&model("occt_box12_r5").unwrap(), "C06_sphere");
    let whole = by_default(&model);
    let peak = |r: &hier_fair::FairModelReport, name: &str| {
        r.surfaces
            .iter()
            .filter(|s| s.name.starts_with(name))
            .map(|s| s.fairness_verdict().peak_ratio)
            .fold(0.0, f64::max)
    };
    assert!(whole.links.iter().all(|l| l.met));
    let before = peak(&whole, "C06_sphere");
    assert!(
        before <= hier_fair::fairness::PEAK_FACTOR,
        "the pole's spike: {before}"
    );
    let (split, record) = hier_fair::poles::split_pole_corners(&model);
    assert_eq!(record.len(), 1);
    let quads = by_default(&split);
    assert!(quads.links.iter().all(|l| l.met), "{:?}", quads.problems);
    let after = peak(&quads, "C06_sphere.q");
    assert!(after < 2.0, "split: {after} (unsplit {before})");
}
