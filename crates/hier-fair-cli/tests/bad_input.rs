//! The bad-input catalogue: every file of `tests/bad_input/` with the command it is given to
//! and the exact first line of stderr (and exit code) it must give — `expected.tsv`, one line
//! per file: FILE, ARGS (OUT stands for an output path in a fresh folder), CODE, FIRST LINE.
//! No bad input may panic, hang, exceed the memory limit, or write an output (exit 1 is the one
//! partial-result case: the faired model and report are written, the failing surface named).

use std::path::Path;
use std::process::Command;

/// Address space each run of the catalogue may use (`ulimit -v`, KiB): 2 GiB — the binary, its
/// threads' stacks and the largest input here need well under 100 MB; an input that made a
/// reader allocate without bound (a grid count, a net size) would abort instead of answering.
const MEMORY_LIMIT_KB: u64 = 2 * 1024 * 1024;

#[test]
fn every_bad_input_gives_its_one_line() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_input");
    let table = std::fs::read_to_string(dir.join("expected.tsv")).unwrap();
    let mut covered = Vec::new();
    for (n, line) in table.lines().enumerate() {
        let fields: Vec<&str> = line.split('\t').collect();
        let [file, args, code, expected] = fields[..] else {
            panic!("expected.tsv line {}: four tab-separated fields", n + 1);
        };
        let out = tempfile::tempdir().unwrap();
        // OUT, or OUT.ext for an output whose format its extension names
        let out_base = out.path().join("o");
        let mut out_path = out_base.clone();
        let args: Vec<String> = args
            .split(' ')
            .map(|a| match a.strip_prefix("OUT") {
                Some(ext) => {
                    out_path = out_base.with_file_name(format!("o{ext}"));
                    out_path.to_string_lossy().to_string()
                }
                None => a.to_string(),
            })
            .collect();
        // under a memory limit: no bad input may reserve more than MEMORY_LIMIT_KB
        let o = Command::new("sh")
            .arg("-c")
            .arg(format!("ulimit -v {MEMORY_LIMIT_KB} && exec \"$0\" \"$@\""))
            .arg(env!("CARGO_BIN_EXE_hier-fair"))
            .args(&args)
            .current_dir(&dir)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        let first = stderr
            .lines()
            .next()
            .unwrap_or("")
            .replace(&*out_base.to_string_lossy(), "OUT");
        assert_eq!(first, expected, "{file}");
        assert_eq!(
            o.status.code(),
            Some(code.parse().unwrap()),
            "{file}: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{file}: {stderr}");
        if code == "2" {
            assert!(!out_path.exists(), "{file}: an output was written");
        }
        covered.push(file.to_string());
    }
    // every file of the folder is in the table, and there are at least 40
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .filter(|f| f != "expected.tsv")
        .collect();
    files.sort();
    covered.sort();
    assert_eq!(files, covered);
    assert!(files.len() >= 40, "{} files", files.len());
}
