//! Shaded-relief pictures: a terrain or model seen from above as a PNG, coloured by height and
//! lit by a sun in the north-west, with polylines (the reference mesh) and markers (control
//! points) drawn over it.
//!
//! The model's triangles are rasterised into a height buffer (the highest surface wins, as seen
//! from above) with normals interpolated from the vertex normals of the (deformed) surface
//! (Phong shading: smooth light over a faceted mesh); point clouds are shaded from the slope of
//! the height buffer (Horn's 3 × 3 estimate, as GIS hillshades do). Several panels share one [`View`]
//! (the same window and the same height colours), so "before" and "after" pictures compare
//! pixel for pixel. Everything is computed in `f64` with a fixed order of operations and
//! encoded with fixed PNG settings: the same input gives the same bytes.

use spline2d::model::Model;

/// Sun direction: azimuth clockwise from north and altitude, in degrees.
const SUN_AZIMUTH: f64 = 315.0;
const SUN_ALTITUDE: f64 = 45.0;
/// Brightness of a surface facing away from the sun.
const AMBIENT: f64 = 0.25;
/// Background (no surface) colour.
const BACKGROUND: [u8; 3] = [236, 236, 232];
/// Colour of polylines.
const LINE: [u8; 3] = [24, 24, 24];
/// Height colours from the lowest to the highest point.
const TINTS: [(f64, [f64; 3]); 5] = [
    (0.0, [56.0, 120.0, 72.0]),
    (0.25, [120.0, 170.0, 95.0]),
    (0.5, [215.0, 205.0, 140.0]),
    (0.75, [170.0, 120.0, 80.0]),
    (1.0, [250.0, 250.0, 250.0]),
];
/// Smallest and largest picture width.
const MIN_WIDTH: u32 = 16;
const MAX_WIDTH: u32 = 8192;

/// Why a picture could not be drawn.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ReliefError {
    /// No finite vertex, or all of them on one line seen from above.
    #[error("nothing to draw: the model has no area seen from above")]
    Empty,
    /// The requested width is out of range.
    #[error("picture width must be between {MIN_WIDTH} and {MAX_WIDTH} pixels, got {0}")]
    Width(u32),
    /// The PNG encoder failed.
    #[error("cannot encode the PNG: {0}")]
    Encode(String),
}

/// A point to mark with a disc.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Marker {
    /// Position.
    pub at: [f64; 2],
    /// Fill colour.
    pub colour: [u8; 3],
    /// Radius in pixels.
    pub radius: f64,
}

/// What one picture shows.
#[derive(Debug, Clone, Copy)]
pub struct Panel<'a> {
    /// The surface: its triangles are rasterised (a model without triangles is drawn as points).
    pub model: &'a Model,
    /// Polylines drawn over the surface.
    pub lines: &'a [Vec<[f64; 2]>],
    /// Discs drawn last.
    pub markers: &'a [Marker],
}

/// The window, pixel size and height colour range shared by panels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// World coordinates of the picture's left and top edges.
    left: f64,
    top: f64,
    /// Pixels per world unit.
    scale: f64,
    width: u32,
    height: u32,
    /// Heights mapped to the first and last tint.
    low: f64,
    high: f64,
    /// What one unit of x, y and z is in the common length the light sees (see
    /// [`Shading`]): the normals are those of the surface scaled by these.
    shading: [f64; 3],
}

/// How the surface is scaled for its light: a vertical exaggeration, and the length of one
/// horizontal unit in height units (1 when both are metres; for a geographic grid, whose
/// positions are degrees and heights metres, the metres of a degree at the grid's latitude).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shading {
    /// Heights are multiplied by this for the light (positive).
    pub exaggeration: f64,
    /// Whether positions are degrees of longitude (x) and latitude (y) and heights metres.
    pub degrees: bool,
}

impl Default for Shading {
    fn default() -> Self {
        Shading {
            exaggeration: 1.0,
            degrees: false,
        }
    }
}

