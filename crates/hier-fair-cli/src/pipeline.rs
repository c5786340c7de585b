//! `hier-fair fair MODEL.json` and `hier-fair demo`: the hierarchical fairing of a whole model
//! (hier-fair's framework), its outputs — faired model (JSON, IGES), `report.json`,
//! `report.md`, pictures — and a progress bar on a terminal.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use hier_fair::render::{self, Shading, View};
use hier_fair::{FairModelReport, FairParams, LinkFair, Model, Progress, RoleMethods};
use nurbs_core::BSplineSurface;

use crate::files;
use crate::options::ModelOptions;

/// The model bundled in the binary for `hier-fair demo`: the X-node of `fixtures/models/`
/// (a corner patch linked G2 to four fillets, made G1-only, \[SV\] Fig. 6).
pub(crate) const DEMO_MODEL: &str = include_str!("../../../fixtures/models/x_node.json");

/// Whether JSON text is a model (surfaces with names and roles) rather than a bare surface file.
pub fn is_model(text: &str) -> bool {
    serde_json::from_str::<serde_json::Value>(text)
        .ok()
        .and_then(|v| {
            v.get("surfaces")?
                .as_array()?
                .first()
                .map(|s| s.get("surface").is_some())
        })
        .unwrap_or(false)
}

/// Runs the framework on `model` with a progress bar when stdout is a terminal.
pub fn fair(model: &Model, options: &ModelOptions) -> Result<(Model, FairModelReport)> {
    if let Some(t) = options.tolerance
        && !(t.is_finite() && t > 0.0)
    {
        bail!("--tolerance must be a finite length > 0, got {t}");
    }
    let built = match options.method {
        Some(m) => crate::methods().build_roles([m; 3], options.iterations)?,
        None => hier_fair::BuiltMethods::new(&RoleMethods::default(), options.iterations),
    };
    // the lengths a user gives are millimetres; the framework takes the model's unit
    let in_units = |mm: f64| mm / model.mm_per_unit();
    let params = FairParams {
        target: options.target,
        tolerance: options.tolerance.map(in_units),
        role_tolerance: options.role_tolerance.map(|t| t.map(in_units)),
        verify_unmet: !options.no_verify,
        prefer_fairer: !options.keep_faired,
        ..FairParams::default()
    };
    let show = !options.quiet && std::io::stdout().is_terminal();
    let bar = if show {
        let bar = indicatif::ProgressBar::new(model.surfaces.len() as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} surfaces {msg}")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        Some(bar)
    } else {
        None
    };
    let progress = |p: Progress<'_>| {
        if let Some(b) = &bar {
            b.set_position(p.done as u64);
            b.set_message(p.name.to_string());
        }
    };
    let result = hier_fair::fair_model_with(model, built.fairers(), &params, &progress);
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    Ok(result?)
}

fn png(path: &Path, img: &image::RgbImage) -> Result<()> {
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .with_context(|| format!("cannot encode {}", path.display()))?;
    files::write_atomic(path, &bytes)
}

/// Picture size (pixels).
pub(crate) const IMAGE_SIZE: (u32, u32) = (900, 700);

/// Writes the pictures into `dir`: zebra and mean-curvature maps before and after (one fixed
/// view, one colour range for both), one curvature plot per link (slave and master normal
/// curvature across the boundary along the link, before light, after dark), one profile plot
/// across each surface that hangs on masters, and zebra and mean-curvature views zoomed on
/// each corner patch ([`crate::corner_views`]). Returns the files.
pub fn write_images(
    dir: &Path,
    original: &Model,
    faired: &Model,
    report: &FairModelReport,
) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let unit = original.units.as_deref().unwrap_or("model unit");
    let mut written = write_maps(dir, original, faired, unit)?;
    for l in &report.links {
        written.push(write_link_plot(dir, l, unit)?);
    }
    for k in 0..original.surfaces.len().min(faired.surfaces.len()) {
        for along in hier_fair::fairness::cross_directions(original, k) {
            written.push(write_profile_plot(dir, original, faired, k, along, unit)?);
        }
    }
    let unmet: Vec<usize> = report
        .links
        .iter()
        .filter(|l| !l.met)
        .map(|l| l.link)
        .collect();
    written.extend(crate::corner_views::write_corner_views(
        dir, original, faired, &unmet, unit, &png,
    )?);
    Ok(written)
}

