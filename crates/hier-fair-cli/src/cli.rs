//! `hier-fair`: the command line (see `cli-contract.md`). Every error is one line on stderr and a
//! non-zero exit code; nothing panics on bad input.
//!
//! [`main_with`] is the whole program with a given method registry: a crate that adds its own
//! fairing method registers it and calls `main_with` from its `main`, and `--method` takes the
//! new name (`examples/custom_method.rs`).

use std::path::PathBuf;
use std::process::ExitCode;

use crate::kind::FileKind;
use crate::{eval, files};
use anyhow::{Result, bail};
use clap::{Parser, Subcommand};

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
    /// Reads a STEP file (faces, and surfaces outside faces) or IGES file (surfaces 128, 120, 122, 118, 140 and planes 108, 190, trimmed by 144, bounded by 143, or faces 510 of a B-rep solid 186), known by its content, into a model and finds its hierarchy (links, targets, roles) from the geometry
    Import {
        /// STEP or IGES file
        input: PathBuf,
        /// Model JSON to write
        #[arg(short = 'o', long = "output")]
        output: PathBuf,
        /// Prints every decision of the hierarchy (which side lies on which surface, at what distance and angle, why each role)
        #[arg(long)]
        explain: bool,
    },
    /// Finds the links and roles of a model from its geometry, keeping the links it has and its roles when it gives any
    Build {
        /// Model JSON
        input: PathBuf,
        /// Model JSON to write (never the input)
        #[arg(short = 'o', long = "output")]
        output: PathBuf,
        /// Prints every decision (which side lies on which surface, at what distance and angle, why each role)
        #[arg(long)]
        explain: bool,
    },
    /// Measures the continuity of every link of a model (gap, normal angle, curvature).
    Check {
        /// Model file (or a bare surface file: then there are no links).
        model: PathBuf,
        /// Samples per link, both ends included (default 101; on a file without links a warning).
        #[arg(long)]
        samples: Option<usize>,
        /// Prints JSON (cli-contract.md) instead of a table.
        #[arg(long)]
        json: bool,
        /// Exits with code 1 when a link exceeds the preset (up to its target continuity).
        #[arg(long, value_parser = ["class-a", "standard", "exchange"])]
        fail_above: Option<String>,
        /// Also measures every surface's fairness: peak curvature, mean-curvature spread, the
        /// curvature extrema across its linked sides, thin-plate energy, net and degree.
        #[arg(long)]
        fairness: bool,
        /// Also writes a quality report REPORT.html (one self-contained file to open offline:
        /// a 3D view with zebra and curvature shading, curvature combs across every link, the
        /// link and surface tables).
        #[arg(long)]
        html: Option<PathBuf>,
    },
    /// Sets continuity only (no fairing), slave by slave in hierarchy order.
    Connect {
        /// Model file.
        model: PathBuf,
        /// Output model file (written atomically; never the input).
        #[arg(short = 'o', long = "output")]
        output: PathBuf,
        /// Highest continuity set, G0, G1 or G2 (a cap on each link's own; default: each link's own).
        #[arg(long, value_enum, ignore_case = true)]
        target: Option<crate::values::ContinuityValue>,
        /// Report JSON with before/after continuity per link.
        #[arg(long)]
        report: Option<PathBuf>,
    },
    /// Hierarchical fairing of a model (masters first, continuity set then kept, \[SV\] §3.2), or
    /// fairing of a bare surface file (boundaries and shared edges kept).
    Fair(FairArgs),
    /// Writes the surfaces of a model as STEP (AP214 B-spline faces) or IGES 5.3 (entity 128, trimmed by 144), as the output's extension names.
    Export {
        /// Model JSON (or a bare surface file)
        input: PathBuf,
        /// STEP (.step, .stp) or IGES (.igs, .iges) file to write
        #[arg(short = 'o', long = "output")]
        output: PathBuf,
    },
    /// Runs the main job on the bundled X-node model: fairs it, writes the faired model, the
    /// report and the pictures into a folder and prints a readable summary.
    Demo {
        /// Folder of the results (made if missing; its parent must exist)
        #[arg(long, default_value = "hier-fair-demo")]
        out: PathBuf,
        /// no progress bar
        #[arg(long)]
        quiet: bool,
    },
    /// Evaluates a surface: point, derivatives, normal and curvatures, as JSON on stdout.
    Eval(EvalArgs),
    /// Discrete thin-plate fairing of a triangle mesh region (boundary and K rings fixed).
    FairMesh {
        /// OBJ mesh (polygons are split into triangles)
        input: PathBuf,
        /// OBJ to write
        #[arg(short = 'o', long = "output")]
        output: PathBuf,
        /// Rings fixed beyond the boundary
        #[arg(long, default_value_t = 2)]
        fixed_rings: usize,
        /// JSON list of further vertex indices (0-based) to keep fixed
        #[arg(long)]
        fixed: Option<PathBuf>,
        /// Largest distance a vertex may move (model units): the fairest mesh within it
        #[arg(long, allow_negative_numbers = true)]
        tolerance: Option<f64>,
    },
    /// Labels the boundary segments of a trimmed mesh region (and fits a surface with --fit).
    Label {
        /// OBJ mesh region
        input: PathBuf,
        /// JSON segments (lists of boundary vertex indices); found automatically when absent
        #[arg(long)]
        segments: Option<PathBuf>,
        /// labels JSON to write
        #[arg(short = 'o', long = "output")]
        output: PathBuf,
        /// SVG drawing of the labeled boundary
        #[arg(long)]
        svg: Option<PathBuf>,
        /// bicubic surface fitted with the labels
        #[arg(long)]
        fit: Option<PathBuf>,
    },
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Check {
            model,
            samples,
            json,
            fail_above,
            fairness,
            html,
        } => crate::check::command(model, samples, json, fail_above, fairness, html),
        Command::Connect {
            model,
            output,
            target,
            report,
        } => connect_command(
            model,
            output,
            target.map(crate::values::ContinuityValue::continuity),
            report,
        ),
        Command::FairMesh {
            input,
            output,
            fixed_rings,
            fixed,
            tolerance,
        } => fair_mesh_command(input, output, fixed_rings, fixed, tolerance),
        Command::Label {
            input,
            segments,
            output,
            svg,
            fit,
        } => label_command(input, segments, output, svg, fit),
        Command::Import {
            input,
            output,
            explain,
        } => {
            files::check_outputs(&[("-o", &output)], &[&input])?;
            crate::kind::expect_extension("-o", &output, crate::kind::JSON_OUTPUTS)?;
            println!("{}", crate::exchange::import(&input, &output, explain)?);
            Ok(())
        }
        Command::Build {
            input,
            output,
            explain,
        } => build_command(input, output, explain),
        Command::Export { input, output } => {
            files::check_outputs(&[("-o", &output)], &[&input])?;
            println!("{}", crate::exchange::export(&input, &output)?);
            Ok(())
        }
        Command::Demo { out, quiet } => {
            files::check_output_folder("--out", &out, &[])?;
            print!("{}", crate::pipeline::demo(&out, quiet)?);
            Ok(())
        }
        Command::Fair(args) => fair_command(args),
        Command::Eval(args) => eval_command(args),
    }
}

