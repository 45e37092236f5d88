//! Fuzz target `surface`: [`tetmesh::mesh::io::fuzzing::surface`] on libFuzzer's input.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tetmesh::mesh::io::fuzzing::surface(data));
