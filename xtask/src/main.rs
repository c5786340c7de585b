//! `cargo xtask <command>`:
//! - `snapshots [--update]` — runs the regression pipeline over `fixtures/` and compares with the
//!   insta snapshots (`--update` accepts the new values after review).
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
        Some("fixtures") => match write_fixtures() {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {e:#}");
                ExitCode::from(1)
            }
        },
        _ => {
            eprintln!("usage: cargo xtask snapshots [--update] | fixtures");
            ExitCode::from(2)
        }
    }
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
