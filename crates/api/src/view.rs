//! What an interactive editor draws of a source: which parameters are points to draw and drag,
//! and how they make up the picture (method 6 of the plugin ABI, optional).
//!
//! A view holds structure, not positions: the positions of the points are the parameters'
//! values, which the host keeps exactly. So an editor asks for a view once, draws it from the
//! current values, and during a drag only the moved points travel — the page redraws the
//! pieces that use them.
//!
//! A view may also carry the *models* the source's outputs deform ([`ViewModel`]): a model's
//! vertices and faces as read, and where each vertex sits in the reference mesh (a triangle and
//! barycentric coordinates), so the editor draws the model deformed by the current control
//! points without asking the source again. Models are for drawing only, so they are `f64`.

use crate::exact::Rational;
use crate::system::{ConstraintSystem, ParamId};
use serde::{Deserialize, Serialize};

/// The largest degree a [`BezierTriangles`] view may have (a patch has `(d + 1)(d + 2) / 2`
/// control points; spline2d's own limit is far below).
pub const MAX_VIEW_DEGREE: usize = 64;

/// The most model vertices a view may hold, over all its [`ViewModel`]s: a page draws every
/// one of them on every frame of a drag, and the view crosses the plugin ABI as JSON.
pub const MAX_VIEW_MODEL_VERTICES: usize = 4_000_000;

/// A request for a source's view ([`crate::ConstraintSource::view`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ViewRequest {
    /// The payload schema the host speaks ([`crate::SCHEMA_VERSION`]).
    pub schema: u32,
    /// The run file's outputs for this source, in run-file order: each the RON text of the
    /// output request as written (what [`crate::OutputCheckRequest::output`] carries), already
    /// checked by the source's `check_output`. A source names the models these outputs deform
    /// in [`BezierTriangles::models`] (paths resolved as its render resolves them); with no
    /// outputs (the default, also what hosts before this field send) a view has no models.
    #[serde(default)]
    pub outputs: Vec<String>,
}

/// A source's geometry for an editor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum SourceView {
    /// A deformation of the plane by triangular Bézier patches over a reference mesh
    /// (spline2d).
    BezierTriangles(BezierTriangles),
}

/// A piecewise polynomial map of degree `d` over a planar triangulation, given per triangle
/// by its Bézier control points: the image of the point with barycentric coordinates
/// `(u, v, w)` in triangle `t` is `Σ d!/(i! j! k!) uⁱ vʲ wᵏ c_ijk` over the control points
/// `c_ijk` of `patches[t]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BezierTriangles {
    /// Polynomial degree `d` (at least 1).
    pub degree: usize,
    /// Smoothness `r` the source's conditions enforce across interior edges (`C^r`).
    pub smoothness: usize,
    /// The reference mesh's vertices, exact.
    pub vertices: Vec<[Rational; 2]>,
    /// The reference mesh's triangles (vertex indices, as the source numbers them).
    pub triangles: Vec<[usize; 3]>,
    /// Per triangle, the parameters (of dimension 2) holding its control points, in the order
    /// of the multi-indices `(i, j, k)` (weights on the triangle's first, second and third
    /// vertex) lexicographically descending: `(d,0,0), (d−1,1,0), (d−1,0,1), …, (0,0,d)`.
    /// Points on a shared edge or vertex are the same parameter in every patch.
    pub patches: Vec<Vec<ParamId>>,
    /// The models the outputs named in [`ViewRequest::outputs`] deform, in the order of the
    /// outputs (none when the request names no outputs, and in views from sources before this
    /// field). An editor draws each vertex at the patch value of its embedding.
    #[serde(default)]
    pub models: Vec<ViewModel>,
}

