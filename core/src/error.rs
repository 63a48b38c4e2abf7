//! What can be wrong with a coefficient model or a value for it: one small
//! `Copy` enum shared by the model, its extensions and the file reader.

use crate::sh::MAX_DEGREE;

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
