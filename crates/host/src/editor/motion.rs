//! What the page asks a source to do with the selected points: a selection (anchors and
//! neighbourhood) and a motion (translate, rotate or scale, thesis 18.5), checked and turned
//! into the source's operation text. Every number is exact decimal or fraction text; nothing
//! from the page reaches the operation unchecked.

use api::{format_rational, parse_rational, Rational};
use serde::{Deserialize, Serialize};

/// The largest number of anchors one request may name.
const MAX_ANCHORS: usize = 1_000;

/// The longest text of a number (a mouse move needs a few digits; this bounds the exact
/// numbers a request can make the session compute with).
const MAX_NUMBER_TEXT: usize = 64;

/// The grid of a rotation's `tan(angle / 2)` and of a scaling's powers (`1/precision`): far
/// below what a mouse can point at, small enough to keep committed values short.
const PRECISION: u64 = 1_000_000;

/// Which points move: the anchors (control point names of `source`, without the source's
/// prefix) and the neighbourhood of derived points (`None`: every point).
#[derive(Debug, Clone, PartialEq, Eq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Selection {
    /// The source whose points move.
    pub source: String,
    /// Point names (`v3`, `e3-7:2`, `t5:2,2,1`).
    pub anchors: Vec<String>,
    /// `δ_max` on the control net; `None` for every point.
    pub neighborhood: Option<u32>,
    /// The surface a terrain source edits: `"xy"` (the horizontal map), `"z0"` (bottom) or
    /// `"z1"` (top); `None` for sources without modes.
    #[serde(default)]
    pub mode: Option<String>,
}

/// How the anchors move since the drag began (thesis 18.5: translate, rotate, scale about a
/// centre).
#[derive(Debug, Clone, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Motion {
    /// By `(dx, dy)`.
    Translate {
        /// Displacement in x.
        dx: String,
        /// Displacement in y.
        dy: String,
    },
    /// About `center` by `degrees`, counter-clockwise.
    Rotate {
        /// Centre of rotation.
        center: [String; 2],
        /// Angle in degrees.
        degrees: String,
    },
    /// About `center` by `factor` (positive).
    Scale {
        /// Centre of scaling.
        center: [String; 2],
        /// Scale factor.
        factor: String,
    },
    /// Up by `dz` (a terrain surface's heights, modes z0 and z1, thesis 18.6).
    Lift {
        /// Height change.
        dz: String,
    },
}

/// One frame of a drag, or its end.
#[derive(Debug, Clone, PartialEq, Eq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DragRequest {
    /// Which points move.
    pub selection: Selection,
    /// How, since the drag began.
    pub motion: Motion,
    /// Commit the exact result (the mouse was released).
    pub commit: bool,
    /// The change criterion over every derived point (Brenner 3.1; least squares unless
    /// named).
    #[serde(default)]
    pub criterion: crate::runfile::MeasureName,
}

/// An exact number from the page, bounded in length and written without an exponent (a short
/// text with one, `9e99999`, would be a number of a third of a million bits).
fn exact(what: &str, text: &str) -> Result<Rational, String> {
    if text.len() > MAX_NUMBER_TEXT {
        return Err(format!(
            "{what} has {} characters, more than {MAX_NUMBER_TEXT}",
            text.len()
        ));
    }
    if text.contains(['e', 'E']) {
        return Err(format!(
            "{what} {text:?}: write it without an exponent (a decimal or a fraction)"
        ));
    }
    parse_rational(text).map_err(|e| format!("{what} {text:?}: {e}"))
}

/// A number as RON text of the source's schema (a string of its exact value).
fn number(what: &str, text: &str) -> Result<String, String> {
    Ok(format!("{:?}", format_rational(&exact(what, text)?)))
}

/// Checks a point name before it goes into the source's operation text.
fn check_point_name(name: &str) -> Result<(), String> {
    let allowed = |c: char| c.is_ascii_alphanumeric() || "-_:,.".contains(c);
    if name.is_empty() || name.len() > 64 || !name.chars().all(allowed) {
        return Err(format!("{name:?} is not a control point name"));
    }
    Ok(())
}

