//! The primitive library (§7, Fig. 10-left): example coefficient sets of
//! boxes and plates at several normalised dimensions, and blending of any
//! box from them by normalised inverse-distance weights.
//!
//! Normalised dimension space: `n = (l_x, l_y, l_z) / |l|` with `l_y > 0`,
//! `l_x >= l_z >= 0` (1/8 of the unit hemisphere); plates are `l_z = 0`.
//! Shapes with no covered area (`l_y = 0`, or `l_x = l_z = 0`) are
//! implicit examples with all-zero coefficients ([`ZERO_EXAMPLES`]).

use anyhow::{bail, Context, Result};
use nalgebra::{Matrix3, Vector3};
use omniad_core::Coefficients;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Name of the index file in a library directory.
pub const INDEX: &str = "library.toml";

/// Normalised dimensions of shapes with no area (all coefficients zero):
/// the `l_y = 0` arc from `(1,0,0)` to `(1,0,1)/√2`, and `(0,1,0)`.
pub const ZERO_EXAMPLES: [[f64; 3]; 5] = [
    [1.0, 0.0, 0.0],
    [0.965_925_826_289_068_3, 0.0, 0.258_819_045_102_521],
    [0.866_025_403_784_438_6, 0.0, 0.5],
    [
        std::f64::consts::FRAC_1_SQRT_2,
        0.0,
        std::f64::consts::FRAC_1_SQRT_2,
    ],
    [0.0, 1.0, 0.0],
];

