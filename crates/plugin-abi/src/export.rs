//! Plugin side: what [`export_source!`](crate::export_source) expands to.
//!
//! The macro only declares the two `#[no_mangle]` symbols and two statics; the work happens in
//! the functions below, which are public for the macro's sake only (`#[doc(hidden)]`, not part
//! of the API).

use crate::abi::{
    ByteBuffer, CreateFn, PluginHeader, PluginVTable, ABI_VERSION, MAGIC, METHOD_BUILD,
    METHOD_CHECK_OPERATION, METHOD_CHECK_OUTPUT, METHOD_PLAN, METHOD_RENDER, METHOD_VIEW,
    STATUS_BAD_INPUT, STATUS_OK, STATUS_PANIC, STATUS_SOURCE_ERROR, VTABLE_SIZE,
};
use api::{
    BuildRequest, ConstraintSource, OperationCheckRequest, OutputCheckRequest, PlanRequest,
    RenderRequest, SourceError, ViewRequest,
};
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::any::Any;
use std::ffi::{c_void, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::OnceLock;

pub use api::ConstraintSource as Source;

/// Exports a [`ConstraintSource`](api::ConstraintSource) from a `cdylib` crate as a dynamic
/// plugin.
///
/// The argument is an expression that can be called with no arguments and returns the source
/// (a `fn() -> S`, such as `MySource::default`, or a closure); it is called once per instance
/// the host creates, plus once when the host first loads the library, to read the kind and
/// version for the header.
///
/// ```no_run
/// use api::{
///     BuildRequest, ConstraintSource, Contribution, OperationCheckRequest, OperationPlan,
///     OutputCheck, OutputCheckRequest, OutputFile, PlanRequest, RenderRequest, SourceError,
/// };
///
/// #[derive(Default)]
/// struct MySource;
///
/// impl ConstraintSource for MySource {
///     fn kind(&self) -> &str {
///         "mine"
///     }
///     fn version(&self) -> &str {
///         "1.0.0"
///     }
///     fn build(&mut self, _: &BuildRequest) -> Result<Contribution, SourceError> {
///         Ok(Contribution::default())
///     }
///     fn plan(&self, _: &PlanRequest) -> Result<OperationPlan, SourceError> {
///         Err(SourceError::new("no operations"))
///     }
///     fn render(&self, _: &RenderRequest) -> Result<Vec<OutputFile>, SourceError> {
///         Err(SourceError::new("no outputs"))
///     }
///     fn check_operation(&self, _: &OperationCheckRequest) -> Result<(), SourceError> {
///         Err(SourceError::new("no operations"))
///     }
///     fn check_output(&self, _: &OutputCheckRequest) -> Result<OutputCheck, SourceError> {
///         Err(SourceError::new("no outputs"))
///     }
/// }
///
/// plugin_abi::export_source!(MySource::default);
/// ```
///
/// It expands to the probe symbol `ecles_plugin_abi_version`, the entry symbol
/// `ecles_plugin_entry_v1`, the static vtable and the (lazily filled) static header. Use it
/// once per library: the symbol names are fixed, so two plugins exported this way cannot be
/// linked into one binary. Keep the source's library code in a crate of its own (or behind a
/// feature) if it must also be linked statically next to other plugins.
#[macro_export]
macro_rules! export_source {
    ($constructor:expr $(,)?) => {
        const _: () = {
            fn __ecles_construct() -> ::std::boxed::Box<dyn $crate::__private::Source> {
                ::std::boxed::Box::new(($constructor)())
            }

            extern "C" fn __ecles_create() -> *mut ::std::ffi::c_void {
                $crate::__private::create(__ecles_construct)
            }

            static __ECLES_VTABLE: $crate::abi::PluginVTable =
                $crate::__private::vtable(__ecles_create);
            static __ECLES_HEADER: $crate::__private::HeaderSlot =
                $crate::__private::HeaderSlot::new();

            // The frozen probe: nothing in it can panic.
            #[allow(unsafe_code)] // `no_mangle` is an unsafe attribute; the names are ours.
            #[unsafe(no_mangle)]
            extern "C" fn ecles_plugin_abi_version() -> u32 {
                $crate::abi::ABI_VERSION
            }

            #[allow(unsafe_code)] // `no_mangle` is an unsafe attribute; the names are ours.
            #[unsafe(no_mangle)]
            extern "C" fn ecles_plugin_entry_v1() -> *const $crate::abi::PluginHeader {
                __ECLES_HEADER.get(&__ECLES_VTABLE, __ecles_construct)
            }
        };
    };
}

/// Builds a boxed source; what the macro's constructor wrapper is.
pub type Constructor = fn() -> Box<dyn ConstraintSource>;

/// The object behind an instance handle (a thin pointer to a boxed trait object).
struct Instance {
    source: Box<dyn ConstraintSource>,
}

/// The vtable of a plugin whose `create` is `create`; everything else is shared code.
pub const fn vtable(create: CreateFn) -> PluginVTable {
    PluginVTable {
        create: Some(create),
        destroy: Some(destroy),
        call: Some(call),
        free_buffer: Some(free_buffer),
    }
}

/// The header and the strings it points to.
struct HeaderData {
    header: PluginHeader,
    // Owned here so the header's pointers stay valid; a CString's bytes do not move with it.
    _kind: CString,
    _version: CString,
}

/// The static header of a plugin, filled on the first call of the entry symbol (kind and
/// version come from an instance, so they are not constants).
pub struct HeaderSlot(OnceLock<Option<HeaderData>>);

impl Default for HeaderSlot {
    fn default() -> Self {
        Self::new()
    }
}

impl HeaderSlot {
    /// An empty slot.
    pub const fn new() -> Self {
        HeaderSlot(OnceLock::new())
    }

    /// The header, filled from a freshly constructed instance on first use; null if the
    /// constructor panicked or the kind or version contains a NUL byte.
    pub fn get(
        &'static self,
        vtable: &'static PluginVTable,
        construct: Constructor,
    ) -> *const PluginHeader {
        let filled = catch_unwind(AssertUnwindSafe(|| {
            self.0.get_or_init(|| {
                let source = construct();
                let kind = CString::new(source.kind()).ok()?;
                let version = CString::new(source.version()).ok()?;
                drop_quietly(source);
                Some(HeaderData {
                    header: PluginHeader {
                        magic: MAGIC,
                        abi_version: ABI_VERSION,
                        vtable_size: VTABLE_SIZE,
                        kind: kind.as_ptr(),
                        version: version.as_ptr(),
                        vtable,
                    },
                    _kind: kind,
                    _version: version,
                })
            })
        }));
        match filled {
            Ok(Some(data)) => &data.header,
            // A panic leaves the slot empty (OnceLock does not poison), so the next call retries.
            Ok(None) | Err(_) => std::ptr::null(),
        }
    }
}

/// Drops a value, swallowing a panic of its destructor.
fn drop_quietly<T>(value: T) {
    if let Err(payload) = catch_unwind(AssertUnwindSafe(move || drop(value))) {
        // Dropping the payload could panic again; leak it instead.
        std::mem::forget(payload);
    }
}

/// The text of a panic payload (`&str` and `String` payloads, as `panic!` makes them).
fn panic_message(payload: &(dyn Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "panic with a non-string payload".to_string()
    }
}

/// `create` of the vtable: constructs an instance; null if the constructor panicked.
pub fn create(construct: Constructor) -> *mut c_void {
    match catch_unwind(construct) {
        Ok(source) => Box::into_raw(Box::new(Instance { source })).cast(),
        Err(payload) => {
            drop_quietly(payload);
            std::ptr::null_mut()
        }
    }
}

/// `destroy` of the vtable.
///
/// # Safety
/// `handle` is null or a live handle returned by [`create`] of this library, not in use by a
/// running call, and is not used again.
unsafe extern "C" fn destroy(handle: *mut c_void) {
    if handle.is_null() {
        return;
    }
    // SAFETY: by the contract above, `handle` came from `Box::into_raw` in `create` and is
    // destroyed once, so rebuilding the box is sound.
    let instance = unsafe { Box::from_raw(handle.cast::<Instance>()) };
    drop_quietly(instance);
}

/// `free_buffer` of the vtable.
///
/// # Safety
/// `buffer` was written by [`call`] of this library, unchanged, and is freed once.
unsafe extern "C" fn free_buffer(buffer: ByteBuffer) {
    if buffer.ptr.is_null() {
        return;
    }
    // SAFETY: `call` made the buffer from a `Vec<u8>` with exactly this pointer, length and
    // capacity (see `buffer_from_vec`) and it is freed once, so the Vec can be rebuilt.
    let bytes = unsafe { Vec::from_raw_parts(buffer.ptr, buffer.len, buffer.cap) };
    drop_quietly(bytes);
}

/// Gives up ownership of `bytes` as a [`ByteBuffer`] for [`free_buffer`] to take back.
fn buffer_from_vec(bytes: Vec<u8>) -> ByteBuffer {
    let mut bytes = std::mem::ManuallyDrop::new(bytes);
    ByteBuffer {
        ptr: bytes.as_mut_ptr(),
        len: bytes.len(),
        cap: bytes.capacity(),
    }
}

/// `call` of the vtable.
///
/// # Safety
/// `handle` is null or a live handle returned by [`create`] of this library and no other call
/// uses it at the same time; `input_ptr` points to `input_len` readable bytes unless
/// `input_len` is 0; `output` is null or valid for writing one [`ByteBuffer`].
unsafe extern "C" fn call(
    handle: *mut c_void,
    method: u32,
    input_ptr: *const u8,
    input_len: usize,
    output: *mut ByteBuffer,
) -> i32 {
    if output.is_null() {
        return STATUS_BAD_INPUT;
    }
    let result = catch_unwind(AssertUnwindSafe(|| {
        if handle.is_null() {
            return bad_input("null instance handle");
        }
        let input: &[u8] = if input_len == 0 {
            &[]
        } else if input_ptr.is_null() {
            return bad_input("null input pointer with a nonzero length");
        } else {
            // SAFETY: by the contract above the host passes `input_len` readable bytes at
            // `input_ptr`, which it keeps alive and unchanged during the call.
            unsafe { std::slice::from_raw_parts(input_ptr, input_len) }
        };
        // SAFETY: a non-null handle is a live `Instance` from `create` (contract above) and the
        // host runs one call at a time on it, so this is the only reference.
        let instance = unsafe { &mut *handle.cast::<Instance>() };
        dispatch(instance.source.as_mut(), method, input)
    }));
    let (status, bytes) = match result {
        Ok(answer) => answer,
        Err(payload) => {
            let message = panic_message(payload.as_ref());
            drop_quietly(payload);
            (STATUS_PANIC, message.into_bytes())
        }
    };
    // SAFETY: `output` is non-null and valid for one write (contract above); the old contents
    // are not read or dropped (the host passes an empty buffer).
    unsafe { output.write(buffer_from_vec(bytes)) };
    status
}

fn bad_input(message: impl Into<String>) -> (i32, Vec<u8>) {
    (STATUS_BAD_INPUT, message.into().into_bytes())
}

/// Runs one method on a source: JSON in, status and bytes out, exactly as a plugin's `call`
/// does (without the panic guard). Every byte sequence is answered with a status; public so
/// that the decoding of requests can be fuzzed.
pub fn dispatch(source: &mut dyn ConstraintSource, method: u32, input: &[u8]) -> (i32, Vec<u8>) {
    match method {
        METHOD_BUILD => run(input, "BuildRequest", |r: BuildRequest| source.build(&r)),
        METHOD_PLAN => run(input, "PlanRequest", |r: PlanRequest| source.plan(&r)),
        METHOD_RENDER => run(input, "RenderRequest", |r: RenderRequest| source.render(&r)),
        METHOD_CHECK_OPERATION => run(
            input,
            "OperationCheckRequest",
            |r: OperationCheckRequest| source.check_operation(&r),
        ),
        METHOD_CHECK_OUTPUT => run(input, "OutputCheckRequest", |r: OutputCheckRequest| {
            source.check_output(&r)
        }),
        METHOD_VIEW => run(input, "ViewRequest", |r: ViewRequest| source.view(&r)),
        other => bad_input(format!("unknown method {other}")),
    }
}

fn run<Req: DeserializeOwned, Ans: Serialize>(
    input: &[u8],
    what: &str,
    method: impl FnOnce(Req) -> Result<Ans, SourceError>,
) -> (i32, Vec<u8>) {
    // A request of a newer payload schema may mean something this plugin cannot know:
    // refuse it, naming both versions, rather than read it half.
    #[derive(serde::Deserialize)]
    struct SchemaProbe {
        #[serde(default = "schema_v1")]
        schema: u32,
    }
    fn schema_v1() -> u32 {
        1
    }
    if let Ok(probe) = serde_json::from_slice::<SchemaProbe>(input) {
        if probe.schema > api::SCHEMA_VERSION {
            return bad_input(format!(
                "the {what} has payload schema {}, newer than this plugin's {}; rebuild the plugin against a matching api",
                probe.schema,
                api::SCHEMA_VERSION
            ));
        }
    }
    let request: Req = match serde_json::from_slice(input) {
        Ok(request) => request,
        Err(e) => return bad_input(format!("input is not a JSON {what}: {e}")),
    };
    let (status, encoded) = match method(request) {
        Ok(answer) => (STATUS_OK, serde_json::to_vec(&answer)),
        Err(error) => (STATUS_SOURCE_ERROR, serde_json::to_vec(&error)),
    };
    match encoded {
        Ok(bytes) => (status, bytes),
        Err(e) => {
            let error = SourceError::new(format!("could not serialise the answer: {e}"));
            // A SourceError is a struct with one string: it always serialises.
            let bytes = serde_json::to_vec(&error).unwrap_or_default();
            (STATUS_SOURCE_ERROR, bytes)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use api::{Contribution, OperationPlan, OutputFile};

    /// A source whose build echoes the name, panics on "boom" and refuses on "no".
    struct Echo;

    impl ConstraintSource for Echo {
        fn kind(&self) -> &str {
            "echo"
        }
        fn version(&self) -> &str {
            "9.9"
        }
        fn build(&mut self, request: &BuildRequest) -> Result<Contribution, SourceError> {
            match request.name.as_str() {
                "boom" => panic!("boom at build"),
                "no" => Err(SourceError::new("refused")),
                name => Ok(Contribution {
                    warnings: vec![name.to_string()],
                    ..Contribution::default()
                }),
            }
        }
        fn plan(&self, _: &PlanRequest) -> Result<OperationPlan, SourceError> {
            Err(SourceError::new("no plans"))
        }
        fn render(&self, _: &RenderRequest) -> Result<Vec<OutputFile>, SourceError> {
            std::panic::panic_any(42_u32)
        }
        fn check_operation(&self, request: &OperationCheckRequest) -> Result<(), SourceError> {
            match request.operation.as_str() {
                "ok" => Ok(()),
                _ => Err(SourceError::new("no operations")),
            }
        }
        fn check_output(&self, _: &OutputCheckRequest) -> Result<api::OutputCheck, SourceError> {
            Ok(api::OutputCheck::new(vec!["x.svg".into()], vec![]))
        }
    }

    #[test]
    fn checks_answer_through_the_abi() {
        let ok = serde_json::to_vec(&OperationCheckRequest {
            schema: api::SCHEMA_VERSION,
            operation: "ok".into(),
        })
        .expect("serialise");
        assert_eq!(
            invoke(METHOD_CHECK_OPERATION, &ok),
            (STATUS_OK, "null".into())
        );
        let no = serde_json::to_vec(&OperationCheckRequest {
            schema: api::SCHEMA_VERSION,
            operation: "turn".into(),
        })
        .expect("serialise");
        let (status, text) = invoke(METHOD_CHECK_OPERATION, &no);
        assert_eq!(status, STATUS_SOURCE_ERROR);
        assert!(text.contains("no operations"), "{text}");
        let output = serde_json::to_vec(&OutputCheckRequest {
            schema: api::SCHEMA_VERSION,
            output: "()".into(),
            base_dir: ".".into(),
            input_limit: 1,
        })
        .expect("serialise");
        let (status, text) = invoke(METHOD_CHECK_OUTPUT, &output);
        assert_eq!(status, STATUS_OK);
        let check: api::OutputCheck = serde_json::from_str(&text).expect("an OutputCheck");
        assert!(check.checked);
        assert_eq!(check.files, ["x.svg"]);
        let (status, text) = invoke(99, b"{}");
        assert_eq!(status, STATUS_BAD_INPUT);
        assert!(text.starts_with("unknown method"), "{text}");
    }

    fn construct() -> Box<dyn ConstraintSource> {
        Box::new(Echo)
    }

    fn request(name: &str) -> Vec<u8> {
        let request = BuildRequest {
            schema: api::SCHEMA_VERSION,
            input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
            name: name.into(),
            config: String::new(),
            base_dir: ".".into(),
            system: Default::default(),
            values: Default::default(),
            sources: vec![],
        };
        serde_json::to_vec(&request).expect("serialise")
    }

    /// Calls `method` on a fresh instance; returns the status and the output text.
    fn invoke(method: u32, input: &[u8]) -> (i32, String) {
        let handle = create(construct);
        assert!(!handle.is_null());
        let mut out = ByteBuffer::empty();
        // SAFETY: live handle, valid input slice, valid output slot.
        let status = unsafe { call(handle, method, input.as_ptr(), input.len(), &mut out) };
        // SAFETY: the buffer was written by `call` above.
        let bytes = unsafe { std::slice::from_raw_parts(out.ptr, out.len) }.to_vec();
        // SAFETY: freed once, as written; the handle is destroyed once.
        unsafe {
            free_buffer(out);
            destroy(handle);
        }
        (status, String::from_utf8(bytes).expect("utf-8"))
    }

    #[test]
    fn dispatches_by_method_and_reports_every_status() {
        let (status, text) = invoke(METHOD_BUILD, &request("a"));
        assert_eq!(status, STATUS_OK);
        let c: Contribution = serde_json::from_str(&text).expect("contribution");
        assert_eq!(c.warnings, vec!["a".to_string()]);

        let (status, text) = invoke(METHOD_BUILD, &request("no"));
        assert_eq!(status, STATUS_SOURCE_ERROR);
        let e: SourceError = serde_json::from_str(&text).expect("source error");
        assert_eq!(e.message, "refused");

        let (status, text) = invoke(METHOD_BUILD, &request("boom"));
        assert_eq!((status, text.as_str()), (STATUS_PANIC, "boom at build"));

        let (status, text) = invoke(METHOD_BUILD, b"{not json");
        assert_eq!(status, STATUS_BAD_INPUT);
        assert!(text.contains("BuildRequest"), "{text}");

        let (status, text) = invoke(7, &request("a"));
        assert_eq!(
            (status, text.as_str()),
            (STATUS_BAD_INPUT, "unknown method 7")
        );

        let (status, _) = invoke(METHOD_BUILD, &[]);
        assert_eq!(status, STATUS_BAD_INPUT);
    }

    #[test]
    fn null_pointers_are_bad_input_not_crashes() {
        let mut out = ByteBuffer::empty();
        // SAFETY: null handle and output are explicitly allowed by `call`'s contract.
        unsafe {
            assert_eq!(
                call(std::ptr::null_mut(), 1, std::ptr::null(), 0, &mut out),
                STATUS_BAD_INPUT
            );
            free_buffer(out);
            let handle = create(construct);
            assert_eq!(
                call(handle, 1, std::ptr::null(), 0, std::ptr::null_mut()),
                STATUS_BAD_INPUT
            );
            let mut out = ByteBuffer::empty();
            assert_eq!(
                call(handle, 1, std::ptr::null(), 5, &mut out),
                STATUS_BAD_INPUT
            );
            free_buffer(out);
            destroy(handle);
            destroy(std::ptr::null_mut());
            free_buffer(ByteBuffer::empty());
        }
    }

    #[test]
    fn a_constructor_panic_gives_a_null_handle_and_a_null_header() {
        fn panicking() -> Box<dyn ConstraintSource> {
            panic!("constructor")
        }
        assert!(create(panicking).is_null());
        static VTABLE: PluginVTable = vtable(dummy_create);
        extern "C" fn dummy_create() -> *mut c_void {
            std::ptr::null_mut()
        }
        static SLOT: HeaderSlot = HeaderSlot::new();
        assert!(SLOT.get(&VTABLE, panicking).is_null());
        // The slot was left empty: a working constructor fills it later.
        let header = SLOT.get(&VTABLE, construct);
        assert!(!header.is_null());
        // SAFETY: non-null pointer into the static slot.
        let header = unsafe { &*header };
        assert_eq!(header.magic, MAGIC);
        assert_eq!(header.vtable_size, VTABLE_SIZE);
        // SAFETY: the header's kind is a NUL-terminated string owned by the slot.
        let kind = unsafe { std::ffi::CStr::from_ptr(header.kind) };
        assert_eq!(kind.to_str(), Ok("echo"));
    }

    #[test]
    fn a_non_string_panic_payload_is_described() {
        let input = serde_json::to_vec(&RenderRequest {
            schema: api::SCHEMA_VERSION,
            input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
            output: String::new(),
            base_dir: ".".into(),
            system: Default::default(),
            initial: Default::default(),
            values: Default::default(),
            highlight: None,
            structure: None,
        })
        .expect("serialise");
        let (status, text) = invoke(METHOD_RENDER, &input);
        assert_eq!(status, STATUS_PANIC);
        assert_eq!(text, "panic with a non-string payload");
    }
}
