//! Free-format parameter parsing (\[IGES\] §2.2.2–2.2.3): fields separated by the parameter
//! delimiter, a record ended by the record delimiter, Hollerith strings `nHtext`, integers and
//! reals with an `E` or `D` exponent, empty fields meaning "default".

use crate::error::IgesError;

/// One parsed parameter.
#[derive(Debug, Clone, PartialEq)]
pub enum Param {
    /// an empty field (the default value)
    Empty,
    /// a number (integers are exact in f64 below 2⁵³)
    Number(f64),
    /// a Hollerith string
    Text(String),
}

/// A parameter with the line it starts on.
#[derive(Debug, Clone, PartialEq)]
pub struct Located {
    /// the value
    pub value: Param,
    /// 1-based file line
    pub line: usize,
}

/// Parses free-format text (records' data columns concatenated, with the file line of each
/// character) up to and including the record delimiter. Returns the parameters.
pub fn parse_params(
    text: &[u8],
    lines: &[usize],
    pdelim: u8,
    rdelim: u8,
) -> Result<Vec<Located>, IgesError> {
    let mut out = Vec::new();
    let mut i = 0;
    let line_at = |k: usize| lines.get(k).or(lines.last()).copied().unwrap_or(0);
    loop {
        // skip blanks before a field
        i = skip_blanks(text, i);
        let start_line = line_at(i);
        if i >= text.len() {
            return Err(IgesError::Parameter {
                line: start_line,
                detail: "parameter data ends without the record delimiter".into(),
            });
        }
        let (value, end) = field(text, i, start_line, pdelim, rdelim)?;
        i = skip_blanks(text, end);
        out.push(Located {
            value,
            line: start_line,
        });
        if i >= text.len() {
            return Err(IgesError::Parameter {
                line: line_at(i),
                detail: "parameter data ends without the record delimiter".into(),
            });
        }
        let d = text[i];
        i += 1;
        if d == rdelim {
            return Ok(out);
        }
        if d != pdelim {
            return Err(IgesError::Parameter {
                line: line_at(i - 1),
                detail: format!("expected a delimiter, found {:?}", d as char),
            });
        }
    }
}

/// The index of the first character at or after `i` that is not a blank.
fn skip_blanks(text: &[u8], mut i: usize) -> usize {
    while i < text.len() && text[i] == b' ' {
        i += 1;
    }
    i
}

/// The field starting at `i` (on file line `line`): a Hollerith string, or up to the next
/// delimiter a number or nothing (the default); with the index just past it.
fn field(
    text: &[u8],
    i: usize,
    line: usize,
    pdelim: u8,
    rdelim: u8,
) -> Result<(Param, usize), IgesError> {
    // Hollerith: digits followed by H
    let mut j = i;
    while j < text.len() && text[j].is_ascii_digit() {
        j += 1;
    }
    if j > i && j < text.len() && (text[j] == b'H' || text[j] == b'h') {
        return hollerith(text, i, j, line);
    }
    let mut k = i;
    while k < text.len() && text[k] != pdelim && text[k] != rdelim {
        k += 1;
    }
    let raw = std::str::from_utf8(&text[i..k]).unwrap_or("").trim();
    if raw.is_empty() {
        return Ok((Param::Empty, k));
    }
    let x = parse_number(raw).ok_or_else(|| IgesError::Parameter {
        line,
        detail: format!("{raw:?} is not a number"),
    })?;
    Ok((Param::Number(x), k))
}

/// The Hollerith string `nHtext` whose count n is `text[i..h]` (the H at `h`), with the index
/// just past its text.
fn hollerith(text: &[u8], i: usize, h: usize, line: usize) -> Result<(Param, usize), IgesError> {
    let n: usize = std::str::from_utf8(&text[i..h])
        .ok()
        .and_then(|s| s.parse().ok())
        .ok_or_else(|| IgesError::Parameter {
            line,
            detail: "bad Hollerith length".into(),
        })?;
    let from = h + 1;
    let to = from + n;
    if to > text.len() {
        return Err(IgesError::Parameter {
            line,
            detail: format!("Hollerith string of {n} characters runs past the data"),
        });
    }
    Ok((
        Param::Text(String::from_utf8_lossy(&text[from..to]).into_owned()),
        to,
    ))
}

/// Parses an IGES number: optional sign, digits with an optional decimal point, optional
/// exponent `E`/`D`. NaN and infinity spellings are rejected.
pub fn parse_number(raw: &str) -> Option<f64> {
    let s: String = raw
        .chars()
        .map(|c| if c == 'D' || c == 'd' { 'E' } else { c })
        .collect();
    let ok = s
        .chars()
        .all(|c| c.is_ascii_digit() || matches!(c, '+' | '-' | '.' | 'E' | 'e'))
        && s.chars().any(|c| c.is_ascii_digit());
    if !ok {
        return None;
    }
    s.parse::<f64>().ok().filter(|x| x.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Vec<Param>, IgesError> {
        let lines = vec![1; text.len()];
        parse_params(text.as_bytes(), &lines, b',', b';')
            .map(|v| v.into_iter().map(|p| p.value).collect())
    }

    #[test]
    fn numbers_strings_defaults() {
        let p = parse("128,3,-1.5D-3,.25,1.E2,,5Hab,;d;").unwrap();
        assert_eq!(
            p,
            vec![
                Param::Number(128.0),
                Param::Number(3.0),
                Param::Number(-1.5e-3),
                Param::Number(0.25),
                Param::Number(100.0),
                Param::Empty,
                Param::Text("ab,;d".into())
            ]
        );
        assert!(parse("1,NaN;").is_err());
        assert!(parse("1,inf;").is_err());
        assert!(parse("1,2").is_err());
        assert!(parse("1,9Habc;").is_err());
    }
}
