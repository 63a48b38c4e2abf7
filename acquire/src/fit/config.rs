//! Settings of the least-squares fit (`crate::fit::lsq`).

/// Settings of the least-squares fit.
#[derive(Clone, Debug, PartialEq)]
pub struct LsqConfig {
    /// SH degree N.
    pub degree: usize,
    /// Smoothing weight relative to the mean data weight per coefficient
    /// (dimensionless; default 1e-3). The force and torque fits choose
    /// their own by cross-validation when `cross_validate` is set and there
    /// are enough takes (see `crate::fit::select`).
    pub smoothing: f64,
    /// Order `p` of the force fit's smoothness penalty: SH degree `l` is
    /// penalised by `l(l+1) (l(l+1)/(N(N+1)))^(p-1)`, a Sobolev-type norm
    /// of order `p` on the sphere, scaled so that degree N costs `N(N+1)`
    /// whatever `p` (the smoothing weights of every order then sit in the
    /// same range). Order 1 is the Dirichlet energy; higher orders hold
    /// the highest degrees down harder, where the reconstruction's noise
    /// would otherwise go. `None` (default): cross-validation chooses it
    /// among `SMOOTHNESS_ORDERS` together with the weight (order 2 without
    /// cross-validation). The torque fit always chooses among all orders
    /// (order 1 without cross-validation).
    pub smoothness_order: Option<u32>,
    /// Choose the force and torque fits' smoothing by leave-one-take-out
    /// cross-validation (default true).
    pub cross_validate: bool,
    /// Fit the model extensions (spin coupling, gravity coupling) and
    /// keep those that predict held-out takes better
    /// ([`crate::fit::extensions`]; default true).
    pub extensions: bool,
    /// Smallest allowed eigenvalue of D relative to its largest (default 1e-3).
    pub damping_floor: f64,
    /// Required margin of `-C_F(E)·E` (default 1e-3).
    pub thrust_margin: f64,
    /// SH degree N_T of the final torque fit. `None` (default): N or N+2
    /// (within the core's maximum), chosen by the held-out takes' torque
    /// error (`crate::fit::torque::refit_final_torque`).
    pub torque_degree: Option<usize>,
    /// Half-width `m` of the windows the final torque fit takes its frames
    /// in ([`crate::fit::torque_window`]; 1: each frame alone; default
    /// [`FINAL_TORQUE_WINDOW`]).
    pub torque_window: usize,
}

/// The final torque fit's window half-width `m`
/// ([`crate::fit::torque_window`]): 2 gained less than 3 on the six sets it
/// was chosen on, 4-5 no more, 7 lost (BENCHMARKS.md, issue 20, stop 34).
pub const FINAL_TORQUE_WINDOW: usize = 3;

impl Default for LsqConfig {
    fn default() -> Self {
        Self {
            degree: 8,
            smoothing: 1e-3,
            smoothness_order: None,
            cross_validate: true,
            extensions: true,
            damping_floor: 1e-3,
            thrust_margin: 1e-3,
            torque_degree: None,
            torque_window: FINAL_TORQUE_WINDOW,
        }
    }
}