/// `hier-fair fair-mesh`.
fn fair_mesh_command(
    input: PathBuf,
    output: PathBuf,
    fixed_rings: usize,
    fixed: Option<PathBuf>,
    tolerance: Option<f64>,
) -> Result<()> {
    let mut inputs = vec![input.as_path()];
    inputs.extend(fixed.as_deref());
    files::check_outputs(&[("-o", &output)], &inputs)?;
    crate::kind::expect("fair-mesh", &input, &[crate::kind::FileKind::Obj])?;
    crate::kind::expect_option("fair-mesh --fixed", fixed.as_deref(), FileKind::Indices)?;
    crate::kind::expect_extension("-o", &output, crate::kind::MESH_OUTPUTS)?;
    println!(
        "{}",
        crate::mesh::run(&input, &output, fixed_rings, fixed.as_deref(), tolerance)?
    );
    Ok(())
}

/// `hier-fair build`.
fn build_command(input: PathBuf, output: PathBuf, explain: bool) -> Result<()> {
    files::check_outputs(&[("-o", &output)], &[&input])?;
    crate::kind::expect("build", &input, &[FileKind::Model, FileKind::Surfaces])?;
    crate::kind::expect_extension("-o", &output, crate::kind::JSON_OUTPUTS)?;
    println!("{}", crate::exchange::build(&input, &output, explain)?);
    Ok(())
}

