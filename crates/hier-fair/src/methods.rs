//! The fairing methods of the workspace behind one name each, and the choice of method per role.
//!
//! Any [`SurfaceFairing`] implementation can be plugged into the framework
//! ([`crate::framework::fair_model_with`]); [`Method`] only names the ones that ship with
//! hier-fair: `energy` (Hadenfeld local energy fairing, fair-energy), `energy-global` (one sparse
//! solve, fair-energy), `krr` (knot removal–reinsertion, fair-krr), `curvature` (target
//! curvature, fair-curvature) and `greiner` (curvature approximation, fair-curvature).
//!
//! A [`MethodRegistry`] names the methods a program offers: the built-in ones, and any a crate
//! that embeds hier-fair registers — the framework builds its per-role methods from it
//! ([`MethodRegistry::build_roles`]) and the command line's `--method` takes its names
//! (`hier_fair_cli::cli::main_with`).
//!
//! Defaults per role ([`RoleMethods::default`]): local energy fairing everywhere — it keeps every
//! control point inside its tolerance ball by construction (\[H\] §3), moves only the free
//! points, and never increases the energy, which is what a slave squeezed between fixed frames
//! needs; primaries (large, design intent) get it too, with their boundaries kept.

use nurbs_core::SurfaceFairing;

use crate::model::Role;

/// Least number of single-point moves per free control point of the local energy methods
/// (the limit is the larger of this × free points and the method's fixed limit, 10,000 or
/// `--iterations`). Why this many: the local method (\[H\]) moves one point at a time, so a
/// change at one side of the net reaches the other side one neighbour per sweep, and the
/// smoothest part of the energy needs about as many sweeps as the net is wide; the framework
/// bounds a net at [`crate::framework::MAX_NET`] = 64 points per direction, and this is the
/// next round number above it. A fixed limit cannot serve both a 4 × 4 patch and the nets of
/// several hundred free points knot insertion makes (measured: a five-sided quad ended 0.03 %
/// above its starting energy at 10,000 moves, below it at 20,000).
pub const MOVES_PER_FREE_POINT: usize = 100;

/// A fairing method of the workspace.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Method {
    /// Hadenfeld's local energy fairing
    Energy,
    /// sparse global thin-plate solve, clamped to the tolerance
    EnergyGlobal,
    /// Hadenfeld's extension to Bézier-spline surfaces: the λ-weighted jumps of the cross
    /// derivative at interior knots of full multiplicity join the functional, and the joints are
    /// made exactly C¹ within the tolerance (the net keeps its shape)
    EnergyBezier,
    /// knot removal and reinsertion
    Krr,
    /// target-curvature fairing of isocurves and refit (\[SV\] §5.2)
    Curvature,
    /// Greiner's curvature approximation (\[SV\] §5.3)
    Greiner,
}

impl Method {
    /// All methods, in CLI order.
    pub const ALL: [Method; 6] = [
        Method::Energy,
        Method::EnergyGlobal,
        Method::EnergyBezier,
        Method::Krr,
        Method::Curvature,
        Method::Greiner,
    ];

