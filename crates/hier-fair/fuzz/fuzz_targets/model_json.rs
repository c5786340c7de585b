#![no_main]
//! Any text: the model reader (and the bare-surface reader behind it) returns, never panics;
//! a model it accepts validates and serializes.

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(model) = hier_fair::Model::from_json(text) {
        let _ = model.validate();
        let _ = model.to_json();
    }
});
