//! What an interactive editor draws of a source: which parameters are points to draw and drag,
//! and how they make up the picture (method 6 of the plugin ABI, optional).
//!
//! A view holds structure, not positions: the positions of the points are the parameters'
//! values, which the host keeps exactly. So an editor asks for a view once, draws it from the
//! current values, and during a drag only the moved points travel — the page redraws the
//! pieces that use them.
//!
//! Two kinds exist: [`BezierTriangles`], a planar deformation by triangular Bézier patches
//! (spline2d), and [`Prisms`], the 2.5D deformation of one layer of prisms over a planar mesh
//! (terrain: a bottom and a top height surface and an optional horizontal map, Bézier splines
//! on the same mesh).
//!
//! A view may also carry the *models* the source's outputs deform ([`ViewModel`]): a model's
//! vertices and faces as read, and where each vertex sits in the reference mesh (a triangle and
//! barycentric coordinates, and for prisms its relative height in the layer), so the editor
//! draws the model deformed by the current control points without asking the source again.
//! Models are for drawing only, so they are `f64`.

use crate::exact::Rational;
use crate::system::{ConstraintSystem, ParamId};
use serde::{Deserialize, Serialize};

/// The largest degree a view may have (a patch has `(d + 1)(d + 2) / 2` control points;
/// spline2d's and terrain's own limits are far below).
pub const MAX_VIEW_DEGREE: usize = 64;

/// The most model vertices a view may hold, over all its [`ViewModel`]s: a page draws every
/// one of them on every frame of a drag, and the view crosses the plugin ABI as JSON.
pub const MAX_VIEW_MODEL_VERTICES: usize = 4_000_000;

/// The models of a view as a source collects them: their vertices counted against
/// [`MAX_VIEW_MODEL_VERTICES`] (before a model is placed, the costly part) and their indices
/// turned into the view's `u32`. One implementation for every source that draws models.
#[derive(Debug, Default)]
pub struct ViewModels {
    models: Vec<ViewModel>,
    vertices: usize,
}

impl ViewModels {
    /// Counts a model of `vertices` vertices in, refusing one that would bring the view above
    /// [`MAX_VIEW_MODEL_VERTICES`]; call before placing it.
    pub fn reserve(&mut self, vertices: usize) -> Result<(), String> {
        self.vertices = self
            .vertices
            .checked_add(vertices)
            .filter(|&total| total <= MAX_VIEW_MODEL_VERTICES)
            .ok_or_else(|| {
                format!(
                    "{vertices} vertices bring the view's models above {MAX_VIEW_MODEL_VERTICES} vertices, the most an editor draws"
                )
            })?;
        Ok(())
    }

    /// Adds a model: its vertices, triangles (vertex indices), per vertex its reference
    /// triangle and barycentric coordinates (`None`: not placed, it stays) and its relative
    /// heights (empty for a planar view).
    pub fn push(
        &mut self,
        name: String,
        vertices: Vec<[f64; 3]>,
        triangles: &[[usize; 3]],
        embedding: impl IntoIterator<Item = Option<(usize, [f64; 3])>>,
        relative_height: Vec<f64>,
    ) -> Result<(), String> {
        let index = |i: usize, what: &str| {
            u32::try_from(i).map_err(|_| format!("{what} {i} does not fit a view's index"))
        };
        let faces = triangles
            .iter()
            .map(|t| t.iter().map(|&v| index(v, "vertex")).collect())
            .collect::<Result<_, _>>()?;
        let embedding = embedding
            .into_iter()
            .map(|place| {
                place
                    .map(|(t, beta)| Ok((index(t, "triangle")?, beta)))
                    .transpose()
            })
            .collect::<Result<_, String>>()?;
        self.models.push(ViewModel {
            name,
            vertices,
            faces,
            embedding,
            relative_height,
        });
        Ok(())
    }

