//! Host side: loading a plugin library and calling it as a [`ConstraintSource`].

use crate::abi::{
    AbiVersionFn, ByteBuffer, CallFn, CreateFn, DestroyFn, EntryFnV1, FreeBufferFn, PluginHeader,
    PluginVTable, ABI_VERSION, ENTRY_SYMBOL_V1, MAGIC, METHOD_BUILD, METHOD_CHECK_OPERATION,
    METHOD_CHECK_OUTPUT, METHOD_PLAN, METHOD_RENDER, METHOD_VIEW, PROBE_SYMBOL, STATUS_BAD_INPUT,
    STATUS_OK, STATUS_PANIC, STATUS_SOURCE_ERROR, VTABLE_SIZE,
};
use api::{
    BuildRequest, ConstraintSource, Contribution, OperationCheckRequest, OperationPlan,
    OutputCheck, OutputCheckRequest, OutputFile, PlanRequest, RenderRequest, SourceError,
    SourceView, ViewRequest,
};
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::ffi::{c_char, c_void, CStr};
use std::fmt;
use std::path::{Path, PathBuf};

/// Why a plugin library could not be loaded. Every variant names the library's path.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LoadError {
    /// No file at the path.
    #[error("plugin library {} not found", path.display())]
    NotFound {
        /// The library path.
        path: PathBuf,
    },
    /// The file exists but the system loader refused it (not a library, wrong architecture,
    /// missing dependency, ...).
    #[error("cannot open plugin library {}: {message}", path.display())]
    Open {
        /// The library path.
        path: PathBuf,
        /// The loader's message.
        message: String,
    },
    /// The library does not export a symbol every plugin must export.
    #[error(
        "{} is not an ecles plugin: it does not export the symbol `{symbol}`",
        path.display()
    )]
    MissingSymbol {
        /// The library path.
        path: PathBuf,
        /// The missing symbol's name.
        symbol: String,
    },
    /// The plugin speaks another ABI version.
    #[error(
        "plugin {} speaks plugin ABI version {found}, but this host speaks version {expected}; \
         rebuild the plugin against a matching plugin-abi",
        path.display()
    )]
    AbiMismatch {
        /// The library path.
        path: PathBuf,
        /// The version the plugin's probe returned.
        found: u32,
        /// [`ABI_VERSION`].
        expected: u32,
    },
    /// The plugin's header is malformed.
    #[error("plugin {} has a bad header: {reason}", path.display())]
    BadHeader {
        /// The library path.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
}

/// The vtable functions of a validated plugin (none null).
#[derive(Clone, Copy)]
struct Functions {
    create: CreateFn,
    destroy: DestroyFn,
    call: CallFn,
    free_buffer: FreeBufferFn,
}

/// A loaded and validated plugin library: its identity, and a factory of instances.
///
/// The library stays loaded for the rest of the process (see [`load`]).
#[derive(Clone)]
pub struct LoadedPlugin {
    /// Plugin kind, as named in run files.
    pub kind: String,
    /// Plugin version.
    pub version: String,
    /// ABI version the plugin speaks (equal to [`ABI_VERSION`]).
    pub abi_version: u32,
    /// Path the library was loaded from, as given to [`load`].
    pub path: PathBuf,
    functions: Functions,
}

impl fmt::Debug for LoadedPlugin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("LoadedPlugin")
            .field("kind", &self.kind)
            .field("version", &self.version)
            .field("abi_version", &self.abi_version)
            .field("path", &self.path)
            .finish_non_exhaustive()
    }
}

impl LoadedPlugin {
    /// A new instance of the plugin's source.
    ///
    /// If the plugin's constructor fails (panics), the instance still reports the kind and
    /// version, and every method returns a [`SourceError`] saying so.
    pub fn instantiate(&self) -> DynamicSource {
        let handle = (self.functions.create)();
        DynamicSource {
            kind: self.kind.clone(),
            version: self.version.clone(),
            path: self.path.clone(),
            functions: self.functions,
            handle,
        }
    }
}

