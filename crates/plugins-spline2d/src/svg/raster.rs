//! A picture as PNG: the SVG this crate draws, rasterised with anti-aliasing by `resvg`
//! (tiny-skia), on white, at twice its size, with the same layers. The panels' titles are text:
//! they are drawn with a sans-serif font of the machine (`DejaVu Sans`, `Liberation Sans`,
//! `Noto Sans`, `Arial` or `Helvetica`, the first found among the fonts `fontdb` finds on the
//! system), so only the titles' pixels depend on the machine's fonts; a machine without any of
//! them gets the picture without titles, and the output says so ([`missing_fonts_note`]).

use resvg::usvg::fontdb;
use std::sync::{Arc, OnceLock};

/// Largest side of a rasterised picture, in pixels.
pub const MAX_SIDE: u32 = 8192;

/// Pixels per SVG unit.
const SCALE: f32 = 2.0;

/// Sans-serif families the titles are drawn with, in order of preference.
const SANS_SERIF: [&str; 5] = [
    "DejaVu Sans",
    "Liberation Sans",
    "Noto Sans",
    "Arial",
    "Helvetica",
];

/// The system's fonts, read once per process, with the sans-serif family set to the first of
/// [`SANS_SERIF`] present; `None` when none is.
fn fonts() -> &'static (Arc<fontdb::Database>, Option<&'static str>) {
    static FONTS: OnceLock<(Arc<fontdb::Database>, Option<&'static str>)> = OnceLock::new();
    FONTS.get_or_init(|| {
        let mut database = fontdb::Database::new();
        database.load_system_fonts();
        let family = SANS_SERIF.into_iter().find(|name| {
            database
                .faces()
                .any(|face| face.families.iter().any(|(family, _)| family == name))
        });
        if let Some(name) = family {
            database.set_sans_serif_family(name);
        }
        (Arc::new(database), family)
    })
}

/// A note for the output when this machine has none of the fonts the titles are drawn with.
pub fn missing_fonts_note() -> Option<String> {
    fonts().1.is_none().then(|| {
        format!(
            "no sans-serif font found ({}): the PNG has no titles",
            SANS_SERIF.join(", ")
        )
    })
}

/// The PNG of `svg`.
pub fn svg_to_png(svg: &str) -> Result<Vec<u8>, String> {
    let options = resvg::usvg::Options {
        fontdb: Arc::clone(&fonts().0),
        ..resvg::usvg::Options::default()
    };
    let tree = resvg::usvg::Tree::from_str(svg, &options)
        .map_err(|e| format!("the picture cannot be rasterised: {e}"))?;
    let size = tree
        .size()
        .to_int_size()
        .scale_by(SCALE)
        .filter(|s| s.width() <= MAX_SIDE && s.height() <= MAX_SIDE)
        .ok_or_else(|| {
            format!(
                "the picture is larger than {MAX_SIDE} pixels on a side at {SCALE} pixels per unit"
            )
        })?;
    let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width(), size.height())
        .ok_or_else(|| "the picture has no pixels".to_string())?;
    pixmap.fill(resvg::tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::from_scale(SCALE, SCALE),
        &mut pixmap.as_mut(),
    );
    pixmap
        .encode_png()
        .map_err(|e| format!("the picture cannot be encoded as PNG: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A title is drawn when the machine has a sans-serif font, and the output says when it
    /// has none.
    #[test]
    fn titles_are_drawn_with_a_sans_serif_font() {
        let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="60" height="20" viewBox="0 0 60 20"><text x="30" y="15" font-family="sans-serif" font-size="14" text-anchor="middle">Worm</text></svg>"#;
        let png = svg_to_png(svg).expect("rasterised");
        let decoder = png::Decoder::new(std::io::Cursor::new(png));
        let mut reader = decoder.read_info().expect("a PNG");
        let mut pixels = vec![0; reader.output_buffer_size().expect("a size")];
        reader.next_frame(&mut pixels).expect("pixels");
        let ink = pixels.chunks(4).filter(|p| p[0] < 128).count();
        match fonts().1 {
            Some(_) => {
                assert!(ink > 50, "{ink} dark pixels of the title");
                assert_eq!(missing_fonts_note(), None);
            }
            None => {
                assert_eq!(ink, 0);
                assert!(missing_fonts_note().is_some());
            }
        }
    }

    #[test]
    fn a_drawing_is_rasterised_with_its_shapes_at_twice_its_size() {
        let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="20" height="10" viewBox="0 0 20 10"><rect x="10" y="0" width="10" height="10" fill="black"/></svg>"#;
        let png = svg_to_png(svg).expect("rasterised");
        let decoder = png::Decoder::new(std::io::Cursor::new(png));
        let mut reader = decoder.read_info().expect("a PNG");
        let mut pixels = vec![0; reader.output_buffer_size().expect("size")];
        let info = reader.next_frame(&mut pixels).expect("pixels");
        assert_eq!((info.width, info.height), (40, 20));
        let at = |x: usize, y: usize| pixels[(y * 40 + x) * 4];
        assert_eq!((at(5, 5), at(30, 5)), (255, 0), "white left, black right");
        let huge = svg.replace(r#"width="20""#, r#"width="20000""#);
        assert!(svg_to_png(&huge).is_err());
    }
}
