//! Coefficient files, `*.omni`.
//!
//! Layout (all little-endian):
//!
//! | offset | size | content |
//! |---|---|---|
//! | 0 | 8 | magic `\x89OMNIAD\n` |
//! | 8 | 2 | format version, u16 ([`FORMAT_VERSION`]) |
//! | 10 | 4 | payload length n, u32 |
//! | 14 | n | payload: postcard-encoded fields, see below |
//! | 14+n | 4 | CRC-32 (IEEE) of bytes `0..14+n` |
//!
//! Nothing may follow the CRC. Numbers in the payload are always `f64`
//! (fitting precision), converted to the reader's scalar type on decode.
//!
//! Payload of version 1, in order: name (str), degree N (u8), pole ([f64; 3]),
//! reference length (f64), six coefficient sets `alpha^1..3, beta^1..3`
//! (each: count u16, then that many f64; the count is (N+1)² for alpha and
//! (N_T+1)² for beta, all three beta sets alike, with N_T the torque's own
//! degree, `0..=MAX_DEGREE`, which the count alone states), D (`[xx,yy,zz,xy,xz,yz]`
//! f64), mass properties (Option of mass f64 and inertia [f64; 6]),
//! provenance (method str, source str, frames used u32, frames dropped
//! u32, force residuals (u8 count, f64s), torque residuals (same), coverage
//! (u16 count, u16s)), extensions (u8 count, then each kind u16, version
//! u8, byte count u8, bytes).
//!
//! A file whose torque has the force's degree (N_T = N) is byte for byte
//! what this format always wrote; a reader older than the torque's own
//! degree refuses one with N_T ≠ N (its beta count is not (N+1)²:
//! [`FileError::BadCount`] at `beta`) rather than misreading it, so the
//! layout, and with it the version, is unchanged.
//!
//! Decoding fills fixed storage with no allocation and never panics; every
//! problem is a [`FileError`].

use crate::coefficients::{
    Coefficients, Extension, MassProperties, ModelError, Provenance, COVERAGE_CELLS,
    EXTENSION_CAPACITY, MAX_EXTENSIONS, MAX_ITERATIONS, NAME_CAPACITY, TEXT_CAPACITY,
};
use crate::crc32::crc32;
use crate::lanes::LaneScalar;
use crate::math::{six_from_symmetric, symmetric_from_six};
use crate::rigid_body::RigidBody;
use crate::sh::{coeff_count, MAX_DEGREE};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// File magic.
pub const MAGIC: [u8; 8] = *b"\x89OMNIAD\n";
/// Current (and only) format version.
pub const FORMAT_VERSION: u16 = 1;
/// Header bytes before the payload.
pub const HEADER_LEN: usize = 14;
/// Upper bound of an encoded file, bytes: a buffer this large always fits.
pub const MAX_FILE_SIZE: usize = 12 * 1024;

/// What is wrong with a coefficient file. Small and `Copy`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileError {
    /// The first 8 bytes are not [`MAGIC`].
    BadMagic,
    /// A format version this build does not know.
    UnknownVersion(u16),
    /// The file ends early.
    Truncated,
    /// The stored CRC does not match the content.
    CrcMismatch {
        /// CRC stored in the file.
        stored: u32,
        /// CRC computed over the content.
        computed: u32,
    },
    /// Bytes after the CRC (count).
    TrailingBytes(usize),
    /// The payload could not be decoded at this field.
    Malformed(&'static str),
    /// The payload is shorter or longer than its fields (bytes left over).
    PayloadLength,
    /// A count does not match the degree, or exceeds capacity; names it.
    BadCount(&'static str),
    /// The decoded values do not make a valid model.
    Model(ModelError),
    /// The output buffer is too small to encode into.
    BufferTooSmall,
}

impl From<ModelError> for FileError {
    fn from(e: ModelError) -> Self {
        Self::Model(e)
    }
}

impl core::fmt::Display for FileError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::BadMagic => write!(f, "not an omniad coefficient file (bad magic bytes)"),
            Self::UnknownVersion(v) => {
                write!(
                    f,
                    "unknown format version {v} (this build reads 1..={FORMAT_VERSION})"
                )
            }
            Self::Truncated => write!(f, "file is truncated"),
            Self::CrcMismatch { stored, computed } => write!(
                f,
                "CRC mismatch: stored {stored:#010x}, computed {computed:#010x} (file corrupt)"
            ),
            Self::TrailingBytes(n) => write!(f, "{n} unexpected bytes after the CRC"),
            Self::Malformed(field) => write!(f, "malformed payload at field `{field}`"),
            Self::PayloadLength => write!(f, "payload length does not match its content"),
            Self::BadCount(field) => write!(f, "bad element count in `{field}`"),
            Self::Model(e) => write!(f, "invalid model: {e}"),
            Self::BufferTooSmall => write!(f, "output buffer too small"),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for FileError {}

/// Field-by-field postcard reader over a byte slice.
struct Reader<'a> {
    rest: &'a [u8],
}

