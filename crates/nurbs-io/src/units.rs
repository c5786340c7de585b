//! Length units: a model's unit as text, its size in millimetres, and lengths a user writes with
//! a unit suffix.
//!
//! A model keeps its coordinates in its file's unit (STEP's `length_unit`, \[ISO41\] measure_schema;
//! IGES's Global unit flag, \[IGES\] §2.2.4.3, Global parameters 14–15). Its unit is written as text: a
//! name this module knows ([`UNITS`]: the SI prefixes of the metre STEP uses and the IGES unit
//! flags' units), or — for a STEP conversion-based unit without a known name — `"<factor> mm"`,
//! its size in millimetres (`'UNKNOWN'` defined as 10 mm is `"10 mm"`). Tolerances a user gives
//! or a program defaults to are lengths in millimetres, converted with [`mm_per_unit`].

/// The unit names known, with their size in millimetres (exact by definition: the inch is
/// 25.4 mm since 1959, the mil a thousandth of it, the microinch a millionth, the mile 5280 ft).
pub const UNITS: [(&str, f64); 12] = [
    ("mm", 1.0),
    ("cm", 10.0),
    ("dm", 100.0),
    ("m", 1000.0),
    ("km", 1.0e6),
    ("um", 1.0e-3),
    ("nm", 1.0e-6),
    ("in", 25.4),
    ("ft", 304.8),
    ("mil", 0.0254),
    ("uin", 2.54e-5),
    ("mi", 1_609_344.0),
];

/// Other spellings of the names in [`UNITS`] (IGES unit names, STEP conversion-based unit
/// names, English words), lower case.
const ALIASES: [(&str, &str); 15] = [
    ("millimetre", "mm"),
    ("millimeter", "mm"),
    ("centimetre", "cm"),
    ("centimeter", "cm"),
    ("metre", "m"),
    ("meter", "m"),
    ("kilometre", "km"),
    ("kilometer", "km"),
    ("micron", "um"),
    ("µm", "um"),
    ("inch", "in"),
    ("inches", "in"),
    ("foot", "ft"),
    ("feet", "ft"),
    ("mile", "mi"),
];

/// The canonical name of a unit word (lower case, aliases resolved), if known.
fn canonical(word: &str) -> Option<&'static str> {
    let w = word.trim().to_lowercase();
    let w = ALIASES
        .iter()
        .find(|(a, _)| *a == w)
        .map_or(w.as_str(), |(_, c)| c);
    UNITS.iter().find(|(n, _)| *n == w).map(|(n, _)| *n)
}

/// Millimetres per `unit`: a known name (any case, with the aliases of IGES and STEP), the
/// microinch `uin`, or `"<factor> <unit>"` (a conversion-based unit); `None` for anything else.
pub fn mm_per_unit(unit: &str) -> Option<f64> {
    let text = unit.trim();
    if let Some(name) = canonical(text) {
        return Some(UNITS.iter().find(|(n, _)| *n == name)?.1);
    }
    let (factor, rest) = text.split_once(char::is_whitespace)?;
    let factor: f64 = factor.parse().ok()?;
    let base = mm_per_unit(rest)?;
    (factor.is_finite() && factor > 0.0).then_some(factor * base)
}

/// The text of a unit of `mm` millimetres: a name of [`UNITS`] when it is one of them (within
/// 1e-12 relative), else `"<mm> mm"`.
pub fn unit_text(mm: f64) -> String {
    UNITS
        .iter()
        .find(|(_, size)| (size - mm).abs() <= 1e-12 * size)
        .map_or_else(|| format!("{mm} mm"), |(n, _)| n.to_string())
}

/// The IGES unit flags 1–11 other than 3 (\[IGES\] §2.2.4.3, Global parameter 14) with the unit
/// each stands for.
const IGES_FLAGS: [(i64, &str); 10] = [
    (1, "in"),
    (2, "mm"),
    (4, "ft"),
    (5, "mi"),
    (6, "m"),
    (7, "km"),
    (8, "mil"),
    (9, "um"),
    (10, "cm"),
    (11, "uin"),
];

/// The unit text of an IGES file's Global unit flag and name: the flag's unit where the flag
/// names one, the name (flag 3, "refer to parameter 15") otherwise, lower case.
pub fn iges_unit(flag: i64, name: &str) -> String {
    IGES_FLAGS
        .iter()
        .find(|(f, _)| *f == flag)
        .map_or_else(|| name.trim().to_lowercase(), |(_, u)| u.to_string())
}