/// `hier-fair connect`.
fn connect_command(
    model: PathBuf,
    output: PathBuf,
    target: Option<nurbs_core::Continuity>,
    report: Option<PathBuf>,
) -> Result<()> {
    let mut outputs = vec![("-o", output.as_path())];
    outputs.extend(report.as_deref().map(|r| ("--report", r)));
    files::check_outputs(&outputs, &[&model])?;
    crate::kind::expect(
        "connect",
        &model,
        &[
            crate::kind::FileKind::Model,
            crate::kind::FileKind::Surfaces,
        ],
    )?;
    crate::kind::expect_extension("-o", &output, crate::kind::JSON_OUTPUTS)?;
    if let Some(r) = &report {
        crate::kind::expect_extension("--report", r, crate::kind::JSON_OUTPUTS)?;
    }
    let text = files::read_text(&model)?;
    let outcome = crate::connect::run(&text, &model.display().to_string(), target)?;
    files::write_atomic(&output, outcome.model_json.as_bytes())?;
    if let Some(r) = &report {
        files::write_atomic(
            r,
            (serde_json::to_string_pretty(&outcome.report)? + "\n").as_bytes(),
        )?;
    }
    print!("{}", outcome.summary);
    println!("{}; wrote {}", outcome.verdict, output.display());
    Ok(())
}

/// `hier-fair label`.
fn label_command(
    input: PathBuf,
    segments: Option<PathBuf>,
    output: PathBuf,
    svg: Option<PathBuf>,
    fit: Option<PathBuf>,
) -> Result<()> {
    let mut outputs = vec![("-o", output.as_path())];
    outputs.extend(svg.as_deref().map(|p| ("--svg", p)));
    outputs.extend(fit.as_deref().map(|p| ("--fit", p)));
    let mut inputs = vec![input.as_path()];
    inputs.extend(segments.as_deref());
    files::check_outputs(&outputs, &inputs)?;
    crate::kind::expect("label", &input, &[crate::kind::FileKind::Obj])?;
    crate::kind::expect_option("label --segments", segments.as_deref(), FileKind::Segments)?;
    crate::kind::expect_extension("-o", &output, crate::kind::JSON_OUTPUTS)?;
    if let Some(p) = &svg {
        crate::kind::expect_extension("--svg", p, crate::kind::SVG_OUTPUTS)?;
    }
    if let Some(p) = &fit {
        crate::kind::expect_extension("--fit", p, crate::kind::JSON_OUTPUTS)?;
    }
    let out = crate::label::LabelOutputs {
        labels: &output,
        svg: svg.as_deref(),
        fit: fit.as_deref(),
    };
    print!("{}", crate::label::run(&input, segments.as_deref(), out)?);
    Ok(())
}

