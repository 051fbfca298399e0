//! Deforming a raster image with a spline deformation `φ` of the plane (thesis 19, "image
//! morphing"): the output pixel at `q` shows the input at the preimage `p` with `φ(p) = q`.
//!
//! The preimage is found by mapping forward, as a renderer maps a texture: each displaced
//! reference triangle is cut into `n²` small triangles (barycentric grid of step `1/n`, `n`
//! chosen so that the deformed small triangles are at most [`MAX_PIECE_PIXELS`] pixels across),
//! their corners are mapped by `φ` (the float twin of the exact spline), and each deformed small
//! triangle is filled pixel by pixel with the preimage interpolated linearly from its corners,
//! then the input sampled there bilinearly. Within a small triangle of side `h` pixels the
//! preimage is off by `O(h² |φ''|)`: for a smooth deformation and `h ≤ 2` far below a pixel.
//! This is exact where `φ` is affine (a translation shifts the image exactly), costs one
//! evaluation of `φ` per output pixel or less, and needs no Newton iteration that could fail
//! to converge.
//!
//! * Where `φ` does not move a triangle (its control points at their nominal places), the
//!   output is the input, pixel for pixel; outside the reference mesh too (a deformation of
//!   the mesh leaves the rest of the plane in place, as it does a model's vertices).
//! * Pixels inside the reference mesh that no deformed triangle covers (the picture moved
//!   away from them) get the `fill` colour; where `φ` folds the plane, the triangle drawn last
//!   (the higher-numbered) wins.
//! * A pixel's sample point is its centre; a preimage outside the input takes the colour of its
//!   nearest edge pixel (clamped).

use crate::eval::FloatSpline;

/// Largest side, in output pixels, of a deformed small triangle.
pub const MAX_PIECE_PIXELS: f64 = 2.0;

/// Most pieces a reference triangle is cut into along a side.
pub const MAX_SUBDIVISION: usize = 1024;

/// Where an image lies in the model's plane: the model coordinates of its top-left corner and
/// the model units per pixel (pixels are square; rows go down, `y` goes up).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// `x` of the image's left edge.
    pub left: f64,
    /// `y` of the image's top edge.
    pub top: f64,
    /// Model units per pixel (positive).
    pub units_per_pixel: f64,
}

impl Placement {
    /// The pixel coordinates (column, row; pixel `(i, j)` spans `[i, i+1) × [j, j+1)`) of the
    /// model point `p`.
    fn pixel_of(&self, p: [f64; 2]) -> [f64; 2] {
        [
            (p[0] - self.left) / self.units_per_pixel,
            (self.top - p[1]) / self.units_per_pixel,
        ]
    }
}

/// An RGBA image, 8 bits per channel, row by row from the top.
#[derive(Debug, Clone, PartialEq)]
pub struct Rgba {
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `4 · width · height` bytes.
    pub pixels: Vec<u8>,
}

/// Why an image cannot be deformed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ImageError {
    /// The pixel buffer does not match the size, or the size is zero.
    #[error("the image is {width} × {height} pixels but has {bytes} bytes of RGBA")]
    Size {
        /// Pixels per row.
        width: usize,
        /// Rows.
        height: usize,
        /// Bytes given.
        bytes: usize,
    },
    /// The placement is not finite and positive.
    #[error("the image's placement must be finite with positive units per pixel")]
    Placement,
    /// The spline does not deform the plane.
    #[error("an image can only be deformed by a spline with 2 coordinates, this one has {0}")]
    NotAPlaneDeformation(usize),
    /// The triangles given are not the spline's.
    #[error("{given} reference triangles given, the spline has {spline}")]
    Triangles {
        /// Triangles given.
        given: usize,
        /// Triangles of the spline.
        spline: usize,
    },
}