    /// The models collected.
    pub fn into_models(self) -> Vec<ViewModel> {
        self.models
    }
}

/// A request for a source's view ([`crate::ConstraintSource::view`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ViewRequest {
    /// The payload schema the host speaks ([`crate::SCHEMA_VERSION`]).
    pub schema: u32,
    /// The run file's outputs for this source, in run-file order: each the RON text of the
    /// output request as written (what [`crate::OutputCheckRequest::output`] carries), already
    /// checked by the source's `check_output`. A source names the models these outputs deform
    /// in its view's `models` ([`BezierTriangles::models`], [`Prisms::models`]; paths resolved
    /// as its render resolves them); with no outputs (the default, also what hosts before this
    /// field send) a view has no models.
    #[serde(default)]
    pub outputs: Vec<String>,
}

/// A source's geometry for an editor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum SourceView {
    /// A deformation of the plane by triangular Bézier patches over a reference mesh
    /// (spline2d). JSON tag `"bezier_triangles"`.
    BezierTriangles(BezierTriangles),
    /// The 2.5D deformation of one layer of prisms over a reference mesh (terrain). JSON tag
    /// `"prisms"`.
    Prisms(Prisms),
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

/// The 2.5D deformation `ψ` of one layer of prisms over a planar reference mesh (thesis part
/// III; the terrain source): three Bézier splines of the same degree on the same mesh, each
/// given per triangle by its control points in the multi-index order of
/// [`BezierTriangles::patches`] and evaluated by the same formula — `σ0`, the bottom surface
/// (heights), `σ1`, the top surface (heights), and `φ`, the horizontal map (points; the
/// identity when the source does not edit it).
///
/// The reference layer is the prisms between `z = a` ([`Prisms::reference_bottom`]) and
/// `z = b` ([`Prisms::reference_top`]) over the reference mesh. A point `(x, y, z)` with
/// `(x, y)` at barycentric coordinates `β` in triangle `t` and relative height
/// `α = (z − a)/(b − a)` maps to
///
/// ```text
/// ψ(x, y, z) = ( φ_t(β),  (1 − α)·σ0_t(β) + α·σ1_t(β) )
/// ```
///
/// (`φ_t(β) = (x, y)` when [`Prisms::xy`] is `None`). With the initial values (`σ0 ≡ a`,
/// `σ1 ≡ b`, `φ` the identity) `ψ` is the identity. This is the source's `ψ` exactly; its
/// render evaluates it in `f64` as the identity plus a displacement,
/// `(x + Dx, y + Dy, z + (1 − α)·(σ0 − a) + α·(σ1 − b))` with `Dx, Dy` those of `φ` (and the
/// bottom's weight computed as `(b − z)/(b − a)`), which is the same map and keeps the
/// vertices of prisms whose control values did not move exactly in place; an editor may
/// evaluate either form. A point outside the mesh, or with `z` outside
/// `[a, b]` (beyond a relative tolerance of `1e-9·(b − a)`), is left in place: such a model
/// vertex has no embedding ([`ViewModel::embedding`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Prisms {
    /// Polynomial degree `d` of the three splines (at least 1).
    pub degree: usize,
    /// Smoothness `r` the source's conditions enforce across interior edges (`C^r`), for each
    /// of the three splines.
    pub smoothness: usize,
    /// The reference mesh's vertices, exact.
    pub vertices: Vec<[Rational; 2]>,
    /// The reference mesh's triangles (vertex indices, as the source numbers them).
    pub triangles: Vec<[usize; 3]>,
    /// Per triangle, the parameters (of dimension 1: heights) holding the control values of
    /// `σ0`, the bottom surface, in the multi-index order of [`BezierTriangles::patches`];
    /// shared control points are the same parameter in every patch.
    pub bottom: Vec<Vec<ParamId>>,
    /// Per triangle, the parameters (of dimension 1) of `σ1`, the top surface, in the same
    /// order.
    pub top: Vec<Vec<ParamId>>,
    /// Per triangle, the parameters (of dimension 2: points) of `φ`, the horizontal map, in the
    /// same order, when the source edits it; `None` when `φ` is the identity (no parameters).
    #[serde(default)]
    pub xy: Option<Vec<Vec<ParamId>>>,
    /// `a`: the bottom of the reference layer of prisms, exact.
    pub reference_bottom: Rational,
    /// `b`: the top of the reference layer (`a < b`), exact.
    pub reference_top: Rational,
    /// The models the outputs named in [`ViewRequest::outputs`] deform, in the order of the
    /// outputs (none when the request names no outputs), each vertex with its embedding and
    /// its relative height ([`ViewModel::relative_height`]).
    #[serde(default)]
    pub models: Vec<ViewModel>,
}

