//! GeoTIFF elevation models (`.tif`, `.tiff`): one band of heights, read and written by the
//! `tiff` crate, with the georeferencing of the GeoTIFF tags.
//!
//! **Reading.** The first image's single sample per pixel (8-, 16-, 32- or 64-bit integers,
//! signed or not, or 32- and 64-bit floats), north-up: `ModelPixelScaleTag` gives the cell
//! `(sx, sy)` and `ModelTiepointTag` the model point `(X, Y)` of raster point `(I, J)`; a
//! `ModelTransformationTag` is read when it has no rotation (a north-up grid), and refused
//! otherwise. `GTRasterTypeGeoKey` (1025) says what the raster point is: `PixelIsArea` (the
//! default) a pixel's corner — the sample of pixel `(c, r)` is at its centre,
//! `X + (c + ½ − I)·sx`, `Y − (r + ½ − J)·sy` — and `PixelIsPoint` the sample itself,
//! `X + (c − I)·sx`. Tag values are `f64` and read exactly (every `f64` is a rational), so the
//! positions are exact. Missing samples: `GDAL_NODATA` (tag 42113, the text GDAL writes,
//! compared with each sample as an `f64`) and NaN.
//!
//! **Writing.** A terrain without φ written back as the same GeoTIFF: the same size, sample
//! type and georeferencing tags (`ModelPixelScaleTag`, `ModelTiepointTag`,
//! `ModelTransformationTag`, `GeoKeyDirectoryTag`, `GeoDoubleParamsTag`, `GeoAsciiParamsTag`,
//! `GDAL_METADATA`, `GDAL_NODATA`), the missing samples as they were, unmoved samples with
//! their own values, moved heights in the sample type (integers rounded to the nearest, a
//! height beyond the type's range refused). The image is written uncompressed in strips, as the
//! `tiff` encoder lays it out: the same raster, not the same bytes — except when no height
//! changes: then the file is written back byte for byte.

use crate::heightfield::{HeightField, HeightFieldError, MAX_SAMPLES};
use api::exact::rational_from_f64;
use api::Rational;
use std::io::Cursor;
use std::path::Path;
use tiff::decoder::{Decoder, DecodingResult, Limits};
use tiff::encoder::{colortype, TiffEncoder};
use tiff::tags::Tag;

/// True for a path with the extension `.tif` or `.tiff` (any case).
pub fn is_geotiff(path: &Path) -> bool {
    path.extension().is_some_and(|e| {
        let e = e.to_string_lossy();
        e.eq_ignore_ascii_case("tif") || e.eq_ignore_ascii_case("tiff")
    })
}

/// `GDAL_METADATA`: not named by the `tiff` crate.
const GDAL_METADATA: u16 = 42112;

/// The sample type of a GeoTIFF band.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SampleType {
    /// Unsigned 8-bit integers.
    U8,
    /// Signed 8-bit integers.
    I8,
    /// Unsigned 16-bit integers.
    U16,
    /// Signed 16-bit integers.
    I16,
    /// Unsigned 32-bit integers.
    U32,
    /// Signed 32-bit integers.
    I32,
    /// 32-bit floats.
    F32,
    /// 64-bit floats.
    F64,
}

/// A tag kept for writing back, with its value as read.
#[derive(Debug, Clone, PartialEq)]
enum KeptTag {
    Doubles(u16, Vec<f64>),
    Shorts(u16, Vec<u16>),
    Text(u16, String),
}

/// What a GeoTIFF height field keeps to be written back.
#[derive(Debug, Clone, PartialEq)]
pub struct GeoTiff {
    /// The file as read: written back as it is when no height changes.
    bytes: Vec<u8>,
    sample: SampleType,
    /// Raw samples as `f64` in file order (the northernmost row first), NaN and no-data
    /// values as they were.
    raw: Vec<f64>,
    tags: Vec<KeptTag>,
}

