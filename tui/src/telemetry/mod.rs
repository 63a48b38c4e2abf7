//! View 4: telemetry. Replays a flight log (the bundled Kitepower cycle,
//! CC-BY 4.0, see `data/flight/README.md`) with sparklines.

pub mod series;
pub mod view;

use ratatui::crossterm::event::{KeyCode, KeyEvent};

/// The bundled log: Kitepower 2019-10-08, pumping cycle 1.
pub const BUNDLED: &str = include_str!("../../../data/flight/kitepower-2019-10-08-cycle1.csv");
/// Largest telemetry file read, bytes.
pub const MAX_LOG_BYTES: usize = 256 << 20;
/// Display frame rate while replaying, Hz.
pub const FRAME_HZ: f64 = 30.0;

/// A parsed flight log: named columns of numbers, first column time (s).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FlightLog {
    /// Column names (from the header).
    pub names: Vec<String>,
    /// Rows of values (NaN where missing).
    pub rows: Vec<Vec<f64>>,
}

impl FlightLog {
    /// Parses comma-separated text with a header line.
    pub fn parse(text: &str) -> Self {
        let mut lines = omniad_io::csv_lines(text);
        let names = lines
            .next()
            .unwrap_or("")
            .split(',')
            .map(|s| s.trim().to_string())
            .collect();
        let rows = lines
            .filter(|l| !l.trim().is_empty())
            .map(|l| {
                l.split(',')
                    .map(|v| {
                        v.trim()
                            .trim_end_matches('\r')
                            .parse::<f64>()
                            .unwrap_or(f64::NAN)
                    })
                    .collect()
            })
            .collect();
        Self { names, rows }
    }

    /// Column `c` as a series.
    pub fn column(&self, c: usize) -> Vec<f64> {
        self.rows
            .iter()
            .map(|r| r.get(c).copied().unwrap_or(f64::NAN))
            .collect()
    }

    /// Duration, s (last time stamp).
    pub fn duration(&self) -> f64 {
        self.rows
            .last()
            .and_then(|r| r.first())
            .copied()
            .unwrap_or(0.0)
    }
}

/// The telemetry view's state.
#[derive(Clone, Debug)]
pub struct TelemetryView {
    /// Label of the source.
    pub source: String,
    /// The log being replayed.
    pub log: FlightLog,
    /// Replay position, samples (fractional).
    pub cursor: f64,
    /// Replaying on each tick.
    pub playing: bool,
    /// Replay speed, × real time.
    pub speed: f64,
    /// The plotted quantities.
    pub series: Vec<series::Series>,
    /// Time of each row, s.
    pub time: Vec<f64>,
    /// Mean sample rate, Hz.
    pub rate_hz: f64,
}

impl TelemetryView {
    /// The bundled log, paused one minute in (the traction phase).
    pub fn bundled() -> Self {
        Self::new(
            "replay: Kitepower 2019-10-08 cycle 1 (CC-BY 4.0)".into(),
            FlightLog::parse(BUNDLED),
        )
    }

    /// The log at `path` (a Kitepower cycle file or excerpt, the firmware's
    /// `--csv` output, or any CSV with a time column first); an unreadable
    /// or empty file is an error naming it — never a silent fallback to the
    /// bundled log.
    pub fn load(path: &str) -> Result<Self, String> {
        let bytes = omniad_io::read_capped(std::path::Path::new(path), MAX_LOG_BYTES)
            .map_err(|e| format!("--telemetry {path}: {e}"))?;
        let text =
            String::from_utf8(bytes).map_err(|_| format!("--telemetry {path}: not UTF-8 text"))?;
        let log = FlightLog::parse(text.strip_prefix('\u{feff}').unwrap_or(&text));
        if log.rows.is_empty() {
            return Err(format!("--telemetry {path}: no data rows"));
        }
        let name = std::path::Path::new(path)
            .file_name()
            .map_or(path.into(), |n| n.to_string_lossy().into_owned());
        Ok(Self::new(format!("replay: {name}"), log))
    }

