#![no_main]
//! Any bytes: the reader and the structure check must return, never panic.

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = nurbs_io::read_iges(data);
    let _ = nurbs_io::check_structure(data);
});
