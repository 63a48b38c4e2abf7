//! `kite check`: the static report of §7 — string tension from linear
//! equilibrium (eq. 14), the attachment point on the eq. (16) line, the
//! unbalanced torque (eq. 15), and stability from the eigen-decomposition
//! of the symmetric part of `∂T_kite/∂Θ` — beside the dynamic analysis of
//! [`crate::modes`], and the one verdict of [`crate::verdict`].

use crate::assemble::Design;
pub use crate::attachment::attachment_point;
use crate::modes::ModesReport;
use crate::verdict::{verdict, Tests};
use anyhow::{anyhow, Result};
use nalgebra::{UnitQuaternion, Vector3};
use omniad_core::kite::{stability, statics};
use serde::Serialize;

pub use crate::verdict::Verdict;

/// One eigen-axis of the symmetric part of the Jacobian.
#[derive(Clone, Debug, Serialize)]
pub struct AxisReport {
    /// Eigenvalue, N m/rad (negative: restoring).
    pub eigenvalue: f64,
    /// Unit axis, body frame.
    pub axis: [f64; 3],
    /// `eigenvalue < 0`.
    pub stable: bool,
}

/// Everything `kite check` prints. Vectors are `[x, y, z]`; body frame
/// unless the name says `world`. SI units.
#[derive(Clone, Debug, Serialize)]
pub struct CheckReport {
    /// Kite name.
    pub name: String,
    /// Wind speed, m/s (world +x).
    pub wind_speed: f64,
    /// Mass, kg.
    pub mass: f64,
    /// Centre of mass, design frame, m.
    pub center_of_mass: [f64; 3],
    /// Orientation R as a rotation vector (axis × angle), rad.
    pub orientation: [f64; 3],
    /// `f_string`, world frame, N (eq. 14).
    pub tension_world: [f64; 3],
    /// `F_string = Rᵀ f_string`, N.
    pub tension_body: [f64; 3],
    /// `|f_string|`, N.
    pub tension: f64,
    /// Elevation of the kite above the anchor along the string, degrees.
    pub line_elevation_deg: f64,
    /// `f_string · g > 0`.
    pub pulls_down: bool,
    /// Air force `Σ Q_p F_p`, N.
    pub air_force: [f64; 3],
    /// `T_air`, N m.
    pub air_torque: [f64; 3],
    /// γ of eq. (16), m/N.
    pub gamma: f64,
    /// The same as a distance along the string from the line's foot, m.
    pub attachment_offset: f64,
    /// Attachment point P, body frame (from the centre of mass), m.
    pub attachment: [f64; 3],
    /// `T_kite` at P, N m (eq. 15).
    pub unbalanced_torque: [f64; 3],
    /// `|T_kite|`, N m.
    pub unbalanced_torque_norm: f64,
    /// Axes of `(J + Jᵀ)/2` at the file's orientation (what KiteShop
    /// shows while editing), eigenvalues ascending.
    pub axes: Vec<AxisReport>,
    /// `J = ∂T_kite/∂Θ` at the file's orientation, rows, N m/rad.
    pub jacobian: [[f64; 3]; 3],
    /// §7's static test as the verdict uses it: at the flight model's
    /// equilibrium (where the kite actually hangs), else at the file's
    /// orientation.
    #[serde(rename = "static")]
    pub statics: StaticReport,
    /// Parts of the frame not joined to the first primitive's piece
    /// ([`crate::connect::unjoined`]); empty when the frame is one piece.
    pub unjoined: Vec<String>,
    /// `[[rod]]`s with an end given by coordinates (old files) rather than
    /// a named corner or edge ([`crate::connect::coordinate_rods`]): a
    /// warning; they are joined by where their ends lie.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub joined_by_coordinates: Vec<String>,
    /// Socket bores that run into each other ([`crate::sockets`]): a
    /// fabrication warning, not part of the verdict.
    pub socket_clashes: Vec<crate::sockets::Clash>,
    /// Primitive pairs overlapping along the wind.
    pub overlaps: Vec<[String; 2]>,
    /// The linearised tethered kite: equilibrium and modes.
    pub modes: ModesReport,
    /// Verdict: `stable`, or the first test that failed.
    pub verdict: Verdict,
    /// Why, in words.
    pub reasons: Vec<String>,
}

