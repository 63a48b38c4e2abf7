//! Consistent Overhead Byte Stuffing, panic-free, in place.

/// Encodes `src` into `dst` (no trailing zero); returns the length or
/// `None` when `dst` is too small. `dst` needs `src.len() + src.len()/254 + 1`.
pub fn encode(src: &[u8], dst: &mut [u8]) -> Option<usize> {
    let mut code_at = 0usize;
    let mut out = 1usize;
    let mut code: u8 = 1;
    *dst.get_mut(code_at)? = 0;
    for &b in src {
        if b == 0 {
            *dst.get_mut(code_at)? = code;
            code_at = out;
            *dst.get_mut(code_at)? = 0;
            out += 1;
            code = 1;
        } else {
            *dst.get_mut(out)? = b;
            out += 1;
            code += 1;
            if code == 0xFF {
                *dst.get_mut(code_at)? = code;
                code_at = out;
                *dst.get_mut(code_at)? = 0;
                out += 1;
                code = 1;
            }
        }
    }
    *dst.get_mut(code_at)? = code;
    Some(out)
}

/// Decodes a COBS block (without its terminating zero) in place; returns
/// the decoded length, or `None` when the block is malformed.
pub fn decode_in_place(buf: &mut [u8]) -> Option<usize> {
    let len = buf.len();
    let mut read = 0usize;
    let mut write = 0usize;
    while read < len {
        let code = *buf.get(read)?;
        if code == 0 {
            return None;
        }
        read += 1;
        for _ in 1..code {
            let b = *buf.get(read)?;
            if b == 0 {
                return None;
            }
            *buf.get_mut(write)? = b;
            read += 1;
            write += 1;
        }
        if code != 0xFF && read < len {
            *buf.get_mut(write)? = 0;
            write += 1;
        }
    }
    Some(write)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::indexing_slicing, clippy::unwrap_used)]
    use super::*;

    #[test]
    fn round_trip() {
        let cases: [&[u8]; 6] = [
            &[],
            &[0],
            &[0, 0],
            &[1, 2, 0, 3],
            &[0x11; 300],
            &[0, 0x22, 0x22, 0],
        ];
        for src in cases {
            let mut enc = [0u8; 400];
            let n = encode(src, &mut enc).unwrap();
            assert!(!enc[..n].contains(&0));
            let m = decode_in_place(&mut enc[..n]).unwrap();
            assert_eq!(&enc[..m], src);
        }
    }
}