impl<'a> Reader<'a> {
    fn take<T: Deserialize<'a>>(&mut self, field: &'static str) -> Result<T, FileError> {
        let (v, rest) = postcard::take_from_bytes::<T>(self.rest).map_err(|e| match e {
            postcard::Error::DeserializeUnexpectedEnd => FileError::Truncated,
            _ => FileError::Malformed(field),
        })?;
        self.rest = rest;
        Ok(v)
    }

    fn finite(&mut self, field: &'static str) -> Result<f64, FileError> {
        let v: f64 = self.take(field)?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(ModelError::NonFinite(field).into())
        }
    }

    fn finite_array<const N: usize>(&mut self, field: &'static str) -> Result<[f64; N], FileError> {
        let mut out = [0.0; N];
        for v in out.iter_mut() {
            *v = self.finite(field)?;
        }
        Ok(out)
    }

    fn string<const N: usize>(
        &mut self,
        field: &'static str,
    ) -> Result<heapless::String<N>, FileError> {
        let s: &str = self.take(field)?;
        let mut out = heapless::String::new();
        out.push_str(s).map_err(|_| FileError::BadCount(field))?;
        Ok(out)
    }
}

/// Field-by-field postcard writer into a byte slice.
struct Writer<'a> {
    buf: &'a mut [u8],
    at: usize,
}

impl Writer<'_> {
    fn put<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), FileError> {
        let rest = self
            .buf
            .get_mut(self.at..)
            .ok_or(FileError::BufferTooSmall)?;
        let used = postcard::to_slice(v, rest)
            .map_err(|_| FileError::BufferTooSmall)?
            .len();
        self.at += used;
        Ok(())
    }
}

/// Encodes `model` into `buf`; returns the number of bytes written.
pub fn encode<T: LaneScalar>(model: &Coefficients<T>, buf: &mut [u8]) -> Result<usize, FileError> {
    if buf.len() < HEADER_LEN + 4 {
        return Err(FileError::BufferTooSmall);
    }
    let payload_len = {
        let payload = buf.get_mut(HEADER_LEN..).ok_or(FileError::BufferTooSmall)?;
        let mut w = Writer {
            buf: payload,
            at: 0,
        };
        write_payload(model, &mut w)?;
        w.at
    };
    let end = HEADER_LEN + payload_len;
    let header = buf.get_mut(..HEADER_LEN).ok_or(FileError::BufferTooSmall)?;
    let len32 = u32::try_from(payload_len).map_err(|_| FileError::BufferTooSmall)?;
    for (dst, src) in header.iter_mut().zip(
        MAGIC
            .iter()
            .chain(&FORMAT_VERSION.to_le_bytes())
            .chain(&len32.to_le_bytes()),
    ) {
        *dst = *src;
    }
    let crc = crc32(buf.get(..end).ok_or(FileError::BufferTooSmall)?);
    let tail = buf.get_mut(end..end + 4).ok_or(FileError::BufferTooSmall)?;
    tail.copy_from_slice(&crc.to_le_bytes());
    Ok(end + 4)
}

