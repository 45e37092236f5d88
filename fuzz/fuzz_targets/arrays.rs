//! Fuzz target `arrays`: [`tetmesh::mesh::io::fuzzing::arrays`] (the Python layer's array
//! checks, as `tetrasim.Mesh(nodes, tets)` runs them) on libFuzzer's input.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tetmesh::mesh::io::fuzzing::arrays(data));
