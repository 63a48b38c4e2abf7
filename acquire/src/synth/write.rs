//! Writing a synthetic recording set (see [`crate::synth`]) in the
//! recording format, with `truth/`.

use crate::error::{Error, Result};
use crate::input::camera::Camera;
use crate::input::state_csv::{self, TimeFormat};
use crate::rng::Rng;
use crate::synth::{random_start, simulate, truth_model, ObjectSpec, SynthConfig, SynthForces};
use nalgebra::{Matrix3, UnitQuaternion, Vector2, Vector3};
use omniad_core::rigid_body::AirForces;
use omniad_core::{Environment, RigidBody, State};
use std::fmt::Write as _;
use std::path::Path;

/// The shared sets' camera: portrait 720 x 1280 at 60 fps, 7 m away.
pub fn standard_camera(pixel_noise: f64) -> Camera {
    Camera {
        width: 720,
        height: 1280,
        fps: 60.0,
        focal: Vector2::new(1100.0, 1100.0),
        centre: Vector2::new(359.5, 639.5),
        distortion: [-0.05, 0.01, 0.0005, -0.0003, 0.0],
        rotation: Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0),
        translation: Vector3::new(0.0, 3.5, 7.0),
        pixel_noise,
    }
}

/// Writes `text` to `path` atomically (temporary file + rename).
fn write(path: &Path, text: &str) -> Result<()> {
    omniad_io::write_atomic(path, text.as_bytes()).map_err(|e| Error::io(path, e))
}

fn v3(v: &Vector3<f64>) -> String {
    format!("[{}, {}, {}]", v.x, v.y, v.z)
}

/// Generates the set into `out` (created if needed). Returns each effect's
/// name (as given; `wind` last when the set has one) and measured strength, `RMS|F_effect| / RMS|F_aero|`
/// over the generated frames ([`crate::synth::strength`]), also written to
/// `truth/model.toml`'s `[force_fraction]`.
pub fn generate(out: &Path, cfg: &SynthConfig) -> Result<Vec<(String, f64)>> {
    let truth_dir = out.join("truth");
    std::fs::create_dir_all(&truth_dir).map_err(|e| Error::io(&truth_dir, e))?;
    let spec = ObjectSpec::of(cfg.object);
    let model = truth_model(&spec, cfg.degree)?;
    let inertia = spec.inertia();
    let body = RigidBody::new(spec.mass, inertia).map_err(|e| Error::Data(e.to_string()))?;
    let env = Environment::<f64> {
        wind: cfg.wind,
        ..Environment::standard()
    };
    let effects = cfg
        .effects
        .iter()
        .map(|e| e.effect(&spec, env.air_density))
        .collect::<Result<Vec<_>>>()?;
    let camera = standard_camera(cfg.noise.max(1e-3));
    let markers = spec.markers();
    let forces = SynthForces {
        air: AirForces {
            model: &model,
            environment: env,
        },
        effects: &effects,
    };
    let mut rng = Rng::new(cfg.seed);
    // Outliers draw from their own stream: the same seed gives the same
    // trajectories and noise whatever the outlier fraction.
    let mut jumps = Rng::new(cfg.seed ^ 0x0u64.wrapping_sub(1));
    let mut toml = header(&spec, &inertia, &markers, &camera, cfg.noise);
    let count = cfg.takes.0 + cfg.takes.1;
    let mut strength = crate::synth::strength::Strength::default();
    for i in 0..count {
        let spin = i >= cfg.takes.0;
        let name = format!("{}-{:02}", if spin { "spin" } else { "drop" }, i + 1);
        let states = simulate(
            &body,
            &env,
            &forces,
            random_start(&mut rng, spin, cfg.throw_speed.as_ref()),
            camera.fps,
            400,
        );
        strength.add(&forces, &states, camera.fps);
        let first = states
            .first()
            .copied()
            .ok_or_else(|| Error::Data("empty simulation".into()))?;
        let guess_q = first.orientation
            * UnitQuaternion::from_scaled_axis(rng.direction() * 2f64.to_radians());
        let guess_p = first.position + rng.direction() * 0.03;
        let q = guess_q.quaternion();
        let _ = write!(
            toml,
            "\n[[take]]\nname = \"{name}\"\nkind = \"{}\"\nmarkers = \"{name}.csv\"\ninitial_position = {}\ninitial_orientation = [{}, {}, {}, {}]\n",
            if spin { "spin" } else { "drop" },
            v3(&guess_p),
            q.w, q.i, q.j, q.k
        );
        write(
            &out.join(format!("{name}.csv")),
            &marker_csv(
                &states,
                &spec,
                &markers,
                &camera,
                cfg,
                (&mut rng, &mut jumps),
            ),
        )?;
        write(
            &truth_dir.join(format!("{name}.csv")),
            &truth_csv(&states, camera.fps),
        )?;
    }
    write(&out.join("recording.toml"), &toml)?;
    write(
        &truth_dir.join("coefficients.csv"),
        &coefficients_csv(&model),
    )?;
    let mut fractions: Vec<(String, f64)> = cfg
        .effects
        .iter()
        .map(|e| e.name.clone())
        .zip(strength.fractions())
        .collect();
    if let Some(w) = strength.wind_fraction() {
        fractions.push(("wind".to_owned(), w));
    }
    write(
        &truth_dir.join("model.toml"),
        &truth_toml(&model, cfg, &effects, &fractions),
    )?;
    crate::omni_file::write(
        &truth_dir.join("model.omni"),
        &truth_file(model, &spec, cfg, &effects)?,
    )?;
    Ok(fractions)
}

