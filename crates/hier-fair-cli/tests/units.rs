//! Length units: a model in metres, centimetres or inches is faired as the same model in
//! millimetres (the tolerances a user gives are millimetres, or carry their unit), and its unit
//! goes through STEP and IGES as the unit its coordinates are in.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_hier-fair"))
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("binary runs")
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("hier-fair-units-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn plate_boss() -> Value {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/occt/occt_plate_boss.json");
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// `model` with every control point times `f` and its unit `unit`.
fn scaled(model: &Value, f: f64, unit: &str) -> Value {
    let mut m = model.clone();
    m["units"] = Value::from(unit);
    for s in m["surfaces"].as_array_mut().unwrap() {
        for row in s["surface"]["control_points"].as_array_mut().unwrap() {
            for p in row.as_array_mut().unwrap() {
                for c in p.as_array_mut().unwrap() {
                    *c = Value::from(c.as_f64().unwrap() * f);
                }
            }
        }
    }
    m
}

/// Every control point of the model file `path`, times `f`.
fn points(path: &Path, f: f64) -> Vec<f64> {
    let m: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let mut out = Vec::new();
    for s in m["surfaces"].as_array().unwrap() {
        for row in s["surface"]["control_points"].as_array().unwrap() {
            for p in row.as_array().unwrap() {
                out.extend(
                    p.as_array()
                        .unwrap()
                        .iter()
                        .map(|c| c.as_f64().unwrap() * f),
                );
            }
        }
    }
    out
}

fn stdout(o: &Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).to_string()
}

/// plate_boss in metres, centimetres and inches, faired with the same tolerances in
/// millimetres (one given with its unit), comes out as the millimetre result scaled, to rounding;
/// the verdict names the unit of its gap.
#[test]
fn a_model_in_any_unit_is_faired_as_in_millimetres() {
    let d = dir("fair");
    let base = plate_boss();
    let mut reference = Vec::new();
    for (unit, mm) in [("mm", 1.0), ("m", 1000.0), ("cm", 10.0), ("in", 25.4)] {
        let input = d.join(format!("pb_{unit}.json"));
        std::fs::write(&input, scaled(&base, 1.0 / mm, unit).to_string()).unwrap();
        let output = d.join(format!("pb_{unit}.out.json"));
        let o = run(&[
            "fair",
            input.to_str().unwrap(),
            "-o",
            output.to_str().unwrap(),
            "--quiet",
            "--tolerance-role",
            "primary=0.05mm",
            "--tolerance-role",
            "connecting=0.5",
        ]);
        let text = stdout(&o);
        assert!(text.contains("verdict: 4 of 4 links met"), "{unit}: {text}");
        if unit != "mm" {
            assert!(text.contains(&format!(" {unit}, G1 ≤")), "{unit}: {text}");
        }
        let p = points(&output, mm);
        if unit == "mm" {
            reference = p;
            continue;
        }
        assert_eq!(p.len(), reference.len(), "{unit}: the nets differ");
        let worst = p
            .iter()
            .zip(&reference)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(
            worst < 1e-9,
            "{unit}: {worst} mm from the millimetre result"
        );
    }
}

/// A metre model exported to STEP reads back in metres (SI_UNIT without prefix), its default
/// tolerances the millimetre defaults in metres; IGES carries the metre as unit flag 6; a unit
/// IGES has no flag for is refused there, not written as millimetres.
#[test]
fn units_go_through_step_and_iges() {
    let d = dir("exchange");
    let model = d.join("pb_m.json");
    std::fs::write(&model, scaled(&plate_boss(), 1e-3, "m").to_string()).unwrap();
    let step = d.join("pb_m.step");
    stdout(&run(&[
        "export",
        model.to_str().unwrap(),
        "-o",
        step.to_str().unwrap(),
    ]));
    let text = std::fs::read_to_string(&step).unwrap();
    assert!(
        text.contains("SI_UNIT($,.METRE.)"),
        "no metre in the STEP file"
    );
    let back = d.join("back.json");
    stdout(&run(&[
        "import",
        step.to_str().unwrap(),
        "-o",
        back.to_str().unwrap(),
    ]));
    let m: Value = serde_json::from_str(&std::fs::read_to_string(&back).unwrap()).unwrap();
    assert_eq!(m["units"], "m");
    let check = stdout(&run(&["check", back.to_str().unwrap()]));
    assert!(check.contains("G0 ≤ 0.000001 m"), "{check}");

    let iges = d.join("pb_m.igs");
    stdout(&run(&[
        "export",
        model.to_str().unwrap(),
        "-o",
        iges.to_str().unwrap(),
    ]));
    let back = d.join("back_igs.json");
    stdout(&run(&[
        "import",
        iges.to_str().unwrap(),
        "-o",
        back.to_str().unwrap(),
    ]));
    let m: Value = serde_json::from_str(&std::fs::read_to_string(&back).unwrap()).unwrap();
    assert_eq!(m["units"], "m");

    let odd = d.join("pb_odd.json");
    std::fs::write(&odd, scaled(&plate_boss(), 0.08, "12.5 mm").to_string()).unwrap();
    let o = run(&[
        "export",
        odd.to_str().unwrap(),
        "-o",
        d.join("odd.igs").to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("no IGES unit flag"));
    let odd_step = d.join("odd.step");
    stdout(&run(&[
        "export",
        odd.to_str().unwrap(),
        "-o",
        odd_step.to_str().unwrap(),
    ]));
    let text = std::fs::read_to_string(&odd_step).unwrap();
    assert!(text.contains("CONVERSION_BASED_UNIT('12.5 MM'"), "{text}");
}
