//! Deforming a model by a plane deformation `φ` in `f64`, and the report's note on the vertices
//! it left in place.

use super::{Deformed, Model, ModelError};
use crate::eval::{FloatSpline, Locator};

/// Deforms a model by the plane deformation `spline` (values with 2 coordinates): `(x, y)`
/// of each vertex goes through `φ`, `z` is unchanged. Vertices outside the reference mesh (as
/// seen by `locator`, built from the spline's mesh) keep their position and are listed in
/// [`Deformed::outside`]. Allocates only the output.
///
/// `φ` is evaluated as the identity plus a displacement ([`FloatSpline::evaluate_point_into`];
/// [`FloatSpline::new`] measures 2-coordinate values from the identity): `x' = x + D̂_x`,
/// `y' = y + D̂_y`. A vertex in a triangle whose control points are all at their nominal
/// positions comes back bit-identical, so the identity deformation returns the model
/// unchanged; a moved vertex is within `u·|x'| + 1.01·K·M_x` of the exact `φ` at the rational
/// value of its `f64` coordinates (`u = 2^-53`; `K` and the largest displacement `M_x` of
/// the triangle's control points as stated at [`FloatSpline`]), an error proportional to the
/// displacement rather than to `|x|`.
pub fn deform_model(
    model: &Model,
    spline: &FloatSpline,
    locator: &Locator,
) -> Result<Deformed, ModelError> {
    if spline.dim() != 2 {
        return Err(ModelError::NotAPlaneDeformation { dim: spline.dim() });
    }
    if spline.triangle_count() != locator.triangle_count() {
        return Err(ModelError::MeshMismatch {
            locator: locator.triangle_count(),
            spline: spline.triangle_count(),
        });
    }
    let mut positions = Vec::with_capacity(model.positions.len());
    let mut outside = Vec::new();
    let mut xy = [0.0; 2];
    for (v, p) in model.positions.iter().enumerate() {
        if spline.evaluate_point_into(locator, [p[0], p[1]], &mut xy) {
            positions.push([xy[0], xy[1], p[2]]);
        } else {
            positions.push(*p);
            outside.push(v);
        }
    }
    Ok(Deformed {
        model: Model {
            positions,
            triangles: model.triangles.clone(),
        },
        outside,
    })
}

/// The Jacobian of `ψ(x, y, z) = (φ(x, y), z)` at `p` (row `r`, column `c`: `∂ψ_r/∂x_c`),
/// for transforming normals; `None` outside the mesh. `φ`'s derivatives along `x` and `y` are
/// `Σ_a ∂φ/∂β_a · ∂β_a/∂u`, with the barycentric coordinates' gradients taken from the
/// locator (they are affine, so a unit step gives them).
pub fn plane_jacobian(
    spline: &FloatSpline,
    locator: &Locator,
    p: [f64; 2],
) -> Option<[[f64; 3]; 3]> {
    if spline.dim() != 2 {
        return None;
    }
    let (t, beta) = locator.locate(p)?;
    let (_, partials) = spline.evaluate_with_derivatives(t, beta)?;
    let at_x = locator.barycentric(t, [p[0] + 1.0, p[1]])?;
    let at_y = locator.barycentric(t, [p[0], p[1] + 1.0])?;
    let gradient = |a: usize| [at_x[a] - beta[a], at_y[a] - beta[a]];
    let derivative =
        |c: usize, axis: usize| -> f64 { (0..3).map(|a| partials[a][c] * gradient(a)[axis]).sum() };
    Some([
        [derivative(0, 0), derivative(0, 1), 0.0],
        [derivative(1, 0), derivative(1, 1), 0.0],
        [0.0, 0.0, 1.0],
    ])
}

/// Where [`deform_model`] evaluates each vertex of `model`: the triangle of the reference mesh
/// (as seen by `locator`, built from the spline's mesh) and the vertex's barycentric
/// coordinates there, or `None` for a vertex outside the mesh, which the deformation leaves in
/// place. It is the location [`FloatSpline::evaluate_point_into`] makes (one
/// [`Locator::locate`] of `(x, y)`), so an editor that evaluates the patches at these
/// coordinates draws the model the output renders (up to rounding: the deformation takes the
/// identity part from the vertex itself, `Σ βk·vk` gives it back within a few ulps).
pub fn locate_vertices(model: &Model, locator: &Locator) -> Vec<Option<(usize, [f64; 3])>> {
    model
        .positions
        .iter()
        .map(|p| locator.locate([p[0], p[1]]))
        .collect()
}

/// How many vertex numbers [`left_in_place_note`] lists before it summarises the rest.
const NOTE_LISTS: usize = 20;