/// `hier-fair eval`.
fn eval_command(args: EvalArgs) -> Result<()> {
    let EvalArgs {
        surface,
        grid,
        params,
        summary,
        index,
    } = args;
    crate::kind::expect_option("eval --params", params.as_deref(), FileKind::Params)?;
    // a model's surfaces are evaluated as a surface file's are (chosen by --index)
    let mut surfaces =
        match crate::kind::expect("eval", &surface, &[FileKind::Surfaces, FileKind::Model])? {
            FileKind::Model => hier_fair::Model::from_json(&files::read_text(&surface)?)
                .map_err(|e| anyhow::anyhow!("{}: {e}", surface.display()))?
                .surfaces
                .into_iter()
                .map(|s| s.surface)
                .collect(),
            _ => files::read_surfaces(&surface)?,
        };
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
    let text = match (&p, summary) {
        (eval::Params::Grid(nu, nv), true) => {
            let (count, seconds, checksum) = eval::summarize_grid(&s, *nu, *nv);
            eval::summary_text(count, seconds, checksum) + "\n"
        }
        _ => {
            let count = match &p {
                eval::Params::Grid(nu, nv) => nu * nv,
                eval::Params::List(list) => list.len(),
            };
            if !summary && count > eval::MAX_LISTED_SAMPLES {
                bail!(
                    "listing {count} samples is above the bound of {} (about 2 GB of JSON): use --summary or fewer samples",
                    eval::MAX_LISTED_SAMPLES
                );
            }
            let (samples, seconds) = eval::evaluate(&s, &p)?;
            if summary {
                eval::summary_json(&samples, seconds) + "\n"
            } else {
                eval::results_json(&samples)
            }
        }
    };
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    if let Err(e) = stdout.write_all(text.as_bytes())
        && e.kind() != std::io::ErrorKind::BrokenPipe
    {
        return Err(e.into());
    }
    Ok(())
}

/// The `--tolerance-role` lengths by role rank (primary, connecting, corner), the last given
/// for a role winning.
fn by_role(given: &[(hier_fair::Role, f64)]) -> [Option<f64>; 3] {
    let mut out = [None; 3];
    for &(role, mm) in given {
        out[role.rank()] = Some(mm);
    }
    out
}

/// Validates `fair`'s outputs before any work: none an input or another output, the report
/// page an `.html` file, the pictures' folder one that takes new files.
fn check_fair_outputs(args: &FairArgs) -> Result<()> {
    let input = args.input.as_path();
    let mut outputs = vec![("-o", args.output.as_path())];
    outputs.extend(args.report.as_deref().map(|r| ("--report", r)));
    outputs.extend(args.html.as_deref().map(|h| ("--html", h)));
    files::check_outputs(&outputs, &[input])?;
    if let Some(h) = &args.html {
        crate::kind::expect_extension("--html", h, crate::kind::HTML_OUTPUTS)?;
    }
    if let Some(dir) = &args.images {
        files::check_output_folder("--images", dir, &[input])?;
    }
    Ok(())
}

/// `hier-fair fair`: a model (or a STEP/IGES file) through the framework, or a bare surface file.
fn fair_command(args: FairArgs) -> Result<()> {
    check_fair_outputs(&args)?;
    let FairArgs {
        input,
        output,
        method,
        tolerance,
        tolerance_role,
        iterations,
        keep,
        target,
        report,
        images,
        html,
        quiet,
        no_verify,
        keep_faired,
        split_poles,
    } = args;
    let keep = keep.map(crate::values::ContinuityValue::continuity);
    let target = target.map(crate::values::ContinuityValue::continuity);
    let method = registered_method(method.as_deref(), iterations)?;
    let role_tolerance = by_role(&tolerance_role);
    let iges = crate::kind::fair_input_is_cad(&input, report.as_deref())?;
    let text = if iges {
        String::new()
    } else {
        files::read_text(&input)?
    };
    if iges || crate::pipeline::is_model(&text) {
        crate::kind::expect_model_run(&input, &output, iges, keep.is_some())?;
        let options = crate::options::ModelOptions {
            method,
            tolerance,
            role_tolerance,
            iterations,
            target,
            quiet,
            no_verify,
            keep_faired,
            split_poles,
        };
        let outcome = crate::pipeline::run_fair(
            &input,
            &text,
            &output,
            report.as_deref(),
            images.as_deref(),
            html.as_deref(),
            &options,
        )?;
        crate::pipeline::finish(outcome, quiet);
        return Ok(());
    }
    let model_options = [
        ("--images", images.is_some()),
        ("--target", target.is_some()),
        ("--tolerance-role", role_tolerance != [None; 3]),
        ("--keep-faired", keep_faired),
        ("--no-verify", no_verify),
        ("--split-poles", split_poles),
    ];
    let options = crate::fair::FairOptions {
        method: method.unwrap_or(hier_fair::Method::Energy.name()),
        tolerance: tolerance.unwrap_or(0.02),
        iterations,
        keep: keep.unwrap_or(nurbs_core::Continuity::G0),
    };
    let outputs = (report.as_deref(), html.as_deref());
    fair_surfaces(&input, &output, outputs, &options, &model_options, quiet)
}

