//! Inputs known by their content, outputs by a known list of extensions, options that do not
//! apply refused (cli-contract.md, "Files").

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_hier-fair"))
}

fn root(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).to_string()
}

/// A failed run whose one-line error contains every one of `parts`.
fn refused(o: &Output, parts: &[&str]) {
    assert!(
        !o.status.success(),
        "ran: {}",
        String::from_utf8_lossy(&o.stdout)
    );
    let e = stderr(o);
    assert_eq!(e.trim().lines().count(), 1, "{e}");
    for p in parts {
        assert!(e.contains(p), "{p:?} not in {e}");
    }
}

#[test]
fn a_step_file_renamed_is_imported_by_its_content() {
    let dir = tempfile::tempdir().unwrap();
    let renamed = dir.path().join("box.txt");
    std::fs::copy(root("fixtures/occt_variants/box12_r4.step"), &renamed).unwrap();
    let out = dir.path().join("box.json");
    let o = run(&[
        "import",
        renamed.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("imported 26 faces"));
    // the same file given to `check` is named for what it is
    let o = run(&["check", renamed.to_str().unwrap()]);
    refused(
        &o,
        &["`check` takes a model JSON", "is a STEP file", "`import`"],
    );
}

#[test]
fn a_model_given_to_import_is_named_as_a_model() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.json");
    let model = root("fixtures/occt/occt_plate_boss.json");
    let o = run(&[
        "import",
        model.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    refused(
        &o,
        &[
            "`import` takes a STEP file or an IGES file",
            "is a model JSON",
        ],
    );
    assert!(!out.exists());
}

#[test]
fn eval_reads_a_model_surface_by_index() {
    let model = root("fixtures/occt/occt_plate_boss.json");
    let o = run(&["eval", model.to_str().unwrap(), "--grid", "2,2"]);
    refused(&o, &["holds 10 surfaces", "--index K"]);
    let o = run(&[
        "eval",
        model.to_str().unwrap(),
        "--grid",
        "2,2",
        "--index",
        "1",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["results"].as_array().unwrap().len(), 4);
}

#[test]
fn outputs_are_written_only_in_a_format_their_extension_names() {
    let dir = tempfile::tempdir().unwrap();
    let model = root("fixtures/occt/occt_plate_boss.json");
    let stl = dir.path().join("out.stl");
    let o = run(&[
        "export",
        model.to_str().unwrap(),
        "-o",
        stl.to_str().unwrap(),
    ]);
    refused(&o, &["out.stl", ".step, .stp, .igs, .iges"]);
    let txt = dir.path().join("out.txt");
    let o = run(&[
        "fair",
        model.to_str().unwrap(),
        "-o",
        txt.to_str().unwrap(),
        "--quiet",
    ]);
    refused(&o, &["out.txt", ".json, .step, .stp, .igs, .iges"]);
    assert!(!stl.exists() && !txt.exists());
}

#[test]
fn model_options_on_a_bare_surface_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let surface = root("fixtures/surfaces/hood_panel.json");
    let out = dir.path().join("out.json");
    for extra in [
        &["--target", "G2"][..],
        &["--images", "pics"][..],
        &["--keep-faired"][..],
    ] {
        let mut args = vec![
            "fair",
            surface.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend(extra);
        let o = run(&args);
        refused(&o, &[extra[0], "applies to a model", "is a surface file"]);
    }
    assert!(!out.exists());
}

#[test]
fn an_unknown_file_is_named_with_what_hier_fair_reads() {
    let dir = tempfile::tempdir().unwrap();
    let junk = dir.path().join("notes.md");
    std::fs::write(&junk, "# notes\nnothing here\n").unwrap();
    let out = dir.path().join("out.json");
    let o = run(&["fair", junk.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    refused(
        &o,
        &[
            "`fair` takes",
            "is no file kind hier-fair reads",
            "STEP, IGES",
        ],
    );
}

/// `check` and `connect` end with a verdict line; `check`'s table has a met column.
#[test]
fn check_and_connect_end_with_a_verdict() {
    let model = root("fixtures/occt/occt_plate_boss.json");
    let o = run(&["check", model.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    // the kernel's torus fillets are G1 to their planes and cylinder: no G2 link is met
    assert_eq!(
        text.lines().last().unwrap(),
        "verdict: 0 of 4 links met (G0 ≤ 0.001, G1 ≤ 0.01°, G2 ≤ 0.005 relative, each up to its target)"
    );
    assert!(text.lines().next().unwrap().contains("met"));
    assert_eq!(
        text.lines().filter(|l| l.contains("  no  ")).count(),
        4,
        "{text}"
    );
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("set.json");
    let o = run(&[
        "connect",
        model.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(
        text.lines().last().unwrap(),
        format!(
            "verdict: 4 of 4 links met (G0 ≤ 0.001, G1 ≤ 0.01°, G2 ≤ 0.005 relative, each up to its target); wrote {}",
            out.display()
        )
    );
    // and the model it wrote checks as met
    let o = run(&["check", out.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&o.stdout).ends_with(
        "4 of 4 links met (G0 ≤ 0.001, G1 ≤ 0.01°, G2 ≤ 0.005 relative, each up to its target)\n"
    ));
}

/// The subcommands in the order of the workflow (import → check → fair → export, the tools
/// after).
const SUBCOMMANDS: [&str; 10] = [
    "import",
    "build",
    "check",
    "connect",
    "fair",
    "export",
    "demo",
    "eval",
    "fair-mesh",
    "label",
];

/// `--help` lists the subcommands in the order of the workflow, and the continuity options
/// their values.
#[test]
fn help_follows_the_workflow_and_lists_values() {
    let o = run(&["--help"]);
    let text = String::from_utf8_lossy(&o.stdout);
    let at: Vec<usize> = SUBCOMMANDS
        .iter()
        .map(|c| {
            text.find(&format!("\n  {c} "))
                .unwrap_or_else(|| panic!("{c} not in {text}"))
        })
        .collect();
    assert!(at.windows(2).all(|w| w[0] < w[1]), "{text}");
    let o = run(&["fair", "--help"]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("G0, G1 or G2"), "{text}");
    assert!(text.contains("STEP or IGES"), "{text}");
    let o = run(&["export", "--help"]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("STEP (AP214"));
}

type Options = std::collections::BTreeMap<String, std::collections::BTreeSet<String>>;

/// The long options (`--name`, `-o` read as `--output`) of each subcommand in `synopses`
/// (`hier-fair SUB …` strings).
fn options_of<'a>(synopses: impl Iterator<Item = &'a str>) -> Options {
    let mut out = Options::new();
    for synopsis in synopses {
        let Some(rest) = synopsis.trim().strip_prefix("hier-fair ") else {
            continue;
        };
        let sub = rest.split_whitespace().next().unwrap().to_string();
        let opts = out.entry(sub).or_default();
        for word in rest.split(|c: char| c.is_whitespace() || "[]()".contains(c)) {
            if word == "-o" {
                opts.insert("--output".to_string());
            } else if let Some(name) = word.strip_prefix("--") {
                let name: String = name
                    .chars()
                    .take_while(|c| c.is_ascii_lowercase() || *c == '-')
                    .collect();
                opts.insert(format!("--{name}"));
            }
        }
    }
    out
}

/// The synopses in docs/cli-contract.md's table (each row's first cell), in the table's order.
fn contract_synopses() -> Vec<String> {
    let text = std::fs::read_to_string(root("docs/cli-contract.md")).unwrap();
    let mut synopses = Vec::new();
    for row in text.lines().filter(|l| l.starts_with("| `hier-fair ")) {
        // the first cell: up to the first `|` not escaped as `\|`
        let mut cell = String::new();
        let mut prev = ' ';
        for c in row[1..].chars() {
            if c == '|' && prev != '\\' {
                break;
            }
            cell.push(c);
            prev = c;
        }
        synopses.extend(cell.split('`').skip(1).step_by(2).map(str::to_string));
    }
    synopses
}

/// The options of the synopses in docs/cli-contract.md's table.
fn contract_options() -> Options {
    options_of(contract_synopses().iter().map(String::as_str))
}

/// README.md's command-line synopsis (its indented `hier-fair …` lines), in order.
fn readme_synopses() -> Vec<String> {
    let text = std::fs::read_to_string(root("README.md")).unwrap();
    text.lines()
        .filter(|l| l.starts_with("    hier-fair "))
        .map(str::to_string)
        .collect()
}

/// The options of README.md's command-line synopsis.
fn readme_options() -> Options {
    options_of(readme_synopses().iter().map(String::as_str))
}
/// The long options `hier-fair SUB --help` lists (without `--help`).
fn help_options(sub: &str) -> std::collections::BTreeSet<String> {
    let o = run(&[sub, "--help"]);
    assert!(o.status.success(), "{sub} --help");
    String::from_utf8_lossy(&o.stdout)
        .lines()
        .filter_map(|l| {
            let l = l.trim_start();
            let l = l.strip_prefix("-o, ").unwrap_or(l);
            let name: String = l
                .strip_prefix("--")?
                .chars()
                .take_while(|c| c.is_ascii_lowercase() || *c == '-')
                .collect();
            (name != "help").then(|| format!("--{name}"))
        })
        .collect()
}

/// Every subcommand's `--help`, its synopsis in docs/cli-contract.md and the README's name the
/// same options: an option added to the program and not to the documents (or the other way)
/// fails here.
#[test]
fn help_the_contract_and_the_readme_name_the_same_options() {
    for (doc, options) in [
        ("contract", contract_options()),
        ("README", readme_options()),
    ] {
        for sub in SUBCOMMANDS {
            let documented = options
                .get(sub)
                .unwrap_or_else(|| panic!("{sub} has no synopsis in the {doc}"));
            assert_eq!(&help_options(sub), documented, "{doc}: hier-fair {sub}");
        }
    }
}

/// The values of every option a synopsis writes as a list (`--target G0|G1|G2`), per
/// subcommand.
fn synopsis_values(synopses: &[String]) -> Options {
    let mut out = Options::new();
    for synopsis in synopses {
        let Some(rest) = synopsis.trim().strip_prefix("hier-fair ") else {
            continue;
        };
        let rest = rest.replace("\\|", "|");
        let words: Vec<&str> = rest
            .split(|c: char| c.is_whitespace() || "[]()".contains(c))
            .filter(|w| !w.is_empty())
            .collect();
        let sub = words[0];
        for pair in words.windows(2) {
            if pair[0].starts_with("--") && pair[1].contains('|') {
                out.entry(format!("{sub} {}", pair[0]))
                    .or_default()
                    .extend(pair[1].split('|').map(str::to_string));
            }
        }
    }
    out
}

/// The possible values `hier-fair SUB --help` lists for each option that has them
/// (`[possible values: a, b]`, or a `Possible values:` list of `- a: …` lines).
fn help_values(sub: &str) -> Options {
    let o = run(&[sub, "--help"]);
    let mut out = Options::new();
    let mut option = String::new();
    for line in String::from_utf8_lossy(&o.stdout).lines() {
        let l = line.trim_start();
        let l = l.strip_prefix("-o, ").unwrap_or(l);
        if let Some(name) = l.strip_prefix("--") {
            let name: String = name
                .chars()
                .take_while(|c| c.is_ascii_lowercase() || *c == '-')
                .collect();
            option = format!("{sub} --{name}");
        }
        if let Some((_, list)) = l.split_once("[possible values: ") {
            let list = list.trim_end_matches(']');
            out.entry(option.clone())
                .or_default()
                .extend(list.split(", ").map(str::to_string));
        } else if let Some(item) = l.strip_prefix("- ") {
            let value = item.split(':').next().unwrap().trim().to_string();
            out.entry(option.clone()).or_default().insert(value);
        }
    }
    out
}

/// Every option whose `--help` lists its values (continuities, presets) is written with the
/// same values in docs/cli-contract.md's table and in the README's synopsis, and no synopsis
/// lists values the program does not take.
#[test]
fn help_the_contract_and_the_readme_list_the_same_values() {
    let mut help = Options::new();
    for sub in SUBCOMMANDS {
        help.extend(help_values(sub));
    }
    assert!(help.contains_key("fair --keep"), "{help:?}");
    assert!(help.contains_key("check --fail-above"), "{help:?}");
    for (doc, synopses) in [
        ("contract", contract_synopses()),
        ("README", readme_synopses()),
    ] {
        assert_eq!(synopsis_values(&synopses), help, "{doc}");
    }
}

/// docs/cli-contract.md's table (by each row's first synopsis: `export` shares `import`'s row)
/// and the README's synopsis list the subcommands in the order of the workflow, as `--help`
/// does.
#[test]
fn the_contract_and_the_readme_follow_the_workflow() {
    let contract = std::fs::read_to_string(root("docs/cli-contract.md")).unwrap();
    let rows: Vec<String> = contract
        .lines()
        .filter_map(|l| l.strip_prefix("| `"))
        .filter(|l| l.starts_with("hier-fair "))
        .map(str::to_string)
        .collect();
    for (doc, synopses) in [("contract", rows), ("README", readme_synopses())] {
        let mut ranks: Vec<usize> = synopses
            .iter()
            .filter_map(|s| s.trim().strip_prefix("hier-fair "))
            .map(|rest| {
                let sub = rest.split_whitespace().next().unwrap();
                SUBCOMMANDS.iter().position(|c| *c == sub).unwrap()
            })
            .collect();
        ranks.dedup();
        assert!(ranks.windows(2).all(|w| w[0] < w[1]), "{doc}: {synopses:?}");
    }
}
