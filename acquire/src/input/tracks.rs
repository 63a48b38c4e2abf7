//! Take files: 2-D marker tracks (`frame,marker,u,v`) and 3-D pose tracks
//! (`t,x,y,z,qw,qx,qy,qz`), read into one [`Epoch`] per frame.
//!
//! Marker tracks become dense: every frame index from the first to the last
//! row gets an epoch, with no observations where the format allows a frame
//! to have no rows. Errors name the file, the 1-based line and the column.
//!
//! **Bounded work.** A take is one drop or one throw, seconds long, and the
//! reconstruction allocates per frame, so frame indices are bounded:
//! every index is at most [`MAX_FRAME_INDEX`] (so `k / fps` keeps far
//! better than frame-period precision), and a take spans at most
//! [`MAX_TAKE_FRAMES`] frames from its first to its last row (one stray row
//! such as `4294967295,m0,100,100` would otherwise make a take of four
//! billion empty frames). The error names the file, the line of the row
//! furthest from the take's median frame and its value. Pose tracks are
//! held to the same number of rows.
//!
//! **Encodings.** Every CSV of the recording format is read through
//! [`csv_text`]: UTF-8 with or without a byte-order mark, lines ending in
//! LF, CRLF or CR, at most [`MAX_CSV_BYTES`] bytes.

use crate::error::{Error, Result};
use crate::input::object::Object;
use nalgebra::{UnitQuaternion, Vector2, Vector3};
use std::path::Path;

/// The longest take, in frames from its first to its last row (inclusive):
/// 14 min at 60 fps, 52 s at 960 fps; a drop or throw lasts seconds.
pub const MAX_TAKE_FRAMES: i64 = 50_000;

/// The largest frame index: at 1e6 fps `k / fps` is then at most 1000 s,
/// resolved to about 1e-13 s, far below a frame period.
pub const MAX_FRAME_INDEX: i64 = 1_000_000_000;

/// The largest CSV file read (bytes): a [`MAX_TAKE_FRAMES`]-frame take of
/// 40 markers at 60 bytes a row is 120 MB.
pub const MAX_CSV_BYTES: usize = 256 << 20;

/// One marker seen in one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarkerSighting {
    /// Index into [`Object::markers`].
    pub marker: usize,
    /// Pixel coordinates (u, v), OpenCV convention.
    pub pixel: Vector2<f64>,
}

/// What was observed at one epoch.
#[derive(Clone, Debug, PartialEq)]
pub enum Observation {
    /// The visible markers (possibly none).
    Markers(Vec<MarkerSighting>),
    /// A 3-D pose: centre of mass (m, world) and orientation (body -> world).
    Pose(Vector3<f64>, UnitQuaternion<f64>),
}

/// One frame of a take.
#[derive(Clone, Debug, PartialEq)]
pub struct Epoch {
    /// Time, s.
    pub t: f64,
    /// Observation.
    pub observation: Observation,
}

/// Splits a CSV text into (1-based line number, fields) rows after checking
/// the header names `columns` in order.
pub(crate) fn rows<'a>(
    path: &Path,
    text: &'a str,
    columns: &[&str],
) -> Result<Vec<(usize, Vec<&'a str>)>> {
    let mut lines = csv_lines(text).enumerate();
    let header = lines.next().map(|(_, l)| l.trim()).unwrap_or("");
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    if names != columns {
        return Err(Error::at_line(
            path,
            1,
            None,
            format!("header must be `{}`, found `{header}`", columns.join(",")),
        ));
    }
    let mut out = Vec::new();
    for (i, line) in lines {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != columns.len() {
            return Err(Error::at_line(
                path,
                i + 1,
                None,
                format!("expected {} fields, found {}", columns.len(), fields.len()),
            ));
        }
        out.push((i + 1, fields));
    }
    Ok(out)
}

/// Parses a finite number in column `col` of line `line`.
pub(crate) fn number(path: &Path, line: usize, col: &str, s: &str) -> Result<f64> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(Error::at_line(
            path,
            line,
            Some(col),
            format!("expected a finite number, found `{s}`"),
        )),
    }
}

pub(crate) use omniad_io::csv_lines;

/// Reads a CSV file of the recording format as UTF-8 text, at most
/// [`MAX_CSV_BYTES`] long (see [`csv_lines`] for the line ends).
pub fn csv_text(path: &Path) -> Result<String> {
    omniad_io::read_text(path, MAX_CSV_BYTES).map_err(|e| Error::io(path, e))
}

/// Reads a marker-track file; frame `k` is at time `k / fps`.
pub fn read_markers(path: &Path, object: &Object, fps: f64) -> Result<Vec<Epoch>> {
    parse_markers(path, &csv_text(path)?, object, fps)
}

