//! Fuzz target `scene`: [`tetrascene::fuzzing::scene`] on libFuzzer's input.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tetrascene::fuzzing::scene(data));
