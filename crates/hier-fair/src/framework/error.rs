//! Why a stage could not run on a surface ([`StageError`]): the framework's stages return it,
//! and the job that runs them writes its text into the report as a `failed` problem (or, for a
//! candidate the stages try, drops that candidate). The texts are the report's, word for word.

use nurbs_core::Continuity;
use thiserror::Error;

/// What a stage of the framework could not do to a surface.
#[derive(Debug, Error)]
pub enum StageError {
    /// a continuity step failed (g-continuity's set step)
    #[error("setting {level:?} on {surface}: {source}")]
    Set {
        /// the level being set
        level: Continuity,
        /// the surface (or "NAME's one-hump section")
        surface: String,
        /// why
        source: g_continuity::Error,
    },
    /// preparing the slave for its steps (degree, lead-in rows) failed
    #[error("preparing {surface}: {source}")]
    Prepare {
        /// the surface (or "NAME's one-hump section")
        surface: String,
        /// why
        source: g_continuity::Error,
    },
    /// inserting knots (free rows, the dry run's knots) failed
    #[error("inserting knots into {surface}: {source}")]
    Knots {
        /// the surface (or "NAME's one-hump section")
        surface: String,
        /// why
        source: nurbs_core::Error,
    },
    /// measuring a link on the input failed
    #[error("link {link}: {source}")]
    Measure {
        /// the link's label
        link: String,
        /// why
        source: g_continuity::Error,
    },
    /// a link's side lies farther from its master than it may (`check`'s touch rule)
    #[error(
        "link {link} does not touch its master: gap {gap:.3e} > {limit:.3e} ({factor} × the g0 tolerance)"
    )]
    NotTouching {
        /// the link's label
        link: String,
        /// its largest gap (model units)
        gap: f64,
        /// the limit (model units)
        limit: f64,
        /// the limit in g0 tolerances
        factor: f64,
    },
    /// the fairing method failed
    #[error("{0}")]
    Method(nurbs_core::Error),
    /// the fairing method raised the thin-plate energy (a stage ends fairer or is not used)
    #[error("it raised the thin-plate energy from {before:.4e} to {after:.4e}")]
    RaisedEnergy {
        /// the energy before
        before: f64,
        /// the energy after
        after: f64,
    },
}

/// The result of a stage.
pub type StageResult<T> = std::result::Result<T, StageError>;
