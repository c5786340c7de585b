//! Records and sections of an IGES file (\[IGES\] §2): the fixed 80-column records split into
//! the Start, Global, Directory, Parameter and Terminate sections with their sequence numbers
//! checked, the Global section's delimiters and parameters, the directory entries, an entity's
//! parameter data, the Terminate counts and the unit names.

use crate::error::IgesError;
use crate::params::{Located, Param, parse_params};

/// The section letters in their order in a file (IGES 5.3 §2.1).
const SECTION_ORDER: &[u8; 5] = b"SGDPT";

/// Columns of a record, the section letter column, the data columns of the P section.
pub const RECORD_COLUMNS: usize = 80;
/// Column of the section letter (IGES 5.3 §2.1: columns 73, 0-based 72).
const LETTER_COLUMN: usize = 72;
/// Data columns of a P-section record (IGES 5.3 §2.2.4: 1–64; 65–72 hold the DE pointer).
const P_DATA_COLUMNS: usize = 64;

/// One record: its 72 columns before the section letter and its file line.
pub(crate) struct Record<'a> {
    pub(crate) data: &'a [u8],
    pub(crate) line: usize,
}

/// The records of a file by section: Start, Global, Directory, Parameter, Terminate.
pub(crate) struct Sections<'a> {
    pub(crate) s: Vec<Record<'a>>,
    pub(crate) g: Vec<Record<'a>>,
    pub(crate) d: Vec<Record<'a>>,
    pub(crate) p: Vec<Record<'a>>,
    pub(crate) t: Vec<Record<'a>>,
}

/// A layout error at file line `line`.
fn layout(line: usize, detail: impl Into<String>) -> IgesError {
    IgesError::Layout {
        line,
        detail: detail.into(),
    }
}

/// The records of `bytes` by section, each checked: 80 columns, the section letter in column
/// 73, sections in order, sequence numbers consecutive.
pub(crate) fn split_sections(bytes: &[u8]) -> Result<Sections<'_>, IgesError> {
    let mut sec = Sections {
        s: vec![],
        g: vec![],
        d: vec![],
        p: vec![],
        t: vec![],
    };
    let mut current = 0usize;
    let mut lines: Vec<&[u8]> = bytes.split(|&b| b == b'\n').collect();
    // blank lines after the last record (an empty line after the Terminate record, as some
    // writers leave and Open CASCADE reads) are no records
    while lines
        .last()
        .is_some_and(|l| l.iter().all(|&b| b == b'\r' || b == b' '))
    {
        lines.pop();
    }
    for (k, raw) in lines.iter().enumerate() {
        let line = k + 1;
        let rec = record_columns(raw, line)?;
        let (letter, pos) = section_letter(rec, line)?;
        if pos < current {
            return Err(layout(
                line,
                format!(
                    "section {} after section {}",
                    letter as char, SECTION_ORDER[current] as char
                ),
            ));
        }
        current = pos;
        let seq_text = std::str::from_utf8(&rec[LETTER_COLUMN + 1..rec.len().min(RECORD_COLUMNS)])
            .unwrap_or("")
            .trim();
        let list = match letter {
            b'S' => &mut sec.s,
            b'G' => &mut sec.g,
            b'D' => &mut sec.d,
            b'P' => &mut sec.p,
            _ => &mut sec.t,
        };
        let expected = list.len() + 1;
        match seq_text.parse::<usize>() {
            Ok(n) if n == expected => {}
            _ => {
                return Err(layout(
                    line,
                    format!("sequence number {seq_text:?} in columns 74–80, expected {expected}"),
                ));
            }
        }
        list.push(Record {
            data: &rec[..LETTER_COLUMN],
            line,
        });
    }
    check_sections(&sec)?;
    Ok(sec)
}

/// The record `raw` without its carriage return, checked to have the section letter in column
/// 73 and nothing but blanks past column 80.
fn record_columns(raw: &[u8], line: usize) -> Result<&[u8], IgesError> {
    let rec = raw.strip_suffix(b"\r").unwrap_or(raw);
    if rec.len() <= LETTER_COLUMN {
        return Err(layout(
            line,
            format!(
                "record has {} columns; IGES records have {RECORD_COLUMNS} with the section letter in column 73",
                rec.len()
            ),
        ));
    }
    if rec.len() > RECORD_COLUMNS && rec[RECORD_COLUMNS..].iter().any(|&b| b != b' ') {
        return Err(layout(
            line,
            format!(
                "record has {} columns, more than {RECORD_COLUMNS}",
                rec.len()
            ),
        ));
    }
    Ok(rec)
}

