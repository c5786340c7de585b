//! Errors of the IGES reader and writer; every read error names the line (1-based, as an editor
//! shows it) or the directory entry at fault.

use thiserror::Error;

/// What can go wrong reading or writing IGES.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum IgesError {
    /// A record (line) that breaks the fixed 80-column layout or the section order.
    #[error("line {line}: {detail}")]
    Layout {
        /// 1-based line number in the file
        line: usize,
        /// what is wrong
        detail: String,
    },
    /// A malformed parameter (number, Hollerith string, delimiter).
    #[error("line {line}: {detail}")]
    Parameter {
        /// 1-based line number where the parameter starts
        line: usize,
        /// what is wrong
        detail: String,
    },
    /// A directory entry or its parameter data that is inconsistent.
    #[error("entity {entity_type} at directory line {de}: {detail}")]
    Entity {
        /// directory sequence number (odd line of the D section)
        de: usize,
        /// entity type number
        entity_type: i64,
        /// what is wrong
        detail: String,
    },
    /// Section-level inconsistency (missing section, terminate counts).
    #[error("{detail}")]
    Structure {
        /// what is wrong
        detail: String,
    },
    /// Geometry rejected by the kernel (knots, weights, …).
    #[error("entity {entity_type} at directory line {de}: {source}")]
    Geometry {
        /// directory sequence number
        de: usize,
        /// entity type number
        entity_type: i64,
        /// the kernel's error
        source: nurbs_core::Error,
    },
    /// A value that cannot be written (non-finite numbers).
    #[error("cannot write {what}: {detail}")]
    Write {
        /// the item
        what: String,
        /// what is wrong
        detail: String,
    },
}
