//! A `[[rod]]` end as the designer writes it: a named feature of a
//! primitive (a corner, or a point along an edge) or, in old files, a
//! bare design-frame point. Names are the truth: the point is resolved
//! from the primitive's current size, position and rotation every time
//! the kite is assembled ([`crate::geometry::rod_ends`]), so a rod
//! follows its primitive when the TUI or the optimiser moves, turns or
//! scales it. This module only parses the name into *unit-box
//! coordinates* (each component in `[-1, 1]`, the primitive's local
//! frame divided by its half-size); [`crate::geometry::point_on`] is the
//! one owner of the step from there to the design frame.
//!
//! Syntax (documented in `data/kites/README.md`):
//! `{ primitive = "lead", corner = "+x-y+z" }` — the corner at those
//! signs of the primitive's local axes; `{ primitive = "port", edge =
//! "+x+y", at = 0.25 }` — the edge along the remaining axis (here z) at
//! those signs, `at` the fraction along it from its `-` end (default
//! 0.5). An axis along which the primitive has no extent (a plate's z)
//! may be left out. Objects use their bounding box `size`.

use anyhow::{bail, Result};
use nalgebra::Vector3;
use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::fmt;

/// One end of a `[[rod]]`.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum RodEnd {
    /// Old form: a design-frame point, m; it joins whatever primitive
    /// frame it lies on (within [`crate::connect::CONTACT`]).
    Point([f64; 3]),
    /// A named corner or edge point of a primitive.
    On(Feature),
}

/// `{ primitive = "...", corner = "..." }` or `{ primitive = "...",
/// edge = "...", at = ... }`.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Feature {
    /// The primitive's `name`.
    pub primitive: String,
    /// Signs of the local axes, e.g. `"+x-y+z"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub corner: Option<String>,
    /// Signs of two local axes, e.g. `"+x+y"`: the edge along the third.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub edge: Option<String>,
    /// Edges only: fraction along the edge from its `-` end, 0..1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at: Option<f64>,
}

impl RodEnd {
    /// The primitive this end names (`None` for a bare point).
    pub fn primitive(&self) -> Option<&str> {
        match self {
            Self::Point(_) => None,
            Self::On(f) => Some(&f.primitive),
        }
    }

    /// How a builder reads it: `lead +x-y+z`, `port edge +x+y at 0.25`,
    /// or the point in mm.
    pub fn describe(&self) -> String {
        match self {
            Self::Point(p) => format!(
                "({:.0}, {:.0}, {:.0}) mm",
                p[0] * 1e3,
                p[1] * 1e3,
                p[2] * 1e3
            ),
            Self::On(f) => match (&f.corner, &f.edge) {
                (Some(c), _) => format!("{} {c}", f.primitive),
                (None, Some(e)) => {
                    format!("{} edge {e} at {:.2}", f.primitive, f.at.unwrap_or(0.5))
                }
                (None, None) => f.primitive.clone(),
            },
        }
    }
}

impl Feature {
    /// The named point in unit-box coordinates of a primitive of `size`
    /// (each component in `[-1, 1]`). Errors name the field under `at`
    /// (e.g. `rod[2].from.corner`).
    pub fn unit(&self, size: &[f64; 3], field: &str) -> Result<Vector3<f64>> {
        let flat = size.map(|l| l <= 0.0);
        match (&self.corner, &self.edge) {
            (Some(_), Some(_)) => bail!("{field}: give `corner` or `edge`, not both"),
            (None, None) => bail!("{field}: name a `corner` (e.g. \"+x-y+z\") or an `edge` (e.g. \"+x+y\", with `at`)"),
            (Some(c), None) => {
                if self.at.is_some() {
                    bail!("{field}.at: only an edge takes `at`");
                }
                let signs = parse_signs(c).map_err(|e| anyhow::anyhow!("{field}.corner: {e}"))?;
                if let Some(k) = (0..3).find(|&k| signs[k] == 0.0 && !flat[k]) {
                    bail!("{field}.corner: {c:?} gives no sign for {} (a corner names all three axes; only an axis of zero size may be left out)", AXES[k]);
                }
                Ok(Vector3::from(signs))
            }
            (None, Some(e)) => {
                let mut signs =
                    parse_signs(e).map_err(|err| anyhow::anyhow!("{field}.edge: {err}"))?;
                let free: Vec<usize> = (0..3).filter(|&k| signs[k] == 0.0 && !flat[k]).collect();
                let [k] = free[..] else {
                    bail!("{field}.edge: {e:?} must leave exactly one axis of the primitive free (the one the edge runs along), e.g. \"+x+y\" for an edge along z");
                };
                let t = self.at.unwrap_or(0.5);
                if !(0.0..=1.0).contains(&t) {
                    bail!("{field}.at: must be between 0 and 1 (got {t})");
                }
                signs[k] = 2.0 * t - 1.0;
                Ok(Vector3::from(signs))
            }
        }
    }
}

const AXES: [char; 3] = ['x', 'y', 'z'];

/// `"+x-y+z"` -> `[1, -1, 1]`; an axis not named is 0. Each axis at most
/// once, each with its sign.
fn parse_signs(text: &str) -> std::result::Result<[f64; 3], String> {
    let mut out = [0.0; 3];
    let mut chars = text.chars().filter(|c| !c.is_whitespace());
    while let Some(sign) = chars.next() {
        let s = match sign {
            '+' => 1.0,
            '-' => -1.0,
            other => {
                return Err(format!(
                    "{text:?}: expected + or - before an axis, found {other:?}"
                ))
            }
        };
        let axis = chars
            .next()
            .and_then(|a| AXES.iter().position(|&x| x == a.to_ascii_lowercase()));
        let Some(k) = axis else {
            return Err(format!("{text:?}: expected x, y or z after the sign"));
        };
        if out[k] != 0.0 {
            return Err(format!("{text:?}: axis {} given twice", AXES[k]));
        }
        out[k] = s;
    }
    if out == [0.0; 3] {
        return Err(format!("{text:?}: name signed axes, e.g. \"+x-y+z\""));
    }
    Ok(out)
}

/// An array is a point, a table a named feature; anything else is an
/// error saying which two forms are meant.
impl<'de> Deserialize<'de> for RodEnd {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct EndVisitor;
        impl<'de> Visitor<'de> for EndVisitor {
            type Value = RodEnd;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a table { primitive = \"name\", corner = \"+x-y+z\" } (or edge = \"+x+y\", at = 0.5), or an old-style point [x, y, z]")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> std::result::Result<RodEnd, A::Error> {
                <[f64; 3]>::deserialize(de::value::SeqAccessDeserializer::new(seq))
                    .map(RodEnd::Point)
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> std::result::Result<RodEnd, A::Error> {
                Feature::deserialize(de::value::MapAccessDeserializer::new(map)).map(RodEnd::On)
            }
        }
        d.deserialize_any(EndVisitor)
    }
}
