//! The C ABI between a host and a dynamic plugin: symbols, `#[repr(C)]` structs and codes.
//!
//! Everything in this module is part of the frozen contract described in the crate
//! documentation. Changing the layout of any struct, a function signature, a method number or a
//! status code requires a new [`ABI_VERSION`] and a new entry symbol (`ecles_plugin_entry_v2`);
//! the probe symbol [`PROBE_SYMBOL`] never changes. New method numbers may be added within a
//! version when hosts can do without them: a plugin answers an unknown method with
//! [`STATUS_BAD_INPUT`] and the text "unknown method N", which hosts take as "not supported"
//! (methods 4 and 5, the checks, were added this way).

use std::ffi::{c_char, c_void};

/// Version of the ABI this crate speaks. The probe symbol of a plugin built against it returns
/// this number.
pub const ABI_VERSION: u32 = 1;

/// Name of the probe symbol, NUL-terminated: `extern "C" fn ecles_plugin_abi_version() -> u32`.
///
/// Its signature is frozen forever, so a host of any version can ask a plugin of any version
/// which ABI it speaks before touching anything else.
pub const PROBE_SYMBOL: &[u8] = b"ecles_plugin_abi_version\0";

/// Name of the entry symbol of ABI version 1, NUL-terminated:
/// `extern "C" fn ecles_plugin_entry_v1() -> *const PluginHeader`.
pub const ENTRY_SYMBOL_V1: &[u8] = b"ecles_plugin_entry_v1\0";

/// The first eight bytes of every [`PluginHeader`].
pub const MAGIC: [u8; 8] = *b"ECLESPLG";

/// [`PluginVTable::call`] method: build. Input is a JSON `api::BuildRequest`, output on success
/// a JSON `api::Contribution`.
pub const METHOD_BUILD: u32 = 1;
/// [`PluginVTable::call`] method: plan. Input is a JSON `api::PlanRequest`, output on success a
/// JSON `api::OperationPlan`.
pub const METHOD_PLAN: u32 = 2;
/// [`PluginVTable::call`] method: render. Input is a JSON `api::RenderRequest`, output on
/// success a JSON array of `api::OutputFile`.
pub const METHOD_RENDER: u32 = 3;

/// [`PluginVTable::call`] method: check an operation before any edit runs. Input is a JSON
/// `api::OperationCheckRequest`, output on success JSON `null`.
///
/// Added within ABI version 1: plugins built before it answer [`STATUS_BAD_INPUT`] with
/// "unknown method 4", which hosts must take as "cannot check in advance", not as an error.
pub const METHOD_CHECK_OPERATION: u32 = 4;
/// [`PluginVTable::call`] method: check an output before any edit runs. Input is a JSON
/// `api::OutputCheckRequest`, output on success a JSON `api::OutputCheck`.
///
/// Added within ABI version 1, like [`METHOD_CHECK_OPERATION`].
pub const METHOD_CHECK_OUTPUT: u32 = 5;
/// [`PluginVTable::call`] method: the source's view for an interactive editor. Input is a JSON
/// `api::ViewRequest` (with the run file's outputs of the source), output on success a JSON
/// `api::SourceView` (with the models those outputs deform) or `null` (nothing to draw).
///
/// Added within ABI version 1, like [`METHOD_CHECK_OPERATION`]: "unknown method 6" from an
/// older plugin means "no view". The request's outputs and the view's models came later with
/// serde defaults: an older plugin ignores the outputs and answers without models. The
/// `prisms` kind (the terrain source) came later still, within the same schema; a host built
/// before it reports a prism view as a malformed answer.
pub const METHOD_VIEW: u32 = 6;

/// [`PluginVTable::call`] status: success; the output holds the JSON answer.
pub const STATUS_OK: i32 = 0;
/// [`PluginVTable::call`] status: the source refused; the output holds a JSON
/// `api::SourceError`.
pub const STATUS_SOURCE_ERROR: i32 = 1;
/// [`PluginVTable::call`] status: the source panicked; the output holds the panic message as
/// UTF-8 text.
pub const STATUS_PANIC: i32 = 2;
/// [`PluginVTable::call`] status: the call itself was malformed (unknown method, null handle,
/// input that is not the expected JSON); the output, when it could be written, holds a UTF-8
/// explanation.
pub const STATUS_BAD_INPUT: i32 = 3;

/// Signature of the probe symbol (frozen).
pub type AbiVersionFn = extern "C" fn() -> u32;