/// The input sampled bilinearly at pixel coordinates `(u, v)` (pixel centres at `i + ½`),
/// clamped to the image.
fn sample(image: &Rgba, u: f64, v: f64) -> [u8; 4] {
    let (w, h) = (image.width, image.height);
    let x = (u - 0.5).clamp(0.0, (w - 1) as f64);
    let y = (v - 0.5).clamp(0.0, (h - 1) as f64);
    let (x0, y0) = (x.floor() as usize, y.floor() as usize);
    let (x1, y1) = ((x0 + 1).min(w - 1), (y0 + 1).min(h - 1));
    let (fx, fy) = (x - x0 as f64, y - y0 as f64);
    let at = |i: usize, j: usize, c: usize| f64::from(image.pixels[4 * (j * w + i) + c]);
    let mut out = [0u8; 4];
    for (c, o) in out.iter_mut().enumerate() {
        let top = at(x0, y0, c) * (1.0 - fx) + at(x1, y0, c) * fx;
        let bottom = at(x0, y1, c) * (1.0 - fx) + at(x1, y1, c) * fx;
        *o = (top * (1.0 - fy) + bottom * fy).round().clamp(0.0, 255.0) as u8;
    }
    out
}

/// Calls `paint(i, j, weights)` for every pixel whose centre lies in the triangle `corners`
/// (pixel coordinates), with the centre's barycentric weights; pixels outside the image are
/// skipped. Centres on an edge belong to the triangle (a shared edge may be painted twice, by
/// the same map).
fn fill_triangle(
    corners: [[f64; 2]; 3],
    width: usize,
    height: usize,
    mut paint: impl FnMut(usize, usize, [f64; 3]),
) {
    let [a, b, c] = corners;
    let area = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
    if area == 0.0 || !area.is_finite() {
        return;
    }
    let min_x = a[0].min(b[0]).min(c[0]);
    let max_x = a[0].max(b[0]).max(c[0]);
    let min_y = a[1].min(b[1]).min(c[1]);
    let max_y = a[1].max(b[1]).max(c[1]);
    // Columns i whose centre i + ½ lies in [min_x, max_x].
    let first = |m: f64| (m - 0.5).ceil().max(0.0);
    let last = |m: f64, n: usize| ((m - 0.5).floor()).min(n as f64 - 1.0);
    let (i0, i1) = (first(min_x), last(max_x, width));
    let (j0, j1) = (first(min_y), last(max_y, height));
    if i0 > i1 || j0 > j1 {
        return;
    }
    let tolerance = -1e-9 * area.abs();
    for j in j0 as usize..=j1 as usize {
        let y = j as f64 + 0.5;
        for i in i0 as usize..=i1 as usize {
            let x = i as f64 + 0.5;
            let w0 = ((b[0] - x) * (c[1] - y) - (c[0] - x) * (b[1] - y)) / area;
            let w1 = ((c[0] - x) * (a[1] - y) - (a[0] - x) * (c[1] - y)) / area;
            let w2 = 1.0 - w0 - w1;
            if w0 * area.abs() >= tolerance
                && w1 * area.abs() >= tolerance
                && w2 * area.abs() >= tolerance
            {
                paint(i, j, [w0, w1, w2]);
            }
        }
    }
}

