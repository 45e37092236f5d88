//! Fuzz target `checkpoint`: [`tetrascene::fuzzing::checkpoint`] on libFuzzer's input.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tetrascene::fuzzing::checkpoint(data));