/// A model an output of the source deforms, placed in the reference mesh, for drawing: the
/// image of vertex `v` with embedding `(t, β)` is the value of patch `t` at `β` (the formula at
/// [`BezierTriangles`]), `z` unchanged; a vertex without an embedding stays where it is, as in
/// the deformed model the output renders.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ViewModel {
    /// The model file as the output names it (relative to the run file, as written).
    pub name: String,
    /// Its vertices as read, `(x, y, z)` in file order (`z` is 0 for a planar model). Floats:
    /// for drawing only.
    pub vertices: Vec<[f64; 3]>,
    /// Its faces, as vertex indices (0-based) into [`ViewModel::vertices`], each of at least 3
    /// vertices; none for a point cloud. A source gives the faces its rendered model has
    /// (spline2d: the file's polygons fan-triangulated from their first corner).
    pub faces: Vec<Vec<u32>>,
    /// Per vertex: the reference triangle it lies in (an index into
    /// [`BezierTriangles::triangles`]) and its barycentric coordinates there (weights on the
    /// triangle's first, second and third vertex, summing to 1), exactly where the source's
    /// render evaluates the deformation; `None` for a vertex outside the mesh, which the
    /// deformation leaves in place.
    pub embedding: Vec<Option<(u32, [f64; 3])>>,
}

impl SourceView {
    /// Checks a view against the system before a host uses it (a plugin's answer is outside
    /// data): indices in range, every patch complete, every point a parameter of dimension 2.
    pub fn validate(&self, system: &ConstraintSystem) -> Result<(), String> {
        match self {
            SourceView::BezierTriangles(view) => view.validate(system),
        }
    }
}

impl BezierTriangles {
    /// Control points per patch: `(d + 1)(d + 2) / 2`.
    pub fn points_per_patch(&self) -> usize {
        (self.degree + 1) * (self.degree + 2) / 2
    }

    fn validate(&self, system: &ConstraintSystem) -> Result<(), String> {
        if !(1..=MAX_VIEW_DEGREE).contains(&self.degree) {
            return Err(format!(
                "the view's degree {} is not between 1 and {MAX_VIEW_DEGREE}",
                self.degree
            ));
        }
        if self.patches.len() != self.triangles.len() {
            return Err(format!(
                "the view has {} patches for {} triangles",
                self.patches.len(),
                self.triangles.len()
            ));
        }
        let vertices = self.vertices.len();
        if let Some((t, tri)) = self
            .triangles
            .iter()
            .enumerate()
            .find(|(_, tri)| tri.iter().any(|&v| v >= vertices))
        {
            return Err(format!(
                "the view's triangle {t} {tri:?} names a vertex beyond its {vertices}"
            ));
        }
        let expected = self.points_per_patch();
        for (t, patch) in self.patches.iter().enumerate() {
            if patch.len() != expected {
                return Err(format!(
                    "the view's patch {t} has {} control points, degree {} needs {expected}",
                    patch.len(),
                    self.degree
                ));
            }
            for id in patch {
                match system.param(*id) {
                    None => {
                        return Err(format!(
                            "the view's patch {t} names parameter {id}, which does not exist"
                        ))
                    }
                    Some(p) if p.dim != 2 => {
                        return Err(format!(
                            "the view's patch {t} names {:?} of dimension {}, not a point",
                            p.name, p.dim
                        ))
                    }
                    Some(_) => {}
                }
            }
        }
        self.validate_models()
    }

