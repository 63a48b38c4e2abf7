//! View 4: telemetry. Replays a flight log (the bundled Kitepower cycle,
//! CC-BY 4.0, see `data/flight/README.md`) with sparklines.

pub mod series;
pub mod view;

use ratatui::crossterm::event::{KeyCode, KeyEvent};

/// The bundled log: Kitepower 2019-10-08, pumping cycle 1.
pub const BUNDLED: &str = include_str!("../../../data/flight/kitepower-2019-10-08-cycle1.csv");
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
        let mut lines = text.lines();
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
                    .map(|v| v.trim().parse::<f64>().unwrap_or(f64::NAN))
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
