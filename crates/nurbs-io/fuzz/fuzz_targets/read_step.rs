#![no_main]
//! Any text: the STEP reader must return, never panic.

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = nurbs_io::read_step(text);
    }
});
