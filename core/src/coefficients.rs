//! The OmniAD coefficient model: alpha, beta (eqs. 7-8), the damping tensor
//! D (eq. 6), the object's reference length L and pole Z, the rigid body it
//! was measured on, provenance, and model extensions.

use crate::gravity_coupling::GravityCoupling;
use crate::lanes::SimdCoefficients;
use crate::math::{is_positive_semidefinite, six_from_symmetric, symmetric_from_six, Real};
use crate::sh::{self, MAX_COEFFS, MAX_DEGREE};
use crate::spin_coupling::SpinCoupling;
use nalgebra::{Matrix3, Vector3};

/// Number of interleaved coefficient sets: `alpha^1..3`, `beta^1..3`.
pub const SETS: usize = 6;
/// Longest object name, in bytes (UTF-8).
pub const NAME_CAPACITY: usize = 64;
/// Longest free-text provenance field, in bytes.
pub const TEXT_CAPACITY: usize = 128;
/// Most iterations whose residuals are recorded.
pub const MAX_ITERATIONS: usize = 16;
/// Coverage grid: longitude divisions (as the paper's §6 grid).
pub const COVERAGE_LON: usize = 32;
/// Coverage grid: latitude divisions.
pub const COVERAGE_LAT: usize = 16;
/// Number of coverage cells.
pub const COVERAGE_CELLS: usize = COVERAGE_LON * COVERAGE_LAT;
/// Most model extensions in one model.
pub const MAX_EXTENSIONS: usize = 8;
/// Largest extension payload, in bytes.
pub const EXTENSION_CAPACITY: usize = 112;

/// Why a model (or a value for it) is not acceptable. Small and `Copy`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModelError {
    /// Degree above [`MAX_DEGREE`].
    DegreeTooHigh(u8),
    /// A number is NaN or infinite; names the field.
    NonFinite(&'static str),
    /// The pole is zero-length.
    BadPole,
    /// The reference length is not positive.
    BadReferenceLength,
    /// D is not symmetric positive semi-definite.
    DampingNotPositiveSemidefinite,
    /// Mass not positive or inertia not positive definite.
    BadBody,
    /// A fixed-capacity field is full; names the field.
    CapacityExceeded(&'static str),
    /// Index out of range; names what was indexed.
    OutOfRange(&'static str),
    /// A second extension of a kind a model holds once (the kind).
    DuplicateExtension(u16),
}

impl core::fmt::Display for ModelError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::DegreeTooHigh(n) => write!(f, "degree {n} is above the maximum {MAX_DEGREE}"),
            Self::NonFinite(field) => write!(f, "non-finite number in {field}"),
            Self::BadPole => write!(f, "pole must be a non-zero vector"),
            Self::BadReferenceLength => write!(f, "reference length must be positive"),
            Self::DampingNotPositiveSemidefinite => {
                write!(
                    f,
                    "damping tensor D is not symmetric positive semi-definite"
                )
            }
            Self::BadBody => write!(f, "mass must be positive and inertia positive definite"),
            Self::CapacityExceeded(field) => write!(f, "{field} exceeds its fixed capacity"),
            Self::OutOfRange(what) => write!(f, "{what} index out of range"),
            Self::DuplicateExtension(kind) => {
                write!(f, "a model holds one extension of kind {kind}")
            }
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for ModelError {}

/// Mass properties of the object the coefficients were measured on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProperties {
    /// Mass M, kg.
    pub mass: f64,
    /// Inertia tensor about the centre of mass, body frame, kg m²,
    /// `[xx, yy, zz, xy, xz, yz]`.
    pub inertia: [f64; 6],
}

/// How the coefficients were made.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Provenance {
    /// Method, e.g. `"fit-lsq"`, `"fit-paper"`, `"projection"`.
    pub method: heapless::String<32>,
    /// Free text: source data set or generating command.
    pub source: heapless::String<TEXT_CAPACITY>,
    /// Frames used by the fit.
    pub frames_used: u32,
    /// Frames dropped (stability enforcement, gating, ...).
    pub frames_dropped: u32,
    /// RMS force-coefficient residual per refinement iteration
    /// (non-dimensional, eq. 5).
    pub force_residuals: heapless::Vec<f64, MAX_ITERATIONS>,
    /// RMS torque-coefficient residual per refinement iteration.
    pub torque_residuals: heapless::Vec<f64, MAX_ITERATIONS>,
    /// Frames per direction cell on a [`COVERAGE_LON`] x [`COVERAGE_LAT`]
    /// grid (longitude-major, latitude from +Z to -Z about the pole);
    /// empty when unknown.
    pub coverage: heapless::Vec<u16, COVERAGE_CELLS>,
}

/// Kinds of model extension known to this version. Unknown kinds found in
/// a file are kept (and written back) but not evaluated.
pub mod extension_kind {
    /// Added mass (reserved for the residual-analysis work).
    pub const ADDED_MASS: u16 = 1;
    /// Buoyancy of displaced air (reserved).
    pub const BUOYANCY: u16 = 2;
    /// A force bilinear in Ω and V ([`crate::spin_coupling`]).
    pub const SPIN_COUPLING: u16 = 3;
    /// A force linear in gravity seen from the body: buoyancy and added
    /// mass ([`crate::gravity_coupling`]).
    pub const GRAVITY_COUPLING: u16 = 4;
}

