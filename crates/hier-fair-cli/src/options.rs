//! The options of a model run ([`ModelOptions`]): what `fair` and `demo` pass to the pipeline
//! ([`crate::pipeline`]) and what the check of options a model does not use reads
//! ([`crate::applies`]).

use nurbs_core::Continuity;

/// Options of a model run.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ModelOptions {
    /// one method for every role, by its name in the program's registry ([`crate::methods`];
    /// `None`: the framework's default per role)
    pub method: Option<&'static str>,
    /// deviation tolerance in millimetres, whatever the model's unit (`None`: the model's)
    pub tolerance: Option<f64>,
    /// deviation tolerance per role (primary, connecting, corner) in millimetres, over the
    /// model's
    pub role_tolerance: [Option<f64>; 3],
    /// iteration limit of the methods
    pub iterations: Option<usize>,
    /// highest continuity set
    pub target: Option<Continuity>,
    /// no progress bar
    pub quiet: bool,
    /// no verification run for unmet links
    /// ([`FairParams::verify_unmet`](hier_fair::FairParams::verify_unmet))
    pub no_verify: bool,
    /// keep every method's result where it meets the links, even where the continuity setting
    /// alone is fairer ([`FairParams::prefer_fairer`](hier_fair::FairParams::prefer_fairer) false)
    pub keep_faired: bool,
    /// split every corner patch with a pole into three quads first
    /// ([`hier_fair::poles::split_pole_corners`])
    pub split_poles: bool,
}
