//! The firmware's exit codes (QEMU's exit status through semihosting), in
//! one table shared by the firmware, which exits with them, and the host
//! harness, which names them.

use omniad_core::file::FileError;

/// Why the firmware stopped. The numbers are the semihosting exit status
/// and so QEMU's; they are part of the harness's interface (tests check
/// 13 for a CRC mismatch), so they never change.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum ExitCode {
    /// Every frame processed, telemetry and summary written.
    Ok = 0,
    /// `frames.bin` could not be opened.
    NoInput = 2,
    /// `telemetry.bin` could not be opened or written.
    Output = 3,
    /// Coefficient file: bad magic.
    BadMagic = 10,
    /// Coefficient file: unknown format version.
    UnknownVersion = 11,
    /// Coefficient file: truncated.
    Truncated = 12,
    /// Coefficient file: CRC mismatch.
    CrcMismatch = 13,
    /// Coefficient file: bytes after the CRC.
    TrailingBytes = 14,
    /// Coefficient file: a payload field does not decode.
    Malformed = 15,
    /// Coefficient file: payload shorter or longer than its fields.
    PayloadLength = 16,
    /// Coefficient file: a count does not match the degree or capacity.
    BadCount = 17,
    /// Coefficient file: the values do not make a valid model.
    InvalidModel = 18,
    /// Coefficient file: the model does not fit the firmware's buffer.
    BufferTooSmall = 19,
    /// The coefficient file's mass properties are invalid.
    BadBody = 20,
    /// A panic in a debug build (release builds cannot panic: the link
    /// fails).
    DebugPanic = 101,
}

/// Every code, for [`ExitCode::from_status`].
const ALL: [ExitCode; 15] = [
    ExitCode::Ok,
    ExitCode::NoInput,
    ExitCode::Output,
    ExitCode::BadMagic,
    ExitCode::UnknownVersion,
    ExitCode::Truncated,
    ExitCode::CrcMismatch,
    ExitCode::TrailingBytes,
    ExitCode::Malformed,
    ExitCode::PayloadLength,
    ExitCode::BadCount,
    ExitCode::InvalidModel,
    ExitCode::BufferTooSmall,
    ExitCode::BadBody,
    ExitCode::DebugPanic,
];

impl ExitCode {
    /// The semihosting exit status.
    pub const fn status(self) -> u32 {
        self as u32
    }

    /// The code for a coefficient-file error: 10 + the error's kind.
    pub const fn file_error(e: &FileError) -> Self {
        match e {
            FileError::BadMagic => Self::BadMagic,
            FileError::UnknownVersion(_) => Self::UnknownVersion,
            FileError::Truncated => Self::Truncated,
            FileError::CrcMismatch { .. } => Self::CrcMismatch,
            FileError::TrailingBytes(_) => Self::TrailingBytes,
            FileError::Malformed(_) => Self::Malformed,
            FileError::PayloadLength => Self::PayloadLength,
            FileError::BadCount(_) => Self::BadCount,
            FileError::Model(_) => Self::InvalidModel,
            FileError::BufferTooSmall => Self::BufferTooSmall,
        }
    }

    /// The code QEMU exited with, if it is one of the firmware's.
    pub fn from_status(status: i32) -> Option<Self> {
        ALL.into_iter()
            .find(|c| i64::from(c.status()) == i64::from(status))
    }

    /// What the code means, for people.
    pub const fn describe(self) -> &'static str {
        match self {
            Self::Ok => "ok",
            Self::NoInput => "cannot open frames.bin",
            Self::Output => "cannot write telemetry.bin",
            Self::BadMagic => "bad magic",
            Self::UnknownVersion => "unknown version",
            Self::Truncated => "truncated",
            Self::CrcMismatch => "CRC mismatch",
            Self::TrailingBytes => "trailing bytes",
            Self::Malformed => "malformed payload",
            Self::PayloadLength => "payload length",
            Self::BadCount => "bad count",
            Self::InvalidModel => "invalid model",
            Self::BufferTooSmall => "buffer too small",
            Self::BadBody => "invalid mass properties",
            Self::DebugPanic => "panic (debug build)",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statuses_round_trip_and_are_unique() {
        for c in ALL {
            assert_eq!(ExitCode::from_status(c.status() as i32), Some(c));
        }
        assert_eq!(ExitCode::from_status(1), None);
        assert_eq!(ExitCode::from_status(-1), None);
    }

    #[test]
    fn file_errors_are_ten_plus_kind() {
        let crc = FileError::CrcMismatch {
            stored: 0,
            computed: 1,
        };
        assert_eq!(ExitCode::file_error(&crc).status(), 13);
        assert_eq!(ExitCode::file_error(&FileError::BadMagic).status(), 10);
        assert_eq!(
            ExitCode::file_error(&FileError::BufferTooSmall).status(),
            19
        );
    }
}
