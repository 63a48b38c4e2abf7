//! The OmniAD coefficient model: alpha, beta (eqs. 7-8), the damping tensor
//! D (eq. 6), the object's reference length L and pole Z, the rigid body it
//! was measured on, provenance, and model extensions.
//!
//! The pieces it holds are defined below it, each in its own module, and
//! re-exported here under their historical paths: the error
//! ([`crate::error`]), the metadata ([`crate::metadata`]), the extensions
//! ([`crate::extension`], [`crate::spin_coupling`],
//! [`crate::gravity_coupling`]) and the storage layout ([`crate::lanes`]).

pub use crate::error::ModelError;
pub use crate::extension::{extension_kind, Extension, EXTENSION_CAPACITY, MAX_EXTENSIONS};
pub use crate::lanes::SETS;
pub use crate::metadata::{
    MassProperties, Provenance, COVERAGE_CELLS, COVERAGE_LAT, COVERAGE_LON, MAX_ITERATIONS,
    NAME_CAPACITY, TEXT_CAPACITY,
};

use crate::effect::{Effect, EffectKind};
use crate::gravity_coupling::GravityCoupling;
use crate::lanes::{LaneScalar, SimdCoefficients};
use crate::math::{is_positive_semidefinite, six_from_symmetric, symmetric_from_six};
use crate::sh::{self, MAX_COEFFS, MAX_DEGREE};
use crate::spin_coupling::SpinCoupling;
use nalgebra::{Matrix3, Vector3};

/// The OmniAD coefficients of one object.
///
/// The force (alpha) has degree N ([`Self::degree`]), the torque (beta)
/// its own N_T ([`Self::torque_degree`], N unless set otherwise); the SH
/// basis is evaluated once, to `max(N, N_T)` ([`Self::basis_degree`]).
///
/// Storage is laid out for evaluation speed ([`crate::lanes`]): rows of the six
/// sets `[alpha^1..3, beta^1..3]` in the scalar path's walk order, and,
/// where the scalar type has a SIMD path, a second copy in its lane layout
/// (entries beyond the degree stay zero). The public accessors take the
/// standard index `k = l*l + l + m` and keep both copies equal.
#[derive(Clone, Debug, PartialEq)]
pub struct Coefficients<T: LaneScalar> {
    name: heapless::String<NAME_CAPACITY>,
    /// SH degree N of the force, alpha (eq. 7).
    degree: u8,
    /// SH degree N_T of the torque, beta (eq. 8): its own, as an object's
    /// torque can need a finer angular resolution than its force
    /// (BENCHMARKS.md, issue 20, C_T stop 21). The rows hold both sets in
    /// the walk order of [`Self::basis_degree`]; entries above a set's own
    /// degree stay zero, so they add nothing (not even a rounding: `x + 0·y
    /// = x` exactly, with or without a fused multiply-add).
    torque_degree: u8,
    pole: Vector3<T>,
    reference_length: T,
    rows: [[T; SETS]; MAX_COEFFS],
    simd: T::Simd,
    /// Use the portable path even where a SIMD path exists.
    portable: bool,
    damping: Matrix3<T>,
    /// Mass properties of the measured object, if known.
    pub body: Option<MassProperties>,
    /// How these coefficients were made.
    pub provenance: Provenance,
    /// Terms outside eqs. (5)-(6), as stored ([`Self::extensions`]).
    extensions: heapless::Vec<Extension, MAX_EXTENSIONS>,
    /// The decoded spin-coupling extension, if any (kept equal to
    /// `extensions` by every method that changes them).
    spin_coupling: Option<SpinCoupling<T>>,
    /// The decoded gravity-coupling extension, if any (as `spin_coupling`).
    gravity_coupling: Option<GravityCoupling<T>>,
    /// The decoded named effects ([`crate::effect`]), at most one of each
    /// kind (as `spin_coupling`).
    effects: heapless::Vec<Effect<T>, MAX_EFFECTS>,
}

/// Most named effects in one model: one of each kind.
pub const MAX_EFFECTS: usize = EffectKind::ALL.len();

