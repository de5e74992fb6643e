//! Reading data files named by users (vehicle, tire and road files, an FMU's path file) without trusting
//! them. A file must be a regular file of at most `limit` bytes. This is checked before the file is opened,
//! so that a FIFO does not block and a device is not read until memory runs out. Never more than `limit`
//! bytes are read, because the file may grow between the check and the read. `what` names the file in
//! messages.
//!
//! Its own crate because the model layer (vehicle, tire and road files) and the FMI layer (the driver
//! FMU's path file) both read such files and neither may depend on the other.
use std::io::Read as _;
use std::path::Path;

/// The bytes of `path` (see the crate doc).
pub fn read_bytes(path: &Path, limit: u64, what: &str) -> Result<Vec<u8>, String> {
    let meta = std::fs::metadata(path).map_err(|e| format!("cannot read {what}: {e}"))?;
    if !meta.is_file() {
        return Err(format!("{what} is not a regular file (a directory, FIFO or device)"));
    }
    if meta.len() > limit {
        return Err(format!("{what} has {} bytes, more than the {limit} allowed", meta.len()));
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    std::fs::File::open(path)
        .and_then(|f| f.take(limit + 1).read_to_end(&mut bytes))
        .map_err(|e| format!("cannot read {what}: {e}"))?;
    if bytes.len() as u64 > limit {
        return Err(format!("{what} grew beyond the {limit} bytes allowed"));
    }
    Ok(bytes)
}

/// The text of `path` (see the crate doc); not UTF-8 is an error.
pub fn read_text(path: &Path, limit: u64, what: &str) -> Result<String, String> {
    String::from_utf8(read_bytes(path, limit, what)?).map_err(|e| format!("cannot read {what}: not UTF-8 text ({e})"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_what_is_not_a_bounded_regular_file() {
        let dir = std::env::temp_dir().join(format!("bounded-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("f.txt");
        std::fs::write(&file, "0123456789").unwrap();
        assert_eq!(read_text(&file, 10, "the file").unwrap(), "0123456789");
        assert!(read_text(&file, 9, "the file").unwrap_err().contains("more than the 9 allowed"));
        assert!(read_text(&dir, 100, "the file").unwrap_err().contains("not a regular file"));
        assert!(read_text(&dir.join("missing"), 100, "the file").unwrap_err().contains("cannot read the file"));
        std::fs::write(&file, [0xff, 0xfe]).unwrap();
        assert!(read_text(&file, 10, "the file").unwrap_err().contains("not UTF-8"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
