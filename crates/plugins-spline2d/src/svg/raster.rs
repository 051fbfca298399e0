//! A picture as PNG: the SVG this crate draws, rasterised with anti-aliasing by `resvg`
//! (tiny-skia), on white, at twice its size. Everything drawn as shapes comes out the same as
//! in the SVG; text (the panels' titles and labels) is left out — `resvg` is built without
//! fonts, so that a picture does not depend on the fonts of the machine it is made on.

/// Largest side of a rasterised picture, in pixels.
pub const MAX_SIDE: u32 = 8192;

/// Pixels per SVG unit.
const SCALE: f32 = 2.0;

/// The PNG of `svg`.
pub fn svg_to_png(svg: &str) -> Result<Vec<u8>, String> {
    let tree = resvg::usvg::Tree::from_str(svg, &resvg::usvg::Options::default())
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
