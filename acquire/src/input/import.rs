//! Importing marker tracks exported by common trackers into the recording
//! format's `frame,marker,u,v` ([`crate::input::tracks`]).
//!
//! * **DLTdv** (`*xypts.csv`): header `pt1_cam1_X,pt1_cam1_Y,pt2_cam1_X,…`,
//!   one row per video frame, `NaN` (or empty) where a point is not
//!   digitised. DLTdv's pixel coordinates are MATLAB's: 1-based, with `Y`
//!   measured up from the bottom of the image. With
//!   `y_up_height = Some(H)` and `pixel_offset = 1`, `u = X - 1` and
//!   `v = H - Y` (OpenCV: 0-based, `v` down). `camera` picks the `camN`
//!   columns.
//! * **DeepLabCut** (`CollectedData_*.csv` / analysed-video CSV): three
//!   header rows `scorer`, `bodyparts`, `coords` (`x`, `y`, `likelihood`),
//!   an optional `individuals` row (multi-animal projects; the individual
//!   name is then ignored), then one row per frame whose first cell is the
//!   frame index (or an image path, in which case the row number is used).
//!   DeepLabCut's pixels are already OpenCV's. Points whose `likelihood`
//!   is below `min_likelihood` are treated as hidden.
//!
//! In both, `mapping` names which tracker point is which marker of
//! `[object.markers]` (`pt1` / a body-part name -> marker name); points not
//! in the mapping are ignored. `first_frame` is the frame index of the
//! first data row.

use crate::error::{Error, Result};
use crate::input::tracks::number;
use std::fmt::Write as _;
use std::path::Path;

/// Options of an import.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportOptions {
    /// Tracker point name -> marker name.
    pub mapping: Vec<(String, String)>,
    /// DLTdv camera number (`camN` columns), default 1.
    pub camera: usize,
    /// When set, `v = height - Y` (trackers whose Y axis points up).
    pub y_up_height: Option<f64>,
    /// Subtracted from u (and from v when Y is not flipped): 1 for MATLAB's
    /// 1-based pixels (DLTdv), 0 otherwise.
    pub pixel_offset: f64,
    /// DeepLabCut: points below this likelihood are hidden (default 0.9).
    pub min_likelihood: f64,
    /// Frame index of the first data row.
    pub first_frame: i64,
}

impl Default for ImportOptions {
    fn default() -> Self {
        Self {
            mapping: Vec::new(),
            camera: 1,
            y_up_height: None,
            pixel_offset: 0.0,
            min_likelihood: 0.9,
            first_frame: 0,
        }
    }
}

/// One imported row: frame, marker name, u, v (px).
pub type Row = (i64, String, f64, f64);

impl ImportOptions {
    fn marker(&self, point: &str) -> Option<&str> {
        self.mapping
            .iter()
            .find(|(p, _)| p == point)
            .map(|(_, m)| m.as_str())
    }

    fn pixel(&self, x: f64, y: f64) -> (f64, f64) {
        let u = x - self.pixel_offset;
        let v = match self.y_up_height {
            Some(h) => h - y,
            None => y - self.pixel_offset,
        };
        (u, v)
    }
}

/// A cell that is a missing value (`NaN`, empty).
fn missing(s: &str) -> bool {
    s.is_empty() || s.eq_ignore_ascii_case("nan")
}

/// Reads a DLTdv `xypts.csv`.
pub fn read_dltdv(path: &Path, o: &ImportOptions) -> Result<Vec<Row>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .unwrap_or("")
        .split(',')
        .map(str::trim)
        .collect();
    // (point, x column, y column) for the chosen camera.
    let mut points: Vec<(String, String, usize, usize)> = Vec::new();
    for (i, h) in header.iter().enumerate() {
        let Some(stem) = h.strip_suffix(&format!("_cam{}_X", o.camera)) else {
            continue;
        };
        let y_name = format!("{stem}_cam{}_Y", o.camera);
        let j = header.iter().position(|c| *c == y_name).ok_or_else(|| {
            Error::at_line(path, 1, Some(h), format!("no matching column `{y_name}`"))
        })?;
        if let Some(m) = o.marker(stem) {
            points.push((stem.to_owned(), m.to_owned(), i, j));
        }
    }
    if points.is_empty() {
        return Err(Error::at_line(
            path,
            1,
            None,
            format!("no `ptN_cam{}_X` column of a mapped point", o.camera),
        ));
    }
    let mut out = Vec::new();
    for (row, line) in lines.enumerate() {
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        if cells.iter().all(|c| c.is_empty()) {
            continue;
        }
        let lineno = row + 2;
        for (stem, marker, i, j) in &points {
            let (Some(xs), Some(ys)) = (cells.get(*i), cells.get(*j)) else {
                return Err(Error::at_line(
                    path,
                    lineno,
                    Some(stem),
                    "row has too few fields",
                ));
            };
            if missing(xs) || missing(ys) {
                continue;
            }
            let (u, v) = o.pixel(
                number(path, lineno, header[*i], xs)?,
                number(path, lineno, header[*j], ys)?,
            );
            out.push((o.first_frame + row as i64, marker.clone(), u, v));
        }
    }
    Ok(out)
}

