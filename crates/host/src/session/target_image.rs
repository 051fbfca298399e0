//! The editor's target image named in the run file (`editor: (image: (file: ...))`), checked
//! before anything runs: a regular file within the input limit, a PNG whose header reads or a
//! JPEG (its start-of-image marker), with its size in pixels when known.

use super::Session;
use crate::error::RunError;
use crate::runfile::TargetImage;
use std::path::PathBuf;

/// A checked target image: where it is, its bytes and media type.
#[derive(Debug, Clone)]
pub struct CheckedImage {
    /// The file.
    pub path: PathBuf,
    /// Its contents.
    pub bytes: Vec<u8>,
    /// `image/png` or `image/jpeg`.
    pub media_type: &'static str,
    /// Width and height in pixels (read from a PNG's header; `None` for a JPEG, whose size
    /// the browser reads).
    pub size: Option<(u32, u32)>,
    /// The settings of the run file.
    pub settings: TargetImage,
}

const PNG_SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";
const JPEG_START: &[u8] = &[0xFF, 0xD8, 0xFF];

impl Session {
    /// The run file's target image, read and checked; `None` when the run names none.
    pub fn target_image(&self) -> Result<Option<CheckedImage>, RunError> {
        let Some((config, _)) = &self.run.editor else {
            return Ok(None);
        };
        let Some(settings) = &config.image else {
            return Ok(None);
        };
        let path = self.base_dir.join(&settings.file);
        let bytes = api::input::read_regular_file(&path, "target image", self.input_limit)
            .map_err(|e| RunError::input(format!("{}: editor image: {e}", self.run_name())))?;
        let bad = |why: String| {
            RunError::input(format!(
                "{}: editor image {}: {why}",
                self.run_name(),
                path.display()
            ))
        };
        let (media_type, size) = if bytes.starts_with(PNG_SIGNATURE) {
            let decoder = png::Decoder::new(std::io::Cursor::new(&bytes));
            let reader = decoder
                .read_info()
                .map_err(|e| bad(format!("not a readable PNG: {e}")))?;
            let info = reader.info();
            ("image/png", Some((info.width, info.height)))
        } else if bytes.starts_with(JPEG_START) {
            ("image/jpeg", None)
        } else {
            return Err(bad("neither a PNG nor a JPEG".into()));
        };
        Ok(Some(CheckedImage {
            path,
            bytes,
            media_type,
            size,
            settings: settings.clone(),
        }))
    }
}
