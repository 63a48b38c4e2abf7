//! What a coefficient file says about the model beyond the model itself:
//! the measured object's mass properties and how the coefficients were made
//! (provenance). The model ([`crate::Coefficients`]) carries them so that a
//! file round-trips, but never evaluates them.

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
