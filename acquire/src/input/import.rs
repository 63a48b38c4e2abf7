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
//!
//! Nothing malformed is written: [`ImportOptions::validate`] rejects marker
//! names the CSV cannot hold (empty, commas, quotes, spaces at the ends),
//! two points mapped to one marker, a non-finite or non-positive height and
//! a non-finite likelihood threshold, naming the `omniad import-tracks`
//! option; rows whose frame index would leave `0..=MAX_FRAME_INDEX` or
//! whose pixel is not finite are errors naming the file and line.

use crate::error::{Error, Result};
use crate::input::tracks::{csv_lines, csv_text, number, MAX_FRAME_INDEX};
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
    /// Checks the options before any file is read; errors name the
    /// `omniad import-tracks` option (`--map`, `--height`, ...).
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(Error::Data(m));
        for (i, (point, marker)) in self.mapping.iter().enumerate() {
            for (what, name) in [("point", point), ("marker", marker)] {
                if let Some(why) = unwritable_name(name) {
                    return bad(format!("--map `{point}={marker}`: the {what} name {why}"));
                }
            }
            if let Some((p, _)) = self.mapping.iter().take(i).find(|(_, m)| m == marker) {
                return bad(format!(
                    "--map: points `{p}` and `{point}` both map to marker `{marker}`"
                ));
            }
            if self.mapping.iter().take(i).any(|(p, _)| p == point) {
                return bad(format!("--map: point `{point}` is mapped twice"));
            }
        }
        if let Some(h) = self.y_up_height {
            if !(h.is_finite() && h > 0.0) {
                return bad(format!(
                    "--height must be a positive number of pixels, found {h}"
                ));
            }
        }
        if !(0.0..=1.0).contains(&self.min_likelihood) {
            return bad(format!(
                "--min-likelihood must be a number from 0 to 1, found {}",
                self.min_likelihood
            ));
        }
        if !self.pixel_offset.is_finite() {
            return bad(format!(
                "pixel offset must be finite, found {}",
                self.pixel_offset
            ));
        }
        if self.camera == 0 {
            return bad("--camera: DLTdv cameras are numbered from 1".into());
        }
        if !(0..=MAX_FRAME_INDEX).contains(&self.first_frame) {
            return bad(format!(
                "--first-frame must be from 0 to {MAX_FRAME_INDEX}, found {}",
                self.first_frame
            ));
        }
        Ok(())
    }

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

/// Why a point or marker name cannot stand in a `frame,marker,u,v` row
/// (read back trimmed and split at commas), or `None` when it can.
fn unwritable_name(name: &str) -> Option<&'static str> {
    if name.is_empty() {
        Some("is empty")
    } else if name.contains([',', '"']) {
        Some("holds a comma or a quote")
    } else if name.trim() != name {
        Some("starts or ends with white space")
    } else if name.chars().any(char::is_control) {
        Some("holds a control character")
    } else {
        None
    }
}

/// The frame index of data row `row` (0-based) counted from `first`, if
/// it stays within `0..=MAX_FRAME_INDEX`.
fn frame_at(path: &Path, line: usize, first: i64, row: usize) -> Result<i64> {
    i64::try_from(row)
        .ok()
        .and_then(|r| first.checked_add(r))
        .filter(|k| (0..=MAX_FRAME_INDEX).contains(k))
        .ok_or_else(|| {
            Error::at_line(
                path,
                line,
                None,
                format!("frame index past {MAX_FRAME_INDEX} (--first-frame {first} + row {row})"),
            )
        })
}

/// An output pixel, which must be finite (large inputs can overflow).
fn finite_pixel(path: &Path, line: usize, (u, v): (f64, f64)) -> Result<(f64, f64)> {
    if u.is_finite() && v.is_finite() {
        Ok((u, v))
    } else {
        Err(Error::at_line(
            path,
            line,
            None,
            format!("pixel ({u}, {v}) is not finite"),
        ))
    }
}

/// A cell that is a missing value (`NaN`, empty).
fn missing(s: &str) -> bool {
    s.is_empty() || s.eq_ignore_ascii_case("nan")
}

/// Reads a DLTdv `xypts.csv`.
pub fn read_dltdv(path: &Path, o: &ImportOptions) -> Result<Vec<Row>> {
    o.validate()?;
    let text = csv_text(path)?;
    let mut lines = csv_lines(&text);
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
            let pixel = o.pixel(
                number(path, lineno, header[*i], xs)?,
                number(path, lineno, header[*j], ys)?,
            );
            let (u, v) = finite_pixel(path, lineno, pixel)?;
            out.push((
                frame_at(path, lineno, o.first_frame, row)?,
                marker.clone(),
                u,
                v,
            ));
        }
    }
    Ok(out)
}