/// §7's static test at one attitude.
#[derive(Clone, Debug, Serialize)]
pub struct StaticReport {
    /// `"equilibrium"` or `"file orientation"`.
    pub at: &'static str,
    /// The attitude (x, y, z Euler angles), degrees.
    pub orientation_deg: [f64; 3],
    /// Axes of `(J + Jᵀ)/2`, eigenvalues ascending (the paper's test).
    pub axes: Vec<AxisReport>,
    /// The paper's test: every eigenvalue of `(J + Jᵀ)/2` negative, i.e.
    /// `Θ·JΘ < 0` for every small turn Θ.
    pub symmetric_part_stable: bool,
    /// `J`, rows, N m/rad.
    pub jacobian: [[f64; 3]; 3],
    /// Eigenvalues of `J` itself, `[re, im]`, N m/rad.
    pub jacobian_eigenvalues: Vec<[f64; 2]>,
    /// No static divergence: every real eigenvalue of `J` is negative, so
    /// no turn Θ is met by a torque pushing further along Θ. The paper's
    /// symmetric-part test implies it but is stricter than the physics: a
    /// non-symmetric `J` (roll-yaw coupling through the string) can have
    /// `Θ·JΘ > 0` for some Θ and still turn every Θ into a decaying
    /// oscillation (the stop-19 `fig15-b`: symmetric-part eigenvalue +0.20 about yaw,
    /// `J`'s eigenvalues -0.02 ± 0.26i and -0.55; it flies). Whether such
    /// oscillations decay is the dynamic test's ([`crate::modes`]).
    pub stable: bool,
}

/// §7's eigen-analysis at attitude `r` with the string at `p`.
fn static_test(
    design: &Design,
    wind: Option<f64>,
    r: &UnitQuaternion<f64>,
    p: &Vector3<f64>,
    at: &'static str,
) -> Result<StaticReport> {
    let prims = design.primitives();
    let kite = design.kite(&prims);
    let st = stability::stability(&kite, &design.conditions(wind), r, p)
        .map_err(|e| anyhow!("stability: {e}"))?;
    let axes: Vec<AxisReport> = st
        .axes
        .iter()
        .map(|a| AxisReport {
            eigenvalue: a.eigenvalue,
            axis: a.axis.into(),
            stable: a.stable,
        })
        .collect();
    let (x, y, z) = r.euler_angles();
    let scale = st.jacobian.abs().max().max(f64::MIN_POSITIVE);
    let eig: Vec<[f64; 2]> = st
        .jacobian
        .complex_eigenvalues()
        .iter()
        .map(|l| [l.re, l.im])
        .collect();
    let divergent = eig
        .iter()
        .any(|[re, im]| im.abs() <= 1e-9 * scale && !(*re < 0.0));
    Ok(StaticReport {
        at,
        orientation_deg: [x, y, z].map(f64::to_degrees),
        symmetric_part_stable: axes.iter().all(|a| a.stable),
        stable: !divergent,
        jacobian_eigenvalues: eig,
        axes,
        jacobian: [0, 1, 2].map(|i| [0, 1, 2].map(|j| st.jacobian[(i, j)])),
    })
}