/// A model an output of the source deforms, placed in the reference mesh, for drawing: the
/// image of vertex `v` with embedding `(t, β)` is, in a [`BezierTriangles`] view, the value of
/// patch `t` at `β` (the formula at [`BezierTriangles`]), `z` unchanged, and in a [`Prisms`]
/// view `ψ` of the vertex (the formula at [`Prisms`], with `α` its relative height); a vertex
/// without an embedding stays where it is, as in the deformed model the output renders.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ViewModel {
    /// The model file as the output names it (relative to the run file, as written).
    pub name: String,
    /// Its vertices as read, `(x, y, z)` in file order (`z` is 0 for a planar model). Floats:
    /// for drawing only.
    pub vertices: Vec<[f64; 3]>,
    /// Its faces, as vertex indices (0-based) into [`ViewModel::vertices`], each of at least 3
    /// vertices; none for a point cloud. A source gives the faces its rendered model has
    /// (spline2d and terrain: the file's polygons fan-triangulated from their first corner;
    /// terrain's height fields: two triangles per grid cell, as its deformed OBJ writes them).
    pub faces: Vec<Vec<u32>>,
    /// Per vertex: the reference triangle it lies in (an index into the view's `triangles`)
    /// and its barycentric coordinates there (weights on the triangle's first, second and
    /// third vertex, summing to 1), exactly where the source's render evaluates the
    /// deformation; `None` for a vertex the deformation leaves in place: outside the mesh, and
    /// in a [`Prisms`] view also outside the layer in `z`.
    pub embedding: Vec<Option<(u32, [f64; 3])>>,
    /// Per vertex, in a [`Prisms`] view: its relative height in the reference layer,
    /// `α = (z − a)/(b − a)` (`a`, `b` the view's `reference_bottom` and `reference_top` in
    /// `f64`, as the render computes it), the weight of the top surface in the vertex's image.
    /// Empty in a [`BezierTriangles`] view, which has no layer; a [`Prisms`] view may leave it
    /// empty too, and an editor then computes `α` from `z` by the same formula. Absent from the
    /// JSON when empty (and read as empty), so planar views serialise as before it existed.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub relative_height: Vec<f64>,
}

impl SourceView {
    /// Checks a view against the system before a host uses it (a plugin's answer is outside
    /// data): indices in range, every patch complete, every point a parameter of the dimension
    /// its role needs, the models well formed ([`BezierTriangles`] and [`Prisms`] say what
    /// each kind requires).
    pub fn validate(&self, system: &ConstraintSystem) -> Result<(), String> {
        match self {
            SourceView::BezierTriangles(view) => view.validate(system),
            SourceView::Prisms(view) => view.validate(system),
        }
    }

    /// The models the view carries, whatever its kind.
    pub fn models(&self) -> &[ViewModel] {
        match self {
            SourceView::BezierTriangles(view) => &view.models,
            SourceView::Prisms(view) => &view.models,
        }
    }