    /// The models' part of [`BezierTriangles::validate`]: the vertex bound first (before
    /// anything is walked), then per model one embedding per vertex, faces of at least 3
    /// vertices in range, triangles in range, finite coordinates.
    fn validate_models(&self) -> Result<(), String> {
        let total = self
            .models
            .iter()
            .try_fold(0usize, |sum, m| sum.checked_add(m.vertices.len()))
            .filter(|&total| total <= MAX_VIEW_MODEL_VERTICES);
        if total.is_none() {
            return Err(format!(
                "the view's models have more than {MAX_VIEW_MODEL_VERTICES} vertices in total"
            ));
        }
        let triangles = self.triangles.len();
        for (m, model) in self.models.iter().enumerate() {
            let what = format!("the view's model {m} ({:?})", model.name);
            let vertices = model.vertices.len();
            if model.embedding.len() != vertices {
                return Err(format!(
                    "{what} has {} embedding entries for {vertices} vertices",
                    model.embedding.len()
                ));
            }
            if let Some(v) = model
                .vertices
                .iter()
                .position(|p| !p.iter().all(|c| c.is_finite()))
            {
                return Err(format!(
                    "{what}: vertex {v} has a coordinate that is not finite"
                ));
            }
            for (f, face) in model.faces.iter().enumerate() {
                if face.len() < 3 {
                    return Err(format!(
                        "{what}: face {f} has {} vertices, a face needs at least 3",
                        face.len()
                    ));
                }
                if let Some(v) = face.iter().find(|&&v| v as usize >= vertices) {
                    return Err(format!(
                        "{what}: face {f} names vertex {v}, beyond its {vertices}"
                    ));
                }
            }
            for (v, place) in model.embedding.iter().enumerate() {
                let Some((t, beta)) = place else { continue };
                if *t as usize >= triangles {
                    return Err(format!(
                        "{what}: vertex {v} lies in triangle {t}, beyond the view's {triangles}"
                    ));
                }
                if !beta.iter().all(|b| b.is_finite()) {
                    return Err(format!(
                        "{what}: vertex {v} has barycentric coordinates that are not finite"
                    ));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn system() -> (ConstraintSystem, Vec<ParamId>) {
        let mut s = ConstraintSystem::new();
        let points = (0..3)
            .map(|i| s.add_parameter(format!("v{i}"), 2).expect("fresh"))
            .collect();
        s.add_parameter("h", 1).expect("fresh");
        (s, points)
    }

    fn view(patches: Vec<Vec<ParamId>>) -> SourceView {
        let q = |n: i64| Rational::from_integer(n.into());
        SourceView::BezierTriangles(BezierTriangles {
            degree: 1,
            smoothness: 0,
            vertices: vec![[q(0), q(0)], [q(1), q(0)], [q(0), q(1)]],
            triangles: vec![[0, 1, 2]],
            patches,
            models: Vec::new(),
        })
    }

    /// A unit square of 4 vertices (two triangles, one placed in the view's triangle, one
    /// vertex outside).
    fn model() -> ViewModel {
        ViewModel {
            name: "models/square.obj".into(),
            vertices: vec![
                [0.0, 0.0, 0.0],
                [0.5, 0.0, 1.0],
                [0.5, 0.5, 0.0],
                [2.0, 2.0, 0.0],
            ],
            faces: vec![vec![0, 1, 2], vec![0, 2, 3, 1]],
            embedding: vec![
                Some((0, [1.0, 0.0, 0.0])),
                Some((0, [0.5, 0.5, 0.0])),
                Some((0, [0.0, 0.5, 0.5])),
                None,
            ],
        }
    }

    /// The view with `model` changed by `change`, validated.
    fn with_model(change: impl FnOnce(&mut ViewModel)) -> Result<(), String> {
        let (s, p) = system();
        let SourceView::BezierTriangles(mut v) = view(vec![p]);
        let mut m = model();
        change(&mut m);
        v.models.push(m);
        SourceView::BezierTriangles(v).validate(&s)
    }

    #[test]
    fn a_complete_view_passes_and_broken_ones_are_named() {
        let (s, p) = system();
        assert_eq!(view(vec![p.clone()]).validate(&s), Ok(()));
        let short = view(vec![p[..2].to_vec()]).validate(&s).expect_err("short");
        assert!(short.contains("has 2 control points"), "{short}");
        let scalar = view(vec![vec![p[0], p[1], ParamId(3)]])
            .validate(&s)
            .expect_err("scalar");
        assert!(scalar.contains("\"h\" of dimension 1"), "{scalar}");
        let missing = view(vec![vec![p[0], p[1], ParamId(9)]])
            .validate(&s)
            .expect_err("missing");
        assert!(missing.contains("does not exist"), "{missing}");
        let SourceView::BezierTriangles(mut bad) = view(vec![p.clone()]);
        bad.triangles[0] = [0, 1, 5];
        let beyond = SourceView::BezierTriangles(bad.clone())
            .validate(&s)
            .expect_err("vertex");
        assert!(beyond.contains("beyond its 3"), "{beyond}");
        bad.triangles.clear();
        let count = SourceView::BezierTriangles(bad)
            .validate(&s)
            .expect_err("count");
        assert!(count.contains("1 patches for 0 triangles"), "{count}");
    }

    #[test]
    fn a_view_with_a_placed_model_passes() {
        assert_eq!(with_model(|_| {}), Ok(()));
        // A point cloud (no faces) and a model entirely outside the mesh are fine too.
        assert_eq!(with_model(|m| m.faces.clear()), Ok(()));
        assert_eq!(with_model(|m| m.embedding.fill(None)), Ok(()));
    }

    #[test]
    fn a_model_with_a_missing_embedding_entry_is_refused() {
        let e = with_model(|m| {
            m.embedding.pop();
        })
        .expect_err("short embedding");
        assert!(
            e.contains("model 0 (\"models/square.obj\") has 3 embedding entries for 4 vertices"),
            "{e}"
        );
    }

    #[test]
    fn a_face_beyond_the_vertices_is_refused() {
        let e = with_model(|m| m.faces[1][2] = 4).expect_err("face index");
        assert!(e.contains("face 1 names vertex 4, beyond its 4"), "{e}");
    }

    #[test]
    fn a_face_of_two_vertices_is_refused() {
        let e = with_model(|m| m.faces[0].truncate(2)).expect_err("short face");
        assert!(
            e.contains("face 0 has 2 vertices, a face needs at least 3"),
            "{e}"
        );
    }

    #[test]
    fn an_embedding_beyond_the_triangles_is_refused() {
        let e = with_model(|m| m.embedding[2] = Some((1, [0.0, 0.5, 0.5]))).expect_err("triangle");
        assert!(
            e.contains("vertex 2 lies in triangle 1, beyond the view's 1"),
            "{e}"
        );
    }

    #[test]
    fn coordinates_that_are_not_finite_are_refused() {
        let e = with_model(|m| m.vertices[1][2] = f64::NAN).expect_err("vertex");
        assert!(
            e.contains("vertex 1 has a coordinate that is not finite"),
            "{e}"
        );
        let e = with_model(|m| m.vertices[3][0] = f64::INFINITY).expect_err("vertex");
        assert!(e.contains("vertex 3 has a coordinate"), "{e}");
        let e = with_model(|m| m.embedding[0] = Some((0, [f64::NAN, 0.0, 1.0])))
            .expect_err("barycentric");
        assert!(
            e.contains("vertex 0 has barycentric coordinates that are not finite"),
            "{e}"
        );
    }

    #[test]
    fn too_many_model_vertices_in_total_are_refused() {
        let (s, p) = system();
        let SourceView::BezierTriangles(mut v) = view(vec![p]);
        let half = MAX_VIEW_MODEL_VERTICES / 2;
        let big = ViewModel {
            name: "big.obj".into(),
            vertices: vec![[0.0; 3]; half],
            faces: Vec::new(),
            embedding: vec![None; half],
        };
        // Each model is within the bound, and so are both together; one vertex more is not.
        v.models = vec![big.clone(), big.clone()];
        assert_eq!(SourceView::BezierTriangles(v.clone()).validate(&s), Ok(()));
        v.models[1].vertices.push([0.0; 3]);
        v.models[1].embedding.push(None);
        let e = SourceView::BezierTriangles(v)
            .validate(&s)
            .expect_err("too many");
        assert!(
            e.contains(&format!(
                "more than {MAX_VIEW_MODEL_VERTICES} vertices in total"
            )),
            "{e}"
        );
    }

    #[test]
    fn requests_and_views_from_before_models_read_with_no_models() {
        let request: ViewRequest =
            serde_json::from_str(r#"{"schema": 2}"#).expect("a request without outputs");
        assert!(request.outputs.is_empty());
        let (_, p) = system();
        let v = view(vec![p]);
        let mut json = serde_json::to_value(&v).expect("serialise");
        json.as_object_mut().expect("an object").remove("models");
        assert_eq!(
            serde_json::from_value::<SourceView>(json).expect("parse"),
            v
        );
    }

    #[test]
    fn views_round_trip_through_json() {
        let (_, p) = system();
        let SourceView::BezierTriangles(mut v) = view(vec![p]);
        v.models.push(model());
        let v = SourceView::BezierTriangles(v);
        let text = serde_json::to_string(&v).expect("serialise");
        assert!(text.contains("\"kind\":\"bezier_triangles\""), "{text}");
        assert!(
            text.contains(
                "\"embedding\":[[0,[1.0,0.0,0.0]],[0,[0.5,0.5,0.0]],[0,[0.0,0.5,0.5]],null]"
            ),
            "{text}"
        );
        assert_eq!(serde_json::from_str::<SourceView>(&text).expect("parse"), v);
    }
}