/// Reads a DeepLabCut CSV.
pub fn read_deeplabcut(path: &Path, o: &ImportOptions) -> Result<Vec<Row>> {
    o.validate()?;
    let text = csv_text(path)?;
    let rows: Vec<Vec<&str>> = csv_lines(&text)
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
    let mut frames = std::collections::HashSet::new();
    for (n, cells) in rows.iter().enumerate().skip(co + 1) {
        if cells.iter().all(|c| c.is_empty()) {
            continue;
        }
        let lineno = n + 1;
        let frame = dlc_frame(
            path,
            lineno,
            cells.first().copied(),
            o.first_frame,
            n - co - 1,
        )?;
        if !frames.insert(frame) {
            return Err(Error::at_line(
                path,
                lineno,
                None,
                format!("frame {frame} appears on an earlier row too"),
            ));
        }
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
            let pixel = o.pixel(
                number(path, lineno, "x", get(*i))?,
                number(path, lineno, "y", get(*j))?,
            );
            let (u, v) = finite_pixel(path, lineno, pixel)?;
            out.push((frame, marker.clone(), u, v));
        }
    }
    Ok(out)
}

/// A DeepLabCut row's frame: its first cell when that is an integer (which
/// must be a valid frame index), else `first` + the data row number.
fn dlc_frame(path: &Path, line: usize, cell: Option<&str>, first: i64, row: usize) -> Result<i64> {
    match cell.map(str::parse::<i64>) {
        Some(Ok(k)) if (0..=MAX_FRAME_INDEX).contains(&k) => Ok(k),
        Some(Ok(k)) => Err(Error::at_line(
            path,
            line,
            None,
            format!("frame index {k} is outside 0..={MAX_FRAME_INDEX}"),
        )),
        _ => frame_at(path, line, first, row),
    }
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

    fn assert_names(e: &str, needles: &[&str]) {
        for n in needles {
            assert!(e.contains(n), "error should name {n:?}: {e}");
        }
    }

    #[test]
    fn imports_never_write_malformed_rows() {
        let dir = tempfile::tempdir().expect("tempdir");
        let dlt = dir.path().join("xypts.csv");
        std::fs::write(
            &dlt,
            "\u{feff}pt1_cam1_X,pt1_cam1_Y,pt2_cam1_X,pt2_cam1_Y\r\n1,2,3,4\r\n",
        )
        .expect("write");
        let ok = read_dltdv(&dlt, &opts(&[("pt1", "m0")])).expect("BOM + CRLF");
        assert_eq!(ok, vec![(0, "m0".to_string(), 1.0, 2.0)]);
        let bad_options: [(ImportOptions, &[&str]); 8] = [
            (opts(&[("pt1", "m,0")]), &["--map", "comma"]),
            (opts(&[("pt1", "")]), &["--map", "empty"]),
            (opts(&[("pt1", "m0"), ("pt2", "m0")]), &["pt1", "pt2", "m0"]),
            (
                ImportOptions {
                    y_up_height: Some(f64::NAN),
                    ..opts(&[("pt1", "m0")])
                },
                &["--height", "NaN"],
            ),
            (
                ImportOptions {
                    y_up_height: Some(0.0),
                    ..opts(&[("pt1", "m0")])
                },
                &["--height"],
            ),
            (
                ImportOptions {
                    y_up_height: Some(-5.0),
                    ..opts(&[("pt1", "m0")])
                },
                &["--height"],
            ),
            (
                ImportOptions {
                    min_likelihood: f64::NAN,
                    ..opts(&[("pt1", "m0")])
                },
                &["--min-likelihood"],
            ),
            (
                ImportOptions {
                    first_frame: i64::MAX,
                    ..opts(&[("pt1", "m0")])
                },
                &["--first-frame"],
            ),
        ];
        for (o, needles) in bad_options {
            let e = read_dltdv(&dlt, &o).expect_err("refused").to_string();
            assert_names(&e, needles);
        }
        // Frame numbers that would wrap or leave the format's range.
        let dlc = dir.path().join("dlc.csv");
        std::fs::write(
            &dlc,
            "scorer,S,S,S\nbodyparts,a,a,a\ncoords,x,y,likelihood\n0,1,2,0.99\n9223372036854775807,1,2,0.99\n",
        )
        .expect("write");
        let e = read_deeplabcut(&dlc, &opts(&[("a", "m0")]))
            .expect_err("huge frame")
            .to_string();
        assert_names(&e, &["dlc.csv:5", "9223372036854775807"]);
        std::fs::write(
            &dlc,
            "scorer,S,S,S\nbodyparts,a,a,a\ncoords,x,y,likelihood\n3,1,2,0.99\n3,1,2,0.99\n",
        )
        .expect("write");
        let e = read_deeplabcut(&dlc, &opts(&[("a", "m0")]))
            .expect_err("repeated frame")
            .to_string();
        assert_names(&e, &["dlc.csv:5", "frame 3"]);
        // Finite inputs whose pixel overflows.
        std::fs::write(&dlt, "pt1_cam1_X,pt1_cam1_Y\n-1.7e308,2\n").expect("write");
        let o = ImportOptions {
            pixel_offset: 1.7e308,
            ..opts(&[("pt1", "m0")])
        };
        let e = read_dltdv(&dlt, &o).expect_err("inf").to_string();
        assert_names(&e, &["xypts.csv:2", "not finite"]);
    }
}
