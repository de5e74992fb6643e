//! Data files named by String parameters (a vehicle file, a path file): where they are, and reading them
//! without trusting them.

use super::api::parse_resource_location;
use super::model::{ModelContext, ResourceLocation};
use std::path::{Path, PathBuf};

/// The file a String parameter names: a `file:` URI; a relative path, looked up in the FMU's resources, then
/// in the working directory; an absolute path. `parameter` names the parameter in messages.
pub fn locate(parameter: &str, file: &str, context: &ModelContext) -> Result<PathBuf, String> {
    let file = file.trim();
    if file.is_empty() {
        return Err(format!("{parameter} is empty: name a file"));
    }
    if file.to_ascii_lowercase().starts_with("file:") {
        return match parse_resource_location(Some(file)) {
            ResourceLocation::Dir(p) => Ok(p),
            _ => Err(format!("{parameter} {file:?} is not a local file URI")),
        };
    }
    let path = Path::new(file);
    if path.is_relative() {
        if let ResourceLocation::Dir(dir) = &context.resources {
            let candidate = dir.join(path);
            if candidate.exists() {
                return Ok(candidate);
            }
        }
    }
    Ok(path.to_path_buf())
}

/// The text of `path`, which must be a regular file of at most `limit` bytes. Checked before the file is
/// opened, so that a FIFO does not block and a device is not read until memory runs out; and never more
/// than `limit` bytes are read (the file may grow between the check and the read). `what` names the file
/// in messages.
pub fn read_bounded(path: &Path, limit: u64, what: &str) -> Result<String, String> {
    use std::io::Read as _;
    let meta = std::fs::metadata(path).map_err(|e| format!("cannot read {what}: {e}"))?;
    if !meta.is_file() {
        return Err(format!("{what} is not a regular file (a directory, FIFO or device)"));
    }
    if meta.len() > limit {
        return Err(format!("{what} has {} bytes, more than the {limit} allowed", meta.len()));
    }
    let mut text = String::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(limit + 1).read_to_string(&mut text))
        .map_err(|e| format!("cannot read {what}: {e}"))?;
    if text.len() as u64 > limit {
        return Err(format!("{what} grew beyond the {limit} bytes allowed"));
    }
    Ok(text)
}
