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

/// The text of a data file, read without trusting it (the `bounded-read` crate, shared with the model
/// layer's vehicle, tire and road files).
pub use bounded_read::read_text as read_bounded;
