//! Reading input files (run files, meshes, models, height fields) safely: only regular files,
//! never more than a size limit, binary data refused with the file named.
//!
//! Without these checks `/dev/zero` named as a mesh grows the process to gigabytes, a FIFO
//! blocks forever and a binary file is reported as a confusing syntax error far into it. The
//! file's type and size are checked before a byte is read, and reading stops at the limit even
//! if the file grows meanwhile.

use std::fs::File;
use std::io::Read;
use std::path::Path;

/// The default largest input file, in bytes (256 MiB). Hosts let users raise it
/// (`ecles --max-input-bytes`), and forward the limit to sources in their requests.
pub const DEFAULT_MAX_INPUT_BYTES: u64 = 256 * 1024 * 1024;

/// Why an input file could not be read. Every message names the file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum InputFileError {
    /// The file does not exist or cannot be opened or read.
    #[error("{path}: cannot read the {what}: {message}")]
    Io {
        /// The file.
        path: String,
        /// What the file was meant to be (`"mesh"`, `"run file"`).
        what: String,
        /// The system's message.
        message: String,
    },
    /// Not a regular file (a directory, FIFO, device or socket).
    #[error("{path}: the {what} must be a regular file, but this is {kind}")]
    NotRegular {
        /// The file.
        path: String,
        /// What the file was meant to be.
        what: String,
        /// What it is instead.
        kind: &'static str,
    },
    /// Larger than the limit.
    #[error(
        "{path}: the {what} has {size} bytes, more than the limit of {limit} bytes (raise it with --max-input-bytes)"
    )]
    TooLarge {
        /// The file.
        path: String,
        /// What the file was meant to be.
        what: String,
        /// Its size (at least this many bytes).
        size: u64,
        /// The limit.
        limit: u64,
    },
    /// A text file holding binary data.
    #[error("{path}:{line}:{column}: the {what} is not a text file (binary data: a NUL byte)")]
    Binary {
        /// The file.
        path: String,
        /// What the file was meant to be.
        what: String,
        /// 1-based line of the first NUL byte.
        line: usize,
        /// 1-based column (in bytes) of the first NUL byte.
        column: usize,
    },
}

impl InputFileError {
    /// The message without the file name and role, completing a sentence that starts with
    /// them (`"worm.obj: the mesh "` + `"must be a regular file, but this is a FIFO"`), for
    /// readers that put the name (and the position) in front themselves.
    pub fn reason(&self) -> String {
        match self {
            InputFileError::Io { message, .. } => format!("cannot be read: {message}"),
            InputFileError::NotRegular { kind, .. } => {
                format!("must be a regular file, but this is {kind}")
            }
            InputFileError::TooLarge { size, limit, .. } => format!(
                "has {size} bytes, more than the limit of {limit} bytes (raise it with --max-input-bytes)"
            ),
            InputFileError::Binary { .. } => "is not a text file (binary data: a NUL byte)".into(),
        }
    }

    /// Line and column of the offending byte, for [`InputFileError::Binary`].
    pub fn position(&self) -> Option<(usize, usize)> {
        match self {
            InputFileError::Binary { line, column, .. } => Some((*line, *column)),
            _ => None,
        }
    }
}

/// What kind of non-regular file `file_type` is, in words.
fn describe(file_type: std::fs::FileType) -> &'static str {
    if file_type.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if file_type.is_char_device() {
            return "a character device";
        }
        if file_type.is_block_device() {
            return "a block device";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    "not a regular file"
}

