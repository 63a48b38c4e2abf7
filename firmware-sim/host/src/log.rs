//! Flight logs -> sensor frames (the firmware's input).
//!
//! Two CSV layouts, told apart by their header: a Kitepower log (columns
//! by name, see `data/flight/README.md`: Euler angles and kg of tether
//! force, converted here) and a synthetic log
//! (`time_s,qw,qx,qy,qz,p,q,r,airspeed,aoa_deg,tether_n,depower,steering`,
//! already in the frame's units). An empty or `nan` sensor cell is a
//! dropout and goes to the firmware as NaN, which the firmware must count
//! and skip; text that is not a number, a missing field, and a time that
//! is not a number of seconds from 0 to 1e12 are errors naming file, line
//! and column, because they are a broken file, not a sensor reading.

use anyhow::{anyhow, bail, Context, Result};
use omniad_fw_pipeline::SensorFrame;
use std::path::Path;

/// Longest log read, bytes (about 2.5 million rows; `/dev/zero` is an
/// error, not all memory).
const MAX_LOG_BYTES: usize = 256 << 20;
/// Standard gravity, m/s²: Kitepower logs tether force in kg.
const G: f64 = 9.806_65;

/// The columns a frame is made of, in the order [`to_frame`] reads them;
/// the first is the time, s.
type Columns = [&'static str; 12];

const KITEPOWER: Columns = [
    "time",
    "kite_1_roll",
    "kite_1_pitch",
    "kite_1_yaw",
    "kite_1_roll_rate",
    "kite_1_pitch_rate",
    "kite_1_yaw_rate",
    "airspeed_apparent_windspeed",
    "airspeed_angle_of_attack",
    "ground_tether_force",
    "kite_actual_depower",
    "kite_actual_steering",
];

const SYNTHETIC: [&str; 13] = [
    "time_s", "qw", "qx", "qy", "qz", "p", "q", "r", "airspeed", "aoa_deg", "tether_n", "depower",
    "steering",
];

/// Reads at most `max` frames of a flight log.
pub(crate) fn read_log(path: &Path, max: Option<usize>) -> Result<Vec<SensorFrame>> {
    let bytes = omniad_io::read_capped(path, MAX_LOG_BYTES)
        .with_context(|| format!("cannot read {}", path.display()))?;
    let text = std::str::from_utf8(&bytes)
        .map_err(|e| anyhow!("{}: not UTF-8 text ({e})", path.display()))?;
    parse_log(&path.display().to_string(), text, max)
}

/// [`read_log`] on the file's text; `name` is the file, for errors.
fn parse_log(name: &str, text: &str, max: Option<usize>) -> Result<Vec<SensorFrame>> {
    let mut lines = omniad_io::csv_lines(text).enumerate();
    let header: Vec<&str> = match lines.next() {
        Some((_, h)) => h.split(',').map(str::trim).collect(),
        None => bail!("{name}: empty file (no header line)"),
    };
    let kitepower = header.contains(&"airspeed_apparent_windspeed");
    let names: &[&'static str] = if kitepower { &KITEPOWER } else { &SYNTHETIC };
    let idx: Vec<usize> = names
        .iter()
        .map(|n| {
            let i = header.iter().position(|h| h == n);
            i.ok_or_else(|| anyhow!("{name}: no column `{n}`"))
        })
        .collect::<Result<_>>()?;
    let mut frames = Vec::new();
    for (i, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        if max.is_some_and(|m| frames.len() >= m) {
            break;
        }
        let place = |col: usize| {
            let h = header.get(col).copied().unwrap_or("");
            format!("{name}: line {}, column {} (`{h}`)", i + 1, col + 1)
        };
        let cells: Vec<&str> = line.split(',').collect();
        let mut v = Vec::with_capacity(idx.len());
        for (&col, n) in idx.iter().zip(names) {
            let Some(cell) = cells.get(col) else {
                bail!(
                    "{name}: line {} has {} fields, column `{n}` is field {}",
                    i + 1,
                    cells.len(),
                    col + 1
                );
            };
            v.push(number(cell).with_context(|| place(col))?);
        }
        let Some(&time) = v.first() else { continue };
        if !(time.is_finite() && (0.0..=MAX_TIME_S).contains(&time)) {
            let col = idx.first().copied().unwrap_or(0);
            bail!(
                "{}: time `{time:e}` is not a number of seconds from 0 to {MAX_TIME_S:e}",
                place(col)
            );
        }
        frames.push(if kitepower {
            kitepower_frame(&v)
        } else {
            synthetic_frame(&v)
        });
    }
    Ok(frames)
}

/// A cell's number; an empty cell is a dropout (NaN).
fn number(cell: &str) -> Result<f64> {
    let s = cell.trim();
    if s.is_empty() {
        return Ok(f64::NAN);
    }
    s.parse::<f64>()
        .map_err(|_| anyhow!("`{s}` is not a number"))
}

/// The latest time a log row may carry, s: Unix time of the year 33,658,
/// far past any log, while its milliseconds still fit a `u64` exactly
/// enough (a row at 1e308 s became `u64::MAX` ms).
const MAX_TIME_S: f64 = 1e12;

/// Milliseconds of a time in seconds (finite, from 0 to [`MAX_TIME_S`]).
fn millis(seconds: f64) -> u64 {
    (seconds * 1000.0).round().max(0.0) as u64
}

/// The value at `i` of a row read by [`parse_log`] (which reads every
/// column of its layout, so the row is never short).
fn at(v: &[f64], i: usize) -> f64 {
    v.get(i).copied().unwrap_or(f64::NAN)
}

/// A Kitepower row ([`KITEPOWER`] order): angles in degrees, the attitude
/// as NED -> FRD Euler angles (3-2-1), rates in rad/s, tether force in kg,
/// depower and steering in percent.
fn kitepower_frame(v: &[f64]) -> SensorFrame {
    let deg = |i: usize| at(v, i).to_radians();
    let q = quaternion_from_euler(deg(1), deg(2), deg(3));
    SensorFrame {
        time_ms: millis(at(v, 0)),
        attitude: q.map(|x| x as f32),
        rates: [at(v, 4) as f32, at(v, 5) as f32, at(v, 6) as f32],
        airspeed: at(v, 7) as f32,
        angle_of_attack: deg(8) as f32,
        tether_force: (at(v, 9) * G) as f32,
        depower: (at(v, 10) / 100.0) as f32,
        steering: (at(v, 11) / 100.0) as f32,
    }
}

/// A synthetic row ([`SYNTHETIC`] order): the frame's own units, the angle
/// of attack in degrees.
fn synthetic_frame(v: &[f64]) -> SensorFrame {
    let f = |i: usize| at(v, i) as f32;
    SensorFrame {
        time_ms: millis(at(v, 0)),
        attitude: [f(1), f(2), f(3), f(4)],
        rates: [f(5), f(6), f(7)],
        airspeed: f(8),
        angle_of_attack: at(v, 9).to_radians() as f32,
        tether_force: f(10),
        depower: f(11),
        steering: f(12),
    }
}

/// Unit quaternion `[w, x, y, z]` of the 3-2-1 (yaw, pitch, roll) Euler
/// sequence from NED to FRD: body-to-world rotation.
fn quaternion_from_euler(roll: f64, pitch: f64, yaw: f64) -> [f64; 4] {
    let (sr, cr) = (roll * 0.5).sin_cos();
    let (sp, cp) = (pitch * 0.5).sin_cos();
    let (sy, cy) = (yaw * 0.5).sin_cos();
    [
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEAD: &str = "time_s,qw,qx,qy,qz,p,q,r,airspeed,aoa_deg,tether_n,depower,steering\n";

    fn log(rows: &[&str]) -> String {
        let mut s = HEAD.to_string();
        for r in rows {
            s.push_str(r);
            s.push('\n');
        }
        s
    }

    #[test]
    fn synthetic_rows_become_frames_and_dropouts_stay_nan() {
        let text = log(&[
            "0.1,1,0,0,0,0.1,0.2,0.3,20,5,3000,0.3,0.1",
            "0.2,1,0,0,0,0,0,0,,5,nan,0.3,0",
        ]);
        let f = parse_log("t.csv", &text, None).unwrap();
        assert_eq!(f.len(), 2);
        assert_eq!(f[0].time_ms, 100);
        assert_eq!(f[0].rates, [0.1, 0.2, 0.3]);
        assert_eq!(f[0].angle_of_attack, 5f64.to_radians() as f32);
        assert!(f[1].airspeed.is_nan() && f[1].tether_force.is_nan());
        assert_eq!(parse_log("t.csv", &text, Some(1)).unwrap().len(), 1);
    }

    #[test]
    fn non_finite_time_is_rejected_naming_the_line() {
        let ok = "0.1,1,0,0,0,0,0,0,20,5,3000,0.3,0";
        for bad in ["nan", "inf", "-1", "1e308"] {
            let row = format!("{bad},1,0,0,0,0,0,0,20,5,3000,0.3,0");
            let err = parse_log("t.csv", &log(&[ok, &row]), None).unwrap_err();
            let msg = format!("{err:#}");
            assert!(msg.contains("t.csv: line 3, column 1 (`time_s`)"), "{msg}");
            assert!(msg.contains("time"), "{msg}");
        }
    }

    #[test]
    fn broken_cells_and_short_rows_name_line_and_column() {
        let err = parse_log(
            "t.csv",
            &log(&["0.1,1,0,0,0,0,0,0,fast,5,3000,0.3,0"]),
            None,
        )
        .unwrap_err();
        let msg = format!("{err:#}");
        assert!(
            msg.contains("line 2, column 9 (`airspeed`)") && msg.contains("`fast`"),
            "{msg}"
        );
        let err = parse_log("t.csv", &log(&["0.1,1,0,0"]), None).unwrap_err();
        assert!(err.to_string().contains("line 2 has 4 fields"), "{err}");
        let err = parse_log("t.csv", "time_s,qw\n", None).unwrap_err();
        assert!(err.to_string().contains("no column `qx`"), "{err}");
        assert!(parse_log("t.csv", "", None).is_err());
    }

    #[test]
    fn kitepower_units_are_converted() {
        let mut text = KITEPOWER.join(",");
        text.push_str("\n1570531585.3,0,0,90,0.1,0.2,0.3,15,8,100,22,-35\n");
        let f = parse_log("k.csv", &text, None).unwrap();
        assert_eq!(f[0].time_ms, 1_570_531_585_300);
        let s = std::f32::consts::FRAC_1_SQRT_2;
        let want = [s, 0.0, 0.0, s];
        assert!(f[0]
            .attitude
            .iter()
            .zip(want)
            .all(|(a, b)| (a - b).abs() < 1e-6));
        assert_eq!(f[0].tether_force, (100.0 * G) as f32);
        assert_eq!((f[0].depower, f[0].steering), (0.22, -0.35));
    }
}