/// Reads a GeoTIFF's bytes (`file` names it in errors) as a height field.
pub fn parse(bytes: &[u8], file: &str) -> Result<HeightField, HeightFieldError> {
    let fail = |message: String| HeightFieldError::Io {
        file: file.to_string(),
        message,
    };
    let tiff = |e: tiff::TiffError| {
        fail(format!(
            "not a GeoTIFF this reader accepts ({} bytes): {e}",
            bytes.len()
        ))
    };
    let mut limits = Limits::default();
    // The largest band a height field may have, in 64-bit samples.
    limits.decoding_buffer_size = MAX_SAMPLES * 8;
    let mut decoder = Decoder::new(Cursor::new(bytes))
        .map_err(tiff)?
        .with_limits(limits);
    let (width, height) = decoder.dimensions().map_err(tiff)?;
    let (columns, rows) = (width as usize, height as usize);
    if columns < 2 || rows < 2 {
        return Err(fail(format!(
            "the raster is {columns} × {rows}: a terrain needs at least 2 × 2 samples"
        )));
    }
    if columns.checked_mul(rows).is_none_or(|n| n > MAX_SAMPLES) {
        return Err(fail(format!(
            "{columns} × {rows} samples is more than the limit of {MAX_SAMPLES}"
        )));
    }
    match decoder.colortype().map_err(tiff)? {
        tiff::ColorType::Gray(_) => {}
        other => {
            return Err(fail(format!(
                "a {other:?} raster: an elevation model has one band of heights"
            )))
        }
    }
    let find_doubles = |decoder: &mut Decoder<Cursor<&[u8]>>,
                        tag: Tag|
     -> Result<Option<Vec<f64>>, HeightFieldError> {
        match decoder.find_tag(tag).map_err(tiff)? {
            Some(value) => value
                .into_f64_vec()
                .map(Some)
                .map_err(|e| fail(format!("tag {tag:?}: {e}"))),
            None => Ok(None),
        }
    };
    let scale = find_doubles(&mut decoder, Tag::ModelPixelScaleTag)?;
    let tiepoint = find_doubles(&mut decoder, Tag::ModelTiepointTag)?;
    let transformation = find_doubles(&mut decoder, Tag::ModelTransformationTag)?;
    let keys = match decoder.find_tag(Tag::GeoKeyDirectoryTag).map_err(tiff)? {
        Some(value) => Some(
            value
                .into_u16_vec()
                .map_err(|e| fail(format!("GeoKeyDirectoryTag: {e}")))?,
        ),
        None => None,
    };
    let doubles = find_doubles(&mut decoder, Tag::GeoDoubleParamsTag)?;
    let text = |decoder: &mut Decoder<Cursor<&[u8]>>,
                tag: Tag|
     -> Result<Option<String>, HeightFieldError> {
        match decoder.find_tag(tag).map_err(tiff)? {
            Some(value) => value
                .into_string()
                .map(Some)
                .map_err(|e| fail(format!("tag {tag:?}: {e}"))),
            None => Ok(None),
        }
    };
    let ascii = text(&mut decoder, Tag::GeoAsciiParamsTag)?;
    let metadata = text(&mut decoder, Tag::Unknown(GDAL_METADATA))?;
    let nodata_text = text(&mut decoder, Tag::GdalNodata)?;

    // Cell sizes and the model point of raster point (I, J), north-up.
    let (cell, raster, model) = match (&scale, &tiepoint, &transformation) {
        (Some(s), Some(t), _) if s.len() >= 2 && t.len() >= 6 => ([s[0], s[1]], [t[0], t[1]], [t[3], t[4]]),
        (_, _, Some(m)) if m.len() == 16 => {
            if m[1] != 0.0 || m[4] != 0.0 {
                return Err(fail("ModelTransformationTag rotates the raster: only north-up grids are read".into()));
            }
            ([m[0], -m[5]], [0.0, 0.0], [m[3], m[7]])
        }
        _ => {
            return Err(fail(
                "no georeferencing: ModelPixelScaleTag and ModelTiepointTag (or ModelTransformationTag) are required"
                    .into(),
            ))
        }
    };
    if !(cell[0] > 0.0 && cell[1] > 0.0 && cell.iter().all(|c| c.is_finite())) {
        return Err(fail(format!(
            "cell size {} × {}: must be positive and finite (a north-up grid)",
            cell[0], cell[1]
        )));
    }
    if raster.iter().chain(&model).any(|x| !x.is_finite()) {
        return Err(fail("the tie point is not finite".into()));
    }
    // GTRasterTypeGeoKey: 1 PixelIsArea (default), 2 PixelIsPoint.
    let point = keys.as_deref().is_some_and(|k| {
        k.get(4..)
            .unwrap_or_default()
            .chunks_exact(4)
            .any(|key| key[0] == 1025 && key[1] == 0 && key[3] == 2)
    });
    let exact = |x: f64| rational_from_f64(x).unwrap_or_else(|| Rational::from_integer(0.into()));
    let half = if point {
        Rational::from_integer(0.into())
    } else {
        Rational::new(1.into(), 2.into())
    };
    let (sx, sy) = (exact(cell[0]), exact(cell[1]));
    // The south-west sample: column 0, row `rows − 1` from the top.
    let last_row = Rational::from_integer((rows - 1).into());
    let origin = [
        exact(model[0]) + (&half - exact(raster[0])) * &sx,
        exact(model[1]) - (last_row + &half - exact(raster[1])) * &sy,
    ];

    let samples = decoder.read_image().map_err(tiff)?;
    let (sample, raw): (SampleType, Vec<f64>) = match samples {
        DecodingResult::U8(v) => (SampleType::U8, v.into_iter().map(f64::from).collect()),
        DecodingResult::I8(v) => (SampleType::I8, v.into_iter().map(f64::from).collect()),
        DecodingResult::U16(v) => (SampleType::U16, v.into_iter().map(f64::from).collect()),
        DecodingResult::I16(v) => (SampleType::I16, v.into_iter().map(f64::from).collect()),
        DecodingResult::U32(v) => (SampleType::U32, v.into_iter().map(f64::from).collect()),
        DecodingResult::I32(v) => (SampleType::I32, v.into_iter().map(f64::from).collect()),
        DecodingResult::F32(v) => (SampleType::F32, v.into_iter().map(f64::from).collect()),
        DecodingResult::F64(v) => (SampleType::F64, v),
        _ => {
            return Err(fail(
                "a sample type this reader does not read (16-bit floats, 64-bit integers)".into(),
            ))
        }
    };
    if raw.len() != columns * rows {
        return Err(fail(format!(
            "{} samples for a {columns} × {rows} raster",
            raw.len()
        )));
    }
    let nodata = match &nodata_text {
        Some(t) => {
            let t = t.trim().trim_end_matches('\0');
            Some(
                t.parse::<f64>()
                    .map_err(|_| fail(format!("GDAL_NODATA {t:?} is not a number")))?,
            )
        }
        None => None,
    };
    let missing = |x: f64| x.is_nan() || nodata.is_some_and(|n| n == x);
    // Heights row by row from the south-west.
    let mut heights = Vec::with_capacity(raw.len());
    for row in (0..rows).rev() {
        for column in 0..columns {
            let x = raw[row * columns + column];
            heights.push((!missing(x)).then_some(x));
        }
    }
    if heights.iter().any(|h| h.is_some_and(|x| x.is_infinite())) {
        return Err(fail("a height is infinite".into()));
    }
    let mut tags = Vec::new();
    for (tag, value) in [
        (Tag::ModelPixelScaleTag, scale),
        (Tag::ModelTiepointTag, tiepoint),
        (Tag::ModelTransformationTag, transformation),
        (Tag::GeoDoubleParamsTag, doubles),
    ] {
        if let Some(v) = value {
            tags.push(KeptTag::Doubles(tag.to_u16(), v));
        }
    }
    if let Some(k) = keys {
        tags.push(KeptTag::Shorts(Tag::GeoKeyDirectoryTag.to_u16(), k));
    }
    for (tag, value) in [
        (Tag::GeoAsciiParamsTag.to_u16(), ascii),
        (GDAL_METADATA, metadata),
        (Tag::GdalNodata.to_u16(), nodata_text),
    ] {
        if let Some(v) = value {
            tags.push(KeptTag::Text(tag, v));
        }
    }
    Ok(HeightField::from_geotiff(
        columns,
        rows,
        origin,
        [sx, sy],
        heights,
        GeoTiff {
            bytes: bytes.to_vec(),
            sample,
            raw,
            tags,
        },
    ))
}