/// Samples of a cross-section profile plot: 201, a sample every 0.5 % of the section, so that a
/// lead-in of a twentieth of it is drawn by ten points.
const PROFILE_PLOT_SAMPLES: usize = 201;

/// The curvature plot across slave `k` through the middle of its linked sides (the iso-line
/// running in `along` at the middle of the other parameter): the normal curvature in the
/// line's direction before (light) and after (dark) — the comb a surfacer reads across a
/// fillet (one hump: the lead-ins rise once and fall once). Returns the file.
fn write_profile_plot(
    dir: &Path,
    original: &Model,
    faired: &Model,
    k: usize,
    along: nurbs_core::Direction,
    unit: &str,
) -> Result<PathBuf> {
    let name = &original.surfaces[k].name;
    let profile = |s: &BSplineSurface| -> Vec<(f64, f64)> {
        let p = nurbs_core::fairness::cross_profile(s, along, 0.5, PROFILE_PLOT_SAMPLES);
        let n = (p.len().max(2) - 1) as f64;
        p.iter()
            .enumerate()
            .filter_map(|(i, v)| v.map(|v| (i as f64 / n, v)))
            .collect()
    };
    let curves = vec![
        hier_fair::plots::Series {
            label: "before".to_string(),
            points: profile(&original.surfaces[k].surface),
            colour: image::Rgb([240, 150, 150]),
            dashed: false,
        },
        hier_fair::plots::Series {
            label: "after".to_string(),
            points: profile(&faired.surfaces[k].surface),
            colour: image::Rgb([200, 20, 20]),
            dashed: false,
        },
    ];
    let (param, other) = match along {
        nurbs_core::Direction::U => ("u", "v"),
        nurbs_core::Direction::V => ("v", "u"),
    };
    let file = format!(
        "profile_{}_{param}.png",
        name.replace(|c: char| !c.is_ascii_alphanumeric() && c != '_', "_")
    );
    curvature_plot(
        &dir.join(file),
        &format!("{name}: normal curvature across, along {param} at {other} = middle"),
        &format!("{param} from side to side (0 to 1)"),
        unit,
        &curves,
    )
}

/// A curvature line plot (720 × 320, curvature in 1/`unit`) written to `path`; returns it.
fn curvature_plot(
    path: &Path,
    title: &str,
    x_desc: &str,
    unit: &str,
    curves: &[hier_fair::plots::Series],
) -> Result<PathBuf> {
    let plot = hier_fair::plots::line_plot(
        title,
        x_desc,
        &format!("curvature (1/{unit})"),
        curves,
        720,
        320,
    )
    .map_err(|e| anyhow::anyhow!(e))?;
    png(path, &plot)?;
    Ok(path.to_path_buf())
}

/// The zebra pictures (two views) and the mean-curvature map of the model `before` and `after`
/// (trimmed faces by their trims), in the views, stripe density and colour range of `before`,
/// each titled and labelled; returns the files.
fn write_maps(dir: &Path, before: &Model, after: &Model, unit: &str) -> Result<Vec<PathBuf>> {
    let owned = |m: &Model| -> Vec<(BSplineSurface, Vec<Vec<nurbs_core::Point3>>)> {
        m.surfaces
            .iter()
            .map(|s| (s.surface.clone(), s.trim.clone()))
            .collect()
    };
    let (b, a) = (owned(before), owned(after));
    let surfaces: Vec<&BSplineSurface> = b.iter().map(|f| &f.0).collect();
    let points = render::sample_points(&surfaces);
    let view = View::for_points(&points, IMAGE_SIZE.0, IMAGE_SIZE.1);
    let side_view = View::second_for_points(&points, IMAGE_SIZE.0, IMAGE_SIZE.1);
    let range = render::curvature_range(&surfaces);
    let stripes = render::zebra_stripes(&crate::corner_views::faces(&b), &view);
    let zebra = Shading::Zebra { stripes };
    let mut written = Vec::new();
    for (name, owned) in [("before", &b), ("after", &a)] {
        let faces = crate::corner_views::faces(owned);
        for (suffix, v, what) in [
            ("", &view, "zebra"),
            ("_second_view", &side_view, "zebra, second view"),
        ] {
            let path = dir.join(format!("zebra_{name}{suffix}.png"));
            let img = render::render_faces(&faces, v, zebra);
            png(
                &path,
                &hier_fair::plots::titled(&img, &format!("the model: {what}"), name),
            )?;
            written.push(path);
        }
        let path = dir.join(format!("mean_curvature_{name}.png"));
        let map = crate::corner_views::mean_curvature_map(&faces, &view, range, unit)?;
        png(
            &path,
            &hier_fair::plots::titled(&map, "the model: mean curvature", name),
        )?;
        written.push(path);
    }
    Ok(written)
}

