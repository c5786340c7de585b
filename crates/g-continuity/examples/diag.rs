use g_continuity::*;
use nurbs_core::{Continuity, Side};
fn main() {
    let t = std::fs::read_to_string("/tmp/fillet_freeform.surfs.json").unwrap();
    let s = nurbs_core::io::surfaces_from_json(&t).unwrap();
    let (left, right, fillet) = (&s[0], &s[1], &s[2]);
    println!(
        "fillet {}x{} deg {} {}",
        fillet.num_u(),
        fillet.num_v(),
        fillet.degree_u(),
        fillet.degree_v()
    );
    let params = SetParams::default();
    for (side, master) in [(Side::U0, left), (Side::U1, right)] {
        for mub in [true, false] {
            let mut p = params;
            p.move_unlinked_boundaries = mub;
            let mut sl = fillet.clone();
            let mv = set_g2(master, &mut sl, side, &p).unwrap();
            let m = measure_link(master, &sl, side, &MeasureParams::default()).unwrap();
            println!("{side:?} mub={mub} move {mv:.4e} g2rel {:?}", m.g2_rel);
        }
        let mut p = params;
        p.g2_method = G2Method::FixedDirections;
        let mut sl = fillet.clone();
        let mv = set_g2(master, &mut sl, side, &p).unwrap();
        let m = measure_link(master, &sl, side, &MeasureParams::default()).unwrap();
        println!("{side:?} fixed dirs move {mv:.4e} g2rel {:?}", m.g2_rel);
    }
    let _ = Continuity::G2;
}