/// The section letter of record `rec` and its place in the order S, G, D, P, T.
fn section_letter(rec: &[u8], line: usize) -> Result<(u8, usize), IgesError> {
    let letter = rec[LETTER_COLUMN];
    let Some(pos) = SECTION_ORDER.iter().position(|&c| c == letter) else {
        let what = if matches!(letter, b'C' | b'B') {
            "compressed or binary IGES is not supported"
        } else {
            "column 73 must hold a section letter S, G, D, P or T"
        };
        return Err(layout(line, format!("{what} (found {:?})", letter as char)));
    };
    Ok((letter, pos))
}

/// Checks the sections of a whole file: one Terminate record, a Global section, directory
/// entries in pairs.
fn check_sections(sec: &Sections<'_>) -> Result<(), IgesError> {
    if sec.t.len() != 1 {
        return Err(IgesError::Structure {
            detail: format!(
                "the file must end with one Terminate record, found {} (truncated file?)",
                sec.t.len()
            ),
        });
    }
    if sec.g.is_empty() {
        return Err(IgesError::Structure {
            detail: "the Global section is missing".into(),
        });
    }
    if !sec.d.len().is_multiple_of(2) {
        return Err(layout(
            sec.d.last().map_or(0, |r| r.line),
            "the Directory section has an odd number of records (each entry is two)",
        ));
    }
    Ok(())
}