/// Loads a plugin library and validates it.
///
/// Steps: open the library; call the probe symbol `ecles_plugin_abi_version` (frozen
/// signature) and compare with [`ABI_VERSION`]; call the entry symbol
/// `ecles_plugin_entry_v1`; check the header's magic, ABI version, vtable size, that no pointer
/// is null and that kind and version are UTF-8.
///
/// The library is **never unloaded**, whether loading succeeds or not: once its code has run,
/// instance handles, statics (the header and vtable the host keeps pointers to), thread-local
/// destructors and panic or allocator state of the plugin's own copy of `std` may outlive any
/// owner we could give the library, and unloading under them is undefined behaviour. Loading
/// the same path twice reuses the library the system loader already has.
///
/// Loading runs the library's initialisers: only load plugins you would run as programs.
pub fn load(path: &Path) -> Result<LoadedPlugin, LoadError> {
    match std::fs::metadata(path) {
        Err(_) => {
            return Err(LoadError::NotFound {
                path: path.to_path_buf(),
            })
        }
        // The system loader would block on a FIFO and read a device without end.
        Ok(metadata) if !metadata.is_file() => {
            return Err(LoadError::Open {
                path: path.to_path_buf(),
                message: "not a regular file (a directory, FIFO or device)".into(),
            })
        }
        Ok(_) => {}
    }
    // A bare file name would make the system loader search its library path instead of the
    // current directory: always hand it an absolute path.
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    // SAFETY: opening a library runs its initialisers, arbitrary code from the plugin. That is
    // the point of a plugin: the user named this library in the run file, and it is trusted
    // like the host's own code.
    let library = unsafe { libloading::Library::new(&absolute) }.map_err(|e| LoadError::Open {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    // Never unloaded (see above): leak it before anything else runs from it.
    let library: &'static libloading::Library = Box::leak(Box::new(library));

    // SAFETY: the probe symbol's type is frozen across every ABI version: `extern "C" fn() ->
    // u32`. A library exporting something else under that name is not an ecles plugin and
    // breaks the one promise the name makes.
    let probe = unsafe { library.get::<AbiVersionFn>(PROBE_SYMBOL) }
        .map_err(|_| missing_symbol(path, PROBE_SYMBOL))?;
    let found = probe();
    if found != ABI_VERSION {
        return Err(LoadError::AbiMismatch {
            path: path.to_path_buf(),
            found,
            expected: ABI_VERSION,
        });
    }
    // SAFETY: the probe said version 1, whose entry symbol has exactly this type.
    let entry = unsafe { library.get::<EntryFnV1>(ENTRY_SYMBOL_V1) }
        .map_err(|_| missing_symbol(path, ENTRY_SYMBOL_V1))?;
    let header = entry();
    // SAFETY: the entry symbol of ABI 1 returns null or a pointer to a header, strings and
    // vtable that live as long as the library, which is leaked above.
    unsafe { read_header(header, path) }
}

fn missing_symbol(path: &Path, symbol: &[u8]) -> LoadError {
    let name = symbol.strip_suffix(b"\0").unwrap_or(symbol);
    LoadError::MissingSymbol {
        path: path.to_path_buf(),
        symbol: String::from_utf8_lossy(name).into_owned(),
    }
}

/// Validates a header and copies what the host keeps.
///
/// # Safety
/// `header` is null or points to a [`PluginHeader`] whose non-null `kind` and `version` are
/// NUL-terminated strings and whose non-null `vtable` points to at least `vtable_size` bytes,
/// all valid and unchanged for the rest of the process.
unsafe fn read_header(header: *const PluginHeader, path: &Path) -> Result<LoadedPlugin, LoadError> {
    let bad = |reason: String| LoadError::BadHeader {
        path: path.to_path_buf(),
        reason,
    };
    if header.is_null() {
        return Err(bad(
            "the entry symbol returned a null header (the plugin's constructor panicked, or its \
             kind or version contains a NUL byte)"
                .into(),
        ));
    }
    if !header.is_aligned() {
        return Err(bad("the header pointer is misaligned".into()));
    }
    // SAFETY: non-null and aligned, and valid for reads by this function's contract.
    let header = unsafe { &*header };
    if header.magic != MAGIC {
        return Err(bad(format!(
            "magic is {:?}, expected {:?}",
            String::from_utf8_lossy(&header.magic),
            String::from_utf8_lossy(&MAGIC)
        )));
    }
    if header.abi_version != ABI_VERSION {
        return Err(bad(format!(
            "the header says ABI version {}, but the probe said {ABI_VERSION}",
            header.abi_version
        )));
    }
    // A larger table is accepted: only the fields this host knows are read.
    if header.vtable_size < VTABLE_SIZE {
        return Err(bad(format!(
            "the vtable is {} bytes, expected at least {VTABLE_SIZE}",
            header.vtable_size
        )));
    }
    // SAFETY: NUL-terminated if non-null, by this function's contract.
    let kind = unsafe { read_string(header.kind) }.map_err(|e| bad(format!("kind {e}")))?;
    // SAFETY: as above.
    let version =
        unsafe { read_string(header.version) }.map_err(|e| bad(format!("version {e}")))?;
    if kind.is_empty() {
        return Err(bad("the kind is empty".into()));
    }
    if header.vtable.is_null() {
        return Err(bad("the vtable pointer is null".into()));
    }
    if !header.vtable.is_aligned() {
        return Err(bad("the vtable pointer is misaligned".into()));
    }
    // SAFETY: non-null, aligned, and at least `size_of::<PluginVTable>()` bytes (checked above)
    // valid for reads by this function's contract. Each field is an `Option` of a function
    // pointer, for which every bit pattern a C plugin could leave there (null or an address)
    // is valid.
    let vtable: PluginVTable = unsafe { header.vtable.read() };
    let null = |name: &str| bad(format!("the vtable's `{name}` function is null"));
    let functions = Functions {
        create: vtable.create.ok_or_else(|| null("create"))?,
        destroy: vtable.destroy.ok_or_else(|| null("destroy"))?,
        call: vtable.call.ok_or_else(|| null("call"))?,
        free_buffer: vtable.free_buffer.ok_or_else(|| null("free_buffer"))?,
    };
    Ok(LoadedPlugin {
        kind,
        version,
        abi_version: header.abi_version,
        path: path.to_path_buf(),
        functions,
    })
}

/// Reads a header string.
///
/// # Safety
/// `ptr` is null or points to a NUL-terminated string.
unsafe fn read_string(ptr: *const c_char) -> Result<String, String> {
    if ptr.is_null() {
        return Err("is a null pointer".into());
    }
    // SAFETY: non-null and NUL-terminated by this function's contract.
    let text = unsafe { CStr::from_ptr(ptr) };
    text.to_str()
        .map(str::to_string)
        .map_err(|e| format!("is not UTF-8 ({e})"))
}

/// A source instance living in a dynamic plugin, used like any other [`ConstraintSource`].
///
/// Requests and answers cross the boundary as JSON. Whatever the plugin does wrong (panics,
/// returns invalid JSON or an unknown status) becomes a [`SourceError`] naming the plugin;
/// the host does not crash.
///
/// Not `Send` or `Sync`: the plugin's source type need not be thread-safe.
pub struct DynamicSource {
    kind: String,
    version: String,
    path: PathBuf,
    functions: Functions,
    /// Null if the plugin's constructor failed.
    handle: *mut c_void,
}

impl fmt::Debug for DynamicSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("DynamicSource")
            .field("kind", &self.kind)
            .field("version", &self.version)
            .field("path", &self.path)
            .finish_non_exhaustive()
    }
}