fn write_payload<T: LaneScalar>(m: &Coefficients<T>, w: &mut Writer<'_>) -> Result<(), FileError> {
    let f = |x: T| x.as_f64();
    w.put(m.name())?;
    w.put(&m.degree())?;
    w.put(&m.pole().map(f).data.0[0])?;
    w.put(&f(m.reference_length()))?;
    for set in 0..6 {
        let count = if set < 3 {
            m.coeff_count()
        } else {
            m.torque_coeff_count()
        };
        w.put(&(count as u16))?;
        for k in 0..count {
            let v = if set < 3 {
                m.alpha(set, k)
            } else {
                m.beta(set - 3, k)
            };
            w.put(&v.map(f).unwrap_or(0.0))?;
        }
    }
    w.put(&six_from_symmetric(&m.damping()).map(f))?;
    w.put(&m.body.map(|b| (b.mass, b.inertia)))?;
    let p = &m.provenance;
    w.put(p.method.as_str())?;
    w.put(p.source.as_str())?;
    w.put(&p.frames_used)?;
    w.put(&p.frames_dropped)?;
    for list in [&p.force_residuals, &p.torque_residuals] {
        w.put(&(list.len() as u8))?;
        for v in list.iter() {
            w.put(v)?;
        }
    }
    w.put(&(p.coverage.len() as u16))?;
    for c in p.coverage.iter() {
        w.put(c)?;
    }
    w.put(&(m.extensions().len() as u8))?;
    for e in m.extensions().iter() {
        w.put(&e.kind)?;
        w.put(&e.version)?;
        w.put(&(e.data.len() as u8))?;
        for b in e.data.iter() {
            w.put(b)?;
        }
    }
    Ok(())
}

/// Decodes a whole file. The CRC is checked before anything else is read.
pub fn decode<T: LaneScalar>(bytes: &[u8]) -> Result<Coefficients<T>, FileError> {
    let mut model = Coefficients::zeros(0, Vector3::z(), T::one())?;
    decode_into(bytes, &mut model)?;
    Ok(model)
}

/// Decodes a whole file into `out`, in place: no copy of the model is
/// made on the stack (a `Coefficients<f32>` is about 5 KiB, which matters
/// on a microcontroller). On error `out` is reset to an empty degree-0
/// model, never left half-decoded.
pub fn decode_into<T: LaneScalar>(
    bytes: &[u8],
    out: &mut Coefficients<T>,
) -> Result<(), FileError> {
    let result = decode_checked(bytes, out);
    if result.is_err() {
        // Cannot fail: the arguments are valid.
        let _ = out.reset(0, Vector3::z(), T::one());
    }
    result
}

fn decode_checked<T: LaneScalar>(bytes: &[u8], out: &mut Coefficients<T>) -> Result<(), FileError> {
    let magic = bytes
        .get(..8)
        .ok_or(if bytes.len() < 8 && MAGIC.starts_with(bytes) {
            FileError::Truncated
        } else {
            FileError::BadMagic
        })?;
    if magic != MAGIC {
        return Err(FileError::BadMagic);
    }
    let version = u16::from_le_bytes(read_array(bytes, 8)?);
    if version != FORMAT_VERSION {
        return Err(FileError::UnknownVersion(version));
    }
    let payload_len = u32::from_le_bytes(read_array(bytes, 10)?) as usize;
    let end = HEADER_LEN
        .checked_add(payload_len)
        .ok_or(FileError::Truncated)?;
    let stored = u32::from_le_bytes(read_array(bytes, end)?);
    let computed = crc32(bytes.get(..end).ok_or(FileError::Truncated)?);
    if stored != computed {
        return Err(FileError::CrcMismatch { stored, computed });
    }
    if bytes.len() > end + 4 {
        return Err(FileError::TrailingBytes(bytes.len() - end - 4));
    }
    let payload = bytes.get(HEADER_LEN..end).ok_or(FileError::Truncated)?;
    let mut r = Reader { rest: payload };
    read_payload_v1(&mut r, out)?;
    if !r.rest.is_empty() {
        return Err(FileError::PayloadLength);
    }
    Ok(())
}

fn read_array<const N: usize>(bytes: &[u8], at: usize) -> Result<[u8; N], FileError> {
    let s = bytes
        .get(at..at.checked_add(N).ok_or(FileError::Truncated)?)
        .ok_or(FileError::Truncated)?;
    let mut out = [0u8; N];
    out.copy_from_slice(s);
    Ok(out)
}

