//! From a file's bytes to text: gzip (`.svgz`) undone, and the encodings editors write
//! (UTF-8, UTF-16 with or without a byte-order mark, Latin-1 and the other encodings an XML
//! declaration may name) decoded with `encoding_rs`.

use std::io::Read;

use super::Limits;
use crate::error::{Error, Result};

/// The text of an SVG file's `bytes`: decompressed when gzipped (at most
/// `limits.input_bytes` of output), then decoded by its byte-order mark, else by the encoding
/// its XML declaration names, else as UTF-8. `name` is how errors call the file.
pub fn decode(name: &str, bytes: &[u8], limits: &Limits) -> Result<String> {
    if bytes.starts_with(&[0x1f, 0x8b]) {
        let plain = gunzip(name, bytes, limits)?;
        return decode_text(name, &plain);
    }
    decode_text(name, bytes)
}

/// The gzip stream `bytes` decompressed, refusing more than the byte limit of output (a small
/// file can inflate a thousandfold).
fn gunzip(name: &str, bytes: &[u8], limits: &Limits) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    flate2::read::GzDecoder::new(bytes)
        .take(limits.input_bytes + 1)
        .read_to_end(&mut out)
        .map_err(|e| Error::input(name, format!("not a usable .svgz file: {e}")))?;
    if out.len() as u64 > limits.input_bytes {
        return Err(super::file::too_long(
            name,
            "decompressed, it",
            out.len() as u64,
            limits,
        ));
    }
    Ok(out)
}

fn decode_text(name: &str, bytes: &[u8]) -> Result<String> {
    let (encoding, skip) = match encoding_rs::Encoding::for_bom(bytes) {
        Some((e, bom)) => (e, bom),
        None => (sniff(bytes), 0),
    };
    let body = &bytes[skip..];
    if encoding == encoding_rs::UTF_8 {
        return String::from_utf8(body.to_vec()).map_err(|e| {
            let at = e.utf8_error().valid_up_to() + skip;
            Error::input(
                name,
                format!("not an SVG file: not UTF-8 text (at byte {at}), and no other encoding is declared"),
            )
        });
    }
    encoding
        .decode_without_bom_handling_and_without_replacement(body)
        .map(|t| t.into_owned())
        .ok_or_else(|| {
            Error::input(
                name,
                format!("not an SVG file: not valid {} text", encoding.name()),
            )
        })
}

/// The encoding of text without a byte-order mark: UTF-16 by the shape of `<?`, else the one
/// its XML declaration names (labels as the WHATWG Encoding Standard reads them, so
/// `ISO-8859-1` is windows-1252, a superset), else UTF-8.
fn sniff(bytes: &[u8]) -> &'static encoding_rs::Encoding {
    if bytes.starts_with(&[b'<', 0, b'?', 0]) {
        return encoding_rs::UTF_16LE;
    }
    if bytes.starts_with(&[0, b'<', 0, b'?']) {
        return encoding_rs::UTF_16BE;
    }
    declared(bytes)
        .and_then(|label| encoding_rs::Encoding::for_label(label.as_bytes()))
        // A declaration naming UTF-16 in one-byte text is wrong about itself; read it as UTF-8.
        .filter(|e| *e != encoding_rs::UTF_16LE && *e != encoding_rs::UTF_16BE)
        .unwrap_or(encoding_rs::UTF_8)
}

/// The `encoding` of an XML declaration at the start of `bytes`, if any.
fn declared(bytes: &[u8]) -> Option<String> {
    let head = &bytes[..bytes.len().min(512)];
    if !head.starts_with(b"<?xml") {
        return None;
    }
    let end = head.windows(2).position(|w| w == b"?>")?;
    let decl = std::str::from_utf8(&head[..end]).ok()?;
    let rest = &decl[decl.find("encoding")? + "encoding".len()..];
    let rest = rest.trim_start().strip_prefix('=')?.trim_start();
    let quote = rest.chars().next().filter(|c| *c == '"' || *c == '\'')?;
    let value = &rest[1..];
    Some(value[..value.find(quote)?].to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    const SVG: &str = "<svg viewBox=\"0 0 10 10\"><title>café</title></svg>";

    fn decoded(bytes: &[u8]) -> String {
        decode("a.svg", bytes, &Limits::default()).unwrap()
    }

    #[test]
    fn editors_encodings_decode_to_the_same_text() {
        assert_eq!(decoded(SVG.as_bytes()), SVG);
        let mut bom = vec![0xef, 0xbb, 0xbf];
        bom.extend_from_slice(SVG.as_bytes());
        assert_eq!(decoded(&bom), SVG);
        let latin1_decl = "<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>";
        let text = format!("{latin1_decl}{SVG}");
        let (latin1, _, _) = encoding_rs::WINDOWS_1252.encode(&text);
        assert_eq!(decoded(&latin1), text);
        for (enc, bom) in [
            (encoding_rs::UTF_16LE, [0xff, 0xfe]),
            (encoding_rs::UTF_16BE, [0xfe, 0xff]),
        ] {
            let text = format!("<?xml version=\"1.0\" encoding=\"UTF-16\"?>{SVG}");
            let units: Vec<u16> = text.encode_utf16().collect();
            let mut bytes = bom.to_vec();
            for u in units {
                let b = if enc == encoding_rs::UTF_16LE {
                    u.to_le_bytes()
                } else {
                    u.to_be_bytes()
                };
                bytes.extend_from_slice(&b);
            }
            assert_eq!(decoded(&bytes), text, "{}", enc.name());
            assert_eq!(decoded(&bytes[2..]), text, "{} without a BOM", enc.name());
        }
    }

    #[test]
    fn svgz_is_decompressed_under_the_limit() {
        use std::io::Write;
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        gz.write_all(SVG.as_bytes()).unwrap();
        let bytes = gz.finish().unwrap();
        assert_eq!(decoded(&bytes), SVG);
        // A gzip bomb: 64 MiB of zeros in a few kilobytes.
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
        gz.write_all(&vec![0u8; 64 << 20]).unwrap();
        let bomb = gz.finish().unwrap();
        let e = decode("b.svgz", &bomb, &Limits::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("b.svgz: decompressed, it has") && e.contains("--max-input-bytes"),
            "{e}"
        );
    }

    #[test]
    fn undeclared_bytes_are_located() {
        let e = decode("a.svg", b"<svg>\xe9</svg>", &Limits::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("not UTF-8 text (at byte 5)"), "{e}");
    }
}