/// Metres per degree of longitude and of latitude at latitude `phi` (degrees), on the WGS 84
/// ellipsoid (the usual series, good to a metre per degree).
pub fn metres_per_degree(phi: f64) -> [f64; 2] {
    let r = phi.to_radians();
    [
        111_412.84 * r.cos() - 93.5 * (3.0 * r).cos() + 0.118 * (5.0 * r).cos(),
        111_132.92 - 559.82 * (2.0 * r).cos() + 1.175 * (4.0 * r).cos() - 0.0023 * (6.0 * r).cos(),
    ]
}

/// Checks a picture width: between 16 and 8192 pixels (the height follows the terrain's shape
/// and is capped at 8192 too).
pub fn check_width(width: u32) -> Result<(), ReliefError> {
    if (MIN_WIDTH..=MAX_WIDTH).contains(&width) {
        Ok(())
    } else {
        Err(ReliefError::Width(width))
    }
}

impl View {
    /// A view showing everything in `panels` (with a small margin), `width` pixels wide.
    pub fn fit(panels: &[Panel<'_>], width: u32) -> Result<View, ReliefError> {
        check_width(width)?;
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut include = |p: [f64; 2]| {
            if p.iter().all(|c| c.is_finite()) {
                for axis in 0..2 {
                    lo[axis] = lo[axis].min(p[axis]);
                    hi[axis] = hi[axis].max(p[axis]);
                }
            }
        };
        for panel in panels {
            for p in &panel.model.positions {
                if p.iter().all(|c| c.is_finite()) {
                    include([p[0], p[1]]);
                    low = low.min(p[2]);
                    high = high.max(p[2]);
                }
            }
            for line in panel.lines {
                line.iter().for_each(|p| include(*p));
            }
        }
        let size = [hi[0] - lo[0], hi[1] - lo[1]];
        if !(size[0] > 0.0 && size[1] > 0.0 && size.iter().all(|s| s.is_finite()) && low <= high) {
            return Err(ReliefError::Empty);
        }
        let margin = 0.03 * size[0].max(size[1]);
        let scale = f64::from(width) / (size[0] + 2.0 * margin);
        let height = ((size[1] + 2.0 * margin) * scale)
            .ceil()
            .clamp(1.0, f64::from(MAX_WIDTH));
        Ok(View {
            left: lo[0] - margin,
            top: hi[1] + margin,
            scale,
            width,
            height: height as u32,
            low,
            high,
            shading: [1.0, 1.0, 1.0],
        })
    }

    /// The view with the surface lit as `shading` says; a geographic grid's degrees are turned
    /// into metres at the latitude of the view's centre.
    pub fn with_shading(mut self, shading: Shading) -> View {
        let [x, y] = if shading.degrees {
            let middle = self.top - 0.5 * f64::from(self.height) / self.scale;
            metres_per_degree(middle)
        } else {
            [1.0, 1.0]
        };
        self.shading = [x, y, shading.exaggeration];
        self
    }

    /// Picture size in pixels.
    pub fn size(&self) -> [u32; 2] {
        [self.width, self.height]
    }

    /// Pixel coordinates (x right, y down; pixel `(i, j)` covers `[i, i+1) × [j, j+1)`).
    fn pixel_of(&self, p: [f64; 2]) -> [f64; 2] {
        [
            (p[0] - self.left) * self.scale,
            (self.top - p[1]) * self.scale,
        ]
    }
}

/// Unit normals per vertex: the area-weighted sum of the normals of the vertex's triangles,
/// each turned to face up (a surface seen from above), of the surface scaled by `scale` per
/// axis (see [`Shading`]).
fn vertex_normals(model: &Model, scale: [f64; 3]) -> Vec<[f64; 3]> {
    let mut normals = vec![[0.0f64; 3]; model.positions.len()];
    for tri in &model.triangles {
        let [a, b, c] = tri.map(|v| {
            let p = model.positions[v];
            [p[0] * scale[0], p[1] * scale[1], p[2] * scale[2]]
        });
        let (u, v) = (
            [0, 1, 2].map(|k| b[k] - a[k]),
            [0, 1, 2].map(|k| c[k] - a[k]),
        );
        let mut n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        if n[2] < 0.0 {
            n = n.map(|x| -x);
        }
        if n.iter().all(|x| x.is_finite()) {
            for &vertex in tri {
                for k in 0..3 {
                    normals[vertex][k] += n[k];
                }
            }
        }
    }
    normals
}

/// What is seen from above, per pixel.
struct Raster {
    /// Height of the highest surface (`NaN` where there is none).
    heights: Vec<f64>,
    /// Its normal, interpolated from the vertex normals (unnormalised); `None` for point
    /// clouds, which are shaded from the slope of the height buffer.
    normals: Option<Vec<[f64; 3]>>,
}

/// Rasterises a model seen from above: the highest surface per pixel wins.
fn rasterise(model: &Model, view: &View) -> Raster {
    let (w, h) = (view.width as usize, view.height as usize);
    let mut heights = vec![f64::NAN; w * h];
    let pixel_range = |lo: f64, hi: f64, n: usize| -> Option<(usize, usize)> {
        // Pixel centres i + 0.5 within [lo, hi].
        let first = (lo - 0.5).ceil().max(0.0);
        let last = (hi - 0.5).floor().min(n as f64 - 1.0);
        (first <= last).then_some((first as usize, last as usize))
    };
    if model.triangles.is_empty() {
        for p in &model.positions {
            let [x, y] = view.pixel_of([p[0], p[1]]);
            if x >= 0.0 && y >= 0.0 && x < w as f64 && y < h as f64 && p[2].is_finite() {
                let cell = &mut heights[y as usize * w + x as usize];
                if cell.is_nan() || p[2] > *cell {
                    *cell = p[2];
                }
            }
        }
        return Raster {
            heights,
            normals: None,
        };
    }
    let vertex_normals = vertex_normals(model, view.shading);
    let mut normals = vec![[0.0f64; 3]; w * h];
    for tri in &model.triangles {
        let corners = tri.map(|v| model.positions[v]);
        if corners.iter().flatten().any(|c| !c.is_finite()) {
            continue;
        }
        let [a, b, c] = corners.map(|p| view.pixel_of([p[0], p[1]]));
        let area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        if area == 0.0 {
            continue;
        }
        let slack = -1e-9;
        let xs = pixel_range(a[0].min(b[0]).min(c[0]), a[0].max(b[0]).max(c[0]), w);
        let ys = pixel_range(a[1].min(b[1]).min(c[1]), a[1].max(b[1]).max(c[1]), h);
        let (Some((i0, i1)), Some((j0, j1))) = (xs, ys) else {
            continue;
        };
        let corner_normals = tri.map(|v| vertex_normals[v]);
        for j in j0..=j1 {
            let y = j as f64 + 0.5;
            for i in i0..=i1 {
                let x = i as f64 + 0.5;
                let w0 = ((b[0] - x) * (c[1] - y) - (b[1] - y) * (c[0] - x)) / area;
                let w1 = ((c[0] - x) * (a[1] - y) - (c[1] - y) * (a[0] - x)) / area;
                let w2 = 1.0 - w0 - w1;
                if w0 < slack || w1 < slack || w2 < slack {
                    continue;
                }
                let z = w0 * corners[0][2] + w1 * corners[1][2] + w2 * corners[2][2];
                let k = j * w + i;
                if heights[k].is_nan() || z > heights[k] {
                    heights[k] = z;
                    normals[k] = [0, 1, 2].map(|axis| {
                        w0 * corner_normals[0][axis]
                            + w1 * corner_normals[1][axis]
                            + w2 * corner_normals[2][axis]
                    });
                }
            }
        }
    }
    Raster {
        heights,
        normals: Some(normals),
    }
}

/// The colour of a height `t ∈ [0, 1]` of the range.
fn tint(t: f64) -> [f64; 3] {
    let t = t.clamp(0.0, 1.0);
    for pair in TINTS.windows(2) {
        let ((t0, c0), (t1, c1)) = (pair[0], pair[1]);
        if t <= t1 {
            let s = (t - t0) / (t1 - t0);
            return [0, 1, 2].map(|k| c0[k] + s * (c1[k] - c0[k]));
        }
    }
    TINTS[TINTS.len() - 1].1
}

/// The normal of the height buffer at pixel `(i, j)` from its slope (Horn's 3 × 3 estimate;
/// missing neighbours count as the centre height), unnormalised.
fn slope_normal(heights: &[f64], view: &View, i: usize, j: usize) -> [f64; 3] {
    let (w, h) = (view.width as isize, view.height as isize);
    let centre = heights[j * view.width as usize + i];
    let z = |di: isize, dj: isize| -> f64 {
        let (x, y) = (i as isize + di, j as isize + dj);
        if x < 0 || y < 0 || x >= w || y >= h {
            return centre;
        }
        let v = heights[(y * w + x) as usize];
        if v.is_nan() {
            centre
        } else {
            v
        }
    };
    let east = (z(1, -1) + 2.0 * z(1, 0) + z(1, 1)) - (z(-1, -1) + 2.0 * z(-1, 0) + z(-1, 1));
    // Rows grow southwards, so north is dj = −1.
    let north = (z(-1, -1) + 2.0 * z(0, -1) + z(1, -1)) - (z(-1, 1) + 2.0 * z(0, 1) + z(1, 1));
    let pixel = 1.0 / view.scale;
    let [sx, sy, sz] = view.shading;
    [
        -sz * east / (8.0 * pixel * sx),
        -sz * north / (8.0 * pixel * sy),
        1.0,
    ]
}

/// Hillshade and height colours, as RGB.
fn shade(raster: &Raster, view: &View) -> Vec<[f64; 3]> {
    let (w, h) = (view.width as usize, view.height as usize);
    let (az, alt) = (SUN_AZIMUTH.to_radians(), SUN_ALTITUDE.to_radians());
    let sun = [az.sin() * alt.cos(), az.cos() * alt.cos(), alt.sin()];
    let range = view.high - view.low;
    let background = BACKGROUND.map(f64::from);
    let mut out = Vec::with_capacity(w * h);
    for j in 0..h {
        for i in 0..w {
            let k = j * w + i;
            let height = raster.heights[k];
            if height.is_nan() {
                out.push(background);
                continue;
            }
            let n = match &raster.normals {
                Some(normals) => normals[k],
                None => slope_normal(&raster.heights, view, i, j),
            };
            let norm = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            let lit = if norm > 0.0 {
                ((n[0] * sun[0] + n[1] * sun[1] + n[2] * sun[2]) / norm).max(0.0)
            } else {
                sun[2]
            };
            let brightness = AMBIENT + (1.0 - AMBIENT) * lit;
            let t = if range > 0.0 {
                (height - view.low) / range
            } else {
                0.5
            };
            out.push(tint(t).map(|c| c * brightness));
        }
    }
    out
}

/// Line coverage per pixel (0 to 1), anti-aliased by splitting each sample over the four
/// nearest pixels.
fn line_coverage(lines: &[Vec<[f64; 2]>], view: &View) -> Vec<f64> {
    let (w, h) = (view.width as usize, view.height as usize);
    let mut coverage = vec![0.0f64; w * h];
    let mut splat = |p: [f64; 2]| {
        let (fx, fy) = (p[0] - 0.5, p[1] - 0.5);
        let (i0, j0) = (fx.floor(), fy.floor());
        let (sx, sy) = (fx - i0, fy - j0);
        for (di, wx) in [(0.0, 1.0 - sx), (1.0, sx)] {
            for (dj, wy) in [(0.0, 1.0 - sy), (1.0, sy)] {
                let (i, j) = (i0 + di, j0 + dj);
                if i >= 0.0 && j >= 0.0 && i < w as f64 && j < h as f64 {
                    let cell = &mut coverage[j as usize * w + i as usize];
                    *cell = cell.max(wx * wy);
                }
            }
        }
    };
    for line in lines {
        for pair in line.windows(2) {
            let [a, b] = [pair[0], pair[1]].map(|p| view.pixel_of(p));
            if a.iter().chain(&b).any(|c| !c.is_finite()) {
                continue;
            }
            let length = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
            let steps = (length * 2.0).ceil().min(1e6) as usize + 1;
            for s in 0..=steps {
                let t = s as f64 / steps as f64;
                splat([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
            }
        }
    }
    coverage
}

fn blend(under: [f64; 3], over: [f64; 3], alpha: f64) -> [f64; 3] {
    [0, 1, 2].map(|k| under[k] + alpha * (over[k] - under[k]))
}

/// Draws a panel as PNG bytes.
pub fn render(panel: &Panel<'_>, view: &View) -> Result<Vec<u8>, ReliefError> {
    let (w, h) = (view.width as usize, view.height as usize);
    let raster = rasterise(panel.model, view);
    let mut rgb = shade(&raster, view);
    let line = LINE.map(f64::from);
    for (pixel, c) in rgb.iter_mut().zip(line_coverage(panel.lines, view)) {
        if c > 0.0 {
            *pixel = blend(*pixel, line, 0.85 * c);
        }
    }
    for marker in panel.markers {
        let [cx, cy] = view.pixel_of(marker.at);
        let r = marker.radius.max(0.5);
        if !(cx.is_finite() && cy.is_finite()) {
            continue;
        }
        let fill = marker.colour.map(f64::from);
        let (i0, i1) = (
            (cx - r - 2.0).floor().max(0.0),
            (cx + r + 2.0).ceil().min(w as f64 - 1.0),
        );
        let (j0, j1) = (
            (cy - r - 2.0).floor().max(0.0),
            (cy + r + 2.0).ceil().min(h as f64 - 1.0),
        );
        if i0 > i1 || j0 > j1 {
            continue;
        }
        for j in j0 as usize..=j1 as usize {
            for i in i0 as usize..=i1 as usize {
                let d = ((i as f64 + 0.5 - cx).powi(2) + (j as f64 + 0.5 - cy).powi(2)).sqrt();
                let inner = (r + 0.5 - d).clamp(0.0, 1.0);
                let outer = (r + 1.5 - d).clamp(0.0, 1.0);
                let pixel = &mut rgb[j * w + i];
                *pixel = blend(*pixel, line, outer);
                *pixel = blend(*pixel, fill, inner);
            }
        }
    }
    let bytes: Vec<u8> = rgb
        .iter()
        .flat_map(|c| c.map(|v| v.round().clamp(0.0, 255.0) as u8))
        .collect();
    encode(&bytes, view.width, view.height)
}

/// Encodes 8-bit RGB pixels as PNG with fixed settings.
fn encode(rgb: &[u8], width: u32, height: u32) -> Result<Vec<u8>, ReliefError> {
    let error = |e: png::EncodingError| ReliefError::Encode(e.to_string());
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Balanced);
    let mut writer = encoder.write_header().map_err(error)?;
    writer.write_image_data(rgb).map_err(error)?;
    writer.finish().map_err(error)?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square pyramid: four triangles around an apex.
    fn pyramid(apex: f64) -> Model {
        Model {
            positions: vec![
                [0.0, 0.0, 0.0],
                [10.0, 0.0, 0.0],
                [10.0, 10.0, 0.0],
                [0.0, 10.0, 0.0],
                [5.0, 5.0, apex],
            ],
            triangles: vec![[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]],
        }
    }

    fn decode(bytes: &[u8]) -> (u32, u32, Vec<u8>) {
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder.read_info().expect("png header");
        let mut buffer = vec![0; reader.output_buffer_size().expect("size")];
        let info = reader.next_frame(&mut buffer).expect("frame");
        buffer.truncate(info.buffer_size());
        (info.width, info.height, buffer)
    }

    #[test]
    fn slopes_facing_the_sun_are_brighter_and_bytes_are_deterministic() {
        let model = pyramid(4.0);
        let lines = vec![vec![[0.0, 0.0], [10.0, 10.0]]];
        let markers = [Marker {
            at: [5.0, 5.0],
            colour: [214, 39, 40],
            radius: 3.0,
        }];
        let panel = Panel {
            model: &model,
            lines: &lines,
            markers: &markers,
        };
        let view = View::fit(&[panel], 64).expect("view");
        assert_eq!(view.size(), [64, 64]);
        let bytes = render(&panel, &view).expect("png");
        assert_eq!(bytes, render(&panel, &view).expect("png"));
        let (w, h, pixels) = decode(&bytes);
        assert_eq!((w, h), (64, 64));
        let at = |x: f64, y: f64| {
            let [i, j] = view.pixel_of([x, y]).map(|c| c as usize);
            let k = 3 * (j * 64 + i);
            pixels[k] as u32 + pixels[k + 1] as u32 + pixels[k + 2] as u32
        };
        // The west face (lit from the north-west) is brighter than the east face.
        assert!(at(1.5, 5.0) > at(8.5, 5.0));
        // The marker is red, the margin is background.
        let [i, j] = view.pixel_of([5.0, 5.0]).map(|c| c as usize);
        assert_eq!(
            &pixels[3 * (j * 64 + i)..3 * (j * 64 + i) + 3],
            &[214, 39, 40]
        );
        assert_eq!(&pixels[0..3], &BACKGROUND);
    }

    /// The mean brightness of the pyramid's picture (the tint's range is the same).
    fn mean_brightness(model: &Model, shading: Shading) -> f64 {
        let panel = Panel {
            model,
            lines: &[],
            markers: &[],
        };
        let view = View::fit(&[panel], 64).expect("view").with_shading(shading);
        let (_, _, pixels) = decode(&render(&panel, &view).expect("png"));
        pixels.iter().map(|&p| f64::from(p)).sum::<f64>() / pixels.len() as f64
    }

    /// A geographic grid (degrees across, metres up) is nearly black when degrees are taken
    /// for metres, and lit as it should once they are metres; a vertical exaggeration steepens
    /// the light's contrast.
    #[test]
    fn geographic_grids_and_exaggeration_change_the_light() {
        // 0.01° across, 200 m high: as steep as a 1.1 km wide, 200 m high hill.
        let mut hill = pyramid(200.0);
        for p in &mut hill.positions {
            p[0] = 7.0 + p[0] / 1000.0;
            p[1] = 46.0 + p[1] / 1000.0;
        }
        let as_metres = mean_brightness(&hill, Shading::default());
        let as_degrees = mean_brightness(
            &hill,
            Shading {
                exaggeration: 1.0,
                degrees: true,
            },
        );
        assert!(as_degrees > as_metres + 20.0, "{as_degrees} vs {as_metres}");
        let [x, y] = metres_per_degree(46.0);
        assert!(
            (x - 77_465.0).abs() < 100.0 && (y - 111_152.0).abs() < 100.0,
            "{x} {y}"
        );
        let flat = pyramid(1.0);
        let plain = mean_brightness(&flat, Shading::default());
        let steep = mean_brightness(
            &flat,
            Shading {
                exaggeration: 8.0,
                degrees: false,
            },
        );
        assert!((plain - steep).abs() > 1.0, "{plain} vs {steep}");
    }

    #[test]
    fn empty_models_and_bad_widths_are_refused() {
        let flat = Model {
            positions: vec![[0.0, 0.0, 1.0], [1.0, 0.0, 1.0]],
            triangles: vec![],
        };
        let panel = Panel {
            model: &flat,
            lines: &[],
            markers: &[],
        };
        assert_eq!(View::fit(&[panel], 100), Err(ReliefError::Empty));
        let model = pyramid(1.0);
        let panel = Panel {
            model: &model,
            lines: &[],
            markers: &[],
        };
        assert_eq!(View::fit(&[panel], 3), Err(ReliefError::Width(3)));
        // Point clouds are drawn point by point.
        let cloud = Model {
            positions: model.positions.clone(),
            triangles: vec![],
        };
        let panel = Panel {
            model: &cloud,
            lines: &[],
            markers: &[],
        };
        let view = View::fit(&[panel], 32).expect("view");
        assert!(render(&panel, &view).is_ok());
    }
}