/// `image`, placed in the plane by `placement`, deformed by `spline` over the reference
/// triangles `triangles` (the spline's, as `f64` corners in model coordinates); see the module
/// documentation. `fill` colours what the deformation uncovers.
pub fn deform_image(
    spline: &FloatSpline,
    triangles: &[[[f64; 2]; 3]],
    image: &Rgba,
    placement: Placement,
    fill: [u8; 4],
) -> Result<Rgba, ImageError> {
    let (width, height) = (image.width, image.height);
    if width == 0 || height == 0 || image.pixels.len() != 4 * width * height {
        return Err(ImageError::Size {
            width,
            height,
            bytes: image.pixels.len(),
        });
    }
    let finite = placement.left.is_finite() && placement.top.is_finite();
    if !(finite && placement.units_per_pixel > 0.0 && placement.units_per_pixel.is_finite()) {
        return Err(ImageError::Placement);
    }
    if spline.dim() != 2 {
        return Err(ImageError::NotAPlaneDeformation(spline.dim()));
    }
    if triangles.len() != spline.triangle_count() {
        return Err(ImageError::Triangles {
            given: triangles.len(),
            spline: spline.triangle_count(),
        });
    }
    let mut out = image.clone();
    let displaced: Vec<usize> = (0..triangles.len())
        .filter(|&t| spline.is_displaced(t))
        .collect();
    let pixel = |p: [f64; 2]| placement.pixel_of(p);
    // What the displaced triangles covered is uncovered, unless a deformed triangle covers it.
    for &t in &displaced {
        let corners = triangles[t].map(pixel);
        fill_triangle(corners, width, height, |i, j, _| {
            out.pixels[4 * (j * width + i)..4 * (j * width + i) + 4].copy_from_slice(&fill);
        });
    }
    let mut value = [0.0; 2];
    for &t in &displaced {
        let reference = triangles[t];
        // Cut finely enough for the deformed pieces: the deformed corners and edge midpoints
        // bound the deformed size well for a smooth map.
        let mapped = |beta: [f64; 3], out: &mut [f64; 2]| spline.evaluate_into(t, beta, out);
        let mut longest: f64 = 0.0;
        let probes = [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.5, 0.5, 0.0],
            [0.0, 0.5, 0.5],
            [0.5, 0.0, 0.5],
        ];
        let mut images = [[0.0; 2]; 6];
        for (probe, image) in probes.iter().zip(images.iter_mut()) {
            mapped(*probe, &mut value);
            *image = pixel(value);
        }
        for (a, b) in [(0, 3), (3, 1), (1, 4), (4, 2), (2, 5), (5, 0)] {
            let d = (images[a][0] - images[b][0]).hypot(images[a][1] - images[b][1]);
            longest = longest.max(2.0 * d);
        }
        for r in &reference {
            for s in &reference {
                let [pr, ps] = [pixel(*r), pixel(*s)];
                longest = longest.max((pr[0] - ps[0]).hypot(pr[1] - ps[1]));
            }
        }
        let n = ((longest / MAX_PIECE_PIXELS).ceil() as usize).clamp(1, MAX_SUBDIVISION);
        // φ and the reference point at every node of the barycentric grid, row by row.
        let step = 1.0 / n as f64;
        let mut nodes: Vec<([f64; 2], [f64; 2])> = Vec::with_capacity((n + 1) * (n + 2) / 2);
        for a in 0..=n {
            for b in 0..=n - a {
                let beta = [(n - a - b) as f64 * step, a as f64 * step, b as f64 * step];
                mapped(beta, &mut value);
                let source = [0, 1].map(|k| {
                    beta[0] * reference[0][k]
                        + beta[1] * reference[1][k]
                        + beta[2] * reference[2][k]
                });
                nodes.push((pixel(value), pixel(source)));
            }
        }
        let index = |a: usize, b: usize| a * (n + 1) - a * (a.saturating_sub(1)) / 2 + b;
        let mut piece = |k: [usize; 3]| {
            let [p, q, r] = k.map(|i| nodes[i]);
            fill_triangle([p.0, q.0, r.0], width, height, |i, j, w| {
                let u = w[0] * p.1[0] + w[1] * q.1[0] + w[2] * r.1[0];
                let v = w[0] * p.1[1] + w[1] * q.1[1] + w[2] * r.1[1];
                let colour = sample(image, u, v);
                out.pixels[4 * (j * width + i)..4 * (j * width + i) + 4].copy_from_slice(&colour);
            });
        };
        for a in 0..n {
            for b in 0..n - a {
                piece([index(a, b), index(a + 1, b), index(a, b + 1)]);
                if b + 1 < n - a {
                    piece([index(a + 1, b), index(a + 1, b + 1), index(a, b + 1)]);
                }
            }
        }
    }
    Ok(out)
}

