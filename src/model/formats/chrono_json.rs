//! Chrono's JSON files: comments stripped, and objects read with every key named in its messages (`Obj`,
//! `ImportError`). A leaf module (no imports of the model), so that both the vehicle import
//! (`import_chrono`) and the TMeasy tire reader (`model::tire::tmeasy`) use it without an import circle;
//! each adds the typed readers of its own (points and masses there, load pairs here) in its own `impl Obj`.

use serde_json::{Map, Value};

/// An error of reading a Chrono JSON file: the file, the dotted key and the cause.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ImportError {
    pub file: String,
    pub key: String,
    pub message: String,
}

impl std::fmt::Display for ImportError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.key.is_empty() {
            write!(f, "{}: {}", self.file, self.message)
        } else {
            write!(f, "{}: {}: {}", self.file, self.key, self.message)
        }
    }
}

impl std::error::Error for ImportError {}

/// Readers whose errors are text (the tire readers') take an `ImportError` by its message.
impl From<ImportError> for String {
    fn from(e: ImportError) -> String {
        e.to_string()
    }
}

/// One JSON object of a Chrono file, with the dotted path of its key in that file.
#[derive(Clone)]
pub struct Obj<'a> {
    pub file: &'a str,
    pub path: String,
    pub map: &'a Map<String, Value>,
}

/// What the model does with a key it reads but has no place for: (key, why).
pub type Ignored<'k> = (&'k str, &'k str);

/// A finite number, or none.
pub fn number(v: &Value) -> Option<f64> {
    v.as_f64().filter(|x| x.is_finite())
}

impl<'a> Obj<'a> {
    /// The file's top-level object.
    pub fn root(file: &'a str, map: &'a Map<String, Value>) -> Obj<'a> {
        Obj { file, path: String::new(), map }
    }

    pub fn key(&self, k: &str) -> String {
        if self.path.is_empty() {
            k.to_string()
        } else {
            format!("{}.{k}", self.path)
        }
    }

    pub fn err(&self, k: &str, message: impl Into<String>) -> ImportError {
        ImportError { file: self.file.to_string(), key: self.key(k), message: message.into() }
    }

    pub fn has(&self, k: &str) -> bool {
        self.map.contains_key(k)
    }

    pub fn get(&self, k: &str) -> Result<&'a Value, ImportError> {
        self.map.get(k).ok_or_else(|| self.err(k, "missing"))
    }

    pub fn num(&self, k: &str) -> Result<f64, ImportError> {
        number(self.get(k)?).ok_or_else(|| self.err(k, "must be a finite number"))
    }

    pub fn opt_num(&self, k: &str) -> Result<Option<f64>, ImportError> {
        if self.has(k) {
            self.num(k).map(Some)
        } else {
            Ok(None)
        }
    }

    pub fn text(&self, k: &str) -> Result<&'a str, ImportError> {
        self.get(k)?.as_str().ok_or_else(|| self.err(k, "must be a string"))
    }

    pub fn flag(&self, k: &str) -> Result<bool, ImportError> {
        match self.map.get(k) {
            None => Ok(false),
            Some(v) => v.as_bool().ok_or_else(|| self.err(k, "must be true or false")),
        }
    }

    pub fn array(&self, k: &str, n: usize) -> Result<Vec<f64>, ImportError> {
        let a = self.get(k)?.as_array().ok_or_else(|| self.err(k, format!("must be an array of {n} numbers")))?;
        let v: Vec<f64> = a.iter().filter_map(number).collect();
        if a.len() != n || v.len() != n {
            return Err(self.err(k, format!("must be an array of {n} finite numbers")));
        }
        Ok(v)
    }

    pub fn obj(&self, k: &str) -> Result<Obj<'a>, ImportError> {
        let map = self.get(k)?.as_object().ok_or_else(|| self.err(k, "must be an object"))?;
        Ok(Obj { file: self.file, path: self.key(k), map })
    }

    /// The `i`-th object of the array `k`.
    pub fn item(&self, k: &str, i: usize, v: &'a Value) -> Result<Obj<'a>, ImportError> {
        let path = format!("{k}[{i}]");
        let map = v.as_object().ok_or_else(|| self.err(&path, "must be an object"))?;
        Ok(Obj { file: self.file, path: self.key(&path), map })
    }

    /// Every key must be one the reader uses (`used`) or knows to leave out (`ignored`, each with the
    /// reason, which becomes a warning); any other key is an error.
    pub fn keys(&self, used: &[&str], ignored: &[Ignored], warnings: &mut Vec<String>) -> Result<(), ImportError> {
        for k in self.map.keys() {
            if used.contains(&k.as_str()) {
                continue;
            }
            match ignored.iter().find(|(name, _)| name == k) {
                Some((_, why)) => warnings.push(format!("{}: {}: ignored ({why})", self.file, self.key(k))),
                None => {
                    let mut known: Vec<&str> = used.to_vec();
                    known.extend(ignored.iter().map(|(n, _)| *n));
                    return Err(self.err(k, format!("unknown key (known here: {})", known.join(", "))));
                }
            }
        }
        Ok(())
    }
}

/// Chrono's JSON files may carry comments (rapidjson `kParseCommentsFlag`); serde_json takes none.
pub fn strip_comments(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut chars = text.chars().peekable();
    let mut in_string = false;
    while let Some(c) = chars.next() {
        if in_string {
            out.push(c);
            match c {
                '\\' => {
                    if let Some(n) = chars.next() {
                        out.push(n);
                    }
                }
                '"' => in_string = false,
                _ => {}
            }
            continue;
        }
        match (c, chars.peek()) {
            ('"', _) => {
                in_string = true;
                out.push(c);
            }
            ('/', Some('/')) => {
                for n in chars.by_ref() {
                    if n == '\n' {
                        out.push('\n');
                        break;
                    }
                }
            }
            ('/', Some('*')) => {
                chars.next();
                let mut prev = ' ';
                for n in chars.by_ref() {
                    if prev == '*' && n == '/' {
                        break;
                    }
                    if n == '\n' {
                        out.push('\n');
                    }
                    prev = n;
                }
                out.push(' ');
            }
            _ => out.push(c),
        }
    }
    out
}