impl<T: LaneScalar> Coefficients<T> {
    /// All-zero coefficients of the given degree, pole and reference length
    /// L (m). The pole is normalised.
    pub fn zeros(degree: u8, pole: Vector3<T>, reference_length: T) -> Result<Self, ModelError> {
        let (pole, reference_length) = Self::check_geometry(degree, pole, reference_length)?;
        Ok(Self {
            name: heapless::String::new(),
            degree,
            torque_degree: degree,
            pole,
            reference_length,
            rows: [[T::zero(); SETS]; MAX_COEFFS],
            simd: T::Simd::zeroed(),
            portable: false,
            damping: Matrix3::zeros(),
            body: None,
            provenance: Provenance::default(),
            extensions: heapless::Vec::new(),
            spin_coupling: None,
            gravity_coupling: None,
            effects: heapless::Vec::new(),
        })
    }

    /// Resets `self` in place to all-zero coefficients of the given degree,
    /// pole and reference length, with empty name, body, provenance and
    /// extensions (as [`Self::zeros`], without a stack copy of the model:
    /// that matters on a microcontroller). On error `self` is unchanged.
    pub fn reset(
        &mut self,
        degree: u8,
        pole: Vector3<T>,
        reference_length: T,
    ) -> Result<(), ModelError> {
        self.reset_degrees(degree, degree, pole, reference_length)
    }

    /// [`Self::reset`] with the torque's own degree N_T.
    pub fn reset_degrees(
        &mut self,
        degree: u8,
        torque_degree: u8,
        pole: Vector3<T>,
        reference_length: T,
    ) -> Result<(), ModelError> {
        let (pole, length) = Self::check_geometry(degree, pole, reference_length)?;
        if torque_degree as usize > MAX_DEGREE {
            return Err(ModelError::DegreeTooHigh(torque_degree));
        }
        self.name.clear();
        self.degree = degree;
        self.torque_degree = torque_degree;
        self.pole = pole;
        self.reference_length = length;
        self.rows = [[T::zero(); SETS]; MAX_COEFFS];
        self.simd = T::Simd::zeroed();
        self.damping = Matrix3::zeros();
        self.body = None;
        self.provenance.method.clear();
        self.provenance.source.clear();
        self.provenance.frames_used = 0;
        self.provenance.frames_dropped = 0;
        self.provenance.force_residuals.clear();
        self.provenance.torque_residuals.clear();
        self.provenance.coverage.clear();
        self.extensions.clear();
        self.spin_coupling = None;
        self.gravity_coupling = None;
        self.effects.clear();
        Ok(())
    }

    /// Validates degree, pole and L; returns the unit pole and L.
    fn check_geometry(
        degree: u8,
        pole: Vector3<T>,
        reference_length: T,
    ) -> Result<(Vector3<T>, T), ModelError> {
        if degree as usize > MAX_DEGREE {
            return Err(ModelError::DegreeTooHigh(degree));
        }
        if !crate::math::vector_is_finite(&pole) {
            return Err(ModelError::NonFinite("pole"));
        }
        // Huge and tiny poles keep their direction (`unit_vector`).
        let pole = crate::math::unit_vector(&pole).ok_or(ModelError::BadPole)?;
        if !reference_length.finite() {
            return Err(ModelError::NonFinite("reference_length"));
        }
        if reference_length <= T::zero() {
            return Err(ModelError::BadReferenceLength);
        }
        Ok((pole, reference_length))
    }

