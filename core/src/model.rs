//! The one model selector: which physics moves a body — vacuum, one of the
//! paper's comparison models (Fig. 12: [`crate::reference::kirchhoff`],
//! [`crate::reference::drag_traction`], [`crate::reference::simplified`])
//! or the OmniAD model (eqs. 5-6, [`AirForces`]). `omniad simulate
//! --model`, the validation report and any other caller build a [`Model`]
//! and hand it to [`crate::integrate::rk4_step`] as its [`Forces`].

use crate::aero::Wrench;
use crate::coefficients::Coefficients;
use crate::reference::drag_traction::DragTraction;
use crate::reference::kirchhoff::Kirchhoff;
use crate::reference::shape::Shape;
use crate::reference::simplified::Simplified;
use crate::rigid_body::{AirForces, Environment, Forces, NoForces, State};
use nalgebra::Matrix3;

/// Which model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModelKind {
    /// No air at all (gravity only).
    Vacuum,
    /// Added mass only (Weißmann & Pinkall 2012).
    Kirchhoff,
    /// Per-element normal drag and traction (Wejchert & Haumann 1991).
    DragTraction,
    /// Per-element angle-of-attack lift and drag (Wu & Popović 2003).
    Simplified,
    /// The OmniAD coefficient model (eqs. 5-6 and its extensions).
    Omniad,
}

impl ModelKind {
    /// Every kind, in the paper's Fig. 12 order.
    pub const ALL: [ModelKind; 5] = [
        Self::Vacuum,
        Self::Kirchhoff,
        Self::DragTraction,
        Self::Simplified,
        Self::Omniad,
    ];

    /// The name on the command line and in reports.
    pub const fn name(self) -> &'static str {
        match self {
            Self::Vacuum => "vacuum",
            Self::Kirchhoff => "kirchhoff",
            Self::DragTraction => "drag-traction",
            Self::Simplified => "simplified",
            Self::Omniad => "omniad",
        }
    }

    /// The kind named `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }
}

/// Why a [`Model`] could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SelectError {
    /// A comparison model needs the body's shape.
    NeedsShape(ModelKind),
    /// The OmniAD model needs coefficients.
    NeedsCoefficients,
}

impl core::fmt::Display for SelectError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::NeedsShape(k) => write!(f, "model {} needs a shape (plate or box)", k.name()),
            Self::NeedsCoefficients => write!(f, "model omniad needs a coefficient file"),
        }
    }
}

/// A model ready to move a body.
#[derive(Clone, Copy, Debug)]
pub enum Model<'a> {
    /// No air.
    Vacuum(NoForces),
    /// Added mass only.
    Kirchhoff(Kirchhoff),
    /// Drag and traction.
    DragTraction(DragTraction),
    /// Simplified aerodynamics.
    Simplified(Simplified),
    /// The OmniAD model.
    Omniad(AirForces<'a, f64>),
}

impl<'a> Model<'a> {
    /// The model of `kind` for a body of `shape` (comparison models) or
    /// with `coefficients` (OmniAD) in `environment`.
    pub fn new(
        kind: ModelKind,
        shape: Option<&Shape>,
        coefficients: Option<&'a Coefficients<f64>>,
        environment: Environment<f64>,
    ) -> Result<Self, SelectError> {
        let shape = || shape.copied().ok_or(SelectError::NeedsShape(kind));
        Ok(match kind {
            ModelKind::Vacuum => Self::Vacuum(NoForces),
            ModelKind::Kirchhoff => Self::Kirchhoff(Kirchhoff::new(&shape()?, environment)),
            ModelKind::DragTraction => Self::DragTraction(DragTraction {
                shape: shape()?,
                environment,
            }),
            ModelKind::Simplified => Self::Simplified(Simplified {
                shape: shape()?,
                environment,
            }),
            ModelKind::Omniad => Self::Omniad(AirForces {
                model: coefficients.ok_or(SelectError::NeedsCoefficients)?,
                environment,
            }),
        })
    }

    /// Which kind it is.
    pub fn kind(&self) -> ModelKind {
        match self {
            Self::Vacuum(_) => ModelKind::Vacuum,
            Self::Kirchhoff(_) => ModelKind::Kirchhoff,
            Self::DragTraction(_) => ModelKind::DragTraction,
            Self::Simplified(_) => ModelKind::Simplified,
            Self::Omniad(_) => ModelKind::Omniad,
        }
    }
}

impl Forces<f64> for Model<'_> {
    fn wrench(&self, t: f64, state: &State<f64>) -> Wrench<f64> {
        match self {
            Self::Vacuum(m) => m.wrench(t, state),
            Self::Kirchhoff(m) => m.wrench(t, state),
            Self::DragTraction(m) => m.wrench(t, state),
            Self::Simplified(m) => m.wrench(t, state),
            Self::Omniad(m) => m.wrench(t, state),
        }
    }

    fn added_mass(&self) -> Option<Matrix3<f64>> {
        match self {
            Self::Vacuum(_) | Self::DragTraction(_) | Self::Simplified(_) => None,
            Self::Kirchhoff(m) => m.added_mass(),
            Self::Omniad(m) => m.added_mass(),
        }
    }
}

#[cfg(test)]
mod tests;