/// Reads a regular file of at most `limit` bytes. `what` names the file's role in messages.
///
/// The type is checked (following symbolic links) before the file is opened, so a FIFO is
/// refused without blocking; the size is checked before reading and the read stops one byte
/// past the limit.
pub fn read_regular_file(path: &Path, what: &str, limit: u64) -> Result<Vec<u8>, InputFileError> {
    let name = path.display().to_string();
    let io = |e: std::io::Error| InputFileError::Io {
        path: name.clone(),
        what: what.to_string(),
        message: e.to_string(),
    };
    let check = |metadata: &std::fs::Metadata| -> Result<(), InputFileError> {
        if !metadata.file_type().is_file() {
            return Err(InputFileError::NotRegular {
                path: name.clone(),
                what: what.to_string(),
                kind: describe(metadata.file_type()),
            });
        }
        if metadata.len() > limit {
            return Err(InputFileError::TooLarge {
                path: name.clone(),
                what: what.to_string(),
                size: metadata.len(),
                limit,
            });
        }
        Ok(())
    };
    check(&std::fs::metadata(path).map_err(io)?)?;
    let file = File::open(path).map_err(io)?;
    // The file may have been replaced between the two calls: check what was opened.
    let metadata = file.metadata().map_err(io)?;
    check(&metadata)?;
    let capacity = usize::try_from(metadata.len()).unwrap_or(0);
    let mut bytes = Vec::with_capacity(capacity);
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(InputFileError::TooLarge {
            path: name,
            what: what.to_string(),
            size: bytes.len() as u64,
            limit,
        });
    }
    Ok(bytes)
}

/// Reads a text file of at most `limit` bytes: a regular file without NUL bytes, its UTF-8 byte
/// order mark removed. Bytes that are not UTF-8 become U+FFFD, so a parser accepts them in
/// comments and refuses them, with their line and column, where a number or keyword belongs.
pub fn read_text_file(path: &Path, what: &str, limit: u64) -> Result<String, InputFileError> {
    let bytes = read_regular_file(path, what, limit)?;
    if let Some(at) = bytes.iter().position(|&b| b == 0) {
        let before = &bytes[..at];
        let line = 1 + before.iter().filter(|&&b| b == b'\n').count();
        let line_start = before
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |i| i + 1);
        return Err(InputFileError::Binary {
            path: path.display().to_string(),
            what: what.to_string(),
            line,
            column: at - line_start + 1,
        });
    }
    let bytes = bytes
        .strip_prefix(b"\xef\xbb\xbf".as_slice())
        .map(<[u8]>::to_vec)
        .unwrap_or(bytes);
    Ok(match String::from_utf8(bytes) {
        Ok(text) => text,
        Err(e) => String::from_utf8_lossy(e.as_bytes()).into_owned(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str, bytes: &[u8]) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("api-input-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let path = dir.join(name);
        std::fs::write(&path, bytes).expect("write");
        path
    }

    #[test]
    fn reads_text_without_a_byte_order_mark() {
        let path = temp("bom.txt", b"\xef\xbb\xbfv 1 2\n# caf\xe9\n");
        let text = read_text_file(&path, "mesh", 1000).expect("text");
        assert!(text.starts_with("v 1 2\n"));
        assert!(text.contains('\u{fffd}'));
    }

    #[test]
    fn refuses_binary_data_with_its_position() {
        let path = temp("nul.bin", b"v 1 2\nv 3\x004\n");
        let err = read_text_file(&path, "model", 1000).expect_err("binary");
        assert_eq!(
            err,
            InputFileError::Binary {
                path: path.display().to_string(),
                what: "model".into(),
                line: 2,
                column: 4
            }
        );
        assert!(err
            .to_string()
            .contains(":2:4: the model is not a text file"));
    }

    #[test]
    fn refuses_files_over_the_limit_before_reading() {
        let path = temp("big.txt", &[b'1'; 100]);
        let err = read_regular_file(&path, "height field", 99).expect_err("too large");
        assert!(
            matches!(
                err,
                InputFileError::TooLarge {
                    size: 100,
                    limit: 99,
                    ..
                }
            ),
            "{err}"
        );
        assert_eq!(
            read_regular_file(&path, "height field", 100)
                .expect("at the limit")
                .len(),
            100
        );
    }

    #[test]
    fn refuses_directories_and_devices() {
        let err = read_regular_file(&std::env::temp_dir(), "mesh", 1000).expect_err("dir");
        assert!(err.to_string().contains("a directory"), "{err}");
        #[cfg(unix)]
        {
            let err = read_regular_file(Path::new("/dev/zero"), "mesh", 1000).expect_err("dev");
            assert!(err.to_string().contains("a character device"), "{err}");
        }
        let err =
            read_regular_file(Path::new("/no/such/file.obj"), "mesh", 1000).expect_err("missing");
        assert!(
            err.to_string()
                .starts_with("/no/such/file.obj: cannot read the mesh"),
            "{err}"
        );
    }
}