/// A model extension: a term outside eqs. (5)-(6), stored as a tagged,
/// versioned byte payload so that readers that do not know a kind can still
/// load the file and keep the term.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Extension {
    /// See [`extension_kind`].
    pub kind: u16,
    /// Version of this kind's payload layout.
    pub version: u8,
    /// The payload (postcard of the kind's parameters).
    pub data: heapless::Vec<u8, EXTENSION_CAPACITY>,
}

/// The OmniAD coefficients of one object.
///
/// Storage is laid out for evaluation speed ([`lanes`]): rows of the six
/// sets `[alpha^1..3, beta^1..3]` in the scalar path's walk order, and,
/// where the scalar type has a SIMD path, a second copy in its lane layout
/// (entries beyond the degree stay zero). The public accessors take the
/// standard index `k = l*l + l + m` and keep both copies equal.
#[derive(Clone, Debug, PartialEq)]
pub struct Coefficients<T: Real> {
    name: heapless::String<NAME_CAPACITY>,
    degree: u8,
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
}

impl<T: Real> Coefficients<T> {
    /// All-zero coefficients of the given degree, pole and reference length
    /// L (m). The pole is normalised.
    pub fn zeros(degree: u8, pole: Vector3<T>, reference_length: T) -> Result<Self, ModelError> {
        let (pole, reference_length) = Self::check_geometry(degree, pole, reference_length)?;
        Ok(Self {
            name: heapless::String::new(),
            degree,
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
        let (pole, length) = Self::check_geometry(degree, pole, reference_length)?;
        self.name.clear();
        self.degree = degree;
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
        let len = crate::math::norm(&pole);
        if len <= T::zero() {
            return Err(ModelError::BadPole);
        }
        if !reference_length.finite() {
            return Err(ModelError::NonFinite("reference_length"));
        }
        if reference_length <= T::zero() {
            return Err(ModelError::BadReferenceLength);
        }
        Ok((pole / len, reference_length))
    }

    /// SH degree N.
    pub fn degree(&self) -> u8 {
        self.degree
    }
    /// Number of SH coefficients per component, `(N+1)^2`.
    pub fn coeff_count(&self) -> usize {
        sh::coeff_count(self.degree as usize)
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
        if (spin.is_some() && self.spin_coupling.is_some())
            || (gravity.is_some() && self.gravity_coupling.is_some())
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
        Ok(())
    }

    /// Removes every extension of `kind`.
    pub fn remove_extensions(&mut self, kind: u16) {
        self.extensions.retain(|e| e.kind != kind);
        match kind {
            extension_kind::SPIN_COUPLING => self.spin_coupling = None,
            extension_kind::GRAVITY_COUPLING => self.gravity_coupling = None,
            _ => {}
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

    /// Row of standard index `k` at this model's degree.
    fn row_of(&self, k: usize) -> Option<usize> {
        if k >= self.coeff_count() {
            return None;
        }
        let (l, m) = sh::degree_order(k);
        sh::walk_position(l, m, self.degree as usize)
    }

    fn get(&self, set: usize, k: usize) -> Option<T> {
        self.rows.get(self.row_of(k)?)?.get(set).copied()
    }

    fn set(&mut self, set: usize, k: usize, v: T, field: &'static str) -> Result<(), ModelError> {
        if !v.finite() {
            return Err(ModelError::NonFinite(field));
        }
        let row = self.row_of(k).ok_or(ModelError::OutOfRange(field))?;
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
            if let Some(sums) = self.simd.accumulate(self.degree as usize, e) {
                return sums;
            }
        }
        self.sh_sums_portable(e)
    }

    /// [`Self::sh_sums`] by the portable scalar path: what the firmware
    /// runs, identical to the bit on every target.
    pub fn sh_sums_portable(&self, e: &Vector3<T>) -> [T; SETS] {
        let rows = self.rows.get(..self.coeff_count()).unwrap_or(&[]);
        sh::accumulate(self.degree as usize, e, rows)
    }

    /// Evaluate with the portable path only (e.g. to compare results bit
    /// for bit with the firmware); the SIMD path otherwise.
    pub fn set_portable(&mut self, portable: bool) {
        self.portable = portable;
    }

    /// The same model in another scalar type.
    pub fn cast<U: Real>(&self) -> Coefficients<U> {
        let c = |x: T| U::of_f64(x.as_f64());
        let mut out = Coefficients {
            name: self.name.clone(),
            degree: self.degree,
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
        };
        for k in 0..self.coeff_count() {
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

    /// Changes the degree: truncates (drops l > degree) or zero-extends.
    pub fn with_degree(&self, degree: u8) -> Result<Self, ModelError> {
        if degree as usize > MAX_DEGREE {
            return Err(ModelError::DegreeTooHigh(degree));
        }
        let mut out = self.clone();
        out.degree = degree;
        out.rows = [[T::zero(); SETS]; MAX_COEFFS];
        out.simd = T::Simd::zeroed();
        for k in 0..out.coeff_count().min(self.coeff_count()) {
            for set in 0..SETS {
                if let Some(v) = self.get(set, k) {
                    out.set(set, k, v, "coefficient")?;
                }
            }
        }
        Ok(out)
    }
}
