//! Reading the files a user names (URDFs, scenarios, robot descriptions, meshes) within bounds
//! of time and memory: only regular files (not a device such as `/dev/zero`, a FIFO that may
//! never end, or a directory), no larger than a limit given by the kind of file, and read no
//! further than that limit even when the file grows while it is read; and XML no deeper than
//! [`MAX_XML_DEPTH`] before a recursive parser sees it.

use std::io::{self, Read};
use std::path::Path;

/// The largest text file read (URDF, scenario, robot description), in bytes: 32 MiB, far above
/// real robots' URDFs (example-robot-data's Talos: 0.11 MB; its meshes are files of their own).
pub const MAX_TEXT_BYTES: u64 = 32 << 20;

/// The largest TOML file read (a scenario, a robot description), in bytes: 4 MiB, some four
/// hundred times the largest shipped scenario (Talos walking, 10 kB). A TOML array of numbers
/// takes about twenty times its text's size once parsed, so this bounds a file's memory to
/// about 100 MB.
pub const MAX_TOML_BYTES: u64 = 4 << 20;

/// The largest mesh file read, in bytes: 256 MiB, about nine times the largest mesh of
/// example-robot-data (Go1's `trunk.dae`, 28.8 MB).
pub const MAX_MESH_BYTES: u64 = 256 << 20;

/// The deepest XML element nesting accepted: a URDF needs 5 or 6 (robot, link, visual,
/// geometry, mesh); a recursive parser would overflow its stack on a file nested tens of
/// thousands deep.
pub const MAX_XML_DEPTH: usize = 256;

/// The bytes of the regular file `path`, at most `limit` of them.
///
/// Errors: the file cannot be opened or read (a directory: the operating system's error of
/// reading it, `EISDIR` on Unix); it is not a regular file ([`io::ErrorKind::InvalidInput`]);
/// it holds more than `limit` bytes ([`io::ErrorKind::InvalidData`], the message naming both
/// sizes).
pub fn read_bounded(path: &Path, limit: u64) -> io::Result<Vec<u8>> {
    // The kind first: opening a FIFO would wait for a writer.
    let metadata = std::fs::metadata(path)?;
    if metadata.is_dir() {
        // The operating system's own error for reading a directory (EISDIR on Unix), so that
        // it carries its error number.
        std::fs::File::open(path)?.read_exact(&mut [0u8; 1])?;
    }
    if !metadata.is_file() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "not a regular file",
        ));
    }
    if metadata.len() > limit {
        return Err(too_large(metadata.len(), limit));
    }
    let file = std::fs::File::open(path)?;
    let mut bytes = Vec::with_capacity(metadata.len() as usize);
    file.take(limit + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64, limit));
    }
    Ok(bytes)
}

/// Why `path` is not an existing folder to search (a package directory): "a file", or the
/// error reaching it (`No such file or directory (os error 2)`); `None` when it is one.
pub fn not_a_folder(path: &Path) -> Option<String> {
    match std::fs::metadata(path) {
        Ok(meta) if meta.is_dir() => None,
        Ok(_) => Some("a file".to_string()),
        Err(e) => Some(e.to_string()),
    }
}

/// The text of the regular file `path`, at most [`MAX_TEXT_BYTES`] bytes of UTF-8.
///
/// Errors: as [`read_text_within`].
pub fn read_text(path: &Path) -> io::Result<String> {
    read_text_within(path, MAX_TEXT_BYTES)
}

/// The text of the regular file `path`, at most `limit` bytes of UTF-8 (e.g.
/// [`MAX_TOML_BYTES`]).
///
/// Errors: as [`read_bounded`], and [`io::ErrorKind::InvalidData`] when the text is not UTF-8.
pub fn read_text_within(path: &Path, limit: u64) -> io::Result<String> {
    let bytes = read_bounded(path, limit)?;
    String::from_utf8(bytes).map_err(|e| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to()),
        )
    })
}

/// The error of a file of `size` bytes over `limit`.
fn too_large(size: u64, limit: u64) -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidData,
        format!("the file holds {size} bytes or more, over the limit of {limit} bytes"),
    )
}

/// The deepest element nesting of the XML `text` (elements only; comments, CDATA sections,
/// processing instructions and declarations skipped, quoted attribute values read as text).
/// A scan of the text without building it, linear and without recursion, for a guard before a
/// recursive parser; text that is not well-formed gives a depth all the same.
pub fn xml_depth(text: &str) -> usize {
    let bytes = text.as_bytes();
    let (mut depth, mut deepest, mut at) = (0usize, 0usize, 0usize);
    while let Some(offset) = bytes[at..].iter().position(|&b| b == b'<') {
        let start = at + offset;
        let rest = &text[start..];
        if let Some(skip) = [("<!--", "-->"), ("<![CDATA[", "]]>"), ("<?", "?>")]
            .iter()
            .find(|(open, _)| rest.starts_with(open))
            .map(|(_, close)| rest.find(close).map_or(rest.len(), |e| e + close.len()))
        {
            at = start + skip;
            continue;
        }
        let end = start + tag_end(&bytes[start..]);
        let tag = &bytes[start..end];
        if tag.get(1) == Some(&b'/') {
            depth = depth.saturating_sub(1);
        } else if tag.get(1) != Some(&b'!') && !tag.ends_with(b"/>") {
            depth += 1;
            deepest = deepest.max(depth);
        }
        at = end;
    }
    deepest
}

/// The length of the tag at the start of `bytes` (from its `<` to its `>` included, a `>`
/// within quotes not counting; the whole of `bytes` when it does not close).
fn tag_end(bytes: &[u8]) -> usize {
    let mut quote = None;
    for (i, &b) in bytes.iter().enumerate() {
        match (quote, b) {
            (None, b'"' | b'\'') => quote = Some(b),
            (Some(q), _) if b == q => quote = None,
            (None, b'>') => return i + 1,
            _ => {}
        }
    }
    bytes.len()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn xml_depth_counts_elements_only() {
        let urdf = r#"<?xml version="1.0"?><!-- <a><b><c> --><robot name="r>">
            <link name="a"><visual><geometry><box size="1 1 1"/></geometry></visual></link>
            <![CDATA[<x><y><z>]]><joint name="j" type='fixed'><parent link="a"/></joint></robot>"#;
        assert_eq!(xml_depth(urdf), 4);
        assert_eq!(xml_depth(""), 0);
        assert_eq!(xml_depth(&"<a>".repeat(1000)), 1000);
        assert_eq!(xml_depth("<a><b/></a><c>"), 1);
    }

    #[test]
    fn read_bounded_refuses_devices_directories_and_large_files() {
        let dir = std::env::temp_dir().join(format!("sea_files_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("ten.txt");
        std::fs::write(&file, "0123456789").unwrap();
        assert_eq!(read_bounded(&file, 10).unwrap().len(), 10);
        let error = read_bounded(&file, 9).unwrap_err();
        assert_eq!(error.kind(), io::ErrorKind::InvalidData);
        assert!(
            error.to_string().contains("over the limit of 9 bytes"),
            "{error}"
        );
        let error = read_bounded(&dir, 10).unwrap_err();
        #[cfg(unix)]
        assert_eq!(error.kind(), io::ErrorKind::IsADirectory, "{error}");
        assert!(error.raw_os_error().is_some(), "{error}");
        let error = read_bounded(Path::new("/dev/zero"), 10).unwrap_err();
        assert!(error.to_string().contains("not a regular file"), "{error}");
        std::fs::write(&file, [0xff, 0xfe]).unwrap();
        assert!(read_text(&file)
            .unwrap_err()
            .to_string()
            .contains("not UTF-8"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
