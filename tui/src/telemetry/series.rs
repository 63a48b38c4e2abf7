//! Which quantities a log holds: the bundled Kitepower excerpt, or the
//! firmware simulator's telemetry CSV (`omniad firmware replay --csv`),
//! recognised by their headers.

use super::FlightLog;

/// How a series is computed from a row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Source {
    /// One column times a factor.
    Column(usize, f64),
    /// The norm of three columns.
    Norm([usize; 3]),
    /// One column minus another.
    Difference(usize, usize),
}

/// One plotted quantity.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Label.
    pub label: &'static str,
    /// Unit.
    pub unit: &'static str,
    /// How to compute it.
    pub source: Source,
    /// A stability eigenvalue (negative is stable): shown with ✓/✗.
    pub eigen: bool,
}

impl Series {
    fn col(label: &'static str, unit: &'static str, c: usize, k: f64) -> Self {
        Self {
            label,
            unit,
            source: Source::Column(c, k),
            eigen: false,
        }
    }

    /// The value in `row` (NaN when missing).
    pub fn value(&self, row: &[f64]) -> f64 {
        let at = |c: usize| row.get(c).copied().unwrap_or(f64::NAN);
        match self.source {
            Source::Column(c, k) => at(c) * k,
            Source::Norm([a, b, c]) => (at(a).powi(2) + at(b).powi(2) + at(c).powi(2)).sqrt(),
            Source::Difference(a, b) => at(a) - at(b),
        }
    }
}

/// What a log holds, from its header: the series, the time column and
/// its factor to seconds.
pub fn detect(log: &FlightLog) -> (Vec<Series>, usize, f64) {
    let find = |n: &str| log.names.iter().position(|h| h == n);
    if let (Some(fx), Some(fy), Some(fz)) = (find("force_x"), find("force_y"), find("force_z")) {
        let mut s = vec![Series {
            label: "|force|",
            unit: "N",
            source: Source::Norm([fx, fy, fz]),
            eigen: false,
        }];
        let (predicted, residual) = (find("tether_predicted"), find("tether_residual"));
        if let (Some(p), Some(r)) = (predicted, residual) {
            // The firmware logs predicted and predicted - measured.
            s.push(Series {
                label: "tether measured",
                unit: "N",
                source: Source::Difference(p, r),
                eigen: false,
            });
        }
        if let Some(c) = predicted {
            s.push(Series::col("tether predicted", "N", c, 1.0));
        }
        if let Some(c) = residual {
            s.push(Series::col("tether residual", "N", c, 1.0));
        }
        for (name, label) in [("eig_0", "λ1"), ("eig_1", "λ2"), ("eig_2", "λ3")] {
            if let Some(c) = find(name) {
                s.push(Series {
                    eigen: true,
                    ..Series::col(label, "N·m/rad", c, 1.0)
                });
            }
        }
        return (s, find("time_ms").unwrap_or(0), 1e-3);
    }
    // The bundled excerpt's renamed columns, then the data set's own names
    // (a whole cycle file `*_NNNN.csv` replays as it is).
    let named = [
        ("tether_force_kg", "tether force", "N", 9.81),
        ("ground_tether_force", "tether force", "N", 9.81),
        ("apparent_wind_m_s", "apparent wind", "m/s", 1.0),
        ("airspeed_apparent_windspeed", "apparent wind", "m/s", 1.0),
        ("kite_height_m", "kite height", "m", 1.0),
        ("kite_height", "kite height", "m", 1.0),
        ("angle_of_attack_deg", "angle of attack", "°", 1.0),
        ("airspeed_angle_of_attack", "angle of attack", "°", 1.0),
        ("reelout_speed_m_s", "reel-out speed", "m/s", 1.0),
        ("ground_tether_reelout_speed", "reel-out speed", "m/s", 1.0),
    ];
    let mut s: Vec<Series> = named
        .iter()
        .filter_map(|(n, l, u, k)| find(n).map(|c| Series::col(l, u, c, *k)))
        .collect();
    if s.is_empty() {
        s = (1..log.names.len().min(6))
            .map(|c| Series::col("column", "", c, 1.0))
            .collect();
    }
    (s, find("time_s").or_else(|| find("time")).unwrap_or(0), 1.0)
}
