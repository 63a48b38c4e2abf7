//! The batch path (`omniad_core::batch`) against the single-body path:
//! bit for bit against the portable path (f32 and f64), to
//! single-precision rounding against the AVX single-body path (f32), for
//! the wrench and for whole RK4 steps, with and without extensions, at
//! random directions, speeds and rates, and at the poles and rest.

use nalgebra::{Matrix3, UnitQuaternion, Vector3};
use omniad_core::batch::{rk4_lanes, wrench_batch, wrench_sets, StateLanes};
use omniad_core::effect::{Effect, EffectKind};
use omniad_core::gravity_coupling::GravityCoupling;
use omniad_core::integrate::rk4_step;
use omniad_core::rigid_body::AirForces;
use omniad_core::spin_coupling::SpinCoupling;
use omniad_core::{Coefficients, Environment, LaneScalar, RigidBody, State, Wrench};

/// xorshift in [-1, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
    fn vector<T: LaneScalar>(&mut self, scale: f64) -> Vector3<T> {
        Vector3::new(self.next(), self.next(), self.next()).map(|x| T::of_f64(x * scale))
    }
}

/// A random model of degree `n`, portable (so the single-body path is the
/// reference the batch must match bit for bit), with or without both
/// extensions.
fn model<T: LaneScalar>(n: u8, rng: &mut Rng, extensions: bool) -> Coefficients<T> {
    model_degrees(n, n, rng, extensions)
}

/// [`model`] with the torque of its own degree `nt`.
fn model_degrees<T: LaneScalar>(n: u8, nt: u8, rng: &mut Rng, extensions: bool) -> Coefficients<T> {
    let pole = Vector3::new(0.1, -0.2, 1.0).normalize().map(T::of_f64);
    let mut m = Coefficients::<T>::zeros(n, pole, T::of_f64(0.58))
        .unwrap()
        .with_torque_degree(nt)
        .unwrap();
    for k in 0..m.coeff_count().max(m.torque_coeff_count()) {
        for i in 0..3 {
            if k < m.coeff_count() {
                m.set_alpha(i, k, T::of_f64(rng.next())).unwrap();
            }
            if k < m.torque_coeff_count() {
                m.set_beta(i, k, T::of_f64(0.3 * rng.next())).unwrap();
            }
        }
    }
    let d = Matrix3::new(0.03, 0.002, -0.001, 0.002, 0.02, 0.003, -0.001, 0.003, 0.04);
    m.set_damping(&d.map(T::of_f64)).unwrap();
    if extensions {
        let k = std::array::from_fn(|i| {
            std::array::from_fn(|j| T::of_f64(0.01 * (i + j) as f64 - 0.02))
        });
        m.set_spin_coupling(Some(SpinCoupling { k })).unwrap();
        let g = GravityCoupling::buoyancy(T::of_f64(3e-4), T::of_f64(0.58));
        m.set_gravity_coupling(Some(g)).unwrap();
        // Named effects too (`omniad residual` stores them).
        for (kind, p) in [
            (EffectKind::RotationalLift, 0.05),
            (EffectKind::Buoyancy, 2e-4),
            (EffectKind::LinearDrag, 50.0),
        ] {
            m.set_effect(Effect::new(kind, &[T::of_f64(p)]).unwrap())
                .unwrap();
        }
    }
    m.set_portable(true);
    m
}

/// Velocities and rates: random, plus the awkward ones (rest, no spin,
/// along the pole, against it).
fn inputs<T: LaneScalar>(rng: &mut Rng, pole: Vector3<T>) -> (Vec<Vector3<T>>, Vec<Vector3<T>>) {
    let mut v: Vec<Vector3<T>> = (0..197).map(|_| rng.vector(8.0)).collect();
    let mut w: Vec<Vector3<T>> = (0..197).map(|_| rng.vector(20.0)).collect();
    v.extend([
        Vector3::zeros(),
        pole * T::of_f64(3.0),
        pole * T::of_f64(-2.0),
        rng.vector(1.0),
    ]);
    w.extend([
        rng.vector(1.0),
        Vector3::zeros(),
        rng.vector(5.0),
        Vector3::zeros(),
    ]);
    (v, w)
}

fn bits<T: LaneScalar>(w: &Wrench<T>) -> Vec<u64> {
    w.force
        .iter()
        .chain(w.torque.iter())
        .map(|x| x.as_f64().to_bits())
        .collect()
}

fn batch_matches_portable<T: LaneScalar>() {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let cases = [
        (8, 8, false),
        (8, 8, true),
        (3, 3, false),
        (12, 12, true),
        (0, 0, false),
        // A torque of its own degree, above and below the force's.
        (8, 10, false),
        (10, 6, true),
    ];
    for (n, nt, ext) in cases {
        let m = model_degrees::<T>(n, nt, &mut rng, ext);
        let (v, w) = inputs(&mut rng, m.pole());
        let mut out = vec![Wrench::zero(); v.len()];
        wrench_batch(&m, &v, &w, T::of_f64(1.2), &mut out);
        for i in 0..v.len() {
            let one = m.wrench(&v[i], &w[i], T::of_f64(1.2));
            assert_eq!(bits(&out[i]), bits(&one), "degree {n}, body {i}");
        }
    }
}

#[test]
fn batch_wrench_is_the_portable_wrench_bit_for_bit_f64() {
    batch_matches_portable::<f64>();
}