/// Inverse-distance power of the blending weights (`w ∝ 1/d^p`).
pub const IDW_POWER: f64 = 2.0;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct IndexFile {
    #[serde(rename = "example")]
    examples: Vec<IndexEntry>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct IndexEntry {
    file: PathBuf,
    size: [f64; 3],
}

/// One example: its normalised dimensions and coefficients.
#[derive(Clone, Debug)]
pub struct Example {
    /// `(l_x, l_y, l_z)/|l|`.
    pub normalised: Vector3<f64>,
    /// The coefficients (non-dimensional; L is the example's own).
    pub coefficients: Coefficients<f64>,
    /// Where it was loaded from.
    pub file: PathBuf,
}

/// The loaded library.
#[derive(Clone, Debug)]
pub struct Library {
    /// The measured (or projected) examples.
    pub examples: Vec<Example>,
    /// Common SH degree of the force.
    pub degree: u8,
    /// Common SH degree of the torque (its own, N_T).
    pub torque_degree: u8,
    /// Common pole (primitive frame).
    pub pole: Vector3<f64>,
}

/// The library directory: `$OMNIAD_PRIMITIVES`, else the repository's
/// `data/primitives`.
pub fn default_dir() -> PathBuf {
    std::env::var_os("OMNIAD_PRIMITIVES")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/primitives"))
}

/// `size / |size|`, or `None` for a zero size.
pub fn normalise(size: &[f64; 3]) -> Option<Vector3<f64>> {
    let v = Vector3::from(*size);
    let n = v.norm();
    (n > 0.0 && n.is_finite()).then(|| v / n)
}

impl Library {
    /// Loads `dir/library.toml` and the `.omni` files it lists.
    pub fn load(dir: &Path) -> Result<Self> {
        let index_path = dir.join(INDEX);
        let text = std::fs::read_to_string(&index_path).with_context(|| {
            format!(
                "cannot read primitive library index {}",
                index_path.display()
            )
        })?;
        let index: IndexFile =
            toml::from_str(&text).with_context(|| format!("in {}", index_path.display()))?;
        let mut examples = Vec::new();
        for (i, e) in index.examples.iter().enumerate() {
            let path = dir.join(&e.file);
            let normalised = normalise(&e.size).with_context(|| {
                format!(
                    "{}: example[{i}].size must not be zero",
                    index_path.display()
                )
            })?;
            let bytes =
                std::fs::read(&path).with_context(|| format!("cannot read {}", path.display()))?;
            let coefficients = omniad_core::file::decode::<f64>(&bytes)
                .map_err(|err| anyhow::anyhow!("{}: {err}", path.display()))?;
            examples.push(Example {
                normalised,
                coefficients,
                file: path,
            });
        }
        Self::from_examples(examples)
    }

    /// A library from examples, which must share degrees (N and N_T) and
    /// pole.
    pub fn from_examples(examples: Vec<Example>) -> Result<Self> {
        let Some(first) = examples.first() else {
            bail!("primitive library has no examples");
        };
        let degree = first.coefficients.degree();
        let torque_degree = first.coefficients.torque_degree();
        let pole = first.coefficients.pole();
        for e in &examples {
            let c = &e.coefficients;
            if c.degree() != degree
                || c.torque_degree() != torque_degree
                || (c.pole() - pole).norm() > 1e-9
            {
                bail!(
                    "{}: degree/torque degree/pole differ from the first example; examples must share them",
                    e.file.display()
                );
            }
        }
        Ok(Self {
            examples,
            degree,
            torque_degree,
            pole,
        })
    }

    /// Blending weights `(example index or None for a zero example, w)`,
    /// normalised to sum 1, for the normalised dimensions `n`.
    pub fn weights(&self, n: &Vector3<f64>) -> Vec<(Option<usize>, f64)> {
        let points = self
            .examples
            .iter()
            .enumerate()
            .map(|(i, e)| (Some(i), e.normalised))
            .chain(ZERO_EXAMPLES.iter().map(|z| (None, Vector3::from(*z))));
        let dist: Vec<(Option<usize>, f64)> = points.map(|(i, p)| (i, (p - n).norm())).collect();
        if let Some(&(i, _)) = dist.iter().find(|(_, d)| *d < 1e-9) {
            return vec![(i, 1.0)];
        }
        let raw: Vec<(Option<usize>, f64)> =
            dist.iter().map(|&(i, d)| (i, d.powf(-IDW_POWER))).collect();
        let total: f64 = raw.iter().map(|(_, w)| w).sum();
        raw.into_iter().map(|(i, w)| (i, w / total)).collect()
    }

    /// Coefficients of a box or plate of size `[l_x, l_y, l_z]` (m):
    /// the weighted sum of the examples' alpha, beta and D, with
    /// `L = |l|` (the bounding-box diagonal).
    pub fn blend(&self, size: &[f64; 3], name: &str) -> Result<Coefficients<f64>> {
        let n = normalise(size).context("primitive size is zero")?;
        let mut out = Coefficients::zeros(self.degree, self.pole, Vector3::from(*size).norm())
            .and_then(|m| m.with_torque_degree(self.torque_degree))
            .map_err(|e| anyhow::anyhow!("blend: {e}"))?;
        let count = out.coeff_count().max(out.torque_coeff_count());
        let mut damping = Matrix3::zeros();
        for (i, w) in self.weights(&n) {
            let Some(e) = i.and_then(|i| self.examples.get(i)) else {
                continue;
            };
            let c = &e.coefficients;
            for comp in 0..3 {
                for k in 0..count {
                    if let Some(a) = out.alpha(comp, k) {
                        let a = a + w * c.alpha(comp, k).unwrap_or(0.0);
                        out.set_alpha(comp, k, a)
                            .map_err(|e| anyhow::anyhow!("blend: {e}"))?;
                    }
                    if let Some(b) = out.beta(comp, k) {
                        let b = b + w * c.beta(comp, k).unwrap_or(0.0);
                        out.set_beta(comp, k, b)
                            .map_err(|e| anyhow::anyhow!("blend: {e}"))?;
                    }
                }
            }
            damping += c.damping() * w;
        }
        out.set_damping(&damping)
            .map_err(|e| anyhow::anyhow!("blend: {e}"))?;
        out.set_name(&truncate(name, 60))
            .map_err(|e| anyhow::anyhow!("blend: {e}"))?;
        out.provenance.method = heapless::String::try_from("blend").unwrap_or_default();
        Ok(out)
    }
}

fn truncate(s: &str, n: usize) -> String {
    s.chars().take(n).collect()
}