impl GeoTiff {
    /// The GeoTIFF again with `heights` (row by row from the south-west, `columns` per row)
    /// for the samples with data; see the module documentation.
    pub fn write(
        &self,
        columns: usize,
        old: &[Option<f64>],
        heights: &[Option<f64>],
    ) -> Result<Vec<u8>, String> {
        let rows = self.raw.len() / columns.max(1);
        if heights.len() != self.raw.len() || old.len() != self.raw.len() {
            return Err("the deformed heights do not fit the raster".into());
        }
        if old
            .iter()
            .zip(heights)
            .all(|(a, b)| a.map(f64::to_bits) == b.map(f64::to_bits))
        {
            return Ok(self.bytes.clone());
        }
        // File order, the unmoved samples' raw values kept.
        let mut raw = self.raw.clone();
        for row in 0..rows {
            for column in 0..columns {
                let k = row * columns + column;
                let file = (rows - 1 - row) * columns + column;
                match (old[k], heights[k]) {
                    (None, None) => {}
                    (Some(a), Some(b)) if a.to_bits() == b.to_bits() => {}
                    (_, Some(b)) if b.is_finite() => raw[file] = b,
                    (Some(_), None) => raw[file] = self.missing_value().ok_or_else(|| {
                        format!("sample ({column}, {row}) loses its data, and the raster has no GDAL_NODATA value and integer samples")
                    })?,
                    _ => return Err(format!("sample ({column}, {row}): the height is not finite")),
                }
            }
        }
        let integer = |x: f64, low: f64, high: f64| -> Result<f64, String> {
            let r = x.round();
            if x.is_nan() || (low..=high).contains(&r) {
                Ok(r)
            } else {
                Err(format!(
                    "height {x} does not fit the raster's {:?} samples",
                    self.sample
                ))
            }
        };
        let mut out = Cursor::new(Vec::new());
        let mut encoder = TiffEncoder::new(&mut out).map_err(|e| e.to_string())?;
        let (width, height) = (columns as u32, rows as u32);
        macro_rules! image {
            ($color:ty, $convert:expr) => {{
                let data = raw
                    .iter()
                    .map(|&x| $convert(x))
                    .collect::<Result<Vec<_>, String>>()?;
                let mut image = encoder
                    .new_image::<$color>(width, height)
                    .map_err(|e| e.to_string())?;
                self.write_tags(image.encoder())?;
                image.write_data(&data).map_err(|e| e.to_string())?;
            }};
        }
        // Integer samples are integral (NaN only in float rasters): the casts below are exact
        // after the range checks.
        match self.sample {
            SampleType::U8 => image!(colortype::Gray8, |x| integer(x, 0.0, 255.0)
                .map(|r| r as u8)),
            SampleType::I8 => image!(colortype::GrayI8, |x| integer(x, -128.0, 127.0)
                .map(|r| r as i8)),
            SampleType::U16 => image!(colortype::Gray16, |x| integer(x, 0.0, 65535.0)
                .map(|r| r as u16)),
            SampleType::I16 => image!(colortype::GrayI16, |x| integer(x, -32768.0, 32767.0)
                .map(|r| r as i16)),
            SampleType::U32 => image!(colortype::Gray32, |x| integer(x, 0.0, 4294967295.0)
                .map(|r| r as u32)),
            SampleType::I32 => image!(colortype::GrayI32, |x| integer(
                x,
                -2147483648.0,
                2147483647.0
            )
            .map(|r| r as i32)),
            SampleType::F32 => image!(colortype::Gray32Float, |x: f64| -> Result<f32, String> {
                let y = x as f32;
                if x.is_finite() && !y.is_finite() {
                    Err(format!("height {x} does not fit a 32-bit float"))
                } else {
                    Ok(y)
                }
            }),
            SampleType::F64 => image!(colortype::Gray64Float, |x: f64| -> Result<f64, String> {
                Ok(x)
            }),
        }
        Ok(out.into_inner())
    }

