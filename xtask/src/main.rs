//! `cargo xtask <command>`:
//! - `snapshots [--update]` — runs the regression pipeline over `fixtures/` and compares with the
//!   insta snapshots (`--update` accepts the new values after review).
//! - `regress [--external DIR] [--foreign DIR]` — runs the framework on every fixture model and
//!   on the third-party models of the external DIR (default `fixtures/third_party`:
//!   car_shell1.model.json, submarine_body.model.json, teapot.json) and prints one summary
//!   table; then imports and fairs every STEP and IGES file of `fixtures/foreign/` and of the
//!   foreign DIR (default `../shared/data/foreign` beside the repository, skipped with a note
//!   where absent) and prints a table of links met, conflicts, unmet links and shared edges
//!   left worse, a line per file.
//! - `fixtures` — writes the analytic fixture models of `fixtures/models/` (see
//!   `xtask::fixtures`).

use std::process::{Command, ExitCode};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("snapshots") => {
            let update = args.iter().any(|a| a == "--update");
            let mut cmd = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
            cmd.args(["test", "-p", "xtask", "--test", "snapshots"]);
            if update {
                cmd.env("INSTA_UPDATE", "always");
            } else {
                cmd.env("INSTA_UPDATE", "no");
            }
            match cmd.status() {
                Ok(s) if s.success() => ExitCode::SUCCESS,
                Ok(_) => ExitCode::from(1),
                Err(e) => {
                    eprintln!("error: cannot run cargo: {e}");
                    ExitCode::from(2)
                }
            }
        }
        Some("regress") => {
            let external = folder(&args, "--external", "fixtures/third_party");
            let foreign = folder(&args, "--foreign", "../shared/data/foreign");
            match regress(&external, &foreign) {
                Ok(true) => ExitCode::SUCCESS,
                Ok(false) => ExitCode::from(1),
                Err(e) => {
                    eprintln!("error: {e:#}");
                    ExitCode::from(1)
                }
            }
        }
        Some("fixtures") => match write_fixtures() {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e:#}");
                ExitCode::from(1)
            }
        },
        _ => {
            eprintln!(
                "usage: cargo xtask snapshots [--update] | regress [--external DIR] [--foreign DIR] | fixtures"
            );
            ExitCode::from(2)
        }
    }
}

/// The folder after `flag` in `args`, else `default` under the repository root.
fn folder(args: &[String], flag: &str, default: &str) -> std::path::PathBuf {
    args.iter()
        .position(|a| a == flag)
        .and_then(|k| args.get(k + 1))
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| xtask::root().join(default))
}

fn write_fixtures() -> anyhow::Result<()> {
    let dir = xtask::root().join("fixtures/models");
    std::fs::create_dir_all(&dir)?;
    for (name, model) in xtask::fixtures::all()? {
        let path = dir.join(format!("{name}.json"));
        let text = serde_json::to_string(&model)? + "\n";
        let tmp = dir.join(format!(".{name}.json.tmp"));
        std::fs::write(&tmp, text)?;
        std::fs::rename(&tmp, &path)?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// Prints the regression table and the foreign-file table; false when a model or file cannot
/// be run at all.
fn regress(external: &std::path::Path, foreign: &std::path::Path) -> anyhow::Result<bool> {
    let (table, ok) = xtask::regress_table(external)?;
    print!("{table}");
    let mut dirs = vec![xtask::root().join("fixtures/foreign")];
    if foreign.is_dir() {
        dirs.push(foreign.to_path_buf());
    } else {
        println!("{} not found: its files skipped", foreign.display());
    }
    let (table, foreign_ok) = xtask::foreign_table(&dirs)?;
    print!("{table}");
    Ok(ok && foreign_ok)
}