    /// A paused replay of `log`, one minute in (or half-way through a
    /// shorter log).
    pub fn new(source: String, log: FlightLog) -> Self {
        let (series, tc, k) = series::detect(&log);
        let time: Vec<f64> = log.column(tc).iter().map(|t| t * k).collect();
        let span = time.last().copied().unwrap_or(0.0) - time.first().copied().unwrap_or(0.0);
        let rate_hz = if span > 0.0 {
            (time.len() - 1) as f64 / span
        } else {
            10.0
        };
        let start = (60.0 * rate_hz)
            .min(log.rows.len().saturating_sub(1) as f64 / 2.0)
            .floor();
        Self {
            source,
            log,
            cursor: start,
            playing: false,
            speed: 1.0,
            series,
            time,
            rate_hz,
        }
    }

    /// Duration, s.
    pub fn duration(&self) -> f64 {
        self.time.last().copied().unwrap_or(0.0) - self.time.first().copied().unwrap_or(0.0)
    }

    /// Index of the current sample.
    pub fn index(&self) -> usize {
        (self.cursor.max(0.0) as usize).min(self.log.rows.len().saturating_sub(1))
    }

    /// Advances one display frame; loops at the end.
    pub fn tick(&mut self) {
        let n = self.log.rows.len() as f64;
        if n > 0.0 {
            self.cursor = (self.cursor + self.speed * self.rate_hz / FRAME_HZ) % n;
        }
    }

    /// Handles a key; returns whether it was used.
    pub fn on_key(&mut self, key: KeyEvent) -> bool {
        let last = self.log.rows.len().saturating_sub(1) as f64;
        match key.code {
            KeyCode::Char(' ') => self.playing = !self.playing,
            KeyCode::Left => self.cursor = (self.cursor - 10.0 * self.rate_hz).max(0.0),
            KeyCode::Right => self.cursor = (self.cursor + 10.0 * self.rate_hz).min(last),
            KeyCode::Home => self.cursor = 0.0,
            KeyCode::End => self.cursor = last,
            KeyCode::Char('+') | KeyCode::Char('=') => self.speed = (self.speed * 2.0).min(64.0),
            KeyCode::Char('-') => self.speed = (self.speed / 2.0).max(0.25),
            KeyCode::Char('.') => self.tick(),
            _ => return false,
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(text: &str) -> (tempfile::TempDir, String) {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("log.csv");
        std::fs::write(&p, text).unwrap();
        (dir, p.to_string_lossy().into_owned())
    }

    #[test]
    fn a_firmware_log_shows_measured_predicted_and_residual_tension() {
        let (_d, p) = write(
            "time_ms,force_x,force_y,force_z,tether_predicted,tether_residual\r\n\
             0,1,2,2,3000,500\r\n100,1,2,2,3100,-100\r\n",
        );
        let v = TelemetryView::load(&p).unwrap();
        let labels: Vec<_> = v.series.iter().map(|s| s.label).collect();
        assert_eq!(
            labels,
            [
                "|force|",
                "tether measured",
                "tether predicted",
                "tether residual"
            ]
        );
        let row = &v.log.rows[1];
        assert_eq!(
            v.series[1].value(row),
            3200.0,
            "measured = predicted - residual"
        );
        assert!(v.source.contains("log.csv"));
    }

    #[test]
    fn a_missing_or_empty_log_is_an_error_naming_it() {
        let (_d, p) = write("a,b\n");
        let e = TelemetryView::load(&p).unwrap_err();
        assert!(e.contains("log.csv") && e.contains("no data rows"), "{e}");
        let e = TelemetryView::load("/no/such/log.csv").unwrap_err();
        assert!(e.contains("/no/such/log.csv"), "{e}");
    }

    #[test]
    fn a_whole_kitepower_cycle_file_replays_by_its_own_column_names() {
        let p = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../data/flight/kitepower-2019-10-08/20191008_0001.csv"
        );
        let v = TelemetryView::load(p).unwrap();
        let labels: Vec<_> = v.series.iter().map(|s| s.label).collect();
        assert!(labels.contains(&"tether force") && labels.contains(&"apparent wind"));
        assert!((v.duration() - 133.8).abs() < 1.0, "{}", v.duration());
    }
}
