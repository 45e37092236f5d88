//! Fuzz target `sniffed`: [`tetmesh::mesh::io::fuzzing::sniffed`] on libFuzzer's input.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tetmesh::mesh::io::fuzzing::sniffed(data));