impl DynamicSource {
    /// Path of the library this instance lives in.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// How error messages name the plugin.
    fn describe(&self) -> String {
        format!(
            "plugin {:?} {} ({})",
            self.kind,
            self.version,
            self.path.display()
        )
    }

    /// Runs `method` with `request` and decodes the answer.
    fn invoke<Req: Serialize, Ans: DeserializeOwned>(
        &self,
        method: u32,
        name: &str,
        request: &Req,
    ) -> Result<Ans, SourceError> {
        self.call(method, name, request)?.ok_or_else(|| {
            SourceError::new(format!(
                "{}: {name} {}",
                self.describe(),
                AnswerError::UnknownMethod
            ))
        })
    }

    /// Runs `method` with `request` and decodes the answer; `None` when the plugin does not
    /// know the method.
    fn call<Req: Serialize, Ans: DeserializeOwned>(
        &self,
        method: u32,
        name: &str,
        request: &Req,
    ) -> Result<Option<Ans>, SourceError> {
        let fail = |what: String| SourceError::new(format!("{}: {name} {what}", self.describe()));
        if self.handle.is_null() {
            return Err(fail(
                "failed: the plugin could not create an instance (its constructor panicked)".into(),
            ));
        }
        let input = serde_json::to_vec(request)
            .map_err(|e| fail(format!("request could not be serialised: {e}")))?;
        let mut output = ByteBuffer::empty();
        // SAFETY: `handle` is a live handle of this plugin (created by its `create`, destroyed
        // only in `drop`), used by one call at a time (`DynamicSource` is neither `Sync` nor
        // `Send`, and `build` takes `&mut self`, the others take `&self` but cannot run
        // concurrently on one thread); `input` is alive for the call; `output` is a valid
        // slot.
        let status = unsafe {
            (self.functions.call)(
                self.handle,
                method,
                input.as_ptr(),
                input.len(),
                &mut output,
            )
        };
        let bytes = self.take_buffer(output);
        let bytes = bytes.ok_or_else(|| {
            fail(format!(
                "returned status {status} with a malformed output buffer (null pointer with a \
                 nonzero length)"
            ))
        })?;
        match decode_answer(status, &bytes) {
            Ok(answer) => Ok(Some(answer)),
            Err(AnswerError::UnknownMethod) => Ok(None),
            // The source's own refusal passes through unchanged, as in process.
            Err(AnswerError::Refused(error)) => Err(error),
            Err(other) => Err(fail(other.to_string())),
        }
    }