/// The static report at orientation `r` with the string at `attachment`
/// (body frame; `None`: the file's γ/offset on the eq. 16 line at `r`).
pub fn check_at(
    design: &Design,
    wind: Option<f64>,
    r: &UnitQuaternion<f64>,
    attachment: Option<Vector3<f64>>,
) -> Result<CheckReport> {
    let prims = design.primitives();
    let kite = design.kite(&prims);
    let cond = design.conditions(wind);
    let eq = statics::equilibrium(&kite, &cond, r).map_err(|e| anyhow!("equilibrium: {e}"))?;
    let p = match attachment {
        Some(p) => p,
        None => attachment_point(design, wind, r)?,
    };
    let f = eq.string_body;
    let foot = eq.air.torque.cross(&f) / f.norm_squared().max(f64::MIN_POSITIVE);
    let offset = (p - foot).dot(&f) / f.norm().max(f64::MIN_POSITIVE);
    let gamma = offset / f.norm().max(f64::MIN_POSITIVE);
    let torque = statics::unbalanced_torque(&eq, &p);
    let here = static_test(design, wind, r, &p, "file orientation")?;
    let overlaps: Vec<[String; 2]> = design
        .overlaps(r)
        .into_iter()
        .map(|(a, b)| [a, b])
        .collect();
    let unjoined = crate::connect::unjoined(&design.spec);
    let (equilibrium, modes) = if unjoined.is_empty() && overlaps.is_empty() && eq.pulls_down {
        crate::modes::analyse(design, wind)?
    } else {
        (None, ModesReport::none())
    };
    let statics = match &equilibrium {
        Some(e) => static_test(design, wind, &e.state.orientation, &p, "equilibrium")?,
        None => here.clone(),
    };
    let verdict = verdict(&Tests {
        unjoined: unjoined.len(),
        overlaps: overlaps.len(),
        pulls_down: eq.pulls_down,
        equilibrium: equilibrium.is_some(),
        statically_stable: statics.stable,
        dynamically_stable: modes.stable,
        saturates: modes.bounded,
        gust_tolerant: modes.gusts.as_ref().is_some_and(|g| g.ok)
            && modes.strong_gust.as_ref().is_some_and(|g| g.ok),
    });
    let mut reasons = frame_reasons(design, &unjoined);
    reasons.extend(reasons_after_frame(
        unjoined.is_empty(),
        eq.pulls_down,
        &overlaps,
        &statics,
        &modes,
    ));
    let joined_by_coordinates = crate::connect::coordinate_rods(&design.spec);
    if !joined_by_coordinates.is_empty() {
        reasons.push(format!(
            "{} joined by coordinates, not by a named corner or edge: they do not follow their primitives when these move (write `from = {{ primitive = \"name\", corner = \"+x-y+z\" }}`, see data/kites/README.md)",
            joined_by_coordinates.join(", ")
        ));
    }
    let socket_clashes = crate::sockets::clashes(design);
    if let Some(c) = socket_clashes.first() {
        reasons.push(format!(
            "{} pair(s) of socket bores clash (first: joint_{}, {} and {} at {:.1}°, at least {:.1}° needed); see the cut list",
            socket_clashes.len(),
            c.joint,
            c.rods[0],
            c.rods[1],
            c.angle_deg,
            c.min_angle_deg
        ));
    }
    if torque.norm() > 1e-3 {
        reasons.push(format!(
            "unbalanced torque {:.4} N m at the file's orientation (its part along the string cannot be cancelled by the attachment point): the kite turns to its equilibrium",
            torque.norm()
        ));
    }
    let dir = eq.string_world.normalize();
    Ok(CheckReport {
        name: design.spec.name.clone(),
        wind_speed: cond.wind.norm(),
        mass: design.mass.mass,
        center_of_mass: design.mass.center.into(),
        orientation: r.scaled_axis().into(),
        tension_world: eq.string_world.into(),
        tension_body: f.into(),
        tension: f.norm(),
        line_elevation_deg: (-dir.z).asin().to_degrees(),
        pulls_down: eq.pulls_down,
        air_force: eq.air.force.into(),
        air_torque: eq.air.torque.into(),
        gamma,
        attachment_offset: offset,
        attachment: p.into(),
        unbalanced_torque: torque.into(),
        unbalanced_torque_norm: torque.norm(),
        axes: here.axes,
        jacobian: here.jacobian,
        statics,
        unjoined,
        joined_by_coordinates,
        socket_clashes,
        overlaps,
        modes,
        verdict,
        reasons,
    })
}

/// The file's orientation and attachment.
pub fn check(design: &Design, wind: Option<f64>) -> Result<CheckReport> {
    check_at(design, wind, &design.orientation(), None)
}

/// Why the frame is refused: the unjoined parts, named.
fn frame_reasons(design: &Design, unjoined: &[String]) -> Vec<String> {
    if unjoined.is_empty() {
        return Vec::new();
    }
    let first = design
        .spec
        .primitives
        .first()
        .map_or(String::new(), |p| format!("{:?}", p.name));
    vec![format!(
        "the frame is not one piece: {} not joined to primitive {first} (join them with a [[rod]] from a corner or edge of one to a corner or edge of the other)",
        unjoined.join(", ")
    )]
}