/// The reference triangles of `spline`'s mesh as `f64` corners (for [`deform_image`]).
pub fn reference_triangles(spline: &crate::spline::Spline) -> Vec<[[f64; 2]; 3]> {
    let mesh = spline.mesh();
    mesh.triangles()
        .iter()
        .map(|tri| {
            tri.map(|v| {
                mesh.vertices()[v]
                    .each_ref()
                    .map(api::exact::rational_to_f64)
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::grid;
    use crate::spline::Spline;
    use api::Rational;

    /// A 2 × 2 grid of 20-unit cells (0..40 × 0..40), degree 3, C1; and a 100 × 60 image of
    /// 1/2 unit per pixel with its top-left corner at (−5, 25): the mesh covers columns 10..90
    /// and rows 0..50 (its top is above the image).
    fn setup() -> (Spline, Vec<Vec<Rational>>, Rgba, Placement) {
        let spline = Spline::new(grid(2, 20, false), 3, 1).expect("spline");
        let nominal: Vec<Vec<Rational>> = spline.nominals().iter().map(|p| p.to_vec()).collect();
        let (width, height) = (100, 60);
        let mut pixels = Vec::with_capacity(4 * width * height);
        for j in 0..height {
            for i in 0..width {
                // A pattern that changes from every pixel to the next.
                pixels.extend([
                    (i * 7 % 256) as u8,
                    (j * 11 % 256) as u8,
                    ((i + j) % 256) as u8,
                    255,
                ]);
            }
        }
        let placement = Placement {
            left: -5.0,
            top: 25.0,
            units_per_pixel: 0.5,
        };
        (
            spline,
            nominal,
            Rgba {
                width,
                height,
                pixels,
            },
            placement,
        )
    }

    #[test]
    fn the_identity_leaves_the_image_unchanged() {
        let (spline, nominal, image, placement) = setup();
        let identity = FloatSpline::new(&spline, &nominal).expect("float");
        let out = deform_image(
            &identity,
            &reference_triangles(&spline),
            &image,
            placement,
            [0; 4],
        )
        .expect("deformed");
        assert_eq!(out, image);
    }

    /// Every control point moved by (3, −2) units, 6 and 4 pixels: the image inside the moved
    /// mesh is the input shifted exactly; outside the mesh it is the input; what the mesh
    /// uncovered is filled.
    #[test]
    fn a_translation_shifts_the_image_exactly_and_fills_what_it_uncovers() {
        let (spline, nominal, image, placement) = setup();
        let moved: Vec<Vec<Rational>> = nominal
            .iter()
            .map(|p| {
                vec![
                    &p[0] + Rational::from_integer(3.into()),
                    &p[1] - Rational::from_integer(2.into()),
                ]
            })
            .collect();
        let shifted = FloatSpline::new(&spline, &moved).expect("float");
        let fill = [1, 2, 3, 4];
        let out = deform_image(
            &shifted,
            &reference_triangles(&spline),
            &image,
            placement,
            fill,
        )
        .expect("deformed");
        let at = |img: &Rgba, i: usize, j: usize| {
            img.pixels[4 * (j * 100 + i)..4 * (j * 100 + i) + 4].to_vec()
        };
        // The moved mesh covers columns 16..96 and rows 0..54.
        for j in 4..53 {
            for i in 17..95 {
                assert_eq!(at(&out, i, j), at(&image, i - 6, j - 4), "pixel ({i}, {j})");
            }
        }
        // Uncovered: in the reference mesh, not in the moved one (columns 10..16).
        assert_eq!(at(&out, 12, 30), fill);
        assert_eq!(at(&out, 15, 2), fill);
        assert_ne!(at(&out, 16, 2), fill);
        // Outside both: unchanged.
        assert_eq!(at(&out, 5, 5), at(&image, 5, 5));
        assert_eq!(at(&out, 97, 58), at(&image, 97, 58));
    }

    #[test]
    fn bad_sizes_and_placements_are_refused() {
        let (spline, nominal, mut image, placement) = setup();
        let identity = FloatSpline::new(&spline, &nominal).expect("float");
        let triangles = reference_triangles(&spline);
        let bad = Placement {
            units_per_pixel: 0.0,
            ..placement
        };
        assert_eq!(
            deform_image(&identity, &triangles, &image, bad, [0; 4]),
            Err(ImageError::Placement)
        );
        assert!(deform_image(&identity, &triangles[1..], &image, placement, [0; 4]).is_err());
        image.pixels.pop();
        assert!(matches!(
            deform_image(&identity, &triangles, &image, placement, [0; 4]),
            Err(ImageError::Size { .. })
        ));
    }
}
