//! Fuzz target `tetgen`: [`tetmesh::mesh::io::fuzzing::tetgen`] on libFuzzer's input.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tetmesh::mesh::io::fuzzing::tetgen(data));