    /// SH degree N of the force (alpha, eq. 7).
    pub fn degree(&self) -> u8 {
        self.degree
    }
    /// SH degree N_T of the torque (beta, eq. 8).
    pub fn torque_degree(&self) -> u8 {
        self.torque_degree
    }
    /// The degree the SH basis is evaluated to: `max(N, N_T)`.
    pub fn basis_degree(&self) -> u8 {
        self.degree.max(self.torque_degree)
    }
    /// Number of force (alpha) coefficients per component, `(N+1)^2`.
    pub fn coeff_count(&self) -> usize {
        sh::coeff_count(self.degree as usize)
    }
    /// Number of torque (beta) coefficients per component, `(N_T+1)^2`.
    pub fn torque_coeff_count(&self) -> usize {
        sh::coeff_count(self.torque_degree as usize)
    }
    /// Rows of storage in use: `(max(N, N_T)+1)^2`.
    fn row_count(&self) -> usize {
        sh::coeff_count(self.basis_degree() as usize)
    }
    /// The unit pole Z of the vector basis (body frame).
    pub fn pole(&self) -> Vector3<T> {
        self.pole
    }
    /// Reference length L, m (bounding-box diagonal).
    pub fn reference_length(&self) -> T {
        self.reference_length
    }
    /// Sets L, m.
    pub fn set_reference_length(&mut self, length: T) -> Result<(), ModelError> {
        if !length.finite() {
            return Err(ModelError::NonFinite("reference_length"));
        }
        if length <= T::zero() {
            return Err(ModelError::BadReferenceLength);
        }
        self.reference_length = length;
        Ok(())
    }
    /// Object name.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Sets the name; too long a name is an error (nothing is truncated).
    pub fn set_name(&mut self, name: &str) -> Result<(), ModelError> {
        let mut s = heapless::String::new();
        s.push_str(name)
            .map_err(|_| ModelError::CapacityExceeded("name"))?;
        self.name = s;
        Ok(())
    }
    /// The damping tensor D (symmetric, non-dimensional, eq. 6).
    pub fn damping(&self) -> Matrix3<T> {
        self.damping
    }
    /// Terms outside eqs. (5)-(6), in file order.
    pub fn extensions(&self) -> &[Extension] {
        &self.extensions
    }

    /// Adds an extension. Kinds this build evaluates are checked first (a
    /// malformed payload or a second extension of such a kind is an error);
    /// unknown kinds are kept as they are. Full: `CapacityExceeded`.
    pub fn add_extension(&mut self, e: Extension) -> Result<(), ModelError> {
        let spin = SpinCoupling::from_extension(&e)?;
        let gravity = GravityCoupling::from_extension(&e)?;
        let effect = Effect::from_extension(&e)?;
        if (spin.is_some() && self.spin_coupling.is_some())
            || (gravity.is_some() && self.gravity_coupling.is_some())
            || effect.is_some_and(|f| self.effect(f.kind).is_some())
        {
            return Err(ModelError::DuplicateExtension(e.kind));
        }
        self.extensions
            .push(e)
            .map_err(|_| ModelError::CapacityExceeded("extensions"))?;
        if spin.is_some() {
            self.spin_coupling = spin;
        }
        if gravity.is_some() {
            self.gravity_coupling = gravity;
        }
        if let Some(f) = effect {
            self.effects
                .push(f)
                .map_err(|_| ModelError::CapacityExceeded("effects"))?;
        }
        Ok(())
    }

    /// Removes every extension of `kind`.
    pub fn remove_extensions(&mut self, kind: u16) {
        self.extensions.retain(|e| e.kind != kind);
        match kind {
            extension_kind::SPIN_COUPLING => self.spin_coupling = None,
            extension_kind::GRAVITY_COUPLING => self.gravity_coupling = None,
            tag => self.effects.retain(|f| f.kind.extension_kind() != tag),
        }
    }

    /// The gravity-coupling matrix, if the model has one
    /// ([`crate::gravity_coupling`]); [`crate::rigid_body::AirForces`] adds
    /// its force.
    pub fn gravity_coupling(&self) -> Option<&GravityCoupling<T>> {
        self.gravity_coupling.as_ref()
    }

    /// Sets (or with `None` removes) the gravity-coupling extension.
    pub fn set_gravity_coupling(
        &mut self,
        g: Option<GravityCoupling<T>>,
    ) -> Result<(), ModelError> {
        let ext = g.map(|g| g.to_extension()).transpose()?;
        self.remove_extensions(extension_kind::GRAVITY_COUPLING);
        match ext {
            Some(e) => self.add_extension(e),
            None => Ok(()),
        }
    }

    /// The named effects the model has ([`crate::effect`]); the air
    /// forces ([`crate::rigid_body::AirForces`]) add them and the equations
    /// of motion carry added mass.
    pub fn effects(&self) -> &[Effect<T>] {
        &self.effects
    }

    /// The model's effect of `kind`, if any.
    pub fn effect(&self, kind: EffectKind) -> Option<&Effect<T>> {
        self.effects.iter().find(|f| f.kind == kind)
    }