    /// The CLI name.
    pub fn name(self) -> &'static str {
        match self {
            Method::Energy => "energy",
            Method::EnergyGlobal => "energy-global",
            Method::EnergyBezier => fair_energy::BEZIER_METHOD,
            Method::Krr => "krr",
            Method::Curvature => "curvature",
            Method::Greiner => "greiner",
        }
    }

    /// One line on the method, for `--help`.
    pub fn summary(self) -> &'static str {
        match self {
            Method::Energy => "Hadenfeld's local energy fairing (the default)",
            Method::EnergyGlobal => "one sparse global thin-plate solve, clamped to the tolerance",
            Method::EnergyBezier => {
                "local energy fairing of a Bézier-spline surface, joints of full multiplicity made C1"
            }
            Method::Krr => "knot removal and reinsertion",
            Method::Curvature => "target-curvature fairing of isocurves, surface refitted",
            Method::Greiner => "Greiner's curvature approximation",
        }
    }

    /// Parses a CLI name.
    pub fn parse(name: &str) -> Option<Method> {
        Self::ALL.into_iter().find(|m| m.name() == name)
    }

    /// Whether the method has an iteration limit that `--iterations` sets (the curvature
    /// methods are direct solves).
    pub fn takes_iterations(self) -> bool {
        !matches!(self, Method::Curvature | Method::Greiner)
    }

    /// The method object; `iterations` overrides the method's iteration limit (for the local
    /// energy methods exactly: the per-free-point floor [`MOVES_PER_FREE_POINT`] applies only
    /// to their default limit).
    pub fn build(self, iterations: Option<usize>) -> Box<dyn SurfaceFairing> {
        match self {
            Method::Energy => {
                let mut params = fair_energy::EnergyParams {
                    min_iterations_per_free_point: MOVES_PER_FREE_POINT,
                    ..fair_energy::EnergyParams::default()
                };
                if let Some(n) = iterations {
                    // the user's limit is the limit: no per-free-point floor above it
                    params.max_iterations = n;
                    params.min_iterations_per_free_point = 0;
                }
                Box::new(EnergyFairing {
                    plain: fair_energy::LocalEnergyFairing { params },
                    bezier: bezier_fairing(iterations),
                })
            }
            Method::EnergyGlobal => {
                let mut params = fair_energy::GlobalParams::default();
                if let Some(n) = iterations {
                    params.polish_iterations = n;
                }
                Box::new(fair_energy::GlobalEnergyFairing { params })
            }
            Method::EnergyBezier => Box::new(bezier_fairing(iterations)),
            Method::Krr => {
                let mut params = fair_krr::KrrParams::default();
                if let Some(n) = iterations {
                    params.max_iterations = n;
                }
                Box::new(fair_krr::KrrFairing { params })
            }
            // the curvature methods are direct solves: no iteration limit to override
            Method::Curvature => Box::new(fair_curvature::TargetCurvatureFairing {
                params: fair_curvature::TargetCurvatureParams::default(),
            }),
            Method::Greiner => Box::new(fair_curvature::GreinerFairing {
                params: fair_curvature::GreinerParams::default(),
            }),
        }
    }
}

/// The Bézier-spline flow as the framework uses it: the framework's masks and links refer to the
/// net as it is, so no knot is removed.
fn bezier_fairing(iterations: Option<usize>) -> fair_energy::BezierSplineFairing {
    let mut params = fair_energy::BezierSplineParams {
        energy: fair_energy::EnergyParams {
            min_iterations_per_free_point: MOVES_PER_FREE_POINT,
            ..fair_energy::BezierSplineParams::default().energy
        },
        initial_removal: fair_energy::KnotRemoval::Keep,
        final_removal: fair_energy::KnotRemoval::Keep,
    };
    if let Some(n) = iterations {
        params.energy.max_iterations = n;
        params.energy.min_iterations_per_free_point = 0;
    }
    fair_energy::BezierSplineFairing { params }
}

/// `energy`: Hadenfeld's local energy fairing, with \[H\]'s extension to Bézier-spline surfaces
/// wherever the surface has an interior knot of full multiplicity (C⁰-joined Bézier patches in one
/// surface): those joints come out C¹ (\[H\] part ②; `energy-bezier` forces that flow).
struct EnergyFairing {
    plain: fair_energy::LocalEnergyFairing,
    bezier: fair_energy::BezierSplineFairing,
}

fn has_full_multiplicity_joint(surface: &nurbs_core::BSplineSurface) -> bool {
    [surface.knots_u(), surface.knots_v()].iter().any(|kv| {
        kv.interior_knots()
            .iter()
            .any(|&(_, m)| kv.degree() >= 2 && m >= kv.degree())
    })
}

impl SurfaceFairing for EnergyFairing {
    fn name(&self) -> &str {
        "energy"
    }

