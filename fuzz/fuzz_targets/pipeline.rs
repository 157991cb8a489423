//! Arbitrary bytes through reading → mesh → one frame (`tests/integration/hostile/harness.rs`).
//! A panic, an abort, a hang or an internal error is a finding; a one-line input error is the
//! right answer to a bad file.
#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "../../tests/integration/hostile/harness.rs"]
#[allow(dead_code)]
mod harness;

fuzz_target!(|data: &[u8]| {
    let (source, target) = harness::split(data);
    if let Err(e) = harness::morph_once(source, target) {
        assert!(e.is_input(), "{e}");
        assert!(!e.to_string().contains('\n'), "one line: {e}");
    }
});