    /// Sets (replacing one of the same kind) a named effect.
    pub fn set_effect(&mut self, effect: Effect<T>) -> Result<(), ModelError> {
        let ext = effect.to_extension()?;
        self.remove_effect(effect.kind);
        self.add_extension(ext)
    }

    /// Removes the effect of `kind`, if any.
    pub fn remove_effect(&mut self, kind: EffectKind) {
        self.remove_extensions(kind.extension_kind());
    }

    /// The spin-coupling force's tensor, if the model has one
    /// ([`crate::spin_coupling`]); [`Self::wrench`] adds its force.
    pub fn spin_coupling(&self) -> Option<&SpinCoupling<T>> {
        self.spin_coupling.as_ref()
    }

    /// Sets (or with `None` removes) the spin-coupling extension.
    pub fn set_spin_coupling(&mut self, s: Option<SpinCoupling<T>>) -> Result<(), ModelError> {
        let ext = s.map(|s| s.to_extension()).transpose()?;
        self.remove_extensions(extension_kind::SPIN_COUPLING);
        match ext {
            Some(e) => self.add_extension(e),
            None => Ok(()),
        }
    }

    /// Sets D; it must be finite, symmetric positive semi-definite (§4.1).
    /// The symmetric part of `d` is stored.
    pub fn set_damping(&mut self, d: &Matrix3<T>) -> Result<(), ModelError> {
        let six = six_from_symmetric(d);
        if six.iter().any(|x| !x.finite()) {
            return Err(ModelError::NonFinite("damping"));
        }
        if !is_positive_semidefinite(six.map(|x| x.as_f64())) {
            return Err(ModelError::DampingNotPositiveSemidefinite);
        }
        self.damping = symmetric_from_six(six);
        Ok(())
    }

    /// `alpha^i_k` (force, eq. 7); `component` is `i - 1` in `0..3`.
    pub fn alpha(&self, component: usize, k: usize) -> Option<T> {
        self.get(component, k)
    }
    /// `beta^i_k` (torque, eq. 8); `component` is `i - 1` in `0..3`.
    pub fn beta(&self, component: usize, k: usize) -> Option<T> {
        self.get(component + 3, k)
    }
    /// Sets `alpha^i_k`.
    pub fn set_alpha(&mut self, component: usize, k: usize, v: T) -> Result<(), ModelError> {
        if component >= 3 {
            return Err(ModelError::OutOfRange("alpha component"));
        }
        self.set(component, k, v, "alpha")
    }
    /// Sets `beta^i_k`.
    pub fn set_beta(&mut self, component: usize, k: usize, v: T) -> Result<(), ModelError> {
        if component >= 3 {
            return Err(ModelError::OutOfRange("beta component"));
        }
        self.set(component + 3, k, v, "beta")
    }

    /// Row of standard index `k` of set `set` (alpha 0..3, beta 3..6): in
    /// the walk order of the basis degree, `None` above the set's degree.
    fn row_of(&self, set: usize, k: usize) -> Option<usize> {
        let count = if set < 3 {
            self.coeff_count()
        } else {
            self.torque_coeff_count()
        };
        if k >= count {
            return None;
        }
        let (l, m) = sh::degree_order(k);
        sh::walk_position(l, m, self.basis_degree() as usize)
    }

    fn get(&self, set: usize, k: usize) -> Option<T> {
        self.rows.get(self.row_of(set, k)?)?.get(set).copied()
    }

    fn set(&mut self, set: usize, k: usize, v: T, field: &'static str) -> Result<(), ModelError> {
        if !v.finite() {
            return Err(ModelError::NonFinite(field));
        }
        let row = self.row_of(set, k).ok_or(ModelError::OutOfRange(field))?;
        let slot = self
            .rows
            .get_mut(row)
            .and_then(|row| row.get_mut(set))
            .ok_or(ModelError::OutOfRange(field))?;
        *slot = v;
        let (l, m) = sh::degree_order(k);
        self.simd.set(l, m, set, v);
        Ok(())
    }

