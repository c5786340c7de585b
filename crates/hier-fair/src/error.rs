//! The error type of hier-fair: bad models (naming the surface or link at fault) kept apart from
//! numerical failure.

use thiserror::Error;

/// Everything that can go wrong with a model.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum Error {
    /// Malformed JSON or a missing field.
    #[error("{detail}")]
    Format {
        /// what is wrong
        detail: String,
    },
    /// A surface that does not validate.
    #[error("surface {name}: {source}")]
    Surface {
        /// the surface's name
        name: String,
        /// why
        source: nurbs_core::Error,
    },
    /// Two surfaces with one name.
    #[error("two surfaces are named {name:?}")]
    DuplicateName {
        /// the name
        name: String,
    },
    /// A role other than primary, connecting, corner.
    #[error("surface {name}: unknown role {role:?} (expected primary, connecting or corner)")]
    UnknownRole {
        /// the surface
        name: String,
        /// the role given
        role: String,
    },
    /// A link naming a surface that does not exist.
    #[error("link {link}: no surface is named {name:?}")]
    UnknownSurface {
        /// the link, "slave.side -> master"
        link: String,
        /// the missing name
        name: String,
    },
    /// A fairing method name no registry entry has.
    #[error("unknown fairing method {name:?} (known: {known})")]
    UnknownMethod {
        /// the name given
        name: String,
        /// the names the registry knows, comma-separated
        known: String,
    },
    /// A fairing method registered under a name that is taken.
    #[error("a fairing method named {name:?} is registered already")]
    DuplicateMethod {
        /// the name
        name: String,
    },
    /// A side name other than u0, u1, v0, v1.
    #[error("link {link}: unknown side {side:?} (expected u0, u1, v0 or v1)")]
    UnknownSide {
        /// the link
        link: String,
        /// the side given
        side: String,
    },
    /// A continuity other than G0, G1, G2.
    #[error("link {link}: unknown continuity {continuity:?} (expected G0, G1 or G2)")]
    UnknownContinuity {
        /// the link
        link: String,
        /// the value given
        continuity: String,
    },
    /// The same slave side linked twice.
    #[error("link {link}: side {side} of {slave} is already linked")]
    DuplicateLink {
        /// the link
        link: String,
        /// the slave
        slave: String,
        /// the side
        side: String,
    },
    /// A link whose master is not above its slave in the hierarchy.
    #[error(
        "link {link}: a {slave_role} surface cannot be the slave of a {master_role} master (primary > connecting > corner; primaries are independent)"
    )]
    WrongRoles {
        /// the link
        link: String,
        /// role of the slave
        slave_role: &'static str,
        /// role of the master
        master_role: &'static str,
    },
    /// Links that form a cycle.
    #[error("links form a cycle through {surfaces}")]
    Cycle {
        /// the surfaces on the cycle, "a -> b -> a"
        surfaces: String,
    },
    /// A corner group naming a surface that does not exist, or too few patches.
    #[error("corner {corner}: {detail}")]
    BadCorner {
        /// the group
        corner: String,
        /// what is wrong
        detail: String,
    },
    /// A tolerance that is not finite and positive.
    #[error("tolerance {name} = {value} must be finite and > 0")]
    BadTolerance {
        /// the field
        name: &'static str,
        /// the value given
        value: f64,
    },
    /// A link whose slave side does not touch its master.
    #[error(
        "link {link}: the side does not touch its master (gap {gap:.6e}, limit {limit:.6e} = 100 × the g0 tolerance)"
    )]
    LinkNotTouching {
        /// the link
        link: String,
        /// the largest gap
        gap: f64,
        /// the limit
        limit: f64,
    },
    /// Continuity measuring or setting failed on a link or slave.
    #[error("{place}: {source}")]
    Continuity {
        /// the link or surface
        place: String,
        /// why
        source: g_continuity::Error,
    },
    /// A CAD file that cannot be read, or a model that cannot be written as one
    /// ([`crate::exchange`]).
    #[error("{detail}")]
    Exchange {
        /// what is wrong, naming the file's entity where there is one
        detail: String,
    },
    /// An error of the kernel.
    #[error(transparent)]
    Core(#[from] nurbs_core::Error),
}

/// Why a model's `tolerances.deviation` is not read: neither a length nor an object of the
/// three roles (serde's untagged enums only say that no variant matched).
#[derive(Debug, Error)]
pub(crate) enum DeviationError {
    /// A number that is no length.
    #[error("{0} is not a length")]
    NotALength(serde_json::Number),
    /// An object of the roles that does not read.
    #[error(transparent)]
    Roles(#[from] serde_json::Error),
    /// Neither a number nor an object.
    #[error(
        "expected a length or {{\"primary\": mm, \"connecting\": mm, \"corner\": mm}}, got {0}"
    )]
    Other(serde_json::Value),
}

/// Result alias of the crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;
