//! The one kite verdict: the conjunction of the tests a kite must pass to
//! fly, in the order they can fail, naming the first that fails.
//!
//! 0. the frame is one rigid piece ([`crate::connect`]) — else
//!    `disconnected` (the cells would fly apart on the line);
//! 1. geometry (§7: no two primitives overlap along the wind) — else
//!    `unflyable`;
//! 2. the string pulls down at the file's attitude (§7, `f_string·g > 0`)
//!    — else `string_pushes`;
//! 3. the flight model has an equilibrium near the file's attitude
//!    ([`crate::equilibrium`]) — else `no_equilibrium`;
//! 4. the static test there on §7's Jacobian `J = ∂T_kite/∂Θ`: no static
//!    divergence (every real eigenvalue of `J` negative; see
//!    `check::StaticReport::stable` for why not the paper's stricter
//!    symmetric-part test, which is still reported) — else
//!    `statically_unstable`;
//! 5. every mode of the linearised tethered kite decays
//!    ([`crate::modes`]) — else `dynamically_unstable`;
//!
//!    unless, for 4 and 5, the kite let go from the equilibrium along its
//!    fastest-growing mode ends, in the steady-wind flight, in a bounded
//!    motion inside the flight's limits ([`crate::limit_cycle`]: a limit
//!    cycle; a divergence that ends at another, stable equilibrium is
//!    judged there, [`crate::settle`]). Such a kite flies: the growth the
//!    linearisation predicts is real (the flight grows at the predicted
//!    rate), but it stops at a small amplitude. So `statically_unstable`
//!    and `dynamically_unstable` name a divergence or a growing mode that
//!    does NOT end inside the limits (it crashes, loops, or lies low);
//!    `stable` means the kite rests, or circles on a small limit cycle
//!    (`modes.limit_cycle` in the JSON says which), inside the limits;
//! 6. the gusts of `kite fly` keep it inside the flight's limits on every
//!    one of the seeds it is flown on: the gust response's extremes of
//!    line elevation, spin and height (the model linearised at the gusts'
//!    amplitude, [`crate::equivalent`]; one run's expected extremes,
//!    [`crate::gusts`]), and the nonlinear flight through
//!    the largest gusts and lulls of each wind component at the same
//!    statistic ([`crate::strong_gust`]) — else `gust_sensitive`.

use serde::Serialize;

/// The verdict: `stable` exactly when every test passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Every test passes: the kite will fly (at rest on its line, or on a
    /// small limit cycle inside the flight's limits).
    Stable,
    /// The frame is in more than one piece.
    Disconnected,
    /// Primitives overlap along the wind (geometric refusal).
    Unflyable,
    /// The string would have to push the kite up.
    StringPushes,
    /// No equilibrium of the tethered kite near the file's attitude.
    NoEquilibrium,
    /// A divergent direction of §7's Jacobian at equilibrium, and the
    /// divergence does not end inside the flight's limits.
    StaticallyUnstable,
    /// A growing mode of the linearised tethered kite that does not
    /// saturate inside the flight's limits.
    DynamicallyUnstable,
    /// Every mode decays, but the gusts are predicted to swing the kite
    /// past the flight's limits (line too low, spinning, on the ground).
    GustSensitive,
}

impl Verdict {
    /// The name `kite check --json` prints.
    pub fn name(self) -> &'static str {
        match self {
            Self::Stable => "stable",
            Self::Disconnected => "disconnected",
            Self::Unflyable => "unflyable",
            Self::StringPushes => "string_pushes",
            Self::NoEquilibrium => "no_equilibrium",
            Self::StaticallyUnstable => "statically_unstable",
            Self::DynamicallyUnstable => "dynamically_unstable",
            Self::GustSensitive => "gust_sensitive",
        }
    }
}

/// What each test found.
pub struct Tests {
    /// Parts of the frame not joined to the rest.
    pub unjoined: usize,
    /// Overlapping primitive pairs.
    pub overlaps: usize,
    /// The string pulls down.
    pub pulls_down: bool,
    /// An equilibrium was found.
    pub equilibrium: bool,
    /// No static divergence at the equilibrium.
    pub statically_stable: bool,
    /// Every mode decays.
    pub dynamically_stable: bool,
    /// The motion a growing mode or divergence ends in stays inside the
    /// flight's limits (a limit cycle; [`crate::modes::ModesReport::bounded`]).
    pub saturates: bool,
    /// The predicted gust response stays inside the flight's limits.
    pub gust_tolerant: bool,
}

/// The first failing test, or `Stable`.
pub fn verdict(t: &Tests) -> Verdict {
    if t.unjoined > 0 {
        Verdict::Disconnected
    } else if t.overlaps > 0 {
        Verdict::Unflyable
    } else if !t.pulls_down {
        Verdict::StringPushes
    } else if !t.equilibrium {
        Verdict::NoEquilibrium
    } else if !t.statically_stable && !t.saturates {
        Verdict::StaticallyUnstable
    } else if !t.dynamically_stable && !t.saturates {
        Verdict::DynamicallyUnstable
    } else if !t.gust_tolerant {
        Verdict::GustSensitive
    } else {
        Verdict::Stable
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn passing() -> Tests {
        Tests {
            unjoined: 0,
            overlaps: 0,
            pulls_down: true,
            equilibrium: true,
            statically_stable: true,
            dynamically_stable: true,
            saturates: false,
            gust_tolerant: true,
        }
    }

    #[test]
    fn a_bounded_motion_passes_the_linear_tests_but_not_the_gust_test() {
        let grows = Tests {
            dynamically_stable: false,
            ..passing()
        };
        assert_eq!(verdict(&grows), Verdict::DynamicallyUnstable);
        let diverges = Tests {
            statically_stable: false,
            ..grows
        };
        assert_eq!(verdict(&diverges), Verdict::StaticallyUnstable);
        let saturates = Tests {
            saturates: true,
            ..diverges
        };
        assert_eq!(verdict(&saturates), Verdict::Stable);
        let gusty = Tests {
            gust_tolerant: false,
            ..saturates
        };
        assert_eq!(verdict(&gusty), Verdict::GustSensitive);
        assert_eq!(verdict(&passing()), Verdict::Stable);
    }
}
