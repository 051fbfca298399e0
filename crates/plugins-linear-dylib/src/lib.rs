//! The built-in `linear` constraint source as a dynamic plugin library
//! (`libplugins_linear_dylib.so` on Linux).
//!
//! A separate crate because the exported symbols have fixed names: two exporting crates could
//! not be linked into one binary, and the host links every built-in source statically.

plugin_abi::export_source!(plugins_linear::LinearSource::new);
