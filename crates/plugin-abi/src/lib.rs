//! Dynamic constraint-source plugins for ecles-rs: the frozen C ABI, the plugin-side export
//! macro and the host-side loader.
//!
//! A plugin is a `cdylib` whose library code implements [`api::ConstraintSource`] and ends with
//! [`export_source!`]; a host [`load`]s it and uses [`LoadedPlugin::instantiate`] to get a
//! [`DynamicSource`], which implements the same trait. Requests and answers are the plain data
//! types of [`api::source`], exchanged as JSON bytes, so nothing but `#[repr(C)]` data and
//! `extern "C"` functions crosses the boundary and the two sides may be built by different
//! compilers.
//!
//! # The contract (ABI version 1, frozen)
//!
//! Types and constants are in [`abi`].
//!
//! **Symbols.** A plugin exports exactly two C symbols:
//!
//! * `extern "C" fn ecles_plugin_abi_version() -> u32`: the *probe*. Its name and signature
//!   never change, in any version. It returns the ABI version the plugin speaks
//!   ([`abi::ABI_VERSION`], 1 here). A host calls it first and refuses any other version
//!   ([`LoadError::AbiMismatch`]) before touching anything else.
//! * `extern "C" fn ecles_plugin_entry_v1() -> *const PluginHeader`: the *entry* of version 1.
//!   A later version gets a new entry symbol (`..._v2`), so an old host never misreads a new
//!   header.
//!
//! **Header** ([`abi::PluginHeader`], `#[repr(C)]`): `magic: [u8; 8]` = `b"ECLESPLG"`,
//! `abi_version: u32` (equal to the probe's), `vtable_size: u32` (`size_of` the plugin's vtable;
//! a host rejects a smaller one), `kind` and `version` (`*const c_char`, NUL-terminated UTF-8),
//! `vtable: *const PluginVTable`. The header and everything it points to live as long as the
//! library and never change after the entry first returns them; a null header means the
//! plugin could not describe itself.
//!
//! **Vtable** ([`abi::PluginVTable`], `#[repr(C)]`, nullable C function pointers, none of which
//! may be null):
//!
//! | field | signature | meaning |
//! | --- | --- | --- |
//! | `create` | `fn() -> *mut c_void` | a new instance handle; null if construction failed |
//! | `destroy` | `fn(handle: *mut c_void)` | frees an instance; null is ignored |
//! | `call` | `fn(handle, method: u32, input_ptr: *const u8, input_len: usize, output: *mut ByteBuffer) -> i32` | runs a method |
//! | `free_buffer` | `fn(ByteBuffer)` | frees a buffer `call` wrote |
//!
//! `ByteBuffer` is `#[repr(C)] { ptr: *mut u8, len: usize, cap: usize }`.
//!
//! **Methods** of `call` (input → output on success, all JSON of the [`api`] types):
//! 1 = build (`BuildRequest` → `Contribution`), 2 = plan (`PlanRequest` → `OperationPlan`),
//! 3 = render (`RenderRequest` → array of `OutputFile`).
//!
//! **Status codes** of `call`, and what the output buffer then holds:
//!
//! | status | meaning | output |
//! | --- | --- | --- |
//! | 0 | success | the JSON answer |
//! | 1 | the source refused | a JSON `SourceError` |
//! | 2 | the source panicked | the panic message, UTF-8 |
//! | 3 | bad input (unknown method, null handle or pointer, input not the expected JSON) | an explanation, UTF-8 |
//!
//! The host passes a buffer with a null pointer; the plugin writes one it allocated for every
//! status (except when `output` itself is null: status 3, nothing written).
//!
//! **Rules.**
//!
//! * *Whoever allocates frees*: output buffers are allocated by the plugin and returned through
//!   its `free_buffer`; instances made by `create` are freed by its `destroy`; input bytes
//!   belong to the host, which keeps them alive during the call.
//! * *No unwinding across the boundary*: every exported function body runs inside
//!   [`std::panic::catch_unwind`] (a panic escaping an `extern "C"` function aborts the
//!   process); a panic becomes status 2 (or a null handle / null header). This needs the
//!   plugin built with `panic = "unwind"` (the default): under `panic = "abort"` a plugin's
//!   panic ends the host process.
//! * *One call at a time per instance*: `build` may mutate the instance; the host never runs
//!   two calls on one handle concurrently. Different instances are independent.
//! * *Never unloaded*: a host keeps every library it opened loaded until the process exits
//!   (see [`load`]).
//!
//! # Host side
//!
//! ```no_run
//! use api::ConstraintSource;
//! use std::path::Path;
//!
//! let file = plugin_abi::library_file_name("my_plugin");
//! let plugin = plugin_abi::load(&Path::new("plugins").join(file))?;
//! let mut source = plugin.instantiate();
//! assert_eq!(source.kind(), plugin.kind);
//! # Ok::<(), plugin_abi::LoadError>(())
//! ```
//!
//! Anything the plugin gets wrong (a panic, invalid JSON, an unknown status) becomes an
//! [`api::SourceError`] naming the plugin's kind, version and path.
//!
//! # Plugin side
//!
//! See the `plugin-example` crate, the template: a `cdylib` (plus `rlib` for static use and
//! tests) whose `lib.rs` implements the trait and ends with
//! `plugin_abi::export_source!(MySource::default);`. The macro generates the symbols, so plugin
//! crates need no `unsafe` code of their own.

