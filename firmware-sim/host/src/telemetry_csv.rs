//! The firmware's telemetry as CSV (`--csv`), one row per record, columns
//! named as in `omniad_fw_pipeline::frame::NUMBER_NAMES`. Written
//! atomically: a failed write leaves what was there.

use anyhow::{Context, Result};
use omniad_fw_pipeline::frame::NUMBER_NAMES;
use omniad_fw_pipeline::Telemetry;
use std::path::Path;

/// Writes `records` to `path` (temporary file + rename).
pub fn write_telemetry_csv(path: &Path, records: &[Telemetry]) -> Result<()> {
    omniad_io::write_with(path, |f| {
        write!(f, "seq,time_ms")?;
        for n in NUMBER_NAMES {
            write!(f, ",{n}")?;
        }
        writeln!(f, ",rejected,instructions")?;
        for r in records {
            write!(f, "{},{}", r.seq, r.time_ms)?;
            for x in r.numbers() {
                write!(f, ",{x}")?;
            }
            writeln!(f, ",{},{}", r.rejected, r.instructions)?;
        }
        Ok(())
    })
    .with_context(|| format!("cannot write {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compare::tests::record;

    #[test]
    fn header_and_rows() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.csv");
        write_telemetry_csv(&path, &[record(0), record(1)]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3);
        assert!(lines[0].starts_with("seq,time_ms,force_x,"), "{}", lines[0]);
        assert!(lines[0].ends_with(",rejected,instructions"));
        assert_eq!(lines[0].split(',').count(), lines[2].split(',').count());
        assert!(lines[2].starts_with("1,100,1,-2,300.5,"), "{}", lines[2]);
    }
}