impl Motion {
    /// The coordinates of a motion the sources plan affinely (a translation's `(dx, dy)`, a
    /// lift's `dz`), exact; `None` for a rotation or a scaling.
    pub fn linear_coordinates(&self) -> Result<Option<Vec<Rational>>, String> {
        match self {
            Motion::Translate { dx, dy } => Ok(Some(vec![exact("dx", dx)?, exact("dy", dy)?])),
            Motion::Lift { dz } => Ok(Some(vec![exact("dz", dz)?])),
            _ => Ok(None),
        }
    }

    /// True for a motion that moves nothing: a translation or lift by zero, a rotation by zero
    /// degrees, a scaling by one (numbers that do not parse are not the identity).
    pub fn is_identity(&self) -> bool {
        let is = |what: &str, text: &str, value: i64| {
            exact(what, text).is_ok_and(|q| q == Rational::from_integer(value.into()))
        };
        match self {
            Motion::Translate { dx, dy } => is("dx", dx, 0) && is("dy", dy, 0),
            Motion::Lift { dz } => is("dz", dz, 0),
            Motion::Rotate { degrees, .. } => is("degrees", degrees, 0),
            Motion::Scale { factor, .. } => is("factor", factor, 1),
        }
    }

    /// The motion of the same kind with linear coordinates `coordinates` (see
    /// [`Motion::linear_coordinates`]).
    pub fn with_coordinates(&self, coordinates: &[&str]) -> Option<Motion> {
        match (self, coordinates) {
            (Motion::Translate { .. }, [dx, dy]) => Some(Motion::Translate {
                dx: (*dx).into(),
                dy: (*dy).into(),
            }),
            (Motion::Lift { .. }, [dz]) => Some(Motion::Lift { dz: (*dz).into() }),
            _ => None,
        }
    }
}

impl Selection {
    /// Checks the anchors' count and names (the source is checked by the session).
    pub fn check(&self) -> Result<(), String> {
        if self.anchors.is_empty() || self.anchors.len() > MAX_ANCHORS {
            return Err(format!(
                "a selection needs between 1 and {MAX_ANCHORS} anchors, not {}",
                self.anchors.len()
            ));
        }
        self.anchors.iter().try_for_each(|a| check_point_name(a))
    }