    /// Copies an output buffer and hands it back to the plugin; `None` if it is malformed.
    fn take_buffer(&self, buffer: ByteBuffer) -> Option<Vec<u8>> {
        if buffer.ptr.is_null() {
            return (buffer.len == 0).then(Vec::new);
        }
        // SAFETY: the plugin wrote a non-null buffer of `len` initialised bytes that stays
        // valid until we free it below.
        let bytes = unsafe { std::slice::from_raw_parts(buffer.ptr, buffer.len) }.to_vec();
        // SAFETY: returned unchanged to the plugin that allocated it, once.
        unsafe { (self.functions.free_buffer)(buffer) };
        Some(bytes)
    }
}

/// What was wrong with a plugin's answer (see [`decode_answer`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum AnswerError {
    /// The source refused the request ([`STATUS_SOURCE_ERROR`] with a valid error).
    #[error("refused: {0}")]
    Refused(SourceError),
    /// The plugin does not know the method: it was built before the method existed.
    #[error("does not know this method (built against an older plugin-abi)")]
    UnknownMethod,
    /// Anything else: a panic, an answer that is not the expected JSON, an unknown status.
    #[error("{0}")]
    Malformed(String),
}

/// Decodes the answer of a plugin's `call` (its status code and output bytes) into the
/// expected JSON type. Every byte sequence gives an answer or an [`AnswerError`]; nothing in
/// it can make the host panic or allocate beyond what the JSON itself describes.
pub fn decode_answer<Ans: DeserializeOwned>(status: i32, bytes: &[u8]) -> Result<Ans, AnswerError> {
    match status {
        STATUS_OK => serde_json::from_slice(bytes).map_err(|e| {
            AnswerError::Malformed(format!("returned an answer that is not valid JSON: {e}"))
        }),
        STATUS_SOURCE_ERROR => match serde_json::from_slice::<SourceError>(bytes) {
            Ok(error) => Err(AnswerError::Refused(error)),
            Err(e) => Err(AnswerError::Malformed(format!(
                "failed with an error that is not valid JSON: {e}"
            ))),
        },
        STATUS_PANIC => Err(AnswerError::Malformed(format!(
            "panicked: {}",
            String::from_utf8_lossy(bytes)
        ))),
        STATUS_BAD_INPUT if bytes.starts_with(b"unknown method") => Err(AnswerError::UnknownMethod),
        STATUS_BAD_INPUT => Err(AnswerError::Malformed(format!(
            "rejected the request as bad input: {}",
            String::from_utf8_lossy(bytes)
        ))),
        other => Err(AnswerError::Malformed(format!(
            "returned unknown status {other}"
        ))),
    }
}

