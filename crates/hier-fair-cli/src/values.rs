//! The values of the command line's options: lengths in millimetres (with an optional unit),
//! a role's tolerance, a continuity.

/// A length of `--tolerance`, in millimetres ([`nurbs_io::units::parse_length_mm`]).
pub fn parse_length(s: &str) -> Result<f64, String> {
    nurbs_io::units::parse_length_mm(s).map_err(|e| e.to_string())
}

/// `ROLE=LENGTH` of `--tolerance-role`, the length in millimetres.
pub fn parse_role_tolerance(s: &str) -> Result<(hier_fair::Role, f64), String> {
    let (role, mm) = s
        .split_once('=')
        .ok_or_else(|| format!("expected ROLE=LENGTH (e.g. connecting=0.5), got {s:?}"))?;
    let role = hier_fair::Role::parse(role.trim())
        .ok_or_else(|| format!("unknown role {role:?}: expected primary, connecting or corner"))?;
    let mm = nurbs_io::units::parse_length_mm(mm).map_err(|e| e.to_string())?;
    if !(mm.is_finite() && mm > 0.0) {
        return Err(format!(
            "the tolerance of {} must be a finite length > 0, got {mm}",
            role.name()
        ));
    }
    Ok((role, mm))
}

/// A continuity of `--keep` and `--target`: G0, G1 or G2 (any case).
pub fn parse_keep(text: &str) -> Result<nurbs_core::Continuity, String> {
    match text.to_ascii_uppercase().as_str() {
        "G0" => Ok(nurbs_core::Continuity::G0),
        "G1" => Ok(nurbs_core::Continuity::G1),
        "G2" => Ok(nurbs_core::Continuity::G2),
        _ => Err(format!("expected G0, G1 or G2, got {text}")),
    }
}

/// A continuity of `--keep` and `--target` as clap reads it: G0, G1 or G2 (any case), listed in
/// `--help` as the option's possible values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ContinuityValue {
    /// positional
    #[value(name = "G0")]
    G0,
    /// tangent plane
    #[value(name = "G1")]
    G1,
    /// curvature
    #[value(name = "G2")]
    G2,
}

impl ContinuityValue {
    /// The kernel's continuity.
    pub fn continuity(self) -> nurbs_core::Continuity {
        match self {
            ContinuityValue::G0 => nurbs_core::Continuity::G0,
            ContinuityValue::G1 => nurbs_core::Continuity::G1,
            ContinuityValue::G2 => nurbs_core::Continuity::G2,
        }
    }
}