/// The curvature plot of link `l`: slave and master normal curvature across the join along the
/// slave side, before light, after dark; returns the file.
fn write_link_plot(dir: &Path, l: &LinkFair, unit: &str) -> Result<PathBuf> {
    // light before, dark after; the slave solid red, the master dashed blue
    let curves: Vec<hier_fair::plots::Series> = [
        ("slave before", &l.before, true, [240, 150, 150], false),
        ("master before", &l.before, false, [150, 170, 240], true),
        ("slave after", &l.after, true, [200, 20, 20], false),
        ("master after", &l.after, false, [20, 50, 200], true),
    ]
    .into_iter()
    .map(
        |(label, m, slave, colour, dashed)| hier_fair::plots::Series {
            label: label.to_string(),
            points: curvature_along(m, slave),
            colour: image::Rgb(colour),
            dashed,
        },
    )
    .collect();
    let file = format!(
        "curvature_{}.png",
        l.label
            .replace(" -> ", "_on_")
            .replace(|c: char| !c.is_ascii_alphanumeric() && c != '_', "_")
    );
    curvature_plot(
        &dir.join(file),
        &format!("{}: normal curvature across the join", l.label),
        "t along the slave side (0 to 1)",
        unit,
        &curves,
    )
}

/// The slave's (or master's) normal curvature at the samples of `m` as (t ∈ [0, 1], κ), the
/// samples where it is undefined left out; empty without a measure.
fn curvature_along(m: &Option<g_continuity::LinkMeasure>, slave: bool) -> Vec<(f64, f64)> {
    m.as_ref().map_or_else(Vec::new, |m| {
        let n = m.detail.len().max(2) - 1;
        m.detail
            .iter()
            .enumerate()
            .filter_map(|(k, d)| {
                let v = if slave { d.kappa_slave } else { d.kappa_master };
                v.map(|v| (k as f64 / n as f64, v))
            })
            .collect()
    })
}

/// The faired model as IGES 5.3 (surfaces named as in the model).
pub fn model_iges(model: &Model) -> Result<String> {
    let surfaces: Vec<(&str, &BSplineSurface)> = model
        .surfaces
        .iter()
        .map(|s| (s.name.as_str(), &s.surface))
        .collect();
    Ok(nurbs_io::write_iges(
        &surfaces,
        &[],
        &nurbs_io::IgesWriteParams::default(),
    )?)
}

/// The `demo` subcommand: fairs the bundled X-node and writes everything into `dir`.
pub fn demo(dir: &Path, quiet: bool) -> Result<String> {
    let model = Model::from_json(DEMO_MODEL).context("the bundled model")?;
    let options = ModelOptions {
        quiet,
        ..ModelOptions::default()
    };
    let (faired, report) = fair(&model, &options)?;
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    files::write_atomic(&dir.join("model.json"), model.to_json().as_bytes())?;
    files::write_atomic(&dir.join("faired.json"), faired.to_json().as_bytes())?;
    files::write_atomic(&dir.join("faired.igs"), model_iges(&faired)?.as_bytes())?;
    let json = serde_json::to_string_pretty(&hier_fair::report_json(&report))? + "\n";
    files::write_atomic(&dir.join("report.json"), json.as_bytes())?;
    let verdict = crate::verdict::verdict_line(&report, &model);
    let md = report_md(
        &report,
        &model,
        "hier-fair demo: the X-node (fixtures/models/x_node.json)",
        "; wrote faired.json, faired.igs",
    );
    files::write_atomic(&dir.join("report.md"), md.as_bytes())?;
    let images = write_images(&dir.join("images"), &model, &faired, &report)?;
    let page = html_page("hier-fair demo: the X-node", &model, &faired, &report);
    files::write_atomic(&dir.join("report.html"), page.as_bytes())?;
    let mut text = crate::verdict::summary(
        &report,
        &model,
        "hier-fair demo: X-node — a corner patch linked G2 to four fillets, input G1 only ([SV] Fig. 6)",
    );
    text.push_str(&format!("{verdict}\n"));
    text.push_str(&format!(
        "wrote {0}/faired.json, {0}/faired.igs, {0}/report.json, {0}/report.md, {0}/report.html and {1} pictures in {0}/images\n",
        dir.display(),
        images.len()
    ));
    Ok(text)
}

