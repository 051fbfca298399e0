//! Drawing pictures of a spline deformation with a model, from the public API.

use api::Rational;
use plugins_spline2d::svg::{before_after, Picture};
use spline2d::model::load_model;
use spline2d::spline::Spline;
use std::path::PathBuf;

/// The default input limit.
const LIMIT: u64 = api::input::DEFAULT_MAX_INPUT_BYTES;

fn q(n: i64) -> Rational {
    Rational::from_integer(n.into())
}

/// A model shared with the spline2d library's tests.
fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../spline2d/tests/data")
        .join(name)
}

fn nominal(spline: &Spline) -> Vec<Vec<Rational>> {
    spline.nominals().iter().map(|p| p.to_vec()).collect()
}

#[test]
fn pictures_are_deterministic_and_complete() {
    let spline = Spline::new(spline2d::mesh::grid(2, 10, true), 3, 1).expect("spline");
    let before = nominal(&spline);
    let after: Vec<Vec<Rational>> = before
        .iter()
        .map(|p| {
            let bump = if p[0] > q(5) && p[0] < q(15) && p[1] > q(5) && p[1] < q(15) {
                q(2)
            } else {
                q(0)
            };
            vec![&p[0] + &bump, &p[1] + &bump / q(2)]
        })
        .collect();
    let model = load_model(&data("model_2d_quads.obj"), LIMIT).expect("model");
    let picture = |positions: &[Vec<Rational>]| -> String {
        Picture::new(&spline)
            .positions(positions)
            .control_points(true)
            .control_net(true)
            .anchors(&[0, 5])
            .derived(&[1, 2, 3])
            .conditions(&[0, 3, 7])
            .model(&model, true, true)
            .label(5, "anchor <&> \"A\"")
            .title("edit #1 <drag>")
            .to_svg()
            .expect("svg")
    };
    let svg = picture(&after);
    assert_eq!(svg, picture(&after));
    let n = spline.points().len();
    // control points + 3 derived + 2 anchors + 6 model vertices
    assert_eq!(svg.matches("<circle").count(), n + 3 + 2 + 6);
    assert_eq!(svg.matches("<polygon").count(), 3);
    assert_eq!(
        svg.matches("<polyline").count(),
        spline.topology().edges.len()
    );
    assert!(svg.contains("anchor &lt;&amp;&gt; &quot;A&quot;"));
    assert!(svg.contains("edit #1 &lt;drag&gt;"));
    assert!(!svg.contains("<drag>"));
    assert!(svg.starts_with("<svg ") && svg.ends_with("</svg>\n"));

    let pair = before_after(
        &Picture::new(&spline)
            .positions(&before)
            .control_net(true)
            .anchors(&[0]),
        &Picture::new(&spline)
            .positions(&after)
            .control_net(true)
            .anchors(&[0]),
    )
    .expect("pair");
    assert_eq!(pair.matches("class=\"title\"").count(), 2);
    assert!(pair.contains(">before</text>") && pair.contains(">after</text>"));
    assert_eq!(pair.matches("<circle").count(), 2);
    let example = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("spline2d_before_after.svg");
    std::fs::write(&example, &pair).expect("write example");
    println!("example picture: {}", example.display());
}