fn reasons_after_frame(
    joined: bool,
    pulls_down: bool,
    overlaps: &[[String; 2]],
    statics: &StaticReport,
    modes: &ModesReport,
) -> Vec<String> {
    let mut reasons = Vec::new();
    for [a, b] in overlaps {
        reasons.push(format!("{a} and {b} overlap along the wind"));
    }
    if !pulls_down {
        reasons.push("the string would have to pull upward (f_string · g <= 0)".into());
    } else if joined && overlaps.is_empty() && modes.equilibrium.is_none() {
        reasons.push("the kite on its line has no equilibrium near the file's orientation".into());
    }
    if !statics.stable {
        reasons.push(format!(
            "statically unstable (divergent) at the {}: a real eigenvalue of dT/dTheta is >= 0",
            statics.at
        ));
    }
    for a in statics.axes.iter().filter(|a| !a.stable) {
        reasons.push(format!(
            "paper's test (symmetric part) at the {}: positive about axis [{:.2}, {:.2}, {:.2}] (eigenvalue {:+.4} N m/rad)",
            statics.at, a.axis[0], a.axis[1], a.axis[2], a.eigenvalue
        ));
    }
    let saturates = modes.limit_cycle.as_ref().filter(|c| c.inside_limits);
    for m in modes.modes.iter().filter(|m| !m.stable) {
        reasons.push(match saturates {
            Some(c) => format!(
                "{} mode grows at {:+.3}/s but saturates in a limit cycle inside the flight's limits (line elevation {:.1}-{:.1}°, |Omega| <= {:.2} rad/s in steady wind)",
                m.motion, m.real, c.elevation_deg[0], c.elevation_deg[1], c.max_spin
            ),
            None => format!(
                "dynamically unstable: {} mode grows at {:+.3}/s",
                m.motion, m.real
            ),
        });
    }
    if let Some(g) = modes.gusts.as_ref().filter(|g| !g.ok) {
        reasons.push(format!(
            "gust sensitive: {} m/s gusts are predicted to take the line down to {:.1}° (limit {:.0}°), the spin up to {:.2} rad/s (limit {:.1}), the kite down to {:.2} m (limit {:.1})",
            g.gust, g.min_elevation_deg, g.limits[0], g.max_spin, g.limits[1], g.min_height, g.limits[2]
        ));
    }
    if let Some(g) = modes.strong_gust.as_ref().filter(|g| !g.ok) {
        let m = &g.motion;
        if let Some(end) = g.branch_ends {
            reasons.push(format!(
                "gust sensitive: the kite's equilibrium ends (a fold) {:+.2} m/s {} from the mean wind, inside the run's slow {} of {:.2} m/s: nowhere to rest in it",
                end,
                g.component,
                if g.amplitude < 0.0 { "lull" } else { "gust" },
                g.amplitude.abs(),
            ));
            return reasons;
        }
        reasons.push(format!(
            "gust sensitive: a 1 - cos {} {} of {:.2} m/s over {:.0} s takes the line down to {:.1}° (limit 15°), the spin up to {:.2} rad/s{}",
            g.component,
            if g.amplitude < 0.0 { "lull" } else { "gust" },
            g.amplitude.abs(),
            g.seconds,
            m.elevation_deg[0],
            m.max_spin,
            if m.crashed { ", the kite to the ground" } else { "" }
        ));
    }
    reasons
}

/// Human-readable report.
pub fn render(r: &CheckReport) -> String {
    let v = |x: &[f64; 3]| format!("[{:+.4}, {:+.4}, {:+.4}]", x[0], x[1], x[2]);
    let mut s = format!(
        "kite {:?}: wind {:.2} m/s, mass {:.1} g\n",
        r.name,
        r.wind_speed,
        r.mass * 1e3
    );
    s += &format!(
        "  string tension (world)  {} N  |f| = {:.3} N, line elevation {:.1} deg, pulls down: {}\n",
        v(&r.tension_world),
        r.tension,
        r.line_elevation_deg,
        r.pulls_down
    );
    s += &format!(
        "  air force (body)        {} N\n  air torque T_air        {} N m\n",
        v(&r.air_force),
        v(&r.air_torque)
    );
    s += &format!(
        "  attachment P            {} m  (gamma {:.5} m/N, offset {:+.3} m)\n",
        v(&r.attachment),
        r.gamma,
        r.attachment_offset
    );
    s += &format!(
        "  unbalanced torque       {} N m  |T| = {:.2e}\n",
        v(&r.unbalanced_torque),
        r.unbalanced_torque_norm
    );
    s += "  static (§7) at the file's orientation:\n";
    for a in &r.axes {
        s += &format!(
            "  axis {}  eigenvalue {:+.5} N m/rad  {}\n",
            v(&a.axis),
            a.eigenvalue,
            if a.stable { "stable" } else { "UNSTABLE" }
        );
    }
    s += &crate::modes::render(&r.modes);
    s += &format!(
        "  static test at the {}: {} (paper's symmetric-part test: {})\n",
        r.statics.at,
        if r.statics.stable {
            "no divergence"
        } else {
            "DIVERGENT"
        },
        if r.statics.symmetric_part_stable {
            "stable"
        } else {
            "unstable"
        }
    );
    s += &format!("  verdict: {}\n", r.verdict.name());
    for reason in &r.reasons {
        s += &format!("    - {reason}\n");
    }
    s
}