    /// The models the view carries, to change (a conformance check compares views without
    /// them).
    pub fn models_mut(&mut self) -> &mut Vec<ViewModel> {
        match self {
            SourceView::BezierTriangles(view) => &mut view.models,
            SourceView::Prisms(view) => &mut view.models,
        }
    }
}

/// Control points per patch of degree `d`: `(d + 1)(d + 2) / 2`.
fn points_per_patch(degree: usize) -> usize {
    (degree + 1) * (degree + 2) / 2
}

/// The degree between 1 and [`MAX_VIEW_DEGREE`].
fn check_degree(degree: usize) -> Result<(), String> {
    if !(1..=MAX_VIEW_DEGREE).contains(&degree) {
        return Err(format!(
            "the view's degree {degree} is not between 1 and {MAX_VIEW_DEGREE}"
        ));
    }
    Ok(())
}

/// Every triangle's corners among the `vertices` vertices.
fn check_triangles(vertices: usize, triangles: &[[usize; 3]]) -> Result<(), String> {
    if let Some((t, tri)) = triangles
        .iter()
        .enumerate()
        .find(|(_, tri)| tri.iter().any(|&v| v >= vertices))
    {
        return Err(format!(
            "the view's triangle {t} {tri:?} names a vertex beyond its {vertices}"
        ));
    }
    Ok(())
}

/// One spline's patches of a view: one per triangle, each of the degree's count of control
/// points, each a parameter of the system of dimension `dim`. `surface` names the spline in
/// the messages (`""` for a view with one spline, else `"bottom "`, `"top "`, `"xy "`).
fn check_patches(
    surface: &str,
    patches: &[Vec<ParamId>],
    triangles: usize,
    degree: usize,
    dim: usize,
    system: &ConstraintSystem,
) -> Result<(), String> {
    if patches.len() != triangles {
        return Err(format!(
            "the view has {} {surface}patches for {triangles} triangles",
            patches.len()
        ));
    }
    let expected = points_per_patch(degree);
    let role = if dim == 2 { "a point" } else { "a height" };
    for (t, patch) in patches.iter().enumerate() {
        if patch.len() != expected {
            return Err(format!(
                "the view's {surface}patch {t} has {} control points, degree {degree} needs {expected}",
                patch.len()
            ));
        }
        for id in patch {
            match system.param(*id) {
                None => {
                    return Err(format!(
                        "the view's {surface}patch {t} names parameter {id}, which does not exist"
                    ))
                }
                Some(p) if p.dim != dim => {
                    return Err(format!(
                        "the view's {surface}patch {t} names {:?} of dimension {}, not {role}",
                        p.name, p.dim
                    ))
                }
                Some(_) => {}
            }
        }
    }
    Ok(())
}

/// Whether a view's models carry relative heights ([`ViewModel::relative_height`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Heights {
    /// A planar view: none.
    None,
    /// A view of prisms: none or one per vertex.
    PerVertex,
}

