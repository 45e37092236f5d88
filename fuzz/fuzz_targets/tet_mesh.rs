//! Fuzz target `tet_mesh`: [`tetmesh::mesh::io::fuzzing::tet_mesh`] on libFuzzer's input.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tetmesh::mesh::io::fuzzing::tet_mesh(data));