    /// The value of a sample without data: `GDAL_NODATA`, else NaN in a float raster.
    fn missing_value(&self) -> Option<f64> {
        let nodata = self.tags.iter().find_map(|tag| match tag {
            KeptTag::Text(t, text) if *t == Tag::GdalNodata.to_u16() => {
                text.trim().trim_end_matches('\0').parse::<f64>().ok()
            }
            _ => None,
        });
        nodata.or(matches!(self.sample, SampleType::F32 | SampleType::F64).then_some(f64::NAN))
    }

    fn write_tags<W: std::io::Write + std::io::Seek, K: tiff::encoder::TiffKind>(
        &self,
        directory: &mut tiff::encoder::DirectoryEncoder<'_, W, K>,
    ) -> Result<(), String> {
        for tag in &self.tags {
            let written = match tag {
                KeptTag::Doubles(t, v) => {
                    directory.write_tag(Tag::from_u16_exhaustive(*t), v.as_slice())
                }
                KeptTag::Shorts(t, v) => {
                    directory.write_tag(Tag::from_u16_exhaustive(*t), v.as_slice())
                }
                KeptTag::Text(t, v) => {
                    directory.write_tag(Tag::from_u16_exhaustive(*t), v.as_str())
                }
            };
            written.map_err(|e| e.to_string())?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 4 × 3 `f32` GeoTIFF: cells 10 × 5 units, the upper-left corner of the raster at
    /// (1000, 2000) (`PixelIsArea`), `GDAL_NODATA` −9999 on one sample, its heights in file
    /// order (the northernmost row first).
    fn dem(samples: &[f32]) -> Vec<u8> {
        dem_compressed(samples, tiff::encoder::Compression::Uncompressed)
    }

    /// [`dem`] with its strips compressed.
    fn dem_compressed(samples: &[f32], compression: tiff::encoder::Compression) -> Vec<u8> {
        let mut out = Cursor::new(Vec::new());
        let mut encoder = TiffEncoder::new(&mut out)
            .expect("encoder")
            .with_compression(compression);
        let mut image = encoder
            .new_image::<colortype::Gray32Float>(4, 3)
            .expect("image");
        let dir = image.encoder();
        dir.write_tag(Tag::ModelPixelScaleTag, &[10.0f64, 5.0, 0.0][..])
            .expect("tag");
        dir.write_tag(
            Tag::ModelTiepointTag,
            &[0.0f64, 0.0, 0.0, 1000.0, 2000.0, 0.0][..],
        )
        .expect("tag");
        // Version 1.1.0, 2 keys: GTModelTypeGeoKey projected, GTRasterTypeGeoKey PixelIsArea.
        dir.write_tag(
            Tag::GeoKeyDirectoryTag,
            &[1u16, 1, 0, 2, 1024, 0, 1, 1, 1025, 0, 1, 1][..],
        )
        .expect("tag");
        dir.write_tag(Tag::GeoAsciiParamsTag, "made by hand|")
            .expect("tag");
        dir.write_tag(Tag::GdalNodata, "-9999").expect("tag");
        image.write_data(samples).expect("data");
        out.into_inner()
    }

    const SAMPLES: [f32; 12] = [
        1.5, 2.0, 2.5, 3.0, //
        4.0, -9999.0, 5.0, 5.5, //
        6.0, 6.5, 7.0, 7.25,
    ];

    #[test]
    fn a_geotiff_reads_with_exact_georeferencing_and_its_no_data() {
        let field = parse(&dem(&SAMPLES), "dem.tif").expect("read");
        assert_eq!((field.columns, field.rows), (4, 3));
        let q = |n: i64, d: i64| Rational::new(n.into(), d.into());
        // The south-west sample: the centre of the lower-left pixel.
        // x: 1000 + 10/2; y: 2000 − (2 + 1/2)·5.
        assert_eq!(field.origin, [q(1005, 1), q(3975, 2)]);
        assert_eq!(field.cell, [q(10, 1), q(5, 1)]);
        // Row by row from the south: the file's last row first.
        assert_eq!(
            field.heights[..4],
            [Some(6.0), Some(6.5), Some(7.0), Some(7.25)]
        );
        assert_eq!(field.heights[5], None, "GDAL_NODATA");
        assert_eq!(field.heights[11], Some(3.0));
    }

    #[test]
    fn a_geotiff_is_written_back_with_its_georeferencing_and_new_heights() {
        let bytes = dem(&SAMPLES);
        let field = parse(&bytes, "dem.tif").expect("read");
        let same = field
            .write_geotiff(&field.heights)
            .expect("a GeoTIFF")
            .expect("written");
        let again = parse(&same, "dem-deformed.tif").expect("read again");
        assert_eq!(again, field, "same raster, tags and positions");
        let mut raised = field.heights.clone();
        raised[0] = Some(100.125);
        let written = field
            .write_geotiff(&raised)
            .expect("a GeoTIFF")
            .expect("written");
        let again = parse(&written, "dem-deformed.tif").expect("read again");
        assert_eq!(again.heights, raised);
        assert_eq!(
            (again.origin.clone(), again.cell.clone()),
            (field.origin.clone(), field.cell.clone())
        );
        // A sample without data keeps its no-data value in the file.
        let mut decoder = Decoder::new(Cursor::new(written.as_slice())).expect("decoder");
        assert_eq!(
            decoder.get_tag_ascii_string(Tag::GdalNodata).expect("kept"),
            "-9999"
        );
        assert_eq!(
            decoder
                .get_tag_ascii_string(Tag::GeoAsciiParamsTag)
                .expect("kept"),
            "made by hand|"
        );
        match decoder.read_image().expect("image") {
            DecodingResult::F32(v) => assert_eq!((v[5], v[8]), (-9999.0, 100.125)),
            other => panic!("{other:?}"),
        }
        // A sample may gain data (a deformation that covers it) and lose it (GDAL_NODATA).
        let mut filled = raised.clone();
        filled[5] = Some(1.0);
        filled[6] = None;
        let written = field
            .write_geotiff(&filled)
            .expect("a GeoTIFF")
            .expect("written");
        assert_eq!(parse(&written, "x.tif").expect("read").heights, filled);
        // Heights that are not finite are refused.
        filled[7] = Some(f64::INFINITY);
        assert!(field.write_geotiff(&filled).expect("a GeoTIFF").is_err());
    }

    /// LZW and Deflate compressed rasters (as GDAL writes DEMs with `COMPRESS=`) read as the
    /// uncompressed one.
    #[test]
    fn compressed_geotiffs_read_as_uncompressed_ones() {
        let plain = parse(&dem(&SAMPLES), "dem.tif").expect("read");
        for (name, compression) in [
            ("LZW", tiff::encoder::Compression::Lzw),
            (
                "Deflate",
                tiff::encoder::Compression::Deflate(tiff::encoder::DeflateLevel::Balanced),
            ),
        ] {
            let field = parse(&dem_compressed(&SAMPLES, compression), "dem.tif").expect("read");
            assert_eq!(
                (&field.heights, &field.origin, &field.cell),
                (&plain.heights, &plain.origin, &plain.cell),
                "{name}"
            );
        }
    }

    #[test]
    fn integer_rasters_round_and_refuse_heights_beyond_their_type() {
        let mut out = Cursor::new(Vec::new());
        let mut encoder = TiffEncoder::new(&mut out).expect("encoder");
        let mut image = encoder
            .new_image::<colortype::GrayI16>(2, 2)
            .expect("image");
        image
            .encoder()
            .write_tag(Tag::ModelPixelScaleTag, &[1.0f64, 1.0, 0.0][..])
            .expect("tag");
        image
            .encoder()
            .write_tag(
                Tag::ModelTiepointTag,
                &[0.0f64, 0.0, 0.0, 0.0, 2.0, 0.0][..],
            )
            .expect("tag");
        image.write_data(&[10i16, 20, 30, 40]).expect("data");
        let field = parse(&out.into_inner(), "i16.tif").expect("read");
        let mut heights = field.heights.clone();
        heights[0] = Some(31.6);
        let again = parse(
            &field
                .write_geotiff(&heights)
                .expect("tiff")
                .expect("written"),
            "x.tif",
        )
        .expect("read");
        assert_eq!(again.heights[0], Some(32.0));
        heights[0] = Some(40000.0);
        let refused = field
            .write_geotiff(&heights)
            .expect("tiff")
            .expect_err("beyond i16");
        assert!(refused.contains("does not fit"), "{refused}");
    }

    #[test]
    fn files_that_are_not_elevation_models_are_refused_naming_the_file() {
        let message = |bytes: &[u8]| parse(bytes, "dem.tif").expect_err("refused").to_string();
        assert!(
            message(b"II*\0garbage")
                .starts_with("dem.tif: not a GeoTIFF this reader accepts (11 bytes)"),
            "{}",
            message(b"II*\0garbage")
        );
        // No georeferencing.
        let mut out = Cursor::new(Vec::new());
        TiffEncoder::new(&mut out)
            .expect("encoder")
            .write_image::<colortype::Gray32Float>(2, 2, &[0.0, 1.0, 2.0, 3.0])
            .expect("image");
        assert!(message(&out.into_inner()).contains("no georeferencing"));
    }
}