#[test]
fn batch_wrench_is_the_portable_wrench_bit_for_bit_f32() {
    batch_matches_portable::<f32>();
}

/// Against the AVX single-body path (f32): single-precision rounding,
/// relative to the size of the wrench's terms.
#[test]
fn batch_wrench_agrees_with_the_simd_path_to_rounding() {
    let mut rng = Rng(7);
    let portable = model::<f32>(8, &mut rng, false);
    let mut simd = portable.clone();
    simd.set_portable(false);
    let (v, w) = inputs(&mut rng, portable.pole());
    let mut out = vec![Wrench::zero(); v.len()];
    wrench_batch(&portable, &v, &w, 1.2, &mut out);
    for i in 0..v.len() {
        let one = simd.wrench(&v[i], &w[i], 1.2);
        let q = 0.6 * v[i].norm_squared() * 0.58f32.powi(2) * 81.0 + w[i].norm_squared() * 0.1;
        let err = (out[i].force - one.force)
            .norm()
            .max((out[i].torque - one.torque).norm());
        assert!(err <= 2e-6 * q.max(1e-3), "body {i}: {err} vs scale {q}");
    }
}

/// Bodies with their own sets (a kite's primitives): each body's wrench
/// is its own set's, bit for bit.
#[test]
fn sets_gathered_into_lanes_match_each_body_alone() {
    let mut rng = Rng(99);
    let models: Vec<Coefficients<f64>> = (0..3).map(|i| model(8, &mut rng, i == 1)).collect();
    let (v, w) = inputs(&mut rng, Vector3::z());
    let set_of: Vec<usize> = (0..v.len()).map(|i| (i * 7 + i / 3) % 4).collect();
    let mut out = vec![Wrench::zero(); v.len()];
    wrench_sets(&models, &set_of, &v, &w, 1.2, &mut out);
    for i in 0..v.len() {
        let want = models
            .get(set_of[i])
            .map_or(Wrench::zero(), |m| m.wrench(&v[i], &w[i], 1.2));
        assert_eq!(bits(&out[i]), bits(&want), "body {i} (set {})", set_of[i]);
    }
}

fn rk4_matches_single<T: LaneScalar>(extensions: bool) {
    let mut rng = Rng(0xABCD);
    let m = model::<T>(8, &mut rng, extensions);
    rk4_matches_single_for(&m, &mut rng);
}

fn rk4_matches_single_for<T: LaneScalar>(m: &Coefficients<T>, rng: &mut Rng) {
    let inertia = Matrix3::new(1.0e-3, 1e-5, 0.0, 1e-5, 3.6e-4, 0.0, 0.0, 0.0, 1.36e-3);
    let body = RigidBody::new(T::of_f64(0.048), inertia.map(T::of_f64)).unwrap();
    let env = Environment {
        wind: Vector3::new(T::of_f64(0.7), T::of_f64(-0.2), T::zero()),
        ..Environment::standard()
    };
    let states: Vec<State<T>> = (0..16)
        .map(|i| {
            let mut s = State::at_rest(rng.vector(3.0));
            let axis = nalgebra::Unit::new_normalize(rng.vector::<T>(1.0));
            s.orientation = UnitQuaternion::from_axis_angle(&axis, T::of_f64(rng.next() * 3.0));
            if i % 5 != 0 {
                s.velocity = rng.vector(6.0);
                s.angular_velocity = rng.vector(15.0);
            }
            s
        })
        .collect();
    let mut lanes = [StateLanes::splat(&states[0]), StateLanes::splat(&states[0])];
    for (i, s) in states.iter().enumerate() {
        lanes[i / 8].set(i % 8, s);
    }
    let dt = T::of_f64(1.0 / 240.0);
    rk4_lanes(m, &body, &env, dt, 30, &mut lanes);
    let forces = AirForces {
        model: m,
        environment: env,
    };
    for (i, s0) in states.iter().enumerate() {
        let mut s = *s0;
        for _ in 0..30 {
            s = rk4_step(&body, &env, &forces, T::zero(), dt, &s);
        }
        let got = lanes[i / 8].get(i % 8);
        let b = |s: &State<T>| {
            let q = s.orientation.coords;
            [s.position, s.velocity, s.angular_velocity]
                .iter()
                .flat_map(|v| v.iter().copied())
                .chain(q.iter().copied())
                .map(|x| x.as_f64().to_bits())
                .collect::<Vec<_>>()
        };
        assert_eq!(b(&got), b(&s), "body {i}");
    }
}

#[test]
fn batch_rk4_is_the_single_body_rk4_bit_for_bit() {
    rk4_matches_single::<f64>(false);
    rk4_matches_single::<f64>(true);
    rk4_matches_single::<f32>(false);
    rk4_matches_single::<f32>(true);
}

/// A model with added mass changes the equations of motion: the batch
/// steps such lanes through the single-body RK4, which carries it.
#[test]
fn batch_rk4_with_added_mass_is_the_single_body_rk4() {
    let mut rng = Rng(0x1234);
    let mut m = model::<f64>(6, &mut rng, true);
    let a = Effect::new(EffectKind::AddedMass, &[0.01, 0.02, 0.05, 0.0, 0.001, 0.0]).unwrap();
    m.set_effect(a).unwrap();
    rk4_matches_single_for(&m, &mut rng);
}
