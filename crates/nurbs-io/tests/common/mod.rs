//! Helpers shared by the IGES tests: files of entities the writer does not produce.

use nurbs_io::{IgesWriteParams, write_iges};

/// An IGES file of the given entities (type, form, parameters without the type and the final
/// `;`), the Global section of the writer's: for entity types the writer does not produce.
pub fn raw_iges(entities: &[(i64, i64, String)]) -> String {
    let base = write_iges(&[], &[], &IgesWriteParams::default()).unwrap();
    let global: Vec<&str> = base.lines().filter(|l| l.as_bytes()[72] == b'G').collect();
    let mut d = Vec::new();
    let mut p = Vec::new();
    for (k, (kind, form, params)) in entities.iter().enumerate() {
        let de = 2 * k + 1;
        let text = format!("{kind},{params};");
        let first = p.len() + 1;
        // cut at commas so that no number is split across records
        let mut line = String::new();
        let mut lines = Vec::new();
        for token in text.split_inclusive(',') {
            if line.len() + token.len() > 64 {
                lines.push(std::mem::take(&mut line));
            }
            line.push_str(token);
        }
        lines.push(line);
        for l in &lines {
            let seq = p.len() + 1;
            p.push(format!("{l:<64}{de:>8}P{seq:>7}"));
        }
        d.push(format!(
            "{kind:>8}{first:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}D{de:>7}",
            0, 0, 0, 0, 0, 0, "00000000"
        ));
        d.push(format!(
            "{kind:>8}{:>8}{:>8}{:>8}{form:>8}{:>8}{:>8}{:>8}{:>8}D{:>7}",
            0,
            0,
            lines.len(),
            "",
            "",
            "",
            0,
            de + 1
        ));
    }
    let mut out = vec![format!("{:<72}S{:>7}", "raw entities", 1)];
    out.extend(global.iter().map(|s| s.to_string()));
    let t = format!(
        "S{:>7}G{:>7}D{:>7}P{:>7}",
        1,
        global.len(),
        d.len(),
        p.len()
    );
    out.extend(d);
    out.extend(p);
    out.push(format!("{t:<72}T{:>7}", 1));
    out.join("\n") + "\n"
}
