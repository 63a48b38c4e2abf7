//! Reading the Kitepower flight-data CSV as it is (one file per pumping
//! cycle, 51 columns, 10 Hz; `../shared/data/flight/.../README.md`).
//!
//! Columns are found by name, so any subset of the 51 columns in any order
//! reads as long as the [`REQUIRED`] ones are there. A row with a missing
//! or non-finite required value is dropped and counted under the first
//! such column: nothing is dropped silently.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Largest accepted file, bytes (a cycle is about 0.5 MB).
pub const MAX_FILE_BYTES: usize = 256 << 20;

/// The columns the force balance and the model need, in [`Row`] order.
pub const REQUIRED: [&str; 27] = [
    "time",
    "airspeed_temperature",
    "airspeed_angle_of_attack",
    "airspeed_apparent_windspeed",
    "kite_1_vx",
    "kite_1_vy",
    "kite_1_vz",
    "kite_1_ax",
    "kite_1_ay",
    "kite_1_az",
    "kite_1_roll",
    "kite_1_pitch",
    "kite_1_yaw",
    "kite_1_roll_rate",
    "kite_1_pitch_rate",
    "kite_1_yaw_rate",
    "ground_tether_force",
    "kite_pos_north",
    "kite_pos_east",
    "kite_height",
    "kite_distance",
    "kite_actual_depower",
    "kite_actual_steering",
    "ground_wind_velocity",
    "ground_upwind_direction",
    "ground_tether_reelout_speed",
    "flight_phase_index",
];

/// One sample: the [`REQUIRED`] columns in their units as logged (angles
/// of the vane and the Euler angles in degrees, tether force in kg,
/// positions in m relative to the ground station, NED velocities and
/// accelerations, FRD body rates in rad/s, steering and depower in %).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row(pub [f64; REQUIRED.len()]);

/// Index of a required column in [`Row`].
#[derive(Clone, Copy, Debug)]
#[allow(missing_docs)]
pub enum Col {
    Time,
    Temperature,
    AngleOfAttack,
    Airspeed,
    Vx,
    Vy,
    Vz,
    Ax,
    Ay,
    Az,
    Roll,
    Pitch,
    Yaw,
    RollRate,
    PitchRate,
    YawRate,
    TetherForce,
    North,
    East,
    Height,
    Distance,
    Depower,
    Steering,
    GroundWind,
    UpwindDirection,
    ReelOutSpeed,
    PhaseIndex,
}

impl Row {
    /// The value of column `c`.
    pub fn get(&self, c: Col) -> f64 {
        self.0.get(c as usize).copied().unwrap_or(f64::NAN)
    }
}

/// One pumping cycle's samples.
#[derive(Clone, Debug, PartialEq)]
pub struct Cycle {
    /// Cycle number (the `NNNN` of `*_NNNN.csv`).
    pub number: u32,
    /// The file read.
    pub path: PathBuf,
    /// The rows kept, in file order.
    pub rows: Vec<Row>,
    /// Rows read (data lines).
    pub read: usize,
    /// Rows dropped, by the first required column that was missing or
    /// non-finite.
    pub dropped: BTreeMap<String, usize>,
}

/// An input error naming the file and, where there is one, the line.
#[derive(Debug)]
pub struct LogError(pub String);

impl std::fmt::Display for LogError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for LogError {}

/// The cycle number of a file name ending in `_NNNN.csv`.
pub fn cycle_number(path: &Path) -> Option<u32> {
    let stem = path.file_name()?.to_str()?.strip_suffix(".csv")?;
    let (_, digits) = stem.rsplit_once('_')?;
    (digits.len() == 4 && digits.bytes().all(|b| b.is_ascii_digit()))
        .then(|| digits.parse().ok())
        .flatten()
}

