//! A strict structural check of IGES text, stricter than the reader: every record exactly 80
//! columns, section letters in column 73 in order, sequence numbers consecutive, the Terminate
//! counts right, directory entries in pairs, parameter pointers in range and pointing back.
//! Used to verify what the writer produces as another IGES reader would see it.

use crate::error::IgesError;
use crate::reader::{
    RECORD_COLUMNS, check_terminate, entity_params, parse_directory, parse_global, split_sections,
};

/// Section sizes of a well-formed file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StructureReport {
    /// records in the S, G, D, P sections
    pub counts: [usize; 4],
    /// directory entries
    pub entities: usize,
}

/// Checks the structure of `bytes`; returns the section counts.
pub fn check_structure(bytes: &[u8]) -> Result<StructureReport, IgesError> {
    for (k, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        let rec = raw.strip_suffix(b"\r").unwrap_or(raw);
        if !rec.is_empty() && rec.len() != RECORD_COLUMNS {
            return Err(IgesError::Layout {
                line: k + 1,
                detail: format!("record has {} columns, not {RECORD_COLUMNS}", rec.len()),
            });
        }
    }
    let sec = split_sections(bytes)?;
    check_terminate(&sec)?;
    let global = parse_global(&sec.g)?;
    let dir = parse_directory(&sec.d)?;
    let mut covered = vec![false; sec.p.len()];
    for e in &dir {
        entity_params(e, &sec.p, &global)?;
        for k in (e.pointer - 1) as usize..(e.pointer + e.line_count - 1) as usize {
            if covered[k] {
                return Err(IgesError::Layout {
                    line: sec.p[k].line,
                    detail: "parameter line claimed by two directory entries".into(),
                });
            }
            covered[k] = true;
        }
    }
    if let Some(k) = covered.iter().position(|c| !c) {
        return Err(IgesError::Layout {
            line: sec.p[k].line,
            detail: "parameter line belongs to no directory entry".into(),
        });
    }
    Ok(StructureReport {
        counts: [sec.s.len(), sec.g.len(), sec.d.len(), sec.p.len()],
        entities: dir.len(),
    })
}
