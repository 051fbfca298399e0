//! The built-in `terrain` constraint source as a dynamic plugin library
//! (`libplugins_terrain_dylib.so` on Linux).
//!
//! A separate crate because the exported symbols have fixed names: two exporting crates could
//! not be linked into one binary, and the host links every built-in source statically.

plugin_abi::export_source!(plugins_terrain::plugin::TerrainSource::default);