/// The generating model as a coefficient file holds it: the coefficients
/// with the set's object effects stored (a wind is the recording's, not
/// the object's, and is not stored), the object's name and mass
/// properties, and the object, seed and effects in its provenance.
/// `truth/model.omni` lets any command that takes a model use the truth
/// itself: `omniad residual SET --coeffs SET/truth/model.omni` scores the
/// generating model on the reconstructed states, what is left when the
/// model is exactly right.
fn truth_file(
    mut model: omniad_core::Coefficients<f64>,
    spec: &ObjectSpec,
    cfg: &SynthConfig,
    effects: &[omniad_core::effect::Effect<f64>],
) -> Result<omniad_core::Coefficients<f64>> {
    let bad = |what: &str, err: &dyn std::fmt::Display| {
        Error::Data(format!("truth/model.omni: {what}: {err}"))
    };
    for e in effects {
        model
            .set_effect(*e)
            .map_err(|err| bad(e.kind.name(), &err))?;
    }
    model.set_name(spec.name).map_err(|err| bad("name", &err))?;
    model.body = Some(omniad_core::metadata::MassProperties {
        mass: spec.mass,
        inertia: omniad_core::math::six_from_symmetric(&spec.inertia()),
    });
    let mut source = format!("omniad synth truth: {}, seed {}", spec.name, cfg.seed);
    for e in &cfg.effects {
        let _ = write!(source, ", {}={}", e.name, e.scale);
    }
    let p = &mut model.provenance;
    p.method.clear();
    p.source.clear();
    // Both fit their capacities (32 and TEXT_CAPACITY bytes) except a
    // very long effect list, whose source is then left empty rather than
    // cut in the middle of a word.
    let _ = p.method.push_str("synth-truth");
    let _ = p.source.push_str(&source);
    Ok(model)
}