/// The files of `dir` for `cycles`, each named `*_NNNN.csv`; a cycle with
/// no file, or with two, is an error naming it.
pub fn find_cycles(dir: &Path, cycles: &[u32]) -> Result<Vec<PathBuf>, LogError> {
    let entries = std::fs::read_dir(dir)
        .map_err(|e| LogError(format!("cannot read folder {}: {e}", dir.display())))?;
    let mut by_number: BTreeMap<u32, Vec<PathBuf>> = BTreeMap::new();
    for entry in entries.flatten() {
        let path = entry.path();
        if let Some(n) = cycle_number(&path) {
            by_number.entry(n).or_default().push(path);
        }
    }
    cycles
        .iter()
        .map(|n| match by_number.get(n).map(Vec::as_slice) {
            Some([one]) => Ok(one.clone()),
            Some(many) if many.len() > 1 => Err(LogError(format!(
                "cycle {n}: {} files in {} end in _{n:04}.csv",
                many.len(),
                dir.display()
            ))),
            _ => Err(LogError(format!(
                "cycle {n}: no file ending in _{n:04}.csv in {}",
                dir.display()
            ))),
        })
        .collect()
}

/// Parses a cycle list such as `1-30` or `1-5,8,31-40`; a bad item is an
/// error naming it. Duplicates are removed, order is ascending.
pub fn parse_cycles(text: &str) -> Result<Vec<u32>, String> {
    let mut out = Vec::new();
    for item in text.split(',').map(str::trim) {
        let num = |s: &str| {
            s.trim()
                .parse::<u32>()
                .map_err(|_| format!("`{item}` is not a cycle number or a range A-B"))
        };
        let (a, b) = match item.split_once('-') {
            Some((a, b)) => (num(a)?, num(b)?),
            None => (num(item)?, num(item)?),
        };
        if a > b || b - a > 10_000 {
            return Err(format!(
                "`{item}`: a range runs from low to high, at most 10000 cycles"
            ));
        }
        out.extend(a..=b);
    }
    out.sort_unstable();
    out.dedup();
    Ok(out)
}

/// Reads one cycle file.
pub fn read_cycle(path: &Path) -> Result<Cycle, LogError> {
    let text = omniad_io::read_text(path, MAX_FILE_BYTES)
        .map_err(|e| LogError(format!("cannot read {}: {e}", path.display())))?;
    parse(&text, path)
}

/// Parses the text of a cycle file (`path` names it in errors).
pub fn parse(text: &str, path: &Path) -> Result<Cycle, LogError> {
    let mut lines = omniad_io::csv_lines(text);
    let header: Vec<&str> = lines
        .next()
        .ok_or_else(|| LogError(format!("{}: empty file", path.display())))?
        .split(',')
        .map(str::trim)
        .collect();
    let mut index = [0usize; REQUIRED.len()];
    for (slot, name) in index.iter_mut().zip(REQUIRED) {
        *slot = header
            .iter()
            .position(|h| *h == name)
            .ok_or_else(|| LogError(format!("{}: line 1: no column `{name}`", path.display())))?;
    }
    let mut cycle = Cycle {
        number: cycle_number(path).unwrap_or(0),
        path: path.to_path_buf(),
        rows: Vec::new(),
        read: 0,
        dropped: BTreeMap::new(),
    };
    for (i, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        cycle.read += 1;
        let fields: Vec<&str> = line.split(',').collect();
        if fields.len() != header.len() {
            return Err(LogError(format!(
                "{}: line {}: {} fields, the header has {}",
                path.display(),
                i + 2,
                fields.len(),
                header.len()
            )));
        }
        match row(&fields, &index) {
            Ok(r) => cycle.rows.push(r),
            Err(col) => *cycle.dropped.entry(col.to_owned()).or_default() += 1,
        }
    }
    Ok(cycle)
}

/// The largest magnitude any telemetry value may have: above a time in
/// Unix milliseconds (1.6e12) and far above any sensor's range. A logger
/// fault such as `1e308` is a bad value, not a measurement: the fit then
/// found "the training cycles do not determine the model" with no line to
/// look at.
pub const MAX_VALUE: f64 = 1e13;

