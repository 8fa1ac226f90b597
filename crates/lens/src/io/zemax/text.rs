//! The text of a Zemax file from its bytes: OpticStudio writes UTF-16 LE
//! with a byte-order mark; older versions and other programs write UTF-8,
//! Latin-1 (Windows-1252's printable subset) or UTF-16 without a mark.

/// Decodes `bytes`: a byte-order mark decides (UTF-16 LE, UTF-16 BE,
/// UTF-8); without one, zero bytes in every other place mean UTF-16 (LE
/// when the zeros are second), otherwise UTF-8 when it is valid, else
/// Latin-1 (every byte one character). Returns the text and the encoding's
/// name; errors on UTF-16 that is not valid.
pub fn decode(bytes: &[u8]) -> Result<(String, &'static str), String> {
    if let Some(rest) = bytes.strip_prefix(&[0xFF, 0xFE]) {
        return utf16(rest, u16::from_le_bytes).map(|t| (t, "UTF-16 LE"));
    }
    if let Some(rest) = bytes.strip_prefix(&[0xFE, 0xFF]) {
        return utf16(rest, u16::from_be_bytes).map(|t| (t, "UTF-16 BE"));
    }
    if let Some(rest) = bytes.strip_prefix(&[0xEF, 0xBB, 0xBF]) {
        return String::from_utf8(rest.to_vec()).map(|t| (t, "UTF-8")).map_err(|e| e.to_string());
    }
    let sample = &bytes[..bytes.len().min(4096)];
    let zeros_at = |odd: usize| sample.iter().skip(odd).step_by(2).filter(|b| **b == 0).count();
    let half = sample.len() / 2;
    if half > 0 && zeros_at(1) * 4 > half * 3 {
        return utf16(bytes, u16::from_le_bytes).map(|t| (t, "UTF-16 LE"));
    }
    if half > 0 && zeros_at(0) * 4 > half * 3 {
        return utf16(bytes, u16::from_be_bytes).map(|t| (t, "UTF-16 BE"));
    }
    match String::from_utf8(bytes.to_vec()) {
        Ok(t) => Ok((t, "UTF-8")),
        Err(_) => Ok((bytes.iter().map(|b| char::from(*b)).collect(), "Latin-1")),
    }
}

/// UTF-16 code units from byte pairs, decoded (an odd last byte is an
/// error).
fn utf16(bytes: &[u8], unit: fn([u8; 2]) -> u16) -> Result<String, String> {
    if !bytes.len().is_multiple_of(2) {
        return Err("the file looks like UTF-16 but has an odd number of bytes".into());
    }
    let units: Vec<u16> = bytes.chunks_exact(2).map(|c| unit([c[0], c[1]])).collect();
    String::from_utf16(&units).map_err(|_| "the file looks like UTF-16 but is not valid UTF-16".into())
}

/// `text` as UTF-16 LE with a byte-order mark, as OpticStudio writes.
pub fn encode_utf16le(text: &str) -> Vec<u8> {
    let mut out = vec![0xFF, 0xFE];
    for u in text.encode_utf16() {
        out.extend_from_slice(&u.to_le_bytes());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_encoding_decodes_to_the_same_text() {
        let text = "NAME Objectif \u{e9}tude 50mm\nSURF 0\n";
        let le: Vec<u8> = text.encode_utf16().flat_map(|u| u.to_le_bytes()).collect();
        let be: Vec<u8> = text.encode_utf16().flat_map(|u| u.to_be_bytes()).collect();
        let latin1: Vec<u8> = text.chars().map(|c| c as u8).collect();
        for (bytes, name) in [
            (encode_utf16le(text), "UTF-16 LE"),
            ([&[0xFE, 0xFF][..], &be].concat(), "UTF-16 BE"),
            (le, "UTF-16 LE"),
            (be, "UTF-16 BE"),
            (text.as_bytes().to_vec(), "UTF-8"),
            ([&[0xEF, 0xBB, 0xBF][..], text.as_bytes()].concat(), "UTF-8"),
            (latin1, "Latin-1"),
        ] {
            assert_eq!(decode(&bytes).unwrap(), (text.to_string(), name));
        }
        assert!(decode(&[0xFF, 0xFE, 0x41]).is_err());
    }
}
