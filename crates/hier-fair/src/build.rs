//! The hierarchy found from the geometry: links where a surface's side lies on another surface,
//! their targets from the angle there, and the roles from the topology (\[SV\] §1.1: primaries,
//! connecting surfaces between them, corner patches between connecting surfaces).
//!
//! - **A side lies on a surface** when every one of [`crate::topology::SIDE_SAMPLES`] points along
//!   the side projects onto that surface within the model's G0 tolerance, the gap a link may have
//!   and still be met. The surface may be trimmed: the projection goes onto the whole surface, so a
//!   fillet's contact line in the middle of a trimmed face is found as well as one on its boundary.
//!   Of several such surfaces the nearest is taken.
//! - **The target** is G2 where the two normals along the side stay within
//!   [`TANGENT_ANGLE_DEG`] (a tangent join, which the fairing raises to G2), else G0 (a sharp
//!   edge, kept closed).
//! - **Roles**: a surface is *connecting* when it is a strip that turns: between two opposite
//!   sides its normal turns by more than [`TANGENT_ANGLE_DEG`] while it is narrow, at most
//!   [`NARROW_RATIO`] of its length (a fillet — its long sides need not lie on anything within
//!   the tolerance: a kernel's fillet of trimmed faces often does not; a narrow, strongly curved
//!   primary band would be taken for one, and the user fixes its role); *corner* when three
//!   or more sides lie across the ends of connecting surfaces, each no longer than
//!   [`CORNER_SPAN`] × that surface's width (a vertex blend; a side collapsed to a pole counts as
//!   none) — a strip that turns and lies so across three is a vertex blend too, long and narrow
//!   where the fillets meeting at it differ in radius; the rest *primary*.
//! - **n-sided corner groups** (\[SV\] §3.4, a corner region already split into quads): n ≥ 3
//!   surfaces around one centre point, each with the two sides that meet there lying tangentially
//!   on its neighbours around the centre and its other two sides on surfaces outside the group,
//!   one of them a connecting surface (a corner region is bounded by fillets; quads of a face
//!   split around a vertex are not); none of them connecting. They become corner patches of one
//!   group, in cyclic order; their sides on each other are no links (the framework sets those
//!   inside the group). Where the model gives its roles, only corner patches are grouped.
//! - **Links** go from the lower surface in the hierarchy to the higher one: a side of a
//!   connecting surface on a primary, of a corner on a connecting surface or a primary. A side
//!   on a surface of the same role, or on a lower one, is no link (the other surface's side is).
//!
//! What the user fixed stays: existing links are kept (their sides are not linked again), and
//! the roles are found only when every surface is primary (a model as `import` writes it).
//! Every decision goes into the log (`import --explain`, `build --explain`).

use nurbs_core::{BSplineSurface, Continuity, ProjectionParams, Side, SurfaceProjector};

use crate::model::{Link, Model, Role};
use crate::topology::{SIDE_SAMPLES, net_box, other_part};

/// Largest normal angle (degrees) of a tangent join. A kernel's tangent joins are within a few
/// hundredths of a degree where exact and about a degree where approximated (a lofted face's
/// fillet meets its corner blend at up to 1.3°); a designed sharp edge is tens of degrees. 5°
/// lies between the two by a factor of about 4 either way.
pub const TANGENT_ANGLE_DEG: f64 = 5.0;

/// Largest width across a connecting surface, as a fraction of its length along: a fillet is a
/// strip (radius × turn across, the edge's length along), a face bounded by fillets is not.
pub const NARROW_RATIO: f64 = 0.5;

/// Longest side of a corner patch lying on a connecting surface, in widths of that surface: a
/// vertex blend spans the ends of the fillets that meet at it (its side on a fillet is about the
/// fillet's width, a kernel's setback adding up to about half of it), while a face bounded by
/// fillets runs along them, many widths long.
pub const CORNER_SPAN: f64 = 2.0;