/// report.md: the report of `fair` on `model`, what the pictures show, and the verdict line
/// followed by `wrote`.
fn report_md(report: &FairModelReport, model: &Model, title: &str, wrote: &str) -> String {
    let verdict = crate::verdict::verdict_line(report, model);
    hier_fair::report_markdown_in(report, title, model.units.as_deref())
        + &images_legend()
        + &format!("\n## Verdict\n\n{verdict}{wrote}\n")
}

/// What the pictures show, for report.md.
pub fn images_legend() -> String {
    "## Pictures (images/)\n\n\
     - `zebra_before.png`, `zebra_after.png` (and `_second_view`, a quarter turn about the vertical, \
     where stripes along a join in the first view run across it): reflection-line stripes; a stripe \
     that jumps at a boundary shows a G1 break, one that kinks a curvature jump (G1 without G2), \
     one that runs on smoothly G2.\n\
     - `mean_curvature_before.png`, `mean_curvature_after.png`: mean curvature H, blue (negative) – \
     white (0) – red (positive), one colour range (95th percentile of |H| before) for both, \
     the scale and its values (1/length unit) on the colour bar at the right.\n\
     - `curvature_<slave>_<side>_on_<master>.png`: normal curvature across the join along each \
     link (axis: t along the slave side, curvature in 1/length unit); light before, dark after, \
     red solid the slave, blue dashed the master: where they coincide the join is G2.\n\
     - `profile_<surface>_<u|v>.png`: the normal curvature along the middle iso-line across each \
     surface that hangs on masters, from side to side (light before, dark after): the comb a \
     surfacer reads across a fillet; a fair G2 fillet rises once from each side and falls once.\n\
     - `corner_<corner>_zebra_<before|after>.png`, `corner_<corner>_mean_curvature_<before|after>.png`: \
     each corner patch with the surfaces it hangs on, seen along its middle normal and zoomed on it; \
     one colour range for both maps (twice the 95th percentile of the corner's |H| before): the \
     input's curvature at half strength, a spike at a pole or beside a side saturated.\n\
     - `link_<slave>_<side>_zebra_<before|after>.png`, `link_<slave>_<side>_mean_curvature_<before|after>.png`: \
     the same zoomed views of each link left unmet, its slave with its master.\n\
     Every picture is titled and labelled before or after; the zebra stripes are as dense as the \
     view needs (a stripe about 14 pixels wide on a typical curved face: a plane reflects one \
     direction and shows one shade); trimmed faces are drawn within their trims, bounded by them.\n"
        .to_string()
}

/// `fair` on a model: reads nothing (the text is given), writes the faired model atomically (never
/// over the input), the report and pictures when asked; returns the text to print and what
/// failed — surfaces that could not be faired, links left unmet — for the command to exit 1 by
/// (the result and report are written all the same).
pub fn run_fair(
    input: &Path,
    text: &str,
    output: &Path,
    report_path: Option<&Path>,
    images: Option<&Path>,
    html: Option<&Path>,
    options: &ModelOptions,
) -> Result<FairOutcome> {
    files::refuse_overwrite(output, &[input])?;
    if let Some(r) = report_path {
        files::refuse_overwrite(r, &[input, output])?;
    }
    if let Some(h) = html {
        files::refuse_overwrite(h, &[input, output])?;
    }
    // a CAD file in, a CAD file out: STEP or IGES is imported (hierarchy found) and written
    // back in the format the output's extension names
    let model = if crate::kind::is_cad(input)? {
        crate::exchange::model_from_cad(input)?.0
    } else {
        Model::from_json(text).with_context(|| format!("{}", input.display()))?
    };
    // an option that does not apply is said, never silently ignored
    for warning in crate::applies::unused_options(&model, options, &input.display().to_string()) {
        eprintln!("warning: {warning}");
    }
    let (model, splits) = if options.split_poles {
        let (split, splits) = hier_fair::poles::split_pole_corners(&model);
        if splits.is_empty() {
            eprintln!(
                "warning: --split-poles has nothing to apply to: {} has no corner patch with a side collapsed to a point",
                input.display()
            );
        }
        (split, splits)
    } else {
        (model, Vec::new())
    };
    let (faired, mut report) = fair(&model, options)?;
    report.pole_splits = splits;
    let written = if crate::exchange::is_iges(output) || crate::exchange::is_step(output) {
        crate::exchange::cad_text(&faired, output)?
    } else {
        faired.to_json()
    };
    files::write_atomic(output, written.as_bytes())?;
    let extras = Extras {
        report: report_path,
        images,
        html,
    };
    write_extras(&extras, input, &model, &faired, &report)?;
    let failed = report
        .problems
        .iter()
        .filter(|p| p.kind == hier_fair::ProblemKind::Failed)
        .map(|p| format!("{}: {}", p.surface, p.message))
        .collect();
    // left unmet with no named conflict (a conflict verified by the second run is no failure)
    let (_, unmet) = report.unmet_links();
    let mut unmet: Vec<String> = unmet.iter().map(|l| l.label.clone()).collect();
    unmet.sort_unstable();
    let mut text = crate::verdict::summary(
        &report,
        &model,
        &format!("hier-fair fair {}", input.display()),
    );
    text += &crate::verdict::verdict(&report, &model, output);
    Ok(FairOutcome {
        text,
        failed,
        unmet,
    })
}