fn read_payload_v1<T: LaneScalar>(
    r: &mut Reader<'_>,
    m: &mut Coefficients<T>,
) -> Result<(), FileError> {
    let c = T::of_f64;
    let name: heapless::String<NAME_CAPACITY> = r.string("name")?;
    let degree: u8 = r.take("degree")?;
    if degree as usize > MAX_DEGREE {
        return Err(ModelError::DegreeTooHigh(degree).into());
    }
    let pole = r.finite_array::<3>("pole")?;
    let length = r.finite("reference_length")?;
    let torque_degree = torque_degree_ahead(r, coeff_count(degree as usize))?;
    m.reset_degrees(degree, torque_degree, Vector3::from(pole.map(c)), c(length))?;
    m.set_name(&name)?;
    for set in 0..6 {
        let (field, count) = if set < 3 {
            ("alpha", m.coeff_count())
        } else {
            ("beta", m.torque_coeff_count())
        };
        let n: u16 = r.take(field)?;
        if n as usize != count {
            return Err(FileError::BadCount(field));
        }
        for k in 0..count {
            let v = c(r.finite(field)?);
            if set < 3 {
                m.set_alpha(set, k, v)?;
            } else {
                m.set_beta(set - 3, k, v)?;
            }
        }
    }
    let damping = r.finite_array::<6>("damping")?;
    m.set_damping(&symmetric_from_six(damping.map(c)))?;
    let body: Option<(f64, [f64; 6])> = r.take("body")?;
    if let Some((mass, inertia)) = body {
        let props = MassProperties { mass, inertia };
        if !mass.is_finite() || inertia.iter().any(|x| !x.is_finite()) {
            return Err(ModelError::NonFinite("body").into());
        }
        RigidBody::<f64>::from_properties(&props)?;
        m.body = Some(props);
    }
    read_provenance(r, &mut m.provenance)?;
    read_extensions(r, m)?;
    Ok(())
}

/// The torque's degree N_T, read ahead of `r` (which is left where it
/// is) from the first beta count, past the three alpha sets of `count`
/// values each: the storage's layout depends on it, so it is known before
/// any coefficient is stored.
fn torque_degree_ahead(r: &Reader<'_>, count: usize) -> Result<u8, FileError> {
    let mut ahead = Reader { rest: r.rest };
    for _ in 0..3 {
        let n: u16 = ahead.take("alpha")?;
        if n as usize != count {
            return Err(FileError::BadCount("alpha"));
        }
        for _ in 0..count {
            let _: f64 = ahead.take("alpha")?;
        }
    }
    let n: u16 = ahead.take("beta")?;
    (0..=MAX_DEGREE)
        .find(|&d| coeff_count(d) == n as usize)
        .and_then(|d| u8::try_from(d).ok())
        .ok_or(FileError::BadCount("beta"))
}

/// Reads provenance into `p`, which must be empty (after `reset`).
fn read_provenance(r: &mut Reader<'_>, p: &mut Provenance) -> Result<(), FileError> {
    p.method = r.string::<32>("provenance.method")?;
    p.source = r.string::<TEXT_CAPACITY>("provenance.source")?;
    p.frames_used = r.take("provenance.frames_used")?;
    p.frames_dropped = r.take("provenance.frames_dropped")?;
    for (list, field) in [
        (&mut p.force_residuals, "provenance.force_residuals"),
        (&mut p.torque_residuals, "provenance.torque_residuals"),
    ] {
        let n: u8 = r.take(field)?;
        if n as usize > MAX_ITERATIONS {
            return Err(FileError::BadCount(field));
        }
        for _ in 0..n {
            let v = r.finite(field)?;
            list.push(v).map_err(|_| FileError::BadCount(field))?;
        }
    }
    let n: u16 = r.take("provenance.coverage")?;
    if n as usize > COVERAGE_CELLS {
        return Err(FileError::BadCount("provenance.coverage"));
    }
    for _ in 0..n {
        let v: u16 = r.take("provenance.coverage")?;
        p.coverage
            .push(v)
            .map_err(|_| FileError::BadCount("provenance.coverage"))?;
    }
    Ok(())
}

/// Reads extensions into `out`, which must have none (after `reset`).
fn read_extensions<T: LaneScalar>(
    r: &mut Reader<'_>,
    out: &mut Coefficients<T>,
) -> Result<(), FileError> {
    let n: u8 = r.take("extensions")?;
    if n as usize > MAX_EXTENSIONS {
        return Err(FileError::BadCount("extensions"));
    }
    for _ in 0..n {
        let mut e = Extension {
            kind: r.take("extension.kind")?,
            version: r.take("extension.version")?,
            data: heapless::Vec::new(),
        };
        let len: u8 = r.take("extension.data")?;
        if len as usize > EXTENSION_CAPACITY {
            return Err(FileError::BadCount("extension.data"));
        }
        for _ in 0..len {
            let b: u8 = r.take("extension.data")?;
            e.data
                .push(b)
                .map_err(|_| FileError::BadCount("extension.data"))?;
        }
        out.add_extension(e).map_err(|err| match err {
            ModelError::CapacityExceeded(_) => FileError::BadCount("extensions"),
            other => other.into(),
        })?;
    }
    Ok(())
}
