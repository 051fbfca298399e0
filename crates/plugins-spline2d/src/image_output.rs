//! A raster image deformed with the spline (an output's `image`), thesis 19's image morphing:
//!
//! ```ron
//! image: (
//!     file: "photo.png",           // PNG or JPEG, relative to the run file
//!     position: ("0", "40"),       // model coordinates of its top-left corner (default (0, 0))
//!     units_per_pixel: "1/10",     // model units per pixel (default 1)
//!     fill: "#ffffff",             // what the deformation uncovers: #rrggbb or #rrggbbaa
//! ),                               // (default transparent)
//! ```
//!
//! written as `<stem>-deformed.png` (RGBA, the input's size); the algorithm and what happens
//! at the mesh's border are in [`spline2d::image`]. The image is read and checked (format,
//! size) with the rest of the output before any edit runs.

use api::config::check_output_file_name;
use api::exact::{rational_to_f64, Exact};
use api::{OutputFile, Rational};
use serde::Deserialize;
use spline2d::image::{deform_image, reference_triangles, Placement, Rgba};
use std::path::Path;

/// Most pixels on a side of an image to deform.
pub const MAX_IMAGE_SIDE: u32 = 16_384;

/// The `image` of an output, as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ImageConfig {
    file: String,
    #[serde(default)]
    position: Option<(Exact, Exact)>,
    #[serde(default)]
    units_per_pixel: Option<Exact>,
    #[serde(default)]
    fill: Option<String>,
}

/// An image read and checked, ready to deform.
#[derive(Debug, Clone)]
pub(crate) struct CheckedImage {
    /// `<stem>-deformed.png`.
    pub(crate) name: String,
    image: Rgba,
    placement: Placement,
    fill: [u8; 4],
}

/// `#rrggbb` or `#rrggbbaa`.
fn parse_colour(text: &str) -> Option<[u8; 4]> {
    let hex = text.strip_prefix('#')?;
    if !(hex.len() == 6 || hex.len() == 8) || !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    let byte = |k: usize| u8::from_str_radix(&hex[2 * k..2 * k + 2], 16).ok();
    Some([
        byte(0)?,
        byte(1)?,
        byte(2)?,
        if hex.len() == 8 { byte(3)? } else { 255 },
    ])
}

/// Reads and checks the image of `config` (paths against `base_dir`, at most `limit` bytes and
/// [`MAX_IMAGE_SIDE`] pixels on a side, checked from the header before the pixels are
/// decoded).
pub(crate) fn check_image(
    config: &ImageConfig,
    base_dir: &Path,
    limit: u64,
) -> Result<CheckedImage, String> {
    let path = base_dir.join(&config.file);
    let shown = config.file.as_str();
    let units = config
        .units_per_pixel
        .as_ref()
        .map_or_else(|| Rational::from_integer(1.into()), |e| e.0.clone());
    if units <= Rational::from_integer(0.into()) {
        return Err(format!("image {shown:?}: units_per_pixel must be positive"));
    }
    let (left, top) = config.position.as_ref().map_or((0.0, 0.0), |(x, y)| {
        (rational_to_f64(&x.0), rational_to_f64(&y.0))
    });
    let fill = match &config.fill {
        Some(text) => parse_colour(text).ok_or_else(|| {
            format!("image {shown:?}: fill {text:?} must be a colour #rrggbb or #rrggbbaa")
        })?,
        None => [0, 0, 0, 0],
    };
    let placement = Placement {
        left,
        top,
        units_per_pixel: rational_to_f64(&units),
    };
    if !(placement.units_per_pixel > 0.0
        && placement.units_per_pixel.is_finite()
        && left.is_finite()
        && top.is_finite())
    {
        return Err(format!("image {shown:?}: its placement does not fit f64"));
    }
    let stem = Path::new(&config.file)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let name = format!("{stem}-deformed.png");
    check_output_file_name(&name, "deformed image", "png")?;
    let bytes = api::input::read_regular_file(&path, "image", limit).map_err(|e| e.to_string())?;
    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| format!("image {}: {e}", path.display()))?;
    match reader.format() {
        Some(image::ImageFormat::Png | image::ImageFormat::Jpeg) => {}
        _ => return Err(format!("image {}: not a PNG or JPEG file", path.display())),
    }
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_IMAGE_SIDE);
    limits.max_image_height = Some(MAX_IMAGE_SIDE);
    limits.max_alloc = Some(limit.saturating_mul(64).max(1 << 26));
    reader.limits(limits);
    let decoded = reader
        .decode()
        .map_err(|e| format!("image {}: {e}", path.display()))?
        .into_rgba8();
    let (width, height) = (decoded.width() as usize, decoded.height() as usize);
    Ok(CheckedImage {
        name,
        image: Rgba {
            width,
            height,
            pixels: decoded.into_raw(),
        },
        placement,
        fill,
    })
}

/// The deformed image of `checked` under `spline` (the float twin of the spline at its values)
/// as a PNG file.
pub(crate) fn render_image(
    checked: &CheckedImage,
    spline: &spline2d::spline::Spline,
    float: &spline2d::eval::FloatSpline,
) -> Result<OutputFile, String> {
    let out = deform_image(
        float,
        &reference_triangles(spline),
        &checked.image,
        checked.placement,
        checked.fill,
    )
    .map_err(|e| e.to_string())?;
    let buffer = image::RgbaImage::from_raw(out.width as u32, out.height as u32, out.pixels)
        .ok_or_else(|| "the deformed image has the wrong size".to_string())?;
    let mut bytes = Vec::new();
    buffer
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .map_err(|e| format!("the deformed image cannot be encoded: {e}"))?;
    Ok(OutputFile::new(checked.name.clone(), bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_are_hex_with_optional_alpha() {
        assert_eq!(parse_colour("#ff8000"), Some([255, 128, 0, 255]));
        assert_eq!(parse_colour("#ff800080"), Some([255, 128, 0, 128]));
        for bad in ["ff8000", "#ff80", "#gg8000", "#ff8000801"] {
            assert_eq!(parse_colour(bad), None, "{bad}");
        }
    }
}