/// Which surface a side lies on.
#[derive(Debug, Clone, PartialEq)]
pub struct SideContact {
    /// the surface the side lies on
    pub surface: usize,
    /// largest sampled gap
    pub distance: f64,
    /// largest normal angle along the side where both normals are defined (degrees; `None`
    /// where they are nowhere)
    pub angle_deg: Option<f64>,
}

/// What [`build_hierarchy`] decided, for the log.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BuildLog {
    /// one line per decision, in the order they were made
    pub lines: Vec<String>,
    /// links added
    pub links_added: usize,
    /// whether the roles were found (false: the model's own were kept)
    pub roles_found: bool,
}

/// The sample points of `side` of `s`.
fn side_points(s: &BSplineSurface, side: Side) -> Vec<(f64, f64)> {
    g_continuity::sampling::uniform_side_params(s, side, SIDE_SAMPLES)
        .unwrap_or_default()
        .into_iter()
        .map(|t| side.params(s, t))
        .collect()
}

/// The surface (other than `own`) that `side` of surface `own` lies on within `tol`, nearest
/// first; and the nearest surface with its distance when none does (for the log).
fn contact<'m>(
    model: &'m Model,
    own: usize,
    side: Side,
    tol: f64,
    projectors: &mut [Option<SurfaceProjector<'m>>],
) -> (Option<SideContact>, Option<(usize, f64)>) {
    let s = &model.surfaces[own].surface;
    let params = ProjectionParams::default();
    let samples: Vec<_> = side_points(s, side)
        .into_iter()
        .map(|(u, v)| s.derivatives(u, v))
        .collect();
    let mut best: Option<SideContact> = None;
    let mut nearest: Option<(usize, f64)> = None;
    for (k, other) in model.surfaces.iter().enumerate() {
        if k == own || other_part(model, own, k) {
            continue;
        }
        let (lo, hi) = net_box(&other.surface, tol);
        let inside = samples
            .iter()
            .all(|d| (0..3).all(|c| d.point[c] >= lo[c] && d.point[c] <= hi[c]));
        if !inside {
            continue;
        }
        let mut distance: f64 = 0.0;
        // the largest angle where both normals are defined (not at a pole)
        let mut angle: Option<f64> = None;
        let projector =
            projectors[k].get_or_insert_with(|| SurfaceProjector::new(&other.surface, params));
        for d in &samples {
            let f = projector.project(&d.point);
            distance = distance.max(f.distance);
            let a = match (d.normal(), other.surface.derivatives(f.u, f.v).normal()) {
                (Some(n1), Some(n2)) => Some(n1.dot(&n2).abs().clamp(0.0, 1.0).acos().to_degrees()),
                _ => None,
            };
            angle = match (angle, a) {
                (Some(x), Some(y)) => Some(x.max(y)),
                (x, y) => x.or(y),
            };
        }
        if nearest.is_none_or(|(_, d)| distance < d) {
            nearest = Some((k, distance));
        }
        if distance <= tol && best.as_ref().is_none_or(|b| distance < b.distance) {
            best = Some(SideContact {
                surface: k,
                distance,
                angle_deg: angle,
            });
        }
    }
    (best, nearest)
}

/// Whether `s` bridges the surfaces its opposite sides `a`, `b` lie on: narrow across
/// ([`NARROW_RATIO`]) and turning across by more than [`TANGENT_ANGLE_DEG`].
fn bridges(s: &BSplineSurface, a: Side) -> (bool, f64, f64, f64) {
    let (t0, t1) = a.along_domain(s);
    let mid = 0.5 * (t0 + t1);
    let b = a.opposite();
    let (pa, pb) = (a.params(s, mid), b.params(s, mid));
    let (da, db) = (s.derivatives(pa.0, pa.1), s.derivatives(pb.0, pb.1));
    let width = (da.point - db.point).norm();
    let length = side_length(s, a);
    let turn = match (da.normal(), db.normal()) {
        (Some(x), Some(y)) => x.dot(&y).clamp(-1.0, 1.0).acos().to_degrees(),
        _ => 0.0,
    };
    (
        turn > TANGENT_ANGLE_DEG && width <= NARROW_RATIO * length,
        turn,
        width / length.max(f64::MIN_POSITIVE),
        width,
    )
}