/// `fair` on a bare surface file (with its report and page, each where asked for): each surface
/// faired alone, boundaries kept; the model options
/// (`model_options`, each with whether it was given) do not apply and are refused; with `quiet`
/// the verdict line alone is printed, as on a model.
fn fair_surfaces(
    input: &std::path::Path,
    output: &std::path::Path,
    (report, html): (Option<&std::path::Path>, Option<&std::path::Path>),
    options: &crate::fair::FairOptions,
    model_options: &[(&str, bool)],
    quiet: bool,
) -> Result<()> {
    crate::kind::expect_extension("-o", output, crate::kind::JSON_OUTPUTS)?;
    crate::kind::refuse_model_options(input, model_options)?;
    let text = crate::fair::run(input, output, report, html, options)?;
    match text.lines().last() {
        Some(verdict) if quiet => println!("{verdict}"),
        _ => print!("{text}"),
    }
    Ok(())
}

/// The registered method named `name` ([`crate::methods`]), checked against `--iterations`
/// (a direct solve has no iteration limit).
fn registered_method(
    name: Option<&str>,
    iterations: Option<usize>,
) -> Result<Option<&'static str>> {
    let Some(name) = name else {
        return Ok(None);
    };
    let m = crate::methods().entry(name)?;
    if let Some(n) = iterations
        && !m.takes_iterations
    {
        let with: Vec<&str> = crate::methods()
            .entries()
            .iter()
            .filter(|e| e.takes_iterations)
            .map(|e| e.name)
            .collect();
        bail!(
            "--iterations {n}: the method {} is a direct solve with no iteration limit (--iterations applies to {})",
            m.name,
            with.join(", ")
        );
    }
    Ok(Some(m.name))
}

/// Arguments of `hier-fair eval`.
#[derive(clap::Args)]
struct EvalArgs {
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
}