impl Drop for DynamicSource {
    fn drop(&mut self) {
        if !self.handle.is_null() {
            // SAFETY: a live handle of this plugin, destroyed once, with no call running
            // (we hold `&mut self`).
            unsafe { (self.functions.destroy)(self.handle) };
        }
    }
}

impl ConstraintSource for DynamicSource {
    fn kind(&self) -> &str {
        &self.kind
    }

    fn version(&self) -> &str {
        &self.version
    }

    fn build(&mut self, request: &BuildRequest) -> Result<Contribution, SourceError> {
        self.invoke(METHOD_BUILD, "build", request)
    }

    fn plan(&self, request: &PlanRequest) -> Result<OperationPlan, SourceError> {
        self.invoke(METHOD_PLAN, "plan", request)
    }

    fn render(&self, request: &RenderRequest) -> Result<Vec<OutputFile>, SourceError> {
        self.invoke(METHOD_RENDER, "render", request)
    }

    /// A plugin built before checks existed cannot check an operation in advance: it is
    /// accepted here and checked by `plan` at its turn.
    fn check_operation(&self, request: &OperationCheckRequest) -> Result<(), SourceError> {
        match self.call(METHOD_CHECK_OPERATION, "check_operation", request)? {
            Some(()) | None => Ok(()),
        }
    }

    /// A plugin built before checks existed answers an unchecked [`OutputCheck`]: the host
    /// then checks the files when they are rendered.
    fn check_output(&self, request: &OutputCheckRequest) -> Result<OutputCheck, SourceError> {
        Ok(self
            .call(METHOD_CHECK_OUTPUT, "check_output", request)?
            .unwrap_or_default())
    }

    /// A plugin built before views existed has nothing to draw.
    fn view(&self, request: &ViewRequest) -> Result<Option<SourceView>, SourceError> {
        Ok(self.call(METHOD_VIEW, "view", request)?.flatten())
    }
}

#[cfg(test)]
mod tests {
    //! Headers and vtables a real plugin would never produce, built in process.

    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    const KIND: &CStr = c"fake";
    const VERSION: &CStr = c"0.0.1";

    static DESTROYED: AtomicUsize = AtomicUsize::new(0);

    extern "C" fn create_ok() -> *mut c_void {
        // Any non-null token: the fake `call`s below never dereference it.
        std::ptr::NonNull::<u64>::dangling().as_ptr().cast()
    }
    extern "C" fn create_null() -> *mut c_void {
        std::ptr::null_mut()
    }
    unsafe extern "C" fn destroy(_: *mut c_void) {}
    /// Only the vtables of `instances_are_destroyed_once...` use it, so tests running in
    /// parallel do not disturb the count.
    unsafe extern "C" fn destroy_counted(_: *mut c_void) {
        DESTROYED.fetch_add(1, Ordering::SeqCst);
    }
    unsafe extern "C" fn free_buffer(buffer: ByteBuffer) {
        if !buffer.ptr.is_null() {
            // SAFETY: made by `answer` from a Vec with these parts.
            drop(unsafe { Vec::from_raw_parts(buffer.ptr, buffer.len, buffer.cap) });
        }
    }

    /// Writes `status` and `bytes` as a plugin would.
    ///
    /// # Safety
    /// `output` is valid for one write.
    unsafe fn answer(output: *mut ByteBuffer, status: i32, bytes: &[u8]) -> i32 {
        let mut bytes = std::mem::ManuallyDrop::new(bytes.to_vec());
        // SAFETY: valid for one write by the contract.
        unsafe {
            output.write(ByteBuffer {
                ptr: bytes.as_mut_ptr(),
                len: bytes.len(),
                cap: bytes.capacity(),
            })
        };
        status
    }