    fn fair(
        &self,
        problem: &nurbs_core::FairingProblem<'_>,
    ) -> nurbs_core::Result<nurbs_core::Faired> {
        if has_full_multiplicity_joint(problem.surface) && !problem.surface.is_rational() {
            self.bezier.fair(problem)
        } else {
            self.plain.fair(problem)
        }
    }
}

/// The method of each role.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RoleMethods {
    /// primaries
    pub primary: Method,
    /// connecting surfaces
    pub connecting: Method,
    /// corner patches
    pub corner: Method,
}

impl Default for RoleMethods {
    fn default() -> Self {
        Self::all(Method::Energy)
    }
}

impl RoleMethods {
    /// One method for every role.
    pub fn all(method: Method) -> Self {
        Self {
            primary: method,
            connecting: method,
            corner: method,
        }
    }

    /// The method of `role`.
    pub fn of(&self, role: Role) -> Method {
        match role {
            Role::Primary => self.primary,
            Role::Connecting => self.connecting,
            Role::Corner => self.corner,
        }
    }
}

/// Builds a method object from the iteration limit a user gave (`None`: the method's own).
type Build = Box<dyn Fn(Option<usize>) -> Box<dyn SurfaceFairing> + Send + Sync>;

/// A named fairing method of a [`MethodRegistry`].
pub struct MethodEntry {
    /// the name `--method` takes
    pub name: &'static str,
    /// one line for `--help` and error messages
    pub summary: &'static str,
    /// whether the method has an iteration limit that `--iterations` sets
    pub takes_iterations: bool,
    build: Build,
}

impl MethodEntry {
    /// The method object, with `iterations` as its limit where it has one.
    pub fn build(&self, iterations: Option<usize>) -> Box<dyn SurfaceFairing> {
        (self.build)(iterations)
    }
}

impl std::fmt::Debug for MethodEntry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MethodEntry")
            .field("name", &self.name)
            .field("takes_iterations", &self.takes_iterations)
            .finish_non_exhaustive()
    }
}

/// The fairing methods a program offers by name: the built-in [`Method`]s, and any other
/// [`SurfaceFairing`] a crate registers (shared by the framework and the command line).
///
/// ```
/// use hier_fair::{MethodRegistry, model::Role};
/// use nurbs_core::{Faired, FairingProblem, SurfaceFairing};
///
/// /// A method that leaves every surface as it is (a baseline to compare with).
/// struct Keep;
/// impl SurfaceFairing for Keep {
///     fn name(&self) -> &str {
///         "keep"
///     }
///     fn fair(&self, p: &FairingProblem<'_>) -> nurbs_core::Result<Faired> {
///         Ok(Faired::new(p.surface.clone(), 0))
///     }
/// }
///
/// let mut methods = MethodRegistry::builtin();
/// methods.register("keep", "leaves the surface as it is", false, |_| Box::new(Keep)).unwrap();
/// assert!(methods.register("keep", "again", false, |_| Box::new(Keep)).is_err());
/// let built = methods.build_roles(["energy", "keep", "keep"], None).unwrap();
/// assert_eq!(built.fairers().of(Role::Corner).name(), "keep");
/// assert!(methods.build("smooth-everything", None).is_err());
/// ```
#[derive(Debug)]
pub struct MethodRegistry {
    entries: Vec<MethodEntry>,
}

impl Default for MethodRegistry {
    fn default() -> Self {
        Self::builtin()
    }
}

impl MethodRegistry {
    /// The methods that ship with hier-fair ([`Method::ALL`]), in CLI order.
    pub fn builtin() -> Self {
        let mut r = Self {
            entries: Vec::new(),
        };
        for m in Method::ALL {
            let added = r.register(m.name(), m.summary(), m.takes_iterations(), move |n| {
                m.build(n)
            });
            debug_assert!(added.is_ok());
        }
        r
    }