/// The outputs of `fair` besides the model, each where it was asked for.
struct Extras<'a> {
    /// `--report`: report.json
    report: Option<&'a Path>,
    /// `--images`: the pictures' folder
    images: Option<&'a Path>,
    /// `--html`: the quality report page
    html: Option<&'a Path>,
}

/// Writes the report, pictures and page of `extras` for `input` faired into `faired`.
fn write_extras(
    extras: &Extras,
    input: &Path,
    model: &Model,
    faired: &Model,
    report: &FairModelReport,
) -> Result<()> {
    if let Some(r) = extras.report {
        let json = serde_json::to_string_pretty(&hier_fair::report_json(report))? + "\n";
        files::write_atomic(r, json.as_bytes())?;
    }
    if let Some(dir) = extras.images {
        write_images(dir, model, faired, report)?;
        // the pictures come with the report that explains them, as the demo writes it
        let title = format!("hier-fair fair {}", input.display());
        let md = report_md(report, model, &title, "");
        files::write_atomic(&dir.join("report.md"), md.as_bytes())?;
    }
    if let Some(path) = extras.html {
        let title = format!("hier-fair fair {}", input.display());
        files::write_atomic(path, html_page(&title, model, faired, report).as_bytes())?;
    }
    Ok(())
}

/// The quality report of a faired model ([`hier_fair::html`]): `model` as it came in, `faired`,
/// and the tables of `report` (its `report.json` value).
pub fn html_page(title: &str, model: &Model, faired: &Model, report: &FairModelReport) -> String {
    let json = hier_fair::report_json(report);
    hier_fair::html::html_report(&hier_fair::html::HtmlReport {
        title,
        model,
        faired: Some(faired),
        report: Some(&json),
        checks: None,
    })
}

/// What `fair` on a model did, for the command to print and to exit by.
#[derive(Debug, Clone, PartialEq)]
pub struct FairOutcome {
    /// the summary and the verdict line
    pub text: String,
    /// the surfaces that could not be faired, each with why
    pub failed: Vec<String>,
    /// the links left unmet that are no named conflict
    pub unmet: Vec<String>,
}

/// Exits with 1 after naming the first surface that could not be faired and the first link
/// left unmet (the result and report are written already): what a script reads to know that
/// the run did not reach its targets.
pub fn exit_if_failed(failed: &[String], unmet: &[String]) {
    let mut parts = Vec::new();
    if let Some(first) = failed.first() {
        parts.push(format!(
            "{} surface(s) could not be faired, the first {first}",
            failed.len()
        ));
    }
    if let Some(first) = unmet.first() {
        parts.push(format!(
            "{} link(s) unmet and no named conflict, the first {first}",
            unmet.len()
        ));
    }
    if parts.is_empty() {
        return;
    }
    use std::io::Write;
    let _ = std::io::stdout().flush();
    eprintln!(
        "error: {}; the result and report were written",
        parts.join("; ")
    );
    std::process::exit(1);
}

/// Prints what `fair` on a model did — with `quiet` its verdict line alone (the report file
/// holds the rest) — and exits 1 where it failed ([`exit_if_failed`]).
pub fn finish(outcome: FairOutcome, quiet: bool) {
    let text = if quiet {
        outcome
            .text
            .lines()
            .last()
            .map_or(String::new(), |l| format!("{l}\n"))
    } else {
        outcome.text
    };
    print!("{text}");
    exit_if_failed(&outcome.failed, &outcome.unmet);
}