/// `truth/model.toml`: the generating model's constants, the wind, and
/// each effect's SCALE (`[effects]`, as given), parameters
/// (`[parameters]`, the core's order, e.g. buoyancy's V_b in m³) and
/// measured strength (`[force_fraction]`, `RMS|F_effect| / RMS|F_aero|`).
fn truth_toml(
    model: &omniad_core::Coefficients<f64>,
    cfg: &SynthConfig,
    effects: &[omniad_core::effect::Effect<f64>],
    fractions: &[(String, f64)],
) -> String {
    let d = model.damping();
    let mut s = format!(
        "engine = \"omniad-sh\"\ndegree = {}\nseed = {}\ndamping = [{}, {}, {}]\nwind = {}\n[effects]\n",
        cfg.degree,
        cfg.seed,
        v3(&d.row(0).transpose()),
        v3(&d.row(1).transpose()),
        v3(&d.row(2).transpose()),
        v3(&cfg.wind)
    );
    for e in &cfg.effects {
        let _ = writeln!(s, "{} = {}", e.name, e.scale);
    }
    s.push_str("[parameters]\n");
    for e in effects {
        let p: Vec<String> = e.used_params().iter().map(|v| v.to_string()).collect();
        let _ = writeln!(s, "{} = [{}]", e.kind.name(), p.join(", "));
    }
    s.push_str("[force_fraction]\n");
    for (name, f) in fractions {
        let _ = writeln!(s, "{name} = {f:.4}");
    }
    s
}

fn header(
    spec: &ObjectSpec,
    inertia: &Matrix3<f64>,
    markers: &[(Vector3<f64>, usize)],
    c: &Camera,
    noise: f64,
) -> String {
    let mut s = format!(
        "format = \"omniad-recording/1\"\n\n[world]\ngravity = [0.0, 0.0, -9.81]\nair_density = 1.2\nair_viscosity = 1.8e-5\n\n[object]\nname = \"{}\"\nmass = {}\ninertia = [{}, {}, {}]\nreference_length = {}\npole = {}\n\n[object.markers]\n",
        spec.name,
        spec.mass,
        v3(&inertia.row(0).transpose()),
        v3(&inertia.row(1).transpose()),
        v3(&inertia.row(2).transpose()),
        spec.reference_length(),
        v3(&spec.pole)
    );
    for (i, (p, _)) in markers.iter().enumerate() {
        let _ = writeln!(s, "m{i} = {}", v3(p));
    }
    let [k1, k2, p1, p2, k3] = c.distortion;
    let r = &c.rotation;
    let _ = write!(
        s,
        "\n[camera]\nwidth = {}\nheight = {}\nfps = {}\nfx = {}\nfy = {}\ncx = {}\ncy = {}\ndistortion = [{k1}, {k2}, {p1}, {p2}, {k3}]\nrotation = [{}, {}, {}]\ntranslation = {}\npixel_noise = {:?}\n",
        c.width, c.height, c.fps, c.focal.x, c.focal.y, c.centre.x, c.centre.y,
        v3(&r.row(0).transpose()), v3(&r.row(1).transpose()), v3(&r.row(2).transpose()),
        v3(&c.translation),
        noise
    );
    s
}

/// Rows of the markers on the face most turned toward the camera.
fn marker_csv(
    states: &[State<f64>],
    spec: &ObjectSpec,
    markers: &[(Vector3<f64>, usize)],
    cam: &Camera,
    cfg: &SynthConfig,
    (rng, jumps): (&mut Rng, &mut Rng),
) -> String {
    let centre = -cam.rotation.transpose() * cam.translation;
    let mut s = String::from("frame,marker,u,v\n");
    for (k, st) in states.iter().enumerate() {
        let to_cam = st
            .orientation
            .inverse_transform_vector(&(centre - st.position));
        let face = spec
            .faces
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.dot(&to_cam).total_cmp(&b.1.dot(&to_cam)))
            .map(|f| f.0);
        for (i, (p, f)) in markers.iter().enumerate() {
            if Some(*f) != face || rng.uniform() < cfg.dropout {
                continue;
            }
            let Some(mut px) = cam.project(&(st.position + st.orientation * p)) else {
                continue;
            };
            px += Vector2::new(rng.normal(), rng.normal()) * cfg.noise;
            let (p, a, r) = (
                jumps.uniform(),
                jumps.range(0.0, std::f64::consts::TAU),
                jumps.range(20.0, 60.0),
            );
            if p < cfg.outliers {
                px += Vector2::new(a.cos(), a.sin()) * r;
            }
            let _ = writeln!(s, "{k},m{i},{:.3},{:.3}", px.x, px.y);
        }
    }
    s
}

