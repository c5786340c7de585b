//! `hier-fair`: the command line (see `cli-contract.md`). Every error is one line on stderr and a
//! non-zero exit code; nothing panics on bad input.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Result, bail};
use clap::{Parser, Subcommand};
use hier_fair_cli::{eval, files, summary};

#[derive(Parser)]
#[command(
    name = "hier-fair",
    version,
    about = "Constrained hierarchical fairing of B-spline surfaces"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Runs the main job on the bundled default model and prints a readable summary.
    Demo {
        /// Folder for output files (created if missing).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Evaluates a surface: point, derivatives, normal and curvatures as JSON.
    Eval {
        /// Surface file (one surface, a list, {"surfaces": [...]} or {"patches": [...]}).
        surface: PathBuf,
        /// Uniform grid NU,NV over the domain (both ends included, u slowest).
        #[arg(long, conflicts_with = "params", required_unless_present = "params")]
        grid: Option<String>,
        /// PARAMS.json: {"params": [[u, v], ...]}.
        #[arg(long)]
        params: Option<PathBuf>,
        /// Prints only {"count", "seconds", "checksum"}.
        #[arg(long)]
        summary: bool,
        /// Which surface of a multi-surface file (0-based; required when there are several).
        #[arg(long = "index")]
        index: Option<usize>,
    },
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Demo { out } => {
            let surface =
                nurbs_core::io::surfaces_from_json(hier_fair_cli::BUNDLED_SURFACE)?.remove(0);
            let start = std::time::Instant::now();
            let s = summary::summarize(&surface);
            let text = summary::render(
                "bundled hood panel (fixtures/surfaces/hood_panel.json)",
                &s,
                start.elapsed().as_secs_f64(),
            );
            print!("{text}");
            if let Some(dir) = out {
                std::fs::create_dir_all(&dir)
                    .map_err(|e| anyhow::anyhow!("cannot create {}: {e}", dir.display()))?;
                files::write_atomic(
                    &dir.join("summary.json"),
                    serde_json::to_string_pretty(&s)?.as_bytes(),
                )?;
                let mesh = nurbs_core::TriMesh::from_surface(&surface, 101, 101);
                let mut obj = Vec::new();
                mesh.write_obj(&mut obj)?;
                files::write_atomic(&dir.join("surface.obj"), &obj)?;
                println!(
                    "wrote {}/summary.json and {}/surface.obj",
                    dir.display(),
                    dir.display()
                );
            }
            Ok(())
        }
        Command::Eval {
            surface,
            grid,
            params,
            summary,
            index,
        } => {
            let mut surfaces = files::read_surfaces(&surface)?;
            let chosen = match (index, surfaces.len()) {
                (None, 1) => 0,
                (None, n) => bail!(
                    "{} holds {n} surfaces: choose one with --index K",
                    surface.display()
                ),
                (Some(k), n) if k >= n => bail!(
                    "--index {k} is out of range: {} holds {n} surfaces",
                    surface.display()
                ),
                (Some(k), _) => k,
            };
            let s = surfaces.swap_remove(chosen);
            let p = match (grid, params) {
                (Some(g), None) => eval::parse_grid(&g)?,
                (None, Some(path)) => {
                    eval::parse_params(&files::read_text(&path)?, &path.display().to_string())?
                }
                _ => bail!("give exactly one of --grid NU,NV and --params PARAMS.json"),
            };
            let (samples, seconds) = eval::evaluate(&s, &p)?;
            let text = if summary {
                eval::summary_json(&samples, seconds) + "\n"
            } else {
                eval::results_json(&samples)
            };
            use std::io::Write;
            let mut stdout = std::io::stdout().lock();
            if let Err(e) = stdout.write_all(text.as_bytes()) {
                if e.kind() != std::io::ErrorKind::BrokenPipe {
                    return Err(e.into());
                }
            }
            Ok(())
        }
    }
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", format!("{e:#}").replace('\n', " "));
            ExitCode::from(2)
        }
    }
}