/// The length of `side` (the polyline through its samples: a closed side, a ring's, has its
/// circumference, not the zero chord of its ends).
fn side_length(s: &BSplineSurface, side: Side) -> f64 {
    let pts: Vec<_> = side_points(s, side)
        .into_iter()
        .map(|(u, v)| s.point(u, v))
        .collect();
    pts.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
}

/// The two sides of a surface that meet at each of its corners.
const CORNER_SIDES: [(Side, Side); 4] = [
    (Side::U0, Side::V0),
    (Side::U1, Side::V0),
    (Side::U0, Side::V1),
    (Side::U1, Side::V1),
];

/// A corner of a surface whose two sides lie tangentially on two other surfaces: the corner
/// point, those two surfaces, and the surface's two other sides.
type Centre = (nurbs_core::Point3, [usize; 2], [Side; 2]);

/// The n-sided corner groups of the module docs, each in cyclic order: `contacts` are the
/// surfaces each side lies on, `roles` the roles as found or given, `given` whether they are the
/// model's own (then only corner patches are grouped), `taken` the surfaces already in a group.
fn corner_groups(
    model: &Model,
    contacts: &[[Option<SideContact>; 4]],
    roles: &[Role],
    given: bool,
    taken: &[usize],
) -> Vec<Vec<usize>> {
    let n = model.surfaces.len();
    let tangent = |k: usize, side: Side| {
        contacts[k][side.index()]
            .as_ref()
            .filter(|c| c.angle_deg.is_some_and(|a| a <= TANGENT_ANGLE_DEG))
            .map(|c| c.surface)
    };
    let eligible = |k: usize| {
        !taken.contains(&k)
            && if given {
                roles[k] == Role::Corner
            } else {
                roles[k] != Role::Connecting
            }
    };
    let mut centres: Vec<Vec<Centre>> = vec![Vec::new(); n];
    for k in (0..n).filter(|&k| eligible(k)) {
        let s = &model.surfaces[k].surface;
        for (a, b) in CORNER_SIDES {
            let (Some(x), Some(y)) = (tangent(k, a), tangent(k, b)) else {
                continue;
            };
            if x != y && x != k && y != k && eligible(x) && eligible(y) {
                let p = s.point(a.boundary_param(s), b.boundary_param(s));
                centres[k].push((p, [x, y], [a.opposite(), b.opposite()]));
            }
        }
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut used = vec![false; n];
    for start in 0..n {
        for &(centre, [first, _], _) in &centres[start] {
            if used[start] {
                break;
            }
            let cycle = around(model, &centres, &used, start, first, &centre);
            if cycle.len() >= 3 && bounded(&cycle, &centres, contacts, roles, given, &centre, model)
            {
                for &k in &cycle {
                    used[k] = true;
                }
                groups.push(cycle);
            }
        }
    }
    groups
}

/// The corner of surface `k` at `centre` (within [`crate::corners::ON_SIDE`] of its size).
fn centre_of<'c>(
    model: &Model,
    centres: &'c [Vec<Centre>],
    k: usize,
    centre: &nurbs_core::Point3,
) -> impl Iterator<Item = &'c Centre> {
    let tol = crate::corners::ON_SIDE * model.surfaces[k].surface.size();
    centres[k]
        .iter()
        .filter(move |(p, _, _)| (p - centre).norm() <= tol)
}

/// The surfaces around `centre` from `start` towards `first`: each next one has a corner there
/// whose neighbours are the previous surface and a new one; empty when the walk does not close.
fn around(
    model: &Model,
    centres: &[Vec<Centre>],
    used: &[bool],
    start: usize,
    first: usize,
    centre: &nurbs_core::Point3,
) -> Vec<usize> {
    let mut cycle = vec![start];
    let (mut prev, mut cur) = (start, first);
    while cur != start {
        if cycle.contains(&cur) || used[cur] {
            return Vec::new();
        }
        let Some(&(_, [a, b], _)) =
            centre_of(model, centres, cur, centre).find(|(_, nb, _)| nb.contains(&prev))
        else {
            return Vec::new();
        };
        cycle.push(cur);
        (prev, cur) = (cur, if a == prev { b } else { a });
    }
    cycle
}