fn truth_csv(states: &[State<f64>], fps: f64) -> String {
    let rows = states
        .iter()
        .enumerate()
        .map(|(k, st)| (k as f64 / fps, st));
    state_csv::to_csv(rows, TimeFormat::Exact)
}

/// `C_F`, `C_T` on the 32 x 16 grid about body z (as the shared sets).
fn coefficients_csv(model: &omniad_core::Coefficients<f64>) -> String {
    let mut s = String::from("ex,ey,ez,cfx,cfy,cfz,ctx,cty,ctz\n");
    for lat in 0..16 {
        for lon in 0..32 {
            let t = (lat as f64 + 0.5) * std::f64::consts::PI / 16.0;
            let p = lon as f64 * std::f64::consts::TAU / 32.0;
            let e = Vector3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos());
            if let Some(c) = model.at_direction(&e) {
                let _ = writeln!(
                    s,
                    "{},{},{},{},{},{},{},{},{}",
                    e.x,
                    e.y,
                    e.z,
                    c.force.x,
                    c.force.y,
                    c.force.z,
                    c.torque.x,
                    c.torque.y,
                    c.torque.z
                );
            }
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::generate;
    use crate::synth::{truth_model, Effect, ObjectSpec, SynthConfig, SynthObject};
    use nalgebra::Vector3;
    use omniad_core::effect::EffectKind;

    #[test]
    fn the_truth_is_written_as_a_coefficient_file_with_its_object_effects() {
        let dir = tempfile::tempdir().expect("tempdir");
        let cfg = SynthConfig {
            object: SynthObject::Plate,
            effects: ["added_mass=0.3", "linear_drag=600"]
                .iter()
                .map(|e| Effect::parse(e).expect("effect"))
                .collect(),
            wind: Vector3::new(1.0, 0.0, 0.0),
            takes: (1, 0),
            ..SynthConfig::default()
        };
        generate(dir.path(), &cfg).expect("synth");
        let bytes = std::fs::read(dir.path().join("truth/model.omni")).expect("model.omni");
        let file = omniad_core::file::decode::<f64>(&bytes).expect("decodes");
        let spec = ObjectSpec::of(SynthObject::Plate);
        let truth = truth_model(&spec, cfg.degree).expect("truth");
        // The coefficients: the generating model's (stored as f32).
        for c in 0..3 {
            for k in 0..truth.coeff_count() {
                let (a, b) = (file.alpha(c, k).expect("a"), truth.alpha(c, k).expect("b"));
                assert!(
                    (a - b).abs() <= 1e-6 * (1.0 + b.abs()),
                    "alpha {c},{k}: {a} vs {b}"
                );
            }
        }
        // The object's effects at the parameters the physics used, the
        // wind (the recording's) not among them.
        let rho = omniad_core::Environment::<f64>::standard().air_density;
        for e in &cfg.effects {
            let used = e.effect(&spec, rho).expect("effect");
            let stored = file.effect(used.kind).expect("stored");
            for (a, b) in stored.used_params().iter().zip(used.used_params()) {
                assert!(
                    (a - b).abs() <= 1e-6 * b.abs().max(1e-9),
                    "{}: {a} vs {b}",
                    e.name
                );
            }
        }
        assert_eq!(file.effects().len(), 2);
        assert!(file.effect(EffectKind::Buoyancy).is_none());
        assert_eq!(file.name(), "plate");
        assert_eq!(file.body.map(|b| b.mass), Some(spec.mass));
        assert_eq!(file.provenance.method.as_str(), "synth-truth");
    }
}