/// Reads a DeepLabCut CSV.
pub fn read_deeplabcut(path: &Path, o: &ImportOptions) -> Result<Vec<Row>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let rows: Vec<Vec<&str>> = text
        .lines()
        .map(|l| l.split(',').map(str::trim).collect())
        .collect();
    let find = |name: &str| {
        rows.iter()
            .take(4)
            .position(|r| r.first().is_some_and(|c| *c == name))
    };
    let (Some(bp), Some(co)) = (find("bodyparts"), find("coords")) else {
        return Err(Error::at_line(
            path,
            1,
            None,
            "expected DeepLabCut header rows `bodyparts` and `coords`",
        ));
    };
    let (Some(parts), Some(coords)) = (rows.get(bp), rows.get(co)) else {
        return Err(Error::in_file(path, "truncated header"));
    };
    // (marker, x column, y column, likelihood column)
    let mut points: Vec<(String, usize, usize, Option<usize>)> = Vec::new();
    for (i, part) in parts.iter().enumerate().skip(1) {
        if coords.get(i) != Some(&"x") {
            continue;
        }
        let Some(m) = o.marker(part) else { continue };
        let col = |name: &str| {
            (i..parts.len()).find(|&j| parts.get(j) == Some(part) && coords.get(j) == Some(&name))
        };
        let y =
            col("y").ok_or_else(|| Error::at_line(path, co + 1, Some(part), "no `y` column"))?;
        points.push((m.to_owned(), i, y, col("likelihood")));
    }
    if points.is_empty() {
        return Err(Error::at_line(
            path,
            bp + 1,
            None,
            "no body part of the mapping found",
        ));
    }
    let mut out = Vec::new();
    for (n, cells) in rows.iter().enumerate().skip(co + 1) {
        if cells.iter().all(|c| c.is_empty()) {
            continue;
        }
        let lineno = n + 1;
        let index = (n - co - 1) as i64;
        let frame = cells
            .first()
            .and_then(|c| c.parse::<i64>().ok())
            .unwrap_or(o.first_frame + index);
        for (marker, i, j, l) in &points {
            let get = |k: usize| cells.get(k).copied().unwrap_or("");
            if missing(get(*i)) || missing(get(*j)) {
                continue;
            }
            if let Some(l) = l {
                if !missing(get(*l))
                    && number(path, lineno, "likelihood", get(*l))? < o.min_likelihood
                {
                    continue;
                }
            }
            let (u, v) = o.pixel(
                number(path, lineno, "x", get(*i))?,
                number(path, lineno, "y", get(*j))?,
            );
            out.push((frame, marker.clone(), u, v));
        }
    }
    Ok(out)
}

/// The rows as a marker-track file (`frame,marker,u,v`).
pub fn to_marker_csv(rows: &[Row]) -> String {
    let mut s = String::from("frame,marker,u,v\n");
    for (k, m, u, v) in rows {
        let _ = writeln!(s, "{k},{m},{u:.3},{v:.3}");
    }
    s
}

/// Writes the rows' marker-track file to `path` atomically (temporary
/// file + rename: an interrupted import never leaves half a file).
pub fn write_marker_csv(path: &Path, rows: &[Row]) -> Result<()> {
    omniad_io::write_atomic(path, to_marker_csv(rows).as_bytes()).map_err(|e| Error::io(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn opts(map: &[(&str, &str)]) -> ImportOptions {
        ImportOptions {
            mapping: map
                .iter()
                .map(|(a, b)| (a.to_string(), b.to_string()))
                .collect(),
            ..ImportOptions::default()
        }
    }

    #[test]
    fn dltdv_flips_y_and_skips_nan() {
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("xypts.csv");
        std::fs::write(
            &p,
            "pt1_cam1_X,pt1_cam1_Y,pt2_cam1_X,pt2_cam1_Y\n11,1270,NaN,NaN\n12,1260,30,40\n",
        )
        .expect("write");
        let o = ImportOptions {
            y_up_height: Some(1280.0),
            pixel_offset: 1.0,
            ..opts(&[("pt1", "m0"), ("pt2", "m1")])
        };
        let rows = read_dltdv(&p, &o).expect("read");
        assert_eq!(
            rows,
            vec![
                (0, "m0".into(), 10.0, 10.0),
                (1, "m0".into(), 11.0, 20.0),
                (1, "m1".into(), 29.0, 1240.0)
            ]
        );
    }

    #[test]
    fn deeplabcut_uses_likelihood() {
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("dlc.csv");
        std::fs::write(&p, "scorer,S,S,S,S,S,S\nbodyparts,a,a,a,b,b,b\ncoords,x,y,likelihood,x,y,likelihood\n0,1,2,0.99,3,4,0.5\n1,5,6,0.95,7,8,0.97\n").expect("write");
        let rows = read_deeplabcut(&p, &opts(&[("a", "m0"), ("b", "m1")])).expect("read");
        assert_eq!(
            rows,
            vec![
                (0, "m0".into(), 1.0, 2.0),
                (1, "m0".into(), 5.0, 6.0),
                (1, "m1".into(), 7.0, 8.0)
            ]
        );
    }

    #[test]
    fn bad_number_names_file_and_line() {
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("xypts.csv");
        std::fs::write(&p, "pt1_cam1_X,pt1_cam1_Y\n1,2\nfoo,3\n").expect("write");
        let e = read_dltdv(&p, &opts(&[("pt1", "m0")]))
            .expect_err("bad number")
            .to_string();
        assert!(e.contains("xypts.csv:3") && e.contains("pt1_cam1_X"), "{e}");
    }
}
