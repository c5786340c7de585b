#![no_main]
//! Any text: the OBJ reader returns, never panics; a mesh it accepts writes back.

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(mesh) = nurbs_core::TriMesh::from_obj_str(text) {
        let mut out = Vec::new();
        let _ = mesh.write_obj(&mut out);
    }
});