/// Arguments of `hier-fair fair`.
#[derive(clap::Args)]
struct FairArgs {
    /// Model or bare surface file (JSON, model-format.md), or a STEP or IGES file (imported as by `import`)
    input: PathBuf,
    /// Output file (written atomically; never the input or another output): .json, or for a model .step, .stp, .igs, .iges
    #[arg(short = 'o', long = "output")]
    output: PathBuf,
    /// the method for every surface: energy (default), energy-global, energy-bezier, krr,
    /// curvature, greiner, or one the program registered (`cli::main_with`)
    #[arg(long)]
    method: Option<String>,
    /// deviation tolerance, a length in millimetres or with a unit (0.05, 0.002in, 5e-5m),
    /// converted to the model's unit (default: the model's; 0.02 mm for a bare surface)
    #[arg(long, allow_negative_numbers = true, value_parser = crate::values::parse_length)]
    tolerance: Option<f64>,
    /// models: deviation tolerance of one role, ROLE=LENGTH in millimetres or with a unit
    /// (primary, connecting, corner; repeatable); a surface's own "deviation" in the model
    /// still wins
    #[arg(long = "tolerance-role", value_parser = crate::values::parse_role_tolerance)]
    tolerance_role: Vec<(hier_fair::Role, f64)>,
    /// iteration limit of the iterative methods (energy, energy-global polish,
    /// energy-bezier, krr); default: each method's own
    #[arg(long)]
    iterations: Option<usize>,
    /// bare surfaces: the frame kept on all four sides, G0, G1 or G2 (default G0; a model's
    /// links choose its frames: refused there)
    #[arg(long, value_enum, ignore_case = true)]
    keep: Option<crate::values::ContinuityValue>,
    /// models: the highest continuity set on any link, G0, G1 or G2 (a cap on each link's own)
    #[arg(long, value_enum, ignore_case = true)]
    target: Option<crate::values::ContinuityValue>,
    /// report JSON (per surface, per link, problems; cli-contract.md)
    #[arg(long)]
    report: Option<PathBuf>,
    /// models: write pictures (zebra, mean curvature, link curvature plots) into DIR
    #[arg(long)]
    images: Option<PathBuf>,
    /// models: write a quality report REPORT.html, one self-contained file to open offline: a
    /// 3D view with zebra, curvature and deviation shading, curvature combs across every link,
    /// before / after, and the link and surface tables
    #[arg(long)]
    html: Option<PathBuf>,
    /// no progress bar, and the verdict line alone on stdout (the report file holds the rest)
    #[arg(long)]
    quiet: bool,
    /// models: no second run naming the deviation each unmet link needs (faster where links
    /// are left unmet; the report then names only what the first run found)
    #[arg(long)]
    no_verify: bool,
    /// models: keep the fairing method's result of every surface that meets its links, even
    /// where the continuity setting alone is fairer (by default a surface whose faired peak
    /// curvature is beyond 1.6× its input's keeps the fairer setting)
    #[arg(long)]
    keep_faired: bool,
    /// models: split every corner patch with a pole (a side collapsed to a point, e.g. a sphere
    /// octant) into three quads faired as a corner group (\[SV\] §3.4); the output holds the
    /// quads, named PATCH.q0 … PATCH.q2, and the report says what was split
    #[arg(long)]
    split_poles: bool,
}

/// The error and its causes on one line, each cause once: error types that print their source
/// in their own message (thiserror's `{source}`) would otherwise repeat it.
fn one_line(e: &anyhow::Error) -> String {
    let mut out = String::new();
    for cause in e.chain() {
        let text = cause.to_string().replace('\n', " ");
        if out.contains(&text) {
            continue;
        }
        if !out.is_empty() {
            out.push_str(": ");
        }
        out.push_str(&text);
    }
    out
}

/// The program with the methods of `methods` behind `--method` (the built-in ones:
/// [`hier_fair::MethodRegistry::builtin`]): parses the arguments, runs the subcommand, prints
/// an error as one line. Call it once, from `main`.
pub fn main_with(methods: hier_fair::MethodRegistry) -> ExitCode {
    if crate::set_methods(methods).is_err() {
        eprintln!("error: the method registry was set twice");
        return ExitCode::from(2);
    }
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
            eprintln!("error: {}", one_line(&e));
            ExitCode::from(2)
        }
    }
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    /// Every subcommand and every argument has a help text (`hier-fair help`, `--help`).
    #[test]
    fn every_subcommand_and_option_has_help() {
        let cli = super::Cli::command();
        for sub in cli.get_subcommands() {
            assert!(sub.get_about().is_some(), "{} has no help", sub.get_name());
            for arg in sub.get_arguments() {
                let id = arg.get_id().as_str();
                if id == "help" || id == "version" {
                    continue;
                }
                assert!(
                    arg.get_help().is_some(),
                    "{} {id} has no help",
                    sub.get_name()
                );
            }
        }
    }
}
