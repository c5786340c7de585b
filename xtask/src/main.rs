//! `cargo xtask <command>`:
//! - `snapshots [--update]` — runs the regression pipeline over `fixtures/` and compares with the
//!   insta snapshots (`--update` accepts the new values after review).

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
        _ => {
            eprintln!("usage: cargo xtask snapshots [--update]");
            ExitCode::from(2)
        }
    }
}