/// Whether the surfaces of `cycle` bound a corner region: each one's two outer sides lie on
/// surfaces outside the cycle, one of them a connecting surface (any, where the roles are
/// `given`).
fn bounded(
    cycle: &[usize],
    centres: &[Vec<Centre>],
    contacts: &[[Option<SideContact>; 4]],
    roles: &[Role],
    given: bool,
    centre: &nurbs_core::Point3,
    model: &Model,
) -> bool {
    cycle.iter().all(|&k| {
        let Some(&(_, _, outer)) = centre_of(model, centres, k, centre).next() else {
            return false;
        };
        let on: Vec<usize> = outer
            .iter()
            .filter_map(|&side| contacts[k][side.index()].as_ref().map(|c| c.surface))
            .filter(|c| !cycle.contains(c))
            .collect();
        on.len() == 2 && (given || on.iter().any(|&c| roles[c] == Role::Connecting))
    })
}

/// Adds the corner group of the surfaces `cycle` (in cyclic order) to `model`, logged, with the
/// links inside it as the framework takes them: each patch G2 to the one before it around the
/// centre, and the last one to the first as well (a chain that closes, \[SV\] §3.4).
fn add_group(
    model: &mut Model,
    cycle: Vec<usize>,
    contacts: &[[Option<SideContact>; 4]],
    log: &mut BuildLog,
) {
    let n = cycle.len();
    let pairs = (1..n)
        .map(|i| (cycle[i], cycle[i - 1]))
        .chain(std::iter::once((cycle[n - 1], cycle[0])));
    for (slave, master) in pairs {
        let Some(i) = (0..4).find(|&i| {
            contacts[slave][i]
                .as_ref()
                .is_some_and(|c| c.surface == master)
        }) else {
            continue;
        };
        let side = Side::ALL[i];
        if model
            .links
            .iter()
            .any(|l| l.slave == slave && l.side == side)
        {
            continue;
        }
        log.lines.push(format!(
            "{}.{} -> {}: link G2 (inside the corner group, around its centre)",
            model.surfaces[slave].name,
            side.name(),
            model.surfaces[master].name
        ));
        model.links.push(Link {
            slave,
            side,
            master,
            continuity: Continuity::G2,
        });
        log.links_added += 1;
    }
    let names: Vec<&str> = cycle
        .iter()
        .map(|&k| model.surfaces[k].name.as_str())
        .collect();
    let name = format!("group{}", model.corners.len() + 1);
    log.lines.push(format!(
        "{name}: a {}-sided corner region split into quads around one centre: {} (corner patches, in cyclic order)",
        cycle.len(),
        names.join(", ")
    ));
    model.corners.push(crate::model::CornerGroup {
        name,
        patches: cycle,
    });
}

/// Finds the links (and, for a model of primaries only, the roles) of `model` from its geometry;
/// returns the log. See the module docs for the rules.
///
/// ```
/// use hier_fair::{Model, Role, build_hierarchy};
/// // a kernel model with its links and roles taken away gets them back
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/occt/occt_plate_boss.json");
/// let given = Model::from_json(&std::fs::read_to_string(path).unwrap()).unwrap();
/// let mut bare = given.clone();
/// bare.links.clear();
/// bare.surfaces.iter_mut().for_each(|s| s.role = Role::Primary);
/// let log = build_hierarchy(&mut bare);
/// assert_eq!(bare.links.len(), given.links.len());
/// assert!(log.lines.iter().any(|l| l.contains("connecting")));
/// ```
pub fn build_hierarchy(model: &mut Model) -> BuildLog {
    let mut log = BuildLog::default();
    let contacts = find_contacts(model, &mut log);
    // roles, when the model has none of its own
    if model.surfaces.iter().all(|s| s.role == Role::Primary) {
        find_roles(model, &contacts, &mut log);
    } else {
        log.lines
            .push("roles: kept as the model gives them".to_string());
        let roles: Vec<Role> = model.surfaces.iter().map(|s| s.role).collect();
        for cycle in corner_groups(model, &contacts, &roles, true, &grouped(model)) {
            add_group(model, cycle, &contacts, &mut log);
        }
    }
    add_links(model, &contacts, &mut log);
    log
}

