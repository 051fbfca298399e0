//! A deformed terrain sampled again on its own grid, so that a terrain whose horizontal map φ
//! moved its samples can still be written back as the grid it was read from (ESRI, GeoTIFF).
//!
//! The deformed terrain is the deformed triangulated surface (each sample moved by ψ, the
//! triangles of [`HeightField::to_model`]). The height at a grid position `q` is that surface's
//! height above `q`: the deformed triangle whose `x, y` projection contains `q`, interpolated
//! linearly (barycentric coordinates). A sample whose deformed vertex lands exactly on `q`
//! (every sample φ leaves in place) takes that vertex's height exactly, so what the edit does
//! not move is written back unchanged; a position no deformed triangle covers (the terrain's
//! border moved inwards, or a hole) has no data. Where φ folds (it does not for an edit that
//! ECLES accepted with a valid spline, but floats near a fold may), the first triangle in the
//! model's order wins.

use crate::heightfield::HeightField;
use spline2d::model::Model;

/// The heights of `deformed` (the model of `field`, deformed: same vertices and triangles) at
/// `field`'s sample positions, row by row from the south-west as [`HeightField::heights`].
pub fn resample(field: &HeightField, deformed: &Model) -> Vec<Option<f64>> {
    let (columns, rows) = (field.columns, field.rows);
    let xs: Vec<f64> = (0..columns).map(|c| field.position(c, 0)[0]).collect();
    let ys: Vec<f64> = (0..rows).map(|r| field.position(0, r)[1]).collect();
    let mut heights: Vec<Option<f64>> = vec![None; columns * rows];
    // Vertices on a sample position, exactly.
    let mut exact = vec![false; heights.len()];
    for p in &deformed.positions {
        if let (Some(c), Some(r)) = (grid_index(&xs, p[0]), grid_index(&ys, p[1])) {
            let k = r * columns + c;
            if !exact[k] {
                exact[k] = true;
                heights[k] = Some(p[2]);
            }
        }
    }
    for triangle in &deformed.triangles {
        let [a, b, c] = triangle.map(|v| deformed.positions[v]);
        let det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        if det == 0.0 || !det.is_finite() {
            continue;
        }
        let low = |i: usize| a[i].min(b[i]).min(c[i]);
        let high = |i: usize| a[i].max(b[i]).max(c[i]);
        let columns_in = range_between(&xs, low(0), high(0));
        let rows_in = range_between(&ys, low(1), high(1));
        for r in rows_in {
            for col in columns_in.clone() {
                let k = r * columns + col;
                if exact[k] || heights[k].is_some() {
                    continue;
                }
                let (x, y) = (xs[col], ys[r]);
                // Barycentric coordinates of (x, y), with a tolerance for positions on an edge.
                let l1 = ((x - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (y - a[1])) / det;
                let l2 = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / det;
                let l0 = 1.0 - l1 - l2;
                const EDGE: f64 = -1e-12;
                if l0 >= EDGE && l1 >= EDGE && l2 >= EDGE {
                    heights[k] = Some(l0 * a[2] + l1 * b[2] + l2 * c[2]);
                }
            }
        }
    }
    heights
}

/// The index of `value` in the increasing `axis`, when it is exactly one of its entries.
fn grid_index(axis: &[f64], value: f64) -> Option<usize> {
    axis.binary_search_by(|x| x.total_cmp(&value)).ok()
}

/// The indices of the entries of the increasing `axis` in `[low, high]`.
fn range_between(axis: &[f64], low: f64, high: f64) -> std::ops::Range<usize> {
    let start = axis.partition_point(|&x| x < low);
    let end = axis.partition_point(|&x| x <= high);
    start..end.max(start)
}

#[cfg(test)]
mod tests {
    use super::*;

    const GRID: &str =
        "ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 2\nNODATA_value -9999\n\
                        7 8 9\n4 5 6\n1 2 3\n";

    #[test]
    fn an_unmoved_terrain_samples_back_to_its_own_heights() {
        let field = HeightField::parse_esri(GRID, "g.asc").expect("read");
        assert_eq!(resample(&field, &field.to_model()), field.heights);
    }

    #[test]
    fn a_shifted_terrain_is_sampled_where_it_now_lies() {
        let field = HeightField::parse_esri(GRID, "g.asc").expect("read");
        let mut model = field.to_model();
        // The whole terrain moved east by half a cell (1 unit): the western column is left
        // uncovered, the others take the height half-way between their old neighbours.
        for p in &mut model.positions {
            p[0] += 1.0;
        }
        let heights = resample(&field, &model);
        assert_eq!(heights[0], None, "the south-west sample is uncovered");
        // South row heights 1, 2, 3 at x = 1, 3, 5 now; at x = 2: 1.5, at x = 4: 2.5.
        assert_eq!(heights[1], Some(1.5));
        assert_eq!(heights[2], Some(2.5));
        assert_eq!(heights[8], Some(8.5));
    }

    #[test]
    fn samples_left_in_place_keep_their_height_exactly() {
        let field = HeightField::parse_esri(GRID, "g.asc").expect("read");
        let mut model = field.to_model();
        // Only the centre sample moves (sideways and up): the others are exactly theirs.
        model.positions[4][0] += 0.3;
        model.positions[4][2] = 50.0;
        let heights = resample(&field, &model);
        for k in (0..9).filter(|&k| k != 4) {
            assert_eq!(heights[k], field.heights[k], "sample {k}");
        }
        let centre = heights[4].expect("covered");
        assert!(centre > 5.0 && centre < 50.0, "{centre}");
    }
}