/// The IGES unit flag and name (parameters 14 and 15) of a model in `units`; `None` for a unit
/// IGES has no flag for (a conversion-based STEP unit, the decimetre).
pub fn iges_flag(units: &str) -> Option<(i64, String)> {
    let name = unit_text(mm_per_unit(units)?);
    IGES_FLAGS
        .iter()
        .find(|(_, u)| *u == name)
        .map(|&(f, u)| (f, u.to_uppercase()))
}

/// Why a length a user wrote ([`parse_length_mm`]) is not read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LengthError {
    /// No number before the unit (or no unit at all).
    #[error("{text:?} is not a length (a number of millimetres, or with a unit: 0.002in)")]
    NotALength {
        /// the text as given
        text: String,
    },
    /// A number with a unit suffix that is not in [`UNITS`] (nor one of its aliases).
    #[error("{text:?}: unknown unit {unit:?} (known: {})", UNITS.map(|(n, _)| n).join(", "))]
    UnknownUnit {
        /// the text as given
        text: String,
        /// the unit suffix, trimmed
        unit: String,
    },
}

/// A length a user writes, in millimetres: a number (millimetres) or a number with a unit
/// suffix (`0.002in`, `0.05 mm`, `1e-4m`).
pub fn parse_length_mm(text: &str) -> Result<f64, LengthError> {
    let t = text.trim();
    let split = t
        .char_indices()
        .find(|&(i, c)| {
            c.is_alphabetic() && !(matches!(c, 'e' | 'E') && number_goes_on(&t[i + c.len_utf8()..]))
        })
        .map_or(t.len(), |(i, _)| i);
    let (number, unit) = t.split_at(split);
    let value: f64 = number.trim().parse().map_err(|_| LengthError::NotALength {
        text: text.to_string(),
    })?;
    let scale = if unit.trim().is_empty() {
        1.0
    } else {
        mm_per_unit(unit).ok_or_else(|| LengthError::UnknownUnit {
            text: text.to_string(),
            unit: unit.trim().to_string(),
        })?
    };
    Ok(value * scale)
}

/// Whether `rest` continues an exponent (`e-4`, `E3`): a sign or a digit next.
fn number_goes_on(rest: &str) -> bool {
    rest.chars()
        .next()
        .is_some_and(|c| c.is_ascii_digit() || c == '-' || c == '+')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_aliases_and_conversions() {
        assert_eq!(mm_per_unit("mm"), Some(1.0));
        assert_eq!(mm_per_unit("M"), Some(1000.0));
        assert_eq!(mm_per_unit("metre"), Some(1000.0));
        assert_eq!(mm_per_unit("INCH"), Some(25.4));
        assert_eq!(mm_per_unit("ft"), Some(304.8));
        assert_eq!(mm_per_unit("10 mm"), Some(10.0));
        assert_eq!(mm_per_unit("2 in"), Some(50.8));
        assert_eq!(mm_per_unit("parsec"), None);
        assert_eq!(mm_per_unit("-1 mm"), None);
        assert_eq!(mm_per_unit(""), None);
    }

    #[test]
    fn unit_text_names_what_it_can() {
        assert_eq!(unit_text(1000.0), "m");
        assert_eq!(unit_text(25.4), "in");
        assert_eq!(unit_text(10.0), "cm");
        assert_eq!(unit_text(12.5), "12.5 mm");
        assert_eq!(mm_per_unit(&unit_text(12.5)), Some(12.5));
    }

    #[test]
    fn iges_flags_both_ways() {
        for (flag, unit) in IGES_FLAGS {
            assert_eq!(iges_unit(flag, ""), unit);
            assert_eq!(iges_flag(unit), Some((flag, unit.to_uppercase())));
        }
        assert_eq!(iges_unit(3, " INCH "), "inch");
        assert_eq!(iges_flag("inch"), Some((1, "IN".into())));
        assert_eq!(iges_flag("12.5 mm"), None);
        assert_eq!(iges_flag("parsec"), None);
    }

    #[test]
    fn lengths_with_and_without_units() {
        assert_eq!(parse_length_mm("0.05"), Ok(0.05));
        assert_eq!(parse_length_mm("0.05mm"), Ok(0.05));
        assert_eq!(parse_length_mm(" 0.002in "), Ok(0.002 * 25.4));
        assert_eq!(parse_length_mm("1e-4m"), Ok(0.1));
        assert_eq!(parse_length_mm("2E-3 M"), Ok(2.0));
        assert_eq!(parse_length_mm("5e2um"), Ok(0.5));
        assert!(
            parse_length_mm("0.1 parsec")
                .unwrap_err()
                .to_string()
                .contains("unknown unit")
        );
        assert!(parse_length_mm("in").is_err());
        assert!(parse_length_mm("x").is_err());
    }
}