/// The surfaces already in a corner group of `model`.
fn grouped(model: &Model) -> Vec<usize> {
    model
        .corners
        .iter()
        .flat_map(|g| g.patches.iter().copied())
        .collect()
}

/// Which surface each side of each surface lies on (logged). Each surface's projector, with its
/// grid of start points, is built once for all the sides projected onto it.
fn find_contacts(model: &Model, log: &mut BuildLog) -> Vec<[Option<SideContact>; 4]> {
    let tol = model.tolerances.g0;
    let n = model.surfaces.len();
    let mut contacts: Vec<[Option<SideContact>; 4]> = Vec::with_capacity(n);
    let mut projectors: Vec<Option<SurfaceProjector<'_>>> = (0..n).map(|_| None).collect();
    for k in 0..n {
        let mut row: [Option<SideContact>; 4] = Default::default();
        for (i, &side) in Side::ALL.iter().enumerate() {
            let name = &model.surfaces[k].name;
            if g_continuity::measure::is_collapsed(&model.surfaces[k].surface, side) {
                log.lines.push(format!(
                    "{name}.{}: collapsed to a point (a pole): no link",
                    side.name()
                ));
                continue;
            }
            let (c, nearest) = contact(model, k, side, tol, &mut projectors);
            // an assembly's part is linked inside itself only: say so where nothing was found
            let within = model.surfaces[k].part.as_ref().map_or(String::new(), |p| {
                format!(" of its part {p} (another part's surfaces are not linked to it)")
            });
            match (&c, nearest) {
                (Some(c), _) => log.lines.push(format!(
                    "{name}.{}: lies on {} (max distance {:.2e}, max normal angle {})",
                    side.name(),
                    model.surfaces[c.surface].name,
                    c.distance,
                    c.angle_deg.map_or("undefined".to_string(), |a| format!("{a:.3}°"))
                )),
                (None, Some((m, d))) => log.lines.push(format!(
                    "{name}.{}: lies on no surface{within} within {tol:.1e} (closest: {}, max distance {d:.3e})",
                    side.name(),
                    model.surfaces[m].name
                )),
                (None, None) => log.lines.push(format!(
                    "{name}.{}: no other surface{within} is near: a free boundary",
                    side.name()
                )),
            }
            row[i] = c;
        }
        contacts.push(row);
    }
    contacts
}

/// The strips that turn (module docs: *connecting*), logged: every surface's role (connecting
/// or primary) and, for the connecting ones, the width across.
fn strips(
    model: &Model,
    contacts: &[[Option<SideContact>; 4]],
    log: &mut BuildLog,
) -> (Vec<Role>, Vec<f64>) {
    let n = model.surfaces.len();
    let mut roles = vec![Role::Primary; n];
    // the width across each connecting surface
    let mut widths = vec![0.0; n];
    for k in 0..n {
        let s = &model.surfaces[k].surface;
        for (a, b) in [(0, 1), (2, 3)] {
            let tangent = |c: &Option<SideContact>| {
                c.as_ref()
                    .filter(|c| c.angle_deg.is_some_and(|x| x <= TANGENT_ANGLE_DEG))
                    .map(|c| model.surfaces[c.surface].name.as_str())
            };
            let on: Vec<&str> = [tangent(&contacts[k][a]), tangent(&contacts[k][b])]
                .into_iter()
                .flatten()
                .collect();
            let (yes, turn, ratio, width) = bridges(s, Side::ALL[a]);
            if yes {
                roles[k] = Role::Connecting;
                widths[k] = width;
                log.lines.push(format!(
                    "{}: connecting — between its sides {} and {} it turns {turn:.1}° and is {ratio:.2} as wide as long ({})",
                    model.surfaces[k].name,
                    Side::ALL[a].name(),
                    Side::ALL[b].name(),
                    if on.is_empty() {
                        "a strip that lies on no surface within the tolerance: a fillet of trimmed faces".to_string()
                    } else {
                        format!("tangent to {}", on.join(" and "))
                    }
                ));
                break;
            }
        }
    }
    (roles, widths)
}

