//! Text files as spreadsheets and other tools write them.
//!
//! Why one place: every CSV reader of the project (recordings, imported
//! tracks, flight logs, telemetry, firmware logs) must accept what a user's
//! export produces — a UTF-8 byte-order mark, and LF, CRLF or a lone CR
//! (old Mac exports) as line ends — and refuse what no reader should read
//! (an endless device, a file far larger than its format).

use std::io;
use std::path::Path;

/// The lines of a CSV text whose line ends may be LF, CRLF or a lone CR,
/// after a UTF-8 byte-order mark if there is one.
pub fn csv_lines(text: &str) -> impl Iterator<Item = &str> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    text.lines().flat_map(|l| l.split('\r'))
}

/// Reads `path` as UTF-8 text of at most `max` bytes (see
/// [`crate::read_capped`]); invalid UTF-8 is an `InvalidData` error naming
/// the first bad byte.
pub fn read_text(path: &Path, max: usize) -> io::Result<String> {
    let bytes = crate::read_capped(path, max)?;
    String::from_utf8(bytes).map_err(|e| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to()),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_line_end_and_a_byte_order_mark() {
        let text = "\u{feff}a,b\r\n1,2\r3,4\n5,6";
        assert_eq!(
            csv_lines(text).collect::<Vec<_>>(),
            ["a,b", "1,2", "3,4", "5,6"]
        );
    }

    #[test]
    fn invalid_utf8_names_the_byte() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("t.csv");
        std::fs::write(&p, b"ab\xffcd").unwrap();
        let e = read_text(&p, 100).unwrap_err();
        assert!(e.to_string().contains("byte 2"), "{e}");
    }
}