// The workspace denies `unsafe_code`. This crate is one of two places it is allowed (the
// other: exact-ldu's SIMD product chains): an FFI
// boundary (loading libraries, calling foreign function pointers, raw buffers handed across,
// `#[no_mangle]` exports) cannot be written without it. Every `unsafe` block says why it is
// sound, and plugin crates get their exports from the `export_source!` macro instead of
// writing unsafe code themselves.
#![allow(unsafe_code)]

pub mod abi;
mod export;
mod host;

pub use export::dispatch;
pub use host::{decode_answer, load, AnswerError, DynamicSource, LoadError, LoadedPlugin};

use std::path::{Path, PathBuf};

/// Support for [`export_source!`]; not part of the public API.
#[doc(hidden)]
pub mod __private {
    pub use crate::export::{create, vtable, Constructor, HeaderSlot, Source};
}

/// The platform's file name for a dynamic library named `stem`: `libfoo.so` on Linux and other
/// ELF systems, `libfoo.dylib` on macOS, `foo.dll` on Windows.
///
/// Cargo names a `cdylib` after its crate with `-` replaced by `_`: the library of crate
/// `plugin-example` is `library_file_name("plugin_example")`.
pub fn library_file_name(stem: &str) -> String {
    format!(
        "{}{stem}{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    )
}

/// The dynamic library of crate `crate_name` as Cargo builds it for that crate's own
/// integration tests (`tests/*.rs`), for a plugin to test its loaded self.
///
/// When a crate with `crate-type = ["cdylib", "rlib"]` has integration tests, Cargo compiles
/// the `cdylib` into `target/<profile>/deps/`, next to the test executables, from the same
/// sources as the `rlib` the tests link. So an integration test can run the same checks on its
/// source linked statically and on its library loaded through the ABI:
///
/// ```no_run
/// let path = plugin_abi::library_beside_test("plugin-example").expect("test executable path");
/// let plugin = plugin_abi::load(&path).expect("the crate's own library loads");
/// let _source = plugin.instantiate();
/// ```
///
/// Fails only when the test executable's own path is unknown.
pub fn library_beside_test(crate_name: &str) -> std::io::Result<PathBuf> {
    let exe = std::env::current_exe()?;
    let dir = exe.parent().unwrap_or(Path::new("."));
    Ok(dir.join(library_file_name(&crate_name.replace('-', "_"))))
}

#[cfg(test)]
mod tests {
    #[test]
    fn library_file_names_follow_the_platform() {
        let name = super::library_file_name("foo");
        if cfg!(target_os = "windows") {
            assert_eq!(name, "foo.dll");
        } else if cfg!(target_vendor = "apple") {
            assert_eq!(name, "libfoo.dylib");
        } else if cfg!(unix) {
            assert_eq!(name, "libfoo.so");
        }
    }
}