    /// The source's operation (spline2d's schema) moving the selection by `motion` in one
    /// step. Checked names only go in, as RON strings.
    pub fn operation(&self, motion: &Motion) -> Result<String, String> {
        self.check()?;
        let neighborhood = self
            .neighborhood
            .map_or_else(|| "\"all\"".to_string(), |n| n.to_string());
        let anchors: Vec<String> = self.anchors.iter().map(|a| format!("{a:?}")).collect();
        let center = |c: &[String; 2]| -> Result<String, String> {
            Ok(format!(
                "({}, {})",
                number("the centre's x", &c[0])?,
                number("the centre's y", &c[1])?
            ))
        };
        let moved = match motion {
            Motion::Translate { dx, dy } => {
                format!("translate: ({}, {})", number("dx", dx)?, number("dy", dy)?)
            }
            Motion::Rotate { center: c, degrees } => format!(
                "rotate: (center: {}, degrees: {}, precision: {PRECISION})",
                center(c)?,
                number("degrees", degrees)?
            ),
            Motion::Scale { center: c, factor } => format!(
                "scale: (center: {}, factor: {}, precision: {PRECISION})",
                center(c)?,
                number("factor", factor)?
            ),
            Motion::Lift { dz } => format!("dz: {}", number("dz", dz)?),
        };
        let mode = match self.mode.as_deref() {
            None => String::new(),
            Some(m @ ("xy" | "z0" | "z1")) => format!("mode: {m:?}, "),
            Some(other) => return Err(format!("{other:?} is not a mode (xy, z0 or z1)")),
        };
        Ok(format!(
            "({mode}anchors: [{}], neighborhood: {neighborhood}, {moved}, steps: 1)",
            anchors.join(", ")
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn selection(anchors: &[&str]) -> Selection {
        Selection {
            source: "worm".into(),
            anchors: anchors.iter().map(|a| a.to_string()).collect(),
            neighborhood: Some(3),
            mode: None,
        }
    }

    #[test]
    fn motions_become_operations_with_exact_numbers() {
        let s = selection(&["v3", "e0-1:2"]);
        let translate = Motion::Translate {
            dx: "0.50".into(),
            dy: "-1/3".into(),
        };
        assert_eq!(
            s.operation(&translate).expect("translates"),
            r#"(anchors: ["v3", "e0-1:2"], neighborhood: 3, translate: ("1/2", "-1/3"), steps: 1)"#
        );
        let rotate = Motion::Rotate {
            center: ["60".into(), "11.5".into()],
            degrees: "-12.25".into(),
        };
        assert_eq!(
            s.operation(&rotate).expect("rotates"),
            r#"(anchors: ["v3", "e0-1:2"], neighborhood: 3, rotate: (center: ("60", "23/2"), degrees: "-49/4", precision: 1000000), steps: 1)"#
        );
        let all = Selection {
            neighborhood: None,
            ..selection(&["v0"])
        };
        let scale = Motion::Scale {
            center: ["0".into(), "0".into()],
            factor: "1.5".into(),
        };
        assert!(all
            .operation(&scale)
            .expect("scales")
            .contains(r#"neighborhood: "all", scale: (center: ("0", "0"), factor: "3/2""#));
        let terrain = Selection {
            mode: Some("z1".into()),
            ..selection(&["v4"])
        };
        assert_eq!(
            terrain
                .operation(&Motion::Lift { dz: "-2.5".into() })
                .expect("lifts"),
            r#"(mode: "z1", anchors: ["v4"], neighborhood: 3, dz: "-5/2", steps: 1)"#
        );
        let bad = Selection {
            mode: Some("up".into()),
            ..selection(&["v4"])
        };
        assert!(bad.operation(&Motion::Lift { dz: "1".into() }).is_err());
    }

    #[test]
    fn identity_motions_are_recognised_exactly() {
        let t = |dx: &str, dy: &str| Motion::Translate {
            dx: dx.into(),
            dy: dy.into(),
        };
        assert!(t("0", "0/7").is_identity());
        assert!(!t("0", "1/1073741824").is_identity());
        assert!(!t("x", "0").is_identity());
        assert!(Motion::Lift { dz: "0.0".into() }.is_identity());
        let c = ["1".to_string(), "2".to_string()];
        assert!(Motion::Scale {
            center: c.clone(),
            factor: "4/4".into()
        }
        .is_identity());
        assert!(!Motion::Rotate {
            center: c,
            degrees: "0.001".into()
        }
        .is_identity());
    }

    #[test]
    fn bad_names_and_numbers_are_refused_before_any_text_is_made() {
        let translate = |dx: &str| Motion::Translate {
            dx: dx.into(),
            dy: "0".into(),
        };
        for (s, m, why) in [
            (selection(&[]), translate("1"), "between 1 and"),
            (
                selection(&["v3\"]"]),
                translate("1"),
                "not a control point name",
            ),
            (selection(&["v3"]), translate("1x"), "dx"),
            (
                selection(&["v3"]),
                translate(&"1".repeat(65)),
                "65 characters",
            ),
            (
                selection(&["v3"]),
                translate("9e99999"),
                "without an exponent",
            ),
            (
                selection(&["v3"]),
                Motion::Rotate {
                    center: ["0".into(), "nan".into()],
                    degrees: "1".into(),
                },
                "centre's y",
            ),
        ] {
            let error = s.operation(&m).expect_err(why);
            assert!(error.contains(why), "{error}");
        }
    }
}
