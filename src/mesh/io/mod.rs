//! Readers and writers for surface and tet-mesh formats.