/// Parses the text of a marker-track file read from `path` (named in errors).
pub fn parse_markers(path: &Path, text: &str, object: &Object, fps: f64) -> Result<Vec<Epoch>> {
    let mut sightings: Vec<(i64, MarkerSighting, usize)> = Vec::new();
    for (line, f) in rows(path, text, &["frame", "marker", "u", "v"])? {
        let frame: i64 = f[0]
            .parse()
            .ok()
            .filter(|k: &i64| (0..=MAX_FRAME_INDEX).contains(k))
            .ok_or_else(|| {
                Error::at_line(
                    path,
                    line,
                    Some("frame"),
                    format!(
                        "expected a frame index from 0 to {MAX_FRAME_INDEX}, found `{}`",
                        f[0]
                    ),
                )
            })?;
        let marker = object.marker_index(f[1]).ok_or_else(|| {
            Error::at_line(
                path,
                line,
                Some("marker"),
                format!("unknown marker `{}` (not in [object.markers])", f[1]),
            )
        })?;
        let u = number(path, line, "u", f[2])?;
        let v = number(path, line, "v", f[3])?;
        sightings.push((
            frame,
            MarkerSighting {
                marker,
                pixel: Vector2::new(u, v),
            },
            line,
        ));
    }
    densify(path, sightings, fps)
}

/// Builds one epoch per frame index from sightings; duplicates are errors.
pub(crate) fn densify(
    path: &Path,
    mut s: Vec<(i64, MarkerSighting, usize)>,
    fps: f64,
) -> Result<Vec<Epoch>> {
    s.sort_by_key(|(k, m, _)| (*k, m.marker));
    for w in s.windows(2) {
        if let [(k0, m0, _), (k1, m1, line)] = w {
            if k0 == k1 && m0.marker == m1.marker {
                return Err(Error::at_line(
                    path,
                    *line,
                    Some("marker"),
                    format!("second row for this marker in frame {k1}"),
                ));
            }
        }
    }
    let (Some(first), Some(last)) = (s.first().map(|x| x.0), s.last().map(|x| x.0)) else {
        return Err(Error::in_file(path, "no marker rows"));
    };
    check_span(path, &s, first, last)?;
    let mut epochs: Vec<Epoch> = (first..=last)
        .map(|k| Epoch {
            t: k as f64 / fps,
            observation: Observation::Markers(Vec::new()),
        })
        .collect();
    for (k, m, _) in s {
        if let Some(Epoch {
            observation: Observation::Markers(list),
            ..
        }) = epochs.get_mut((k - first) as usize)
        {
            list.push(m);
        }
    }
    Ok(epochs)
}

/// Rejects a take spanning more than [`MAX_TAKE_FRAMES`] frames, naming
/// the row furthest from the median frame (the stray one).
fn check_span(
    path: &Path,
    s: &[(i64, MarkerSighting, usize)],
    first: i64,
    last: i64,
) -> Result<()> {
    if last - first < MAX_TAKE_FRAMES {
        return Ok(());
    }
    let median = s.get(s.len() / 2).map_or(first, |x| x.0);
    let (frame, line) = s
        .iter()
        .map(|(k, _, line)| (*k, *line))
        .max_by_key(|(k, _)| (k - median).abs())
        .unwrap_or((last, 0));
    Err(Error::at_line(
        path,
        line,
        Some("frame"),
        format!(
            "frame {frame} is {} frames from the take's median frame {median}; a take spans \
             at most {MAX_TAKE_FRAMES} frames (a stray row?)",
            (frame - median).abs()
        ),
    ))
}

/// Reads a pose-track file; times must increase strictly.
pub fn read_poses(path: &Path) -> Result<Vec<Epoch>> {
    parse_poses(path, &csv_text(path)?)
}

/// Parses the text of a pose-track file read from `path` (named in errors).
pub fn parse_poses(path: &Path, text: &str) -> Result<Vec<Epoch>> {
    let cols = ["t", "x", "y", "z", "qw", "qx", "qy", "qz"];
    let mut epochs: Vec<Epoch> = Vec::new();
    let rows = rows(path, text, &cols)?;
    if let Some((line, _)) = rows.get(MAX_TAKE_FRAMES as usize) {
        return Err(Error::at_line(
            path,
            *line,
            None,
            format!("a take holds at most {MAX_TAKE_FRAMES} rows"),
        ));
    }
    for (line, f) in rows {
        let mut v = [0.0; 8];
        for ((slot, s), col) in v.iter_mut().zip(&f).zip(cols) {
            *slot = number(path, line, col, s)?;
        }
        let q = crate::input::validate::unit_quaternion(&[v[4], v[5], v[6], v[7]])
            .ok_or_else(|| Error::at_line(path, line, Some("qw"), "zero quaternion"))?;
        if epochs.last().is_some_and(|e| e.t >= v[0]) {
            return Err(Error::at_line(
                path,
                line,
                Some("t"),
                "time must increase from row to row",
            ));
        }
        epochs.push(Epoch {
            t: v[0],
            observation: Observation::Pose(Vector3::new(v[1], v[2], v[3]), q),
        });
    }
    if epochs.len() < 3 {
        return Err(Error::in_file(path, "a pose track needs at least 3 rows"));
    }
    Ok(epochs)
}
