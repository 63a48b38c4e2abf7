//! The state CSV `t,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz`: a synthetic set's
//! `truth/<take>.csv`, `omniad reconstruct`'s output and `omniad simulate
//! --csv`. Time in s, position (m) and velocity (m/s) world frame,
//! orientation `[w, x, y, z]` body -> world, angular velocity (rad/s) body
//! frame (the recording format's conventions). One reader, one writer.

use crate::error::{Error, Result};
use crate::input::tracks::{csv_text, number, rows};
use omniad_core::State;
use std::fmt::Write as _;
use std::path::Path;

/// The columns, in order.
pub const STATE_COLUMNS: [&str; 14] = [
    "t", "x", "y", "z", "qw", "qx", "qy", "qz", "vx", "vy", "vz", "wx", "wy", "wz",
];

/// How the time column is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimeFormat {
    /// Shortest text that reads back exactly (synthetic truth: `k / fps`).
    Exact,
    /// Fixed decimals, microseconds (reconstructions, simulations).
    Micros,
}

/// Reads a state CSV: rows of 14 numbers; errors name `file:line: column`.
pub fn read_states(path: &Path) -> Result<Vec<[f64; 14]>> {
    let text = csv_text(path)?;
    let mut out = Vec::new();
    for (line, f) in rows(path, &text, &STATE_COLUMNS)? {
        let mut v = [0.0; 14];
        for ((slot, s), col) in v.iter_mut().zip(&f).zip(STATE_COLUMNS) {
            *slot = number(path, line, col, s)?;
        }
        out.push(v);
    }
    Ok(out)
}

/// The header line, with its newline.
pub fn header() -> String {
    let mut s = STATE_COLUMNS.join(",");
    s.push('\n');
    s
}

/// Appends one row (state `s` at time `t`) to `out`.
pub fn push_row(out: &mut String, t: f64, s: &State<f64>, time: TimeFormat) {
    let q = s.orientation.quaternion();
    let (p, v, w) = (s.position, s.velocity, s.angular_velocity);
    let _ = match time {
        TimeFormat::Exact => write!(out, "{t}"),
        TimeFormat::Micros => write!(out, "{t:.6}"),
    };
    let _ = writeln!(
        out,
        ",{},{},{},{},{},{},{},{},{},{},{},{},{}",
        p.x, p.y, p.z, q.w, q.i, q.j, q.k, v.x, v.y, v.z, w.x, w.y, w.z
    );
}

/// The whole CSV of `(time, state)` rows.
pub fn to_csv<'a>(
    rows: impl IntoIterator<Item = (f64, &'a State<f64>)>,
    time: TimeFormat,
) -> String {
    let mut out = header();
    for (t, s) in rows {
        push_row(&mut out, t, s, time);
    }
    out
}

/// Writes the CSV of `rows` to `path` atomically (temporary file +
/// rename: an interrupted write never leaves half a file).
pub fn write_states<'a>(
    path: &Path,
    rows: impl IntoIterator<Item = (f64, &'a State<f64>)>,
    time: TimeFormat,
) -> Result<()> {
    omniad_io::write_atomic(path, to_csv(rows, time).as_bytes()).map_err(|e| Error::io(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{UnitQuaternion, Vector3};

    #[test]
    fn written_states_read_back() {
        let s = State {
            position: Vector3::new(1.0, -2.5, 0.125),
            orientation: UnitQuaternion::from_euler_angles(0.1, -0.2, 0.3),
            velocity: Vector3::new(0.5, 0.25, -9.0),
            angular_velocity: Vector3::new(3.0, -1.0, 0.0),
        };
        let dir = tempfile::tempdir().expect("dir");
        let path = dir.path().join("take.csv");
        write_states(&path, [(0.0, &s), (1.0 / 60.0, &s)], TimeFormat::Exact).expect("write");
        let back = read_states(&path).expect("read");
        assert_eq!(back.len(), 2);
        let q = s.orientation.quaternion();
        assert_eq!(back[1][0], 1.0 / 60.0);
        assert_eq!(&back[1][1..8], &[1.0, -2.5, 0.125, q.w, q.i, q.j, q.k]);
    }
}