/// Signature of the entry symbol of ABI version 1. Returns a pointer to a header that lives as
/// long as the library, or null if the plugin could not describe itself (its constructor
/// panicked, or its kind or version contains a NUL byte).
pub type EntryFnV1 = extern "C" fn() -> *const PluginHeader;

/// Creates a source instance; returns an opaque handle, or null if the constructor panicked.
pub type CreateFn = extern "C" fn() -> *mut c_void;

/// Destroys an instance created by [`CreateFn`] of the same plugin. Null is ignored.
///
/// Safety: `handle` is null or a handle returned by the same plugin's `create` that was not
/// destroyed yet, and no call on it is running.
pub type DestroyFn = unsafe extern "C" fn(handle: *mut c_void);

/// Runs `method` (one of the `METHOD_*` numbers) on an instance and returns a `STATUS_*` code.
///
/// The plugin writes a buffer it allocated to `*output` for every status (possibly empty), which
/// the host must hand back to [`FreeBufferFn`]; the only exception is a null `output`, for
/// which it returns [`STATUS_BAD_INPUT`] and writes nothing.
///
/// Safety: `handle` is a live handle of the same plugin not used by another call at the same
/// time; `input_ptr` points to `input_len` readable bytes (or `input_len` is 0); `output` is
/// null or valid for a write of one [`ByteBuffer`].
pub type CallFn = unsafe extern "C" fn(
    handle: *mut c_void,
    method: u32,
    input_ptr: *const u8,
    input_len: usize,
    output: *mut ByteBuffer,
) -> i32;

/// Frees a buffer the same plugin wrote to a `call` output.
///
/// Safety: `buffer` is exactly as the plugin wrote it and is freed once.
pub type FreeBufferFn = unsafe extern "C" fn(buffer: ByteBuffer);

/// Bytes allocated by the plugin and handed to the host, which returns them through
/// [`PluginVTable::free_buffer`] (whoever allocates frees: the two sides may use different
/// allocators).
#[repr(C)]
#[derive(Debug)]
pub struct ByteBuffer {
    /// Start of the bytes; null for "no buffer".
    pub ptr: *mut u8,
    /// Number of initialised bytes.
    pub len: usize,
    /// Allocated capacity (meaningful to the allocating side only).
    pub cap: usize,
}

impl ByteBuffer {
    /// The empty buffer (null pointer): what a host passes in before a call.
    pub const fn empty() -> Self {
        ByteBuffer {
            ptr: std::ptr::null_mut(),
            len: 0,
            cap: 0,
        }
    }
}

/// The functions of a plugin, reached through [`PluginHeader::vtable`].
///
/// Fields are `Option`s of function pointers, which have the layout of nullable C function
/// pointers, so a host can reject a plugin that left one null. New fields, if ever, are only
/// appended in a new ABI version.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct PluginVTable {
    /// Creates an instance.
    pub create: Option<CreateFn>,
    /// Destroys an instance.
    pub destroy: Option<DestroyFn>,
    /// Runs a method on an instance.
    pub call: Option<CallFn>,
    /// Frees an output buffer.
    pub free_buffer: Option<FreeBufferFn>,
}

/// What the entry symbol points to: identifies the plugin and leads to its functions.
///
/// The header, the strings and the vtable it points to live as long as the library (which a
/// host never unloads) and are never written after the entry symbol first returned them.
#[repr(C)]
#[derive(Debug)]
pub struct PluginHeader {
    /// Always [`MAGIC`].
    pub magic: [u8; 8],
    /// The ABI version, equal to what the probe symbol returns.
    pub abi_version: u32,
    /// `size_of::<PluginVTable>()` as the plugin was compiled, so a host rejects a truncated
    /// table.
    pub vtable_size: u32,
    /// Plugin kind as named in run files: a NUL-terminated UTF-8 string.
    pub kind: *const c_char,
    /// Plugin version: a NUL-terminated UTF-8 string.
    pub version: *const c_char,
    /// The functions.
    pub vtable: *const PluginVTable,
}

// SAFETY: a header only points at data that is immutable for the life of the library (the
// vtable of function pointers and two NUL-terminated strings that are never written after the
// header is published), so sharing or sending it between threads cannot race.
unsafe impl Sync for PluginHeader {}
// SAFETY: as above; the header owns nothing that is tied to a thread.
unsafe impl Send for PluginHeader {}

/// `size_of::<PluginVTable>()` as a `u32`, the value of [`PluginHeader::vtable_size`].
pub const VTABLE_SIZE: u32 = std::mem::size_of::<PluginVTable>() as u32;
