//! `hier-fair`: the command line (see `cli-contract.md` and [`hier_fair_cli::cli`]).

use std::process::ExitCode;

fn main() -> ExitCode {
    hier_fair_cli::cli::main_with(hier_fair::MethodRegistry::builtin())
}