/// Absolute zero, °C: `airspeed_temperature` below it is no temperature.
const ABSOLUTE_ZERO_C: f64 = -273.15;

/// The row, or the name of the first required column that is missing, not
/// a finite number, beyond [`MAX_VALUE`], or (the temperature) below
/// absolute zero.
fn row(fields: &[&str], index: &[usize; REQUIRED.len()]) -> Result<Row, &'static str> {
    let mut r = [0.0; REQUIRED.len()];
    for ((slot, &i), name) in r.iter_mut().zip(index).zip(REQUIRED) {
        *slot = fields
            .get(i)
            .and_then(|f| f.trim().parse::<f64>().ok())
            .filter(|v| v.is_finite() && v.abs() <= MAX_VALUE)
            .filter(|v| name != "airspeed_temperature" || *v > ABSOLUTE_ZERO_C)
            .ok_or(name)?;
    }
    Ok(Row(r))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header() -> String {
        let mut h: Vec<&str> = REQUIRED.to_vec();
        h.insert(1, "date");
        h.join(",")
    }

    fn line(time: &str, tether: &str) -> String {
        let mut v: Vec<String> = (0..REQUIRED.len()).map(|i| format!("{}", i)).collect();
        v[0] = time.into();
        v[Col::TetherForce as usize] = tether.into();
        v.insert(1, "2019-10-08".into());
        v.join(",")
    }

    #[test]
    fn rows_with_bad_values_are_counted_by_column() {
        let text = format!(
            "\u{feff}{}\r\n{}\r\n{}\r\n{}\n",
            header(),
            line("1.0", "99"),
            line("nan", "99"),
            line("1.2", "")
        );
        let c = parse(&text, Path::new("x_0007.csv")).unwrap();
        assert_eq!(c.number, 7);
        assert_eq!((c.read, c.rows.len()), (3, 1));
        assert_eq!(c.dropped.get("time"), Some(&1));
        assert_eq!(c.dropped.get("ground_tether_force"), Some(&1));
        assert_eq!(c.rows[0].get(Col::TetherForce), 99.0);
        // A logger's 1e308 and a temperature below absolute zero are bad
        // values too (one of them made the whole fit fail unexplained).
        let mut cold: Vec<String> = line("1.3", "99").split(',').map(str::to_owned).collect();
        cold[1 + 1] = "-300".into(); // airspeed_temperature, after the date
        let text = format!(
            "{}\n{}\n{}\n",
            header(),
            line("1.4", "1e308"),
            cold.join(",")
        );
        let c = parse(&text, Path::new("x_0008.csv")).unwrap();
        assert_eq!((c.read, c.rows.len()), (2, 0));
        assert_eq!(c.dropped.get("ground_tether_force"), Some(&1));
        assert_eq!(c.dropped.get("airspeed_temperature"), Some(&1));
    }

    #[test]
    fn a_missing_column_or_a_short_row_names_file_and_line() {
        let e = parse("time,foo\n1,2\n", Path::new("a.csv")).unwrap_err();
        assert!(
            e.0.contains("a.csv: line 1: no column `airspeed_temperature`"),
            "{e}"
        );
        let text = format!("{}\n1,2\n", header());
        let e = parse(&text, Path::new("b.csv")).unwrap_err();
        assert!(e.0.contains("b.csv: line 2: 2 fields"), "{e}");
    }

    #[test]
    fn cycle_lists_parse_and_bad_items_are_named() {
        assert_eq!(parse_cycles("1-3,5, 3").unwrap(), vec![1, 2, 3, 5]);
        assert!(parse_cycles("4-2").unwrap_err().contains("`4-2`"));
        assert!(parse_cycles("1,x").unwrap_err().contains("`x`"));
    }

    #[test]
    fn cycle_numbers_come_from_the_file_name() {
        assert_eq!(cycle_number(Path::new("d/20191008_0031.csv")), Some(31));
        assert_eq!(cycle_number(Path::new("d/summary.csv")), None);
        assert_eq!(cycle_number(Path::new("d/x_31.csv")), None);
    }
}