    /// The six weighted sums of eqs. (7)-(8), `Σ_k [alpha^i_k, beta^i_k]
    /// Y_k(e)`, at a unit body-frame direction: by the SIMD path where this
    /// machine has one ([`crate::lanes`]), unless [`Self::set_portable`] asked for
    /// the portable path.
    #[inline]
    pub fn sh_sums(&self, e: &Vector3<T>) -> [T; SETS] {
        if !self.portable {
            if let Some(sums) = self.simd.accumulate(self.basis_degree() as usize, e) {
                return sums;
            }
        }
        self.sh_sums_portable(e)
    }

    /// [`Self::sh_sums`] by the portable scalar path: what the firmware
    /// runs, identical to the bit on every target.
    pub fn sh_sums_portable(&self, e: &Vector3<T>) -> [T; SETS] {
        let rows = self.rows.get(..self.row_count()).unwrap_or(&[]);
        sh::accumulate(self.basis_degree() as usize, e, rows)
    }

    /// The portable path's rows in walk order, up to the basis degree (the
    /// batch path, [`crate::batch`], streams through them too).
    pub(crate) fn portable_rows(&self) -> &[[T; SETS]] {
        self.rows.get(..self.row_count()).unwrap_or(&[])
    }

    /// Evaluate with the portable path only (e.g. to compare results bit
    /// for bit with the firmware); the SIMD path otherwise.
    pub fn set_portable(&mut self, portable: bool) {
        self.portable = portable;
    }

    /// The same model in another scalar type.
    pub fn cast<U: LaneScalar>(&self) -> Coefficients<U> {
        let c = |x: T| U::of_f64(x.as_f64());
        let mut out = Coefficients {
            name: self.name.clone(),
            degree: self.degree,
            torque_degree: self.torque_degree,
            pole: self.pole.map(c),
            reference_length: c(self.reference_length),
            rows: [[U::zero(); SETS]; MAX_COEFFS],
            simd: U::Simd::zeroed(),
            portable: self.portable,
            damping: self.damping.map(c),
            body: self.body,
            provenance: self.provenance.clone(),
            extensions: self.extensions.clone(),
            spin_coupling: self.spin_coupling.map(|s| SpinCoupling {
                k: s.k.map(|row| row.map(c)),
            }),
            gravity_coupling: self
                .gravity_coupling
                .map(|g| GravityCoupling { g: g.g.map(c) }),
            effects: self
                .effects
                .iter()
                .map(|f| Effect {
                    kind: f.kind,
                    params: f.params.map(c),
                })
                .collect(),
        };
        for k in 0..self.row_count() {
            for set in 0..SETS {
                if let Some(v) = self.get(set, k) {
                    // Finite in, finite out (a cast to f32 can overflow to
                    // infinity; such a coefficient is left zero).
                    let _ = out.set(set, k, c(v), "coefficient");
                }
            }
        }
        out
    }

    /// Changes the degree of force and torque alike: truncates (drops
    /// l > degree) or zero-extends.
    pub fn with_degree(&self, degree: u8) -> Result<Self, ModelError> {
        self.with_degrees(degree, degree)
    }

    /// Changes the torque's degree N_T alone (as [`Self::with_degree`]).
    pub fn with_torque_degree(&self, torque_degree: u8) -> Result<Self, ModelError> {
        self.with_degrees(self.degree, torque_degree)
    }

    /// Changes the force's degree to `degree` and the torque's to
    /// `torque_degree`: truncates (drops l above each) or zero-extends.
    pub fn with_degrees(&self, degree: u8, torque_degree: u8) -> Result<Self, ModelError> {
        for d in [degree, torque_degree] {
            if d as usize > MAX_DEGREE {
                return Err(ModelError::DegreeTooHigh(d));
            }
        }
        let mut out = self.clone();
        out.degree = degree;
        out.torque_degree = torque_degree;
        out.rows = [[T::zero(); SETS]; MAX_COEFFS];
        out.simd = T::Simd::zeroed();
        for k in 0..out.row_count().min(self.row_count()) {
            for set in 0..SETS {
                if let (Some(v), Some(_)) = (self.get(set, k), out.row_of(set, k)) {
                    out.set(set, k, v, "coefficient")?;
                }
            }
        }
        Ok(out)
    }
}