    /// A `call` that answers build with the garbage the request's `config` names.
    unsafe extern "C" fn call_garbage(
        _: *mut c_void,
        _method: u32,
        input: *const u8,
        len: usize,
        output: *mut ByteBuffer,
    ) -> i32 {
        // SAFETY: the host passes `len` readable bytes.
        let input = unsafe { std::slice::from_raw_parts(input, len) };
        let request: BuildRequest = serde_json::from_slice(input).expect("host sends JSON");
        // SAFETY: the host passes a valid output slot.
        unsafe {
            match request.config.as_str() {
                "invalid json" => answer(output, STATUS_OK, b"{\"parameters\": [oops"),
                "wrong shape" => answer(output, STATUS_OK, b"[1, 2, 3]"),
                "bad error" => answer(output, STATUS_SOURCE_ERROR, b"not an error"),
                "status 42" => answer(output, 42, b""),
                "negative status" => answer(output, -1, b"{}"),
                "panic" => answer(output, STATUS_PANIC, b"it broke"),
                "bad input" => answer(output, STATUS_BAD_INPUT, b"what?"),
                "null buffer" => {
                    output.write(ByteBuffer {
                        ptr: std::ptr::null_mut(),
                        len: 5,
                        cap: 5,
                    });
                    STATUS_OK
                }
                "no buffer" => STATUS_OK, // leaves the host's empty buffer: empty JSON
                "refuse" => answer(output, STATUS_SOURCE_ERROR, br#"{"message":"no thanks"}"#),
                _ => {
                    let empty = serde_json::to_vec(&Contribution::default()).expect("serialise");
                    answer(output, STATUS_OK, &empty)
                }
            }
        }
    }

    static GOOD_VTABLE: PluginVTable = PluginVTable {
        create: Some(create_ok),
        destroy: Some(destroy),
        call: Some(call_garbage),
        free_buffer: Some(free_buffer),
    };

    fn header() -> PluginHeader {
        PluginHeader {
            magic: MAGIC,
            abi_version: ABI_VERSION,
            vtable_size: VTABLE_SIZE,
            kind: KIND.as_ptr(),
            version: VERSION.as_ptr(),
            vtable: &GOOD_VTABLE,
        }
    }

    fn validate(header: PluginHeader) -> Result<LoadedPlugin, LoadError> {
        // Leaked: the loaded plugin may keep pointers into it, as into a real library.
        let header: &'static PluginHeader = Box::leak(Box::new(header));
        // SAFETY: all pointers are null or point to static data as the contract requires.
        unsafe { read_header(header, Path::new("fake/libfake.so")) }
    }

    fn reason(result: Result<LoadedPlugin, LoadError>) -> String {
        match result {
            Err(LoadError::BadHeader { path, reason }) => {
                assert_eq!(path, Path::new("fake/libfake.so"));
                reason
            }
            other => panic!("expected a bad header, got {other:?}"),
        }
    }

    fn build(source: &mut DynamicSource, config: &str) -> Result<Contribution, SourceError> {
        source.build(&BuildRequest {
            schema: api::SCHEMA_VERSION,
            input_limit: api::input::DEFAULT_MAX_INPUT_BYTES,
            name: "f".into(),
            config: config.into(),
            base_dir: ".".into(),
            system: Default::default(),
            values: Default::default(),
            sources: vec![],
        })
    }

    #[test]
    fn loaded_plugins_can_be_shared_between_threads() {
        fn shareable<T: Send + Sync + Clone + 'static>() {}
        shareable::<LoadedPlugin>();
        shareable::<LoadError>();
    }

    #[test]
    fn a_good_header_is_accepted() {
        let plugin = validate(header()).expect("valid");
        assert_eq!(
            (plugin.kind.as_str(), plugin.version.as_str()),
            ("fake", "0.0.1")
        );
        assert_eq!(plugin.abi_version, ABI_VERSION);
        // A longer vtable (a plugin from a later, extended ABI 1) is fine too.
        let mut long = header();
        long.vtable_size += 8;
        assert!(validate(long).is_ok());
    }

    #[test]
    fn malformed_headers_are_rejected_with_a_reason() {
        // SAFETY: null is allowed.
        let null = unsafe { read_header(std::ptr::null(), Path::new("fake/libfake.so")) };
        assert!(reason(null).contains("null header"));

        let mut h = header();
        h.magic = *b"ECLESPLX";
        assert!(reason(validate(h)).contains("magic"));

        let mut h = header();
        h.abi_version = 2;
        assert!(reason(validate(h)).contains("ABI version 2"));

        let mut h = header();
        h.vtable_size = VTABLE_SIZE - 8;
        let r = reason(validate(h));
        assert!(r.contains(&format!("{} bytes", VTABLE_SIZE - 8)), "{r}");

        let mut h = header();
        h.kind = std::ptr::null();
        assert_eq!(reason(validate(h)), "kind is a null pointer");

        let mut h = header();
        h.version = c"\xff\xfe".as_ptr();
        assert!(reason(validate(h)).starts_with("version is not UTF-8"));

        let mut h = header();
        h.kind = c"".as_ptr();
        assert_eq!(reason(validate(h)), "the kind is empty");

        let mut h = header();
        h.vtable = std::ptr::null();
        assert_eq!(reason(validate(h)), "the vtable pointer is null");

        static NO_CALL: PluginVTable = PluginVTable {
            create: Some(create_ok),
            destroy: Some(destroy),
            call: None,
            free_buffer: Some(free_buffer),
        };
        let mut h = header();
        h.vtable = &NO_CALL;
        assert_eq!(reason(validate(h)), "the vtable's `call` function is null");
    }

    #[test]
    fn garbage_answers_become_source_errors_naming_the_plugin() {
        let plugin = validate(header()).expect("valid");
        let mut source = plugin.instantiate();
        let cases = [
            ("invalid json", "returned an answer that is not valid JSON"),
            ("wrong shape", "returned an answer that is not valid JSON"),
            ("bad error", "failed with an error that is not valid JSON"),
            ("status 42", "returned unknown status 42"),
            ("negative status", "returned unknown status -1"),
            ("panic", "build panicked: it broke"),
            ("bad input", "rejected the request as bad input: what?"),
            ("null buffer", "malformed output buffer"),
            ("no buffer", "not valid JSON"),
        ];
        for (config, expected) in cases {
            let error = build(&mut source, config).expect_err(config);
            assert!(
                error
                    .message
                    .starts_with(r#"plugin "fake" 0.0.1 (fake/libfake.so): build "#),
                "{config}: {}",
                error.message
            );
            assert!(
                error.message.contains(expected),
                "{config}: {}",
                error.message
            );
        }
        // A well-formed refusal passes through untouched; a good answer decodes.
        assert_eq!(
            build(&mut source, "refuse"),
            Err(SourceError::new("no thanks"))
        );
        assert_eq!(build(&mut source, "fine"), Ok(Contribution::default()));
    }

    #[test]
    fn instances_are_destroyed_once_and_failed_constructors_are_reported() {
        static COUNTED: PluginVTable = PluginVTable {
            create: Some(create_ok),
            destroy: Some(destroy_counted),
            call: Some(call_garbage),
            free_buffer: Some(free_buffer),
        };
        let mut h = header();
        h.vtable = &COUNTED;
        let plugin = validate(h).expect("valid");
        let before = DESTROYED.load(Ordering::SeqCst);
        drop(plugin.instantiate());
        assert_eq!(DESTROYED.load(Ordering::SeqCst), before + 1);

        static NULL_CREATE: PluginVTable = PluginVTable {
            create: Some(create_null),
            destroy: Some(destroy_counted),
            call: Some(call_garbage),
            free_buffer: Some(free_buffer),
        };
        let mut h = header();
        h.vtable = &NULL_CREATE;
        let plugin = validate(h).expect("valid");
        let mut source = plugin.instantiate();
        assert_eq!(source.kind(), "fake");
        let error = build(&mut source, "fine").expect_err("no instance");
        assert!(error.message.contains("could not create an instance"));
        let before = DESTROYED.load(Ordering::SeqCst);
        drop(source);
        assert_eq!(
            DESTROYED.load(Ordering::SeqCst),
            before,
            "null is not destroyed"
        );
    }
}