/// Concatenates the data columns of records, remembering the file line of every byte.
fn concat(records: &[Record<'_>], columns: usize) -> (Vec<u8>, Vec<usize>) {
    let mut text = Vec::with_capacity(records.len() * columns);
    let mut lines = Vec::with_capacity(records.len() * columns);
    for r in records {
        let d = &r.data[..columns.min(r.data.len())];
        text.extend_from_slice(d);
        lines.extend(std::iter::repeat_n(r.line, d.len()));
    }
    (text, lines)
}

/// The Global section: its delimiters and parameters.
pub(crate) struct Global {
    pdelim: u8,
    rdelim: u8,
    pub(super) params: Vec<Located>,
}

/// Reads the Global section: the two delimiters (`1Hx` or the defaults), then its parameters.
pub(crate) fn parse_global(records: &[Record<'_>]) -> Result<Global, IgesError> {
    let (text, lines) = concat(records, LETTER_COLUMN);
    let first_line = records[0].line;
    let mut i = 0;
    let mut delims = [b',', b';'];
    for k in 0..2 {
        while i < text.len() && text[i] == b' ' {
            i += 1;
        }
        if text.get(i..i + 2) == Some(b"1H") || text.get(i..i + 2) == Some(b"1h") {
            delims[k] = *text
                .get(i + 2)
                .ok_or_else(|| layout(first_line, "Global section ends inside a delimiter"))?;
            i += 3;
        }
        // each of the two fields is followed by the parameter delimiter
        while i < text.len() && text[i] == b' ' {
            i += 1;
        }
        match text.get(i) {
            Some(&c) if c == delims[0] => i += 1,
            _ => {
                return Err(IgesError::Parameter {
                    line: first_line,
                    detail: "Global section: parameter and record delimiters are malformed".into(),
                });
            }
        }
    }
    let [pdelim, rdelim] = delims;
    let params = parse_params(&text[i..], &lines[i..], pdelim, rdelim)?;
    Ok(Global {
        pdelim,
        rdelim,
        params,
    })
}

#[derive(Debug, Clone, Copy)]
pub(crate) struct DirEntry {
    pub(crate) seq: usize,
    pub(crate) entity_type: i64,
    pub(crate) pointer: i64,
    pub(super) transform: i64,
    pub(crate) line_count: i64,
    /// the form number (second line, field 5)
    pub(super) form: i64,
    pub(super) label: [u8; 8],
    pub(super) subscript: i64,
}

/// Reads the directory entries, two records each, checking that both give the same type.
pub(crate) fn parse_directory(records: &[Record<'_>]) -> Result<Vec<DirEntry>, IgesError> {
    let field = |r: &Record<'_>, k: usize| -> Result<i64, IgesError> {
        let raw = std::str::from_utf8(&r.data[8 * k..8 * k + 8])
            .unwrap_or("")
            .trim();
        if raw.is_empty() {
            return Ok(0);
        }
        raw.parse::<i64>().map_err(|_| {
            layout(
                r.line,
                format!("directory field {} is {raw:?}, not an integer", k + 1),
            )
        })
    };
    let mut out = Vec::with_capacity(records.len() / 2);
    for (k, pair) in records.chunks(2).enumerate() {
        let (a, b) = (&pair[0], &pair[1]);
        let entity_type = field(a, 0)?;
        if field(b, 0)? != entity_type {
            return Err(layout(
                b.line,
                format!(
                    "entity type {} differs from {entity_type} on the line before",
                    field(b, 0)?
                ),
            ));
        }
        let mut label = [b' '; 8];
        label.copy_from_slice(&b.data[56..64]);
        out.push(DirEntry {
            seq: 2 * k + 1,
            entity_type,
            pointer: field(a, 1)?,
            transform: field(a, 6)?,
            line_count: field(b, 3)?,
            form: field(b, 4)?,
            label,
            subscript: field(b, 8).unwrap_or(0),
        });
    }
    Ok(out)
}

/// Sets each directory entry's parameter line count (\[IGES\] §2.2.3, field 14) to the run of
/// P records from its pointer that point back to it (columns 65–72), where the two disagree: the
/// back-pointers say which lines are the entity's, and Open CASCADE reads what is there. Returns
/// one warning for all the entries changed, naming the first.
pub(crate) fn reconcile_line_counts(dir: &mut [DirEntry], p: &[Record<'_>]) -> Option<String> {
    let back = |r: &Record<'_>| {
        std::str::from_utf8(&r.data[64..72])
            .unwrap_or("")
            .trim()
            .parse::<usize>()
            .ok()
    };
    let (mut changed, mut first) = (0, None);
    for e in dir.iter_mut() {
        let Some(start) = usize::try_from(e.pointer)
            .ok()
            .and_then(|k| k.checked_sub(1))
            .filter(|&k| k < p.len())
        else {
            continue;
        };
        let run = p[start..]
            .iter()
            .take_while(|r| back(r) == Some(e.seq))
            .count();
        if run > 0 && run as i64 != e.line_count {
            changed += 1;
            first.get_or_insert(format!(
                "entity {} at directory line {} gives {} where {run} point back to it",
                e.entity_type, e.seq, e.line_count
            ));
            e.line_count = run as i64;
        }
    }
    first.map(|f| {
        format!(
            "{changed} directory entries give a parameter line count other than the lines that point back to them (the first: {f}); the lines that point back are read"
        )
    })
}

/// Reads the parameters of one entity.
pub(crate) fn entity_params(
    e: &DirEntry,
    p: &[Record<'_>],
    g: &Global,
) -> Result<Vec<Located>, IgesError> {
    let err = |detail: String| IgesError::Entity {
        de: e.seq,
        entity_type: e.entity_type,
        detail,
    };
    if e.pointer < 1 || e.line_count < 1 || (e.pointer + e.line_count - 1) as usize > p.len() {
        return Err(err(format!(
            "parameter data pointer {} with {} lines is out of range (the P section has {} lines)",
            e.pointer,
            e.line_count,
            p.len()
        )));
    }
    let records = &p[e.pointer as usize - 1..(e.pointer + e.line_count - 1) as usize];
    for r in records {
        let back = std::str::from_utf8(&r.data[64..72])
            .unwrap_or("")
            .trim()
            .parse::<usize>()
            .ok();
        if back != Some(e.seq) {
            return Err(layout(
                r.line,
                format!(
                    "parameter line points back to directory entry {back:?}, expected {}",
                    e.seq
                ),
            ));
        }
    }
    let (text, lines) = concat(records, P_DATA_COLUMNS);
    let params = parse_params(&text, &lines, g.pdelim, g.rdelim)?;
    match params.first().map(|p| &p.value) {
        Some(Param::Number(t)) if *t as i64 == e.entity_type => Ok(params),
        other => Err(err(format!(
            "parameter data starts with {other:?}, not the entity type"
        ))),
    }
}

/// Checks the Terminate record's counts against the sections.
pub(crate) fn check_terminate(sec: &Sections<'_>) -> Result<(), IgesError> {
    let t = &sec.t[0];
    let expected = [
        (b'S', sec.s.len()),
        (b'G', sec.g.len()),
        (b'D', sec.d.len()),
        (b'P', sec.p.len()),
    ];
    for (k, (letter, count)) in expected.iter().enumerate() {
        let field = &t.data[8 * k..8 * k + 8];
        let n = std::str::from_utf8(&field[1..])
            .ok()
            .and_then(|s| s.trim().parse::<usize>().ok());
        if field[0] != *letter || n != Some(*count) {
            return Err(layout(
                t.line,
                format!(
                    "Terminate record says {:?} but the {} section has {count} records",
                    String::from_utf8_lossy(field),
                    *letter as char
                ),
            ));
        }
    }
    Ok(())
}

/// The unit name of an IGES unit flag.
pub fn unit_name(flag: i64) -> &'static str {
    match flag {
        1 => "IN",
        2 => "MM",
        4 => "FT",
        5 => "MI",
        6 => "M",
        7 => "KM",
        8 => "MIL",
        9 => "UM",
        10 => "CM",
        11 => "UIN",
        _ => "unknown",
    }
}