/// The roles of a model of primaries only, from the topology (module docs), logged.
fn find_roles(model: &mut Model, contacts: &[[Option<SideContact>; 4]], log: &mut BuildLog) {
    let n = model.surfaces.len();
    log.roles_found = true;
    let (mut roles, widths) = strips(model, contacts, log);
    // a side across a connecting surface's end, not along it: no longer than CORNER_SPAN ×
    // that surface's width
    let across = |k: usize, roles: &[Role]| {
        let s = &model.surfaces[k].surface;
        Side::ALL
            .iter()
            .zip(&contacts[k])
            .filter(|(side, c)| {
                c.as_ref().is_some_and(|c| {
                    c.surface != k
                        && roles[c.surface] == Role::Connecting
                        && side_length(s, **side) <= CORNER_SPAN * widths[c.surface]
                })
            })
            .count()
    };
    // a strip lying across the ends of three or more strips is a vertex blend that turns
    // between two opposite sides (three fillets of different radii make it long and narrow):
    // a fillet's ends meet at most two of them, a blend or the other half of its ring
    let blends: Vec<usize> = (0..n)
        .filter(|&k| roles[k] == Role::Connecting && across(k, &roles) >= 3)
        .collect();
    for &k in &blends {
        roles[k] = Role::Primary;
        log.lines.push(format!(
            "{}: not connecting after all — it lies across the ends of {} connecting surfaces",
            model.surfaces[k].name,
            across(k, &roles)
        ));
    }
    for k in 0..n {
        if roles[k] != Role::Primary {
            continue;
        }
        let on_connecting = across(k, &roles);
        if on_connecting >= 3 {
            roles[k] = Role::Corner;
            log.lines.push(format!(
                "{}: corner — {on_connecting} of its sides lie across the ends of connecting surfaces",
                model.surfaces[k].name
            ));
        }
    }
    for cycle in corner_groups(model, contacts, &roles, false, &grouped(model)) {
        for &k in &cycle {
            roles[k] = Role::Corner;
        }
        add_group(model, cycle, contacts, log);
    }
    for k in 0..n {
        if roles[k] == Role::Primary {
            log.lines
                .push(format!("{}: primary", model.surfaces[k].name));
        }
        model.surfaces[k].role = roles[k];
    }
}

/// The links from the lower surface to the higher one (module docs), logged; sides the model
/// links already stay.
fn add_links(model: &mut Model, contacts: &[[Option<SideContact>; 4]], log: &mut BuildLog) {
    let n = model.surfaces.len();
    for k in 0..n {
        for (i, &side) in Side::ALL.iter().enumerate() {
            let Some(c) = &contacts[k][i] else { continue };
            let (me, other) = (&model.surfaces[k], &model.surfaces[c.surface]);
            let label = format!("{}.{} -> {}", me.name, side.name(), other.name);
            if model.links.iter().any(|l| l.slave == k && l.side == side) {
                log.lines
                    .push(format!("{label}: the model links this side already: kept"));
                continue;
            }
            if me.role.rank() <= other.role.rank() {
                log.lines.push(format!(
                    "{label}: no link in this direction ({} is not above {})",
                    other.role.name(),
                    me.role.name()
                ));
                continue;
            }
            let tangent = c.angle_deg.is_some_and(|a| a <= TANGENT_ANGLE_DEG);
            let continuity = if tangent {
                Continuity::G2
            } else {
                Continuity::G0
            };
            log.lines.push(format!(
                "{label}: link {continuity:?} ({})",
                if tangent {
                    format!("tangent, normals within {TANGENT_ANGLE_DEG}°")
                } else {
                    "a sharp edge".to_string()
                }
            ));
            model.links.push(Link {
                slave: k,
                side,
                master: c.surface,
                continuity,
            });
            log.links_added += 1;
        }
    }
}