/// The models' part of a view's validation: the vertex bound first (before anything is
/// walked), then per model one embedding per vertex, faces of at least 3 vertices in range,
/// triangles (of the view's `triangles`) in range, finite coordinates, and relative heights
/// as `heights` allows, finite.
fn validate_models(models: &[ViewModel], triangles: usize, heights: Heights) -> Result<(), String> {
    let total = models
        .iter()
        .try_fold(0usize, |sum, m| sum.checked_add(m.vertices.len()))
        .filter(|&total| total <= MAX_VIEW_MODEL_VERTICES);
    if total.is_none() {
        return Err(format!(
            "the view's models have more than {MAX_VIEW_MODEL_VERTICES} vertices in total"
        ));
    }
    for (m, model) in models.iter().enumerate() {
        let what = format!("the view's model {m} ({:?})", model.name);
        let vertices = model.vertices.len();
        if model.embedding.len() != vertices {
            return Err(format!(
                "{what} has {} embedding entries for {vertices} vertices",
                model.embedding.len()
            ));
        }
        let relative = model.relative_height.len();
        match heights {
            Heights::None if relative != 0 => {
                return Err(format!(
                    "{what} has {relative} relative heights, which a planar view does not have"
                ))
            }
            Heights::PerVertex if relative != 0 && relative != vertices => {
                return Err(format!(
                    "{what} has {relative} relative heights for {vertices} vertices"
                ))
            }
            _ => {}
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
        if let Some(v) = model.relative_height.iter().position(|a| !a.is_finite()) {
            return Err(format!(
                "{what}: vertex {v} has a relative height that is not finite"
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

impl BezierTriangles {
    /// Control points per patch: `(d + 1)(d + 2) / 2`.
    pub fn points_per_patch(&self) -> usize {
        points_per_patch(self.degree)
    }

    /// The degree in range, triangles in range, one complete patch per triangle of points
    /// (parameters of dimension 2), and the models ([`validate_models`], without relative
    /// heights).
    fn validate(&self, system: &ConstraintSystem) -> Result<(), String> {
        check_degree(self.degree)?;
        check_triangles(self.vertices.len(), &self.triangles)?;
        check_patches(
            "",
            &self.patches,
            self.triangles.len(),
            self.degree,
            2,
            system,
        )?;
        validate_models(&self.models, self.triangles.len(), Heights::None)
    }
}

impl Prisms {
    /// Control points per patch of each surface: `(d + 1)(d + 2) / 2`.
    pub fn points_per_patch(&self) -> usize {
        points_per_patch(self.degree)
    }

    /// The degree in range, triangles in range, per triangle a complete patch of each surface
    /// (`bottom` and `top` of heights, parameters of dimension 1; `xy`, if any, of points, of
    /// dimension 2), a layer with `a < b`, and the models ([`validate_models`], with none or
    /// one relative height per vertex).
    fn validate(&self, system: &ConstraintSystem) -> Result<(), String> {
        check_degree(self.degree)?;
        check_triangles(self.vertices.len(), &self.triangles)?;
        let triangles = self.triangles.len();
        check_patches("bottom ", &self.bottom, triangles, self.degree, 1, system)?;
        check_patches("top ", &self.top, triangles, self.degree, 1, system)?;
        if let Some(xy) = &self.xy {
            check_patches("xy ", xy, triangles, self.degree, 2, system)?;
        }
        if self.reference_bottom >= self.reference_top {
            return Err(format!(
                "the view's reference layer is empty: its bottom {} is not below its top {}",
                crate::exact::format_rational(&self.reference_bottom),
                crate::exact::format_rational(&self.reference_top)
            ));
        }
        validate_models(&self.models, triangles, Heights::PerVertex)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Models collected for a view: the vertex budget is counted before placing, indices
    /// become the view's, unplaced vertices stay `None`.
    #[test]
    fn view_models_count_their_vertices_and_index_their_faces() {
        let mut models = ViewModels::default();
        models.reserve(3).expect("within the budget");
        models
            .push(
                "m.obj".into(),
                vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
                &[[0, 1, 2]],
                [Some((0, [1.0, 0.0, 0.0])), None, Some((7, [0.0, 0.5, 0.5]))],
                Vec::new(),
            )
            .expect("pushed");
        let error = models
            .reserve(MAX_VIEW_MODEL_VERTICES)
            .expect_err("over the budget");
        assert!(error.contains("above 4000000 vertices"), "{error}");
        let mut wide = ViewModels::default();
        let error = wide
            .push(
                "w.obj".into(),
                Vec::new(),
                &[[0, 1, usize::MAX]],
                [],
                Vec::new(),
            )
            .expect_err("index too large");
        assert!(error.contains("does not fit a view's index"), "{error}");
        let models = models.into_models();
        assert_eq!(models[0].faces, vec![vec![0, 1, 2]]);
        assert_eq!(models[0].embedding[1], None);
        assert_eq!(models[0].embedding[2], Some((7, [0.0, 0.5, 0.5])));
    }

    fn system() -> (ConstraintSystem, Vec<ParamId>) {
        let mut s = ConstraintSystem::new();
        let points = (0..3)
            .map(|i| s.add_parameter(format!("v{i}"), 2).expect("fresh"))
            .collect();
        s.add_parameter("h", 1).expect("fresh");
        (s, points)
    }

    fn q(n: i64) -> Rational {
        Rational::from_integer(n.into())
    }

    fn bezier(patches: Vec<Vec<ParamId>>) -> BezierTriangles {
        BezierTriangles {
            degree: 1,
            smoothness: 0,
            vertices: vec![[q(0), q(0)], [q(1), q(0)], [q(0), q(1)]],
            triangles: vec![[0, 1, 2]],
            patches,
            models: Vec::new(),
        }
    }

    fn view(patches: Vec<Vec<ParamId>>) -> SourceView {
        SourceView::BezierTriangles(bezier(patches))
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
            relative_height: Vec::new(),
        }
    }

    /// The view with `model` changed by `change`, validated.
    fn with_model(change: impl FnOnce(&mut ViewModel)) -> Result<(), String> {
        let (s, p) = system();
        let mut v = bezier(vec![p]);
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
        let mut bad = bezier(vec![p.clone()]);
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
        let mut v = bezier(vec![p]);
        let half = MAX_VIEW_MODEL_VERTICES / 2;
        let big = ViewModel {
            name: "big.obj".into(),
            vertices: vec![[0.0; 3]; half],
            faces: Vec::new(),
            embedding: vec![None; half],
            relative_height: Vec::new(),
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
        let mut v = bezier(vec![p]);
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
        // A planar model has no relative heights, and its JSON does not mention them.
        assert!(!text.contains("relative_height"), "{text}");
    }

    #[test]
    fn degrees_out_of_range_are_refused() {
        let (s, p) = system();
        for degree in [0, MAX_VIEW_DEGREE + 1] {
            let mut v = bezier(vec![p.clone()]);
            v.degree = degree;
            let e = SourceView::BezierTriangles(v)
                .validate(&s)
                .expect_err("degree");
            assert!(
                e.contains(&format!(
                    "degree {degree} is not between 1 and {MAX_VIEW_DEGREE}"
                )),
                "{e}"
            );
        }
    }

    #[test]
    fn a_planar_model_with_relative_heights_is_refused() {
        let e = with_model(|m| m.relative_height = vec![0.5; 4]).expect_err("heights");
        assert!(
            e.contains("has 4 relative heights, which a planar view does not have"),
            "{e}"
        );
    }

    /// A system for a degree-1 prism view over one triangle: three heights of the bottom
    /// (`b0..b2`), three of the top (`t0..t2`) and three points of `φ` (`p0..p2`).
    struct PrismSystem {
        system: ConstraintSystem,
        bottom: Vec<ParamId>,
        top: Vec<ParamId>,
        xy: Vec<ParamId>,
    }

    fn prism_system() -> PrismSystem {
        let mut system = ConstraintSystem::new();
        let mut add = |prefix: &str, dim: usize| -> Vec<ParamId> {
            (0..3)
                .map(|i| {
                    system
                        .add_parameter(format!("{prefix}{i}"), dim)
                        .expect("fresh")
                })
                .collect()
        };
        let (bottom, top, xy) = (add("b", 1), add("t", 1), add("p", 2));
        PrismSystem {
            system,
            bottom,
            top,
            xy,
        }
    }

    /// A unit triangle's prisms between -20 and 20, `φ` edited, with `model()` placed and
    /// its relative heights.
    fn prisms(s: &PrismSystem) -> Prisms {
        let mut placed = model();
        placed.relative_height = placed
            .vertices
            .iter()
            .map(|v| (v[2] + 20.0) / 40.0)
            .collect();
        Prisms {
            degree: 1,
            smoothness: 0,
            vertices: vec![[q(0), q(0)], [q(1), q(0)], [q(0), q(1)]],
            triangles: vec![[0, 1, 2]],
            bottom: vec![s.bottom.clone()],
            top: vec![s.top.clone()],
            xy: Some(vec![s.xy.clone()]),
            reference_bottom: q(-20),
            reference_top: q(20),
            models: vec![placed],
        }
    }

    /// The prism view changed by `change`, validated.
    fn with_prisms(change: impl FnOnce(&mut Prisms, &PrismSystem)) -> Result<(), String> {
        let s = prism_system();
        let mut v = prisms(&s);
        change(&mut v, &s);
        SourceView::Prisms(v).validate(&s.system)
    }

    #[test]
    fn a_complete_prism_view_passes() {
        assert_eq!(with_prisms(|_, _| {}), Ok(()));
        // φ the identity, no models, models without relative heights: all fine.
        assert_eq!(with_prisms(|v, _| v.xy = None), Ok(()));
        assert_eq!(with_prisms(|v, _| v.models.clear()), Ok(()));
        assert_eq!(
            with_prisms(|v, _| v.models[0].relative_height.clear()),
            Ok(())
        );
        // Relative heights outside [0, 1] are the source's business (vertices left in place
        // have no embedding); they only need to be finite.
        assert_eq!(
            with_prisms(|v, _| v.models[0].relative_height[3] = 7.5),
            Ok(())
        );
    }

    #[test]
    fn a_prism_view_of_a_bad_degree_is_refused() {
        let e = with_prisms(|v, _| v.degree = 0).expect_err("degree 0");
        assert!(e.contains("degree 0 is not between 1 and 64"), "{e}");
    }

    #[test]
    fn a_prism_view_with_a_triangle_beyond_its_vertices_is_refused() {
        let e = with_prisms(|v, _| v.triangles[0] = [0, 3, 2]).expect_err("vertex");
        assert!(
            e.contains("triangle 0 [0, 3, 2] names a vertex beyond its 3"),
            "{e}"
        );
    }

    #[test]
    fn a_missing_bottom_top_or_xy_patch_is_refused() {
        let e = with_prisms(|v, _| v.bottom.clear()).expect_err("bottom");
        assert!(e.contains("has 0 bottom patches for 1 triangles"), "{e}");
        let e = with_prisms(|v, s| v.top.push(s.top.clone())).expect_err("top");
        assert!(e.contains("has 2 top patches for 1 triangles"), "{e}");
        let e = with_prisms(|v, _| v.xy = Some(Vec::new())).expect_err("xy");
        assert!(e.contains("has 0 xy patches for 1 triangles"), "{e}");
    }

    #[test]
    fn an_incomplete_patch_of_a_surface_is_refused() {
        let e = with_prisms(|v, _| {
            v.top[0].pop();
        })
        .expect_err("short");
        assert!(
            e.contains("top patch 0 has 2 control points, degree 1 needs 3"),
            "{e}"
        );
        let e = with_prisms(|v, s| v.bottom[0].push(s.bottom[0])).expect_err("long");
        assert!(
            e.contains("bottom patch 0 has 4 control points, degree 1 needs 3"),
            "{e}"
        );
    }

    #[test]
    fn a_height_that_is_a_point_is_refused() {
        let e = with_prisms(|v, s| v.bottom[0][1] = s.xy[0]).expect_err("bottom point");
        assert!(
            e.contains("bottom patch 0 names \"p0\" of dimension 2, not a height"),
            "{e}"
        );
        let e = with_prisms(|v, s| v.top[0][2] = s.xy[1]).expect_err("top point");
        assert!(
            e.contains("top patch 0 names \"p1\" of dimension 2, not a height"),
            "{e}"
        );
    }

    #[test]
    fn a_point_of_phi_that_is_a_height_is_refused() {
        let e = with_prisms(|v, s| {
            if let Some(xy) = v.xy.as_mut() {
                xy[0][0] = s.top[0];
            }
        })
        .expect_err("xy height");
        assert!(
            e.contains("xy patch 0 names \"t0\" of dimension 1, not a point"),
            "{e}"
        );
    }

    #[test]
    fn a_surface_naming_a_missing_parameter_is_refused() {
        let e = with_prisms(|v, _| v.top[0][0] = ParamId(99)).expect_err("missing");
        assert!(
            e.contains("top patch 0 names parameter #99, which does not exist"),
            "{e}"
        );
    }

    #[test]
    fn an_empty_reference_layer_is_refused() {
        let e = with_prisms(|v, _| v.reference_top = q(-20)).expect_err("flat");
        assert!(
            e.contains("reference layer is empty: its bottom -20 is not below its top -20"),
            "{e}"
        );
        let e = with_prisms(|v, _| {
            std::mem::swap(&mut v.reference_bottom, &mut v.reference_top);
        })
        .expect_err("upside down");
        assert!(e.contains("its bottom 20 is not below its top -20"), "{e}");
    }

    #[test]
    fn relative_heights_of_the_wrong_count_are_refused() {
        let e = with_prisms(|v, _| {
            v.models[0].relative_height.pop();
        })
        .expect_err("count");
        assert!(
            e.contains("model 0 (\"models/square.obj\") has 3 relative heights for 4 vertices"),
            "{e}"
        );
    }

    #[test]
    fn relative_heights_that_are_not_finite_are_refused() {
        let e = with_prisms(|v, _| v.models[0].relative_height[2] = f64::INFINITY)
            .expect_err("infinite");
        assert!(
            e.contains("vertex 2 has a relative height that is not finite"),
            "{e}"
        );
    }

    #[test]
    fn prism_models_are_checked_as_planar_ones() {
        let e = with_prisms(|v, _| v.models[0].embedding[1] = Some((1, [0.5, 0.5, 0.0])))
            .expect_err("triangle");
        assert!(
            e.contains("vertex 1 lies in triangle 1, beyond the view's 1"),
            "{e}"
        );
        let e = with_prisms(|v, _| {
            v.models[0].embedding.pop();
        })
        .expect_err("embedding");
        assert!(e.contains("has 3 embedding entries for 4 vertices"), "{e}");
        let e = with_prisms(|v, _| v.models[0].faces[0] = vec![0, 1]).expect_err("face");
        assert!(e.contains("face 0 has 2 vertices"), "{e}");
        let e = with_prisms(|v, _| v.models[0].vertices[0][2] = f64::NAN).expect_err("nan");
        assert!(
            e.contains("vertex 0 has a coordinate that is not finite"),
            "{e}"
        );
    }

    #[test]
    fn prism_views_round_trip_through_json_and_models_and_xy_may_be_absent() {
        let s = prism_system();
        let v = SourceView::Prisms(prisms(&s));
        let text = serde_json::to_string(&v).expect("serialise");
        assert!(text.contains("\"kind\":\"prisms\""), "{text}");
        assert!(
            text.contains("\"relative_height\":[0.5,0.525,0.5,0.5]"),
            "{text}"
        );
        assert_eq!(serde_json::from_str::<SourceView>(&text).expect("parse"), v);
        assert_eq!(v.models().len(), 1);
        let mut plain = v.clone();
        plain.models_mut().clear();
        let SourceView::Prisms(mut identity) = plain.clone() else {
            panic!("a prism view")
        };
        identity.xy = None;
        let mut json = serde_json::to_value(SourceView::Prisms(identity.clone())).expect("json");
        let object = json.as_object_mut().expect("an object");
        object.remove("models");
        object.remove("xy");
        assert_eq!(
            serde_json::from_value::<SourceView>(json).expect("parse"),
            SourceView::Prisms(identity)
        );
    }
}