/// A one-line note for the run report about model vertices a deformation left in place
/// (`where_` says why: "outside the reference mesh"). Vertex numbers are 0-based, as in the
/// reports; the first twenty are listed, the deformed OBJ's header lists them all. `None` when
/// no vertex was left in place.
pub fn left_in_place_note(vertices: &[usize], where_: &str) -> Option<String> {
    if vertices.is_empty() {
        return None;
    }
    let listed: Vec<String> = vertices
        .iter()
        .take(NOTE_LISTS)
        .map(|v| v.to_string())
        .collect();
    let more = vertices.len().saturating_sub(NOTE_LISTS);
    let tail = if more > 0 {
        format!(" and {more} more")
    } else {
        String::new()
    };
    let noun = if vertices.len() == 1 {
        "vertex"
    } else {
        "vertices"
    };
    Some(format!(
        "{} model {noun} {where_} left in place (0-based): {}{tail}",
        vertices.len(),
        listed.join(", ")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spline::tests::grid;
    use crate::spline::Spline;
    use api::Rational;

    fn identity(spline: &Spline) -> Vec<Vec<Rational>> {
        spline.nominals().iter().map(|p| p.to_vec()).collect()
    }

    #[test]
    fn notes_on_vertices_left_in_place() {
        assert_eq!(left_in_place_note(&[], "outside the reference mesh"), None);
        assert_eq!(
            left_in_place_note(&[1], "outside the reference mesh").as_deref(),
            Some("1 model vertex outside the reference mesh left in place (0-based): 1")
        );
        let many: Vec<usize> = (0..23).collect();
        let note = left_in_place_note(&many, "outside the reference mesh").expect("a note");
        assert!(note.starts_with("23 model vertices outside"), "{note}");
        assert!(
            note.ends_with(
                ": 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19 and 3 more"
            ),
            "{note}"
        );
    }

    #[test]
    fn identity_and_outside_vertices() {
        let spline = Spline::new(grid(2, true), 3, 1).expect("spline");
        let float = FloatSpline::new(&spline, &identity(&spline)).expect("float");
        let locator = Locator::new(spline.mesh());
        let model = Model {
            positions: vec![
                [1.5, 2.25, 7.0],
                [25.0, 5.0, 1.0],
                [20.0, 20.0, -1.0],
                [0.0, 0.0, 0.0],
            ],
            triangles: vec![[0, 1, 2]],
        };
        let deformed = deform_model(&model, &float, &locator).expect("deform");
        assert_eq!(deformed.outside, vec![1]);
        for (a, b) in deformed.model.positions.iter().zip(&model.positions) {
            for c in 0..3 {
                assert!((a[c] - b[c]).abs() <= 1e-12 * (1.0 + b[c].abs()));
            }
        }
        assert_eq!(deformed.model.positions[1], model.positions[1]);
        let places = locate_vertices(&model, &locator);
        assert_eq!(places.iter().filter(|p| p.is_none()).count(), 1);
        assert!(places[1].is_none());
        let scalar = FloatSpline::new(
            &spline,
            &vec![vec![Rational::from_integer(1.into())]; spline.points().len()],
        )
        .expect("float");
        assert!(matches!(
            deform_model(&model, &scalar, &locator),
            Err(ModelError::NotAPlaneDeformation { dim: 1 })
        ));
    }

    /// The identity leaves every vertex bit-identical, awkward coordinates included (the
    /// nominal positions of this perturbed mesh have denominator 5, so they are not `f64`s);
    /// after a local edit, vertices in triangles whose control points did not move are
    /// bit-identical and the others agree with the exact `φ` within the stated bound.
    #[test]
    fn identity_and_local_edits_leave_unmoved_vertices_bit_identical() {
        use crate::eval::{
            barycentric_error_bound, displacement_error_factor, evaluate_exact, locate_exact,
            UNIT_ROUNDOFF as U,
        };
        use api::exact::{rational_from_f64, rational_to_f64};
        let spline = Spline::new(crate::mesh::grid(4, 5000, true), 5, 1).expect("spline");
        let nominal = identity(&spline);
        let locator = Locator::new(spline.mesh());
        let awkward = [
            0.1,
            246.5,
            1e-7,
            12345.678,
            0.0,
            20000.0,
            1.0 / 3.0,
            19999.999999999996,
            5e-324,
            7777.7777,
            4.531,
        ];
        let mut positions: Vec<[f64; 3]> = awkward
            .iter()
            .flat_map(|&x| awkward.iter().map(move |&y| [x, y, 0.1]))
            .collect();
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % 2_000_000_000) as f64 / 100_000.0
        };
        for _ in 0..600 {
            positions.push([next(), next(), next()]);
        }
        let model = Model {
            positions,
            triangles: Vec::new(),
        };
        let float = FloatSpline::new(&spline, &nominal).expect("float");
        let deformed = deform_model(&model, &float, &locator).expect("deform");
        assert!(deformed.outside.is_empty());
        for (image, p) in deformed.model.positions.iter().zip(&model.positions) {
            assert_eq!(image.map(f64::to_bits), p.map(f64::to_bits), "{p:?}");
        }
        // Move the control points near the corner (0, 0) by awkward amounts.
        let limit = Rational::from_integer(7000.into());
        let moved: Vec<Vec<Rational>> = spline
            .nominals()
            .iter()
            .enumerate()
            .map(|(i, [x, y])| {
                if x + y < limit {
                    let i = i as i64;
                    vec![
                        x + Rational::new((i * 7 % 13 - 6).into(), 3.into()),
                        y + Rational::new((i * 5 % 11 - 5).into(), 7.into()),
                    ]
                } else {
                    vec![x.clone(), y.clone()]
                }
            })
            .collect();
        let float = FloatSpline::new(&spline, &moved).expect("float");
        let deformed = deform_model(&model, &float, &locator).expect("deform");
        let corners = |t: usize| {
            spline.mesh().triangles()[t].map(|v| {
                let p = &spline.mesh().vertices()[v];
                [rational_to_f64(&p[0]), rational_to_f64(&p[1])]
            })
        };
        let (mut far, mut near, mut worst) = (0, 0, 0.0f64);
        for (image, p) in deformed.model.positions.iter().zip(&model.positions) {
            assert_eq!(image[2].to_bits(), p[2].to_bits());
            let (t, _) = locator.locate([p[0], p[1]]).expect("inside");
            let unchanged = spline
                .triangle_points(t)
                .iter()
                .all(|&i| moved[i] == nominal[i]);
            assert_eq!(float.is_displaced(t), !unchanged);
            if unchanged {
                assert_eq!(image.map(f64::to_bits), p.map(f64::to_bits), "{p:?}");
                far += 1;
                continue;
            }
            near += 1;
            let exact_p = [p[0], p[1]].map(|c| rational_from_f64(c).expect("finite"));
            let (te, _) = locate_exact(spline.mesh(), &exact_p).expect("inside");
            let exact = evaluate_exact(&spline, &moved, &exact_p).expect("inside");
            let (mut m, mut delta) = ([0.0f64; 2], 0.0f64);
            for s in [t, te] {
                for &i in spline.triangle_points(s) {
                    for (c, mc) in m.iter_mut().enumerate() {
                        let d = rational_to_f64(&(&moved[i][c] - &nominal[i][c]));
                        *mc = mc.max(d.abs());
                    }
                }
                delta = delta.max(barycentric_error_bound(corners(s), [p[0], p[1]]));
            }
            let k = displacement_error_factor(spline.degree(), delta);
            for c in 0..2 {
                let exact_c = &exact[c];
                let error = rational_from_f64(image[c]).expect("finite") - exact_c;
                let error = rational_to_f64(&error).abs();
                let bound = (U * rational_to_f64(exact_c).abs() + 1.01 * k * m[c]) * (1.0 + 1e-9);
                assert!(
                    error <= bound,
                    "{p:?} coordinate {c}: error {error:e} > {bound:e}"
                );
                worst = worst.max(error / bound);
            }
        }
        assert!(far > 100 && near > 100, "{far} far, {near} near");
        eprintln!("{near} moved vertices, largest error / bound {worst:.3}");
    }

    /// [`locate_vertices`] places exactly the vertices [`deform_model`] moves, and the patch
    /// value at each place is the deformed vertex (after an edit that moves every triangle).
    #[test]
    fn located_vertices_are_where_the_deformation_evaluates() {
        let spline = Spline::new(grid(3, true), 4, 1).expect("spline");
        let locator = Locator::new(spline.mesh());
        let moved: Vec<Vec<Rational>> = spline
            .nominals()
            .iter()
            .enumerate()
            .map(|(i, [x, y])| {
                let i = i as i64;
                vec![
                    x + Rational::new((i % 7 - 3).into(), 5.into()),
                    y + Rational::new((i % 5 - 2).into(), 3.into()),
                ]
            })
            .collect();
        let float = FloatSpline::new(&spline, &moved).expect("float");
        let mut positions = vec![[31.0, 1.0, 0.0], [-1.0, 2.0, 0.5]];
        for a in 0..=40 {
            for b in 0..=40 {
                positions.push([f64::from(a) * 0.75, f64::from(b) * 0.75, f64::from(a - b)]);
            }
        }
        let model = Model {
            positions,
            triangles: vec![[0, 1, 2]],
        };
        let deformed = deform_model(&model, &float, &locator).expect("deform");
        let places = locate_vertices(&model, &locator);
        assert_eq!(places.len(), model.positions.len());
        let outside: Vec<usize> = (0..places.len()).filter(|&v| places[v].is_none()).collect();
        assert_eq!(outside, deformed.outside);
        assert_eq!(outside, vec![0, 1]);
        for (v, place) in places.iter().enumerate() {
            let Some((t, beta)) = *place else { continue };
            let value = float.evaluate(t, beta).expect("a triangle");
            let image = deformed.model.positions[v];
            for c in 0..2 {
                assert!(
                    (value[c] - image[c]).abs() <= 1e-9 * (1.0 + image[c].abs()),
                    "vertex {v}: {value:?} against {image:?}"
                );
            }
        }
    }
}
