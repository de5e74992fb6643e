//! Data files named by String parameters (a vehicle file, a path file): where they are, and reading them
//! without trusting them.

use super::api::parse_resource_location;
use super::model::{ModelContext, ResourceLocation};
use std::path::{Path, PathBuf};

/// What a String parameter's value names, as far as the value alone tells (no file is looked at).
enum Named<'a> {
    /// A `file:` URI's local path.
    Uri(PathBuf),
    /// A path as written, relative or absolute.
    Path(&'a Path),
}

/// The value itself (surrounding white space ignored): not empty, no NUL character (no file has one in its
/// name, and `fmi2SetString` cannot pass one: only a deserialized state can), and a `file:` URI must be a
/// local file URI (host empty or `localhost`, valid percent escapes of UTF-8, no `%00`).
fn named<'a>(parameter: &str, file: &'a str) -> Result<Named<'a>, String> {
    let file = file.trim();
    if file.is_empty() {
        return Err(format!("{parameter} is empty: name a file"));
    }
    if file.contains('\0') {
        return Err(format!("{parameter} {file:?} contains a NUL character"));
    }
    if file.to_ascii_lowercase().starts_with("file:") {
        return match parse_resource_location(Some(file)) {
            ResourceLocation::Dir(p) if !p.as_os_str().as_encoded_bytes().contains(&0) => Ok(Named::Uri(p)),
            _ => Err(format!("{parameter} {file:?} is not a local file URI")),
        };
    }
    Ok(Named::Path(Path::new(file)))
}

/// The check `locate` makes of a value before it looks for the file: a model calls it wherever such a value
/// enters (set, initialization, a restored state), so that all of them accept and refuse the same values.
pub fn check(parameter: &str, file: &str) -> Result<(), String> {
    named(parameter, file).map(|_| ())
}

/// The file a String parameter names: a `file:` URI; a relative path, looked up in the FMU's resources, then
/// in the working directory; an absolute path. `parameter` names the parameter in messages.
pub fn locate(parameter: &str, file: &str, context: &ModelContext) -> Result<PathBuf, String> {
    let path = match named(parameter, file)? {
        Named::Uri(path) => return Ok(path),
        Named::Path(path) => path,
    };
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