    /// Adds a method under `name`; an error when the name is taken.
    pub fn register(
        &mut self,
        name: &'static str,
        summary: &'static str,
        takes_iterations: bool,
        build: impl Fn(Option<usize>) -> Box<dyn SurfaceFairing> + Send + Sync + 'static,
    ) -> crate::error::Result<()> {
        if self.get(name).is_some() {
            return Err(crate::error::Error::DuplicateMethod { name: name.into() });
        }
        self.entries.push(MethodEntry {
            name,
            summary,
            takes_iterations,
            build: Box::new(build),
        });
        Ok(())
    }

    /// The entry named `name`.
    pub fn get(&self, name: &str) -> Option<&MethodEntry> {
        self.entries.iter().find(|e| e.name == name)
    }

    /// Every entry, in registration order.
    pub fn entries(&self) -> &[MethodEntry] {
        &self.entries
    }

    /// The entry named `name`, or an error naming the known ones.
    pub fn entry(&self, name: &str) -> crate::error::Result<&MethodEntry> {
        self.get(name)
            .ok_or_else(|| crate::error::Error::UnknownMethod {
                name: name.into(),
                known: self
                    .entries
                    .iter()
                    .map(|e| e.name)
                    .collect::<Vec<_>>()
                    .join(", "),
            })
    }

    /// The method named `name`, with `iterations` as its limit where it has one.
    pub fn build(
        &self,
        name: &str,
        iterations: Option<usize>,
    ) -> crate::error::Result<Box<dyn SurfaceFairing>> {
        Ok(self.entry(name)?.build(iterations))
    }

    /// The methods of the three roles, named (primary, connecting, corner).
    pub fn build_roles(
        &self,
        [primary, connecting, corner]: [&str; 3],
        iterations: Option<usize>,
    ) -> crate::error::Result<BuiltMethods> {
        Ok(BuiltMethods {
            primary: self.build(primary, iterations)?,
            connecting: self.build(connecting, iterations)?,
            corner: self.build(corner, iterations)?,
        })
    }
}

/// Method objects per role, borrowed: what the framework runs. Build one from [`RoleMethods`]
/// with [`BuiltMethods`], or point the fields at your own [`SurfaceFairing`] implementations.
#[derive(Clone, Copy)]
pub struct Fairers<'a> {
    /// for primaries
    pub primary: &'a dyn SurfaceFairing,
    /// for connecting surfaces
    pub connecting: &'a dyn SurfaceFairing,
    /// for corner patches
    pub corner: &'a dyn SurfaceFairing,
}

impl<'a> Fairers<'a> {
    /// One method for every role.
    pub fn all(method: &'a dyn SurfaceFairing) -> Self {
        Self {
            primary: method,
            connecting: method,
            corner: method,
        }
    }

    /// The method of `role`.
    pub fn of(&self, role: Role) -> &'a dyn SurfaceFairing {
        match role {
            Role::Primary => self.primary,
            Role::Connecting => self.connecting,
            Role::Corner => self.corner,
        }
    }
}

/// Owned method objects built from [`RoleMethods`].
pub struct BuiltMethods {
    primary: Box<dyn SurfaceFairing>,
    connecting: Box<dyn SurfaceFairing>,
    corner: Box<dyn SurfaceFairing>,
}

impl BuiltMethods {
    /// Builds the built-in methods of each role; `iterations` overrides every method's
    /// iteration limit ([`MethodRegistry::build_roles`] for methods by name).
    pub fn new(methods: &RoleMethods, iterations: Option<usize>) -> Self {
        Self {
            primary: methods.primary.build(iterations),
            connecting: methods.connecting.build(iterations),
            corner: methods.corner.build(iterations),
        }
    }

    /// Borrowed view for the framework.
    pub fn fairers(&self) -> Fairers<'_> {
        Fairers {
            primary: self.primary.as_ref(),
            connecting: self.connecting.as_ref(),
            corner: self.corner.as_ref(),
        }
    }
}
