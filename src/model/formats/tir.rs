//! Reading Pacejka tire property files (`.tir`, the ADAMS/TNO format: PAC2002, MF 6.1/6.2), the first
//! part of the Magic Formula tire (issue 18). This module reads a file into its sections and keys and
//! converts units; the Magic Formula itself (which keys it needs, their defaults) is built on it.
//!
//! The format, as the files in `data/chrono` and the MF-Tyre documentation have it:
//! - `[SECTION]` headers; `KEY = value` lines; `$` starts a comment (whole line or after a value), `!` a
//!   whole-line comment; values are numbers or quoted strings (`'meter'`);
//! - table sections (`[SHAPE]`, `[DEFLECTION_LOAD_CURVE]`, `[BOTTOMING_CURVE]`) hold a `{...}` header and
//!   rows of numbers: kept as rows, unused by the steady-state model (a warning says so);
//! - `[UNITS]` names the units of LENGTH, FORCE, ANGLE, MASS, TIME (and PRESSURE): compared after
//!   normalisation (case, quotes, a plural `s`: `'radians'` is `'radian'`) and converted to SI.
//!
//! Every error names the file, and where it applies the key and the line (1-based).
use std::collections::BTreeMap;
use std::path::Path;

/// The largest `.tir` file read (the shipped ones are 10–20 kB).
pub const MAX_TIR_BYTES: u64 = 4 << 20;

/// A value as written.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Number(f64),
    Text(String),
}

/// One `KEY = value` line.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    pub value: Value,
    /// 1-based line number.
    pub line: usize,
}

/// A `.tir` file read into sections.
#[derive(Debug, Clone, PartialEq)]
pub struct TirFile {
    /// How the file is named in messages.
    pub name: String,
    /// `KEY = value` entries per section (names upper-case, as written).
    pub sections: BTreeMap<String, BTreeMap<String, Entry>>,
    /// Rows of the table sections (`{...}` header skipped).
    pub tables: BTreeMap<String, Vec<Vec<f64>>>,
    /// The (first) line of each `[SECTION]` header, 1-based: where a missing key was expected.
    pub section_lines: BTreeMap<String, usize>,
    /// What was read but is not used, or read leniently.
    pub warnings: Vec<String>,
}

/// A unit kind of the `[UNITS]` section.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnitKind {
    Length,
    Force,
    Angle,
    Mass,
    Time,
    Pressure,
}

impl UnitKind {
    fn key(self) -> &'static str {
        match self {
            UnitKind::Length => "LENGTH",
            UnitKind::Force => "FORCE",
            UnitKind::Angle => "ANGLE",
            UnitKind::Mass => "MASS",
            UnitKind::Time => "TIME",
            UnitKind::Pressure => "PRESSURE",
        }
    }

    /// The SI factor of a unit name (normalised), if known.
    fn factor(self, unit: &str) -> Option<f64> {
        Some(match (self, unit) {
            (UnitKind::Length, "meter" | "metre" | "m") => 1.0,
            (UnitKind::Length, "millimeter" | "millimetre" | "mm") => 1e-3,
            (UnitKind::Length, "centimeter" | "centimetre" | "cm") => 1e-2,
            (UnitKind::Length, "inch" | "in") => 0.0254,
            (UnitKind::Force, "newton" | "n") => 1.0,
            (UnitKind::Force, "kilonewton" | "kn") => 1e3,
            (UnitKind::Force, "pound_force" | "lbf") => 4.448_221_615_260_5,
            (UnitKind::Angle, "radian" | "rad") => 1.0,
            (UnitKind::Angle, "degree" | "deg") => std::f64::consts::PI / 180.0,
            (UnitKind::Mass, "kg" | "kilogram") => 1.0,
            (UnitKind::Mass, "gram" | "g") => 1e-3,
            (UnitKind::Mass, "pound_mass" | "lbm") => 0.453_592_37,
            (UnitKind::Time, "second" | "sec" | "s") => 1.0,
            (UnitKind::Time, "millisecond" | "ms") => 1e-3,
            (UnitKind::Pressure, "pascal" | "pa") => 1.0,
            (UnitKind::Pressure, "kpa" | "kilopascal") => 1e3,
            (UnitKind::Pressure, "bar") => 1e5,
            (UnitKind::Pressure, "psi") => 6_894.757_293_168,
            _ => return None,
        })
    }
}

/// A unit name compared after normalisation: quotes and spaces off, lower case, a plural `s` off
/// (`'Radians'` → `radian`; `s` and `ms` themselves stay).
fn normalise_unit(text: &str) -> String {
    let t = text.trim().trim_matches('\'').trim_matches('"').trim().to_ascii_lowercase();
    if t.len() > 3 && t.ends_with('s') && !t.ends_with("ss") {
        t[..t.len() - 1].to_string()
    } else {
        t
    }
}

/// The value text of a `KEY = value $comment` line: the comment cut at a `$` outside quotes.
fn value_text(rest: &str) -> &str {
    let mut quoted = false;
    for (i, c) in rest.char_indices() {
        match c {
            '\'' | '"' => quoted = !quoted,
            '$' if !quoted => return rest[..i].trim(),
            _ => {}
        }
    }
    rest.trim()
}

impl TirFile {
    /// Reads `path` (a regular file of at most `MAX_TIR_BYTES`).
    pub fn read(path: &Path) -> Result<TirFile, String> {
        let name = path.display().to_string();
        let text = bounded_read::read_text(path, MAX_TIR_BYTES, &format!("the tire file {name}"))?;
        TirFile::parse(&name, &text)
    }

    /// Parses the text of a file named `name` (for messages).
    pub fn parse(name: &str, text: &str) -> Result<TirFile, String> {
        let mut file = TirFile {
            name: name.to_string(),
            sections: BTreeMap::new(),
            tables: BTreeMap::new(),
            section_lines: BTreeMap::new(),
            warnings: Vec::new(),
        };
        let mut section: Option<String> = None;
        let mut table = false;
        for (k, raw) in text.lines().enumerate() {
            let line = k + 1;
            let l = raw.trim();
            if l.is_empty() || l.starts_with('$') || l.starts_with('!') {
                continue;
            }
            if let Some(rest) = l.strip_prefix('[') {
                let Some(end) = rest.find(']') else {
                    return Err(format!("{name}, line {line}: a section header without ']': {l:?}"));
                };
                let s = rest[..end].trim().to_ascii_uppercase();
                table = false;
                file.sections.entry(s.clone()).or_default();
                file.section_lines.entry(s.clone()).or_insert(line);
                section = Some(s);
                continue;
            }
            let Some(s) = section.clone() else {
                return Err(format!("{name}, line {line}: {l:?} before the first [SECTION]"));
            };
            if l.starts_with('{') {
                // A table's column header: the rows below are numbers.
                table = true;
                file.warnings.push(format!("{name}: table section [{s}] is read but not used by the model"));
                continue;
            }
            if let Some((key, rest)) = l.split_once('=') {
                let key = key.trim().to_ascii_uppercase();
                let v = value_text(rest);
                if key.is_empty() {
                    return Err(format!("{name}, line {line}: a value without a key"));
                }
                if v.is_empty() {
                    // A fit that leaves keys empty (teasit's TTC example `obfuscated.tir` leaves 53 of them)
                    // is not a truncated file: say both, the reader cannot tell which.
                    return Err(format!(
                        "{name}, line {line}: {key} has no value (a truncated file, or a key the fit left empty: \
                         give it a value or remove the line)"
                    ));
                }
                let value = if v.starts_with('\'') || v.starts_with('"') {
                    let q = &v[..1];
                    if v.len() < 2 || !v[1..].contains(q) {
                        return Err(format!("{name}, line {line}: {key}: unterminated string {v:?}"));
                    }
                    Value::Text(v.trim_matches(|c| c == '\'' || c == '"').trim().to_string())
                } else {
                    match v.parse::<f64>() {
                        Ok(x) => Value::Number(x),
                        // Kept as text: an error only if the model asks for it as a number (`number`).
                        Err(_) => Value::Text(v.to_string()),
                    }
                };
                let entries = file.sections.entry(s).or_default();
                if entries.insert(key.clone(), Entry { value, line }).is_some() {
                    file.warnings.push(format!("{name}, line {line}: {key} given twice: the last value is used"));
                }
                continue;
            }
            // A table with no `{...}` header ([SHAPE] in some MF-Tool exports) starts with its first row.
            let numeric_row = l.split_whitespace().all(|w| w.parse::<f64>().is_ok());
            if table || numeric_row {
                if !table {
                    table = true;
                    file.warnings.push(format!("{name}: table section [{s}] is read but not used by the model"));
                }
                let row: Result<Vec<f64>, _> = l.split_whitespace().map(str::parse::<f64>).collect();
                match row {
                    Ok(r) => file.tables.entry(s).or_default().push(r),
                    Err(_) => {
                        return Err(format!("{name}, line {line}: [{s}]: a table row that is not numbers: {l:?}"))
                    }
                }
                continue;
            }
            return Err(format!("{name}, line {line}: neither KEY = value nor a section: {l:?}"));
        }
        if file.sections.is_empty() {
            return Err(format!("{name}: no [SECTION] in the file (empty or not a .tir file)"));
        }
        Ok(file)
    }

    fn entry(&self, section: &str, key: &str) -> Option<&Entry> {
        self.sections.get(section).and_then(|s| s.get(key))
    }

    /// A number the model needs: an error naming the file, section and key if it is missing (with the line
    /// of the section's header, where it was expected, or that the section is missing too), and the line if
    /// it is not a number.
    pub fn number(&self, section: &str, key: &str) -> Result<f64, String> {
        match self.entry(section, key) {
            None => Err(match self.section_lines.get(section) {
                Some(line) => format!(
                    "{}, line {line}: [{section}] {key} is missing from the section starting there, and the model \
                     needs it",
                    self.name
                ),
                None => format!(
                    "{}: [{section}] {key} is missing (no [{section}] section), and the model needs it",
                    self.name
                ),
            }),
            Some(e) => self.as_number(section, key, e),
        }
    }

    /// A number that may be left out (`default` then, as the format defines for it).
    pub fn number_or(&self, section: &str, key: &str, default: f64) -> Result<f64, String> {
        match self.entry(section, key) {
            None => Ok(default),
            Some(e) => self.as_number(section, key, e),
        }
    }

    fn as_number(&self, section: &str, key: &str, e: &Entry) -> Result<f64, String> {
        match &e.value {
            Value::Number(x) if x.is_finite() => Ok(*x),
            Value::Number(x) => Err(format!("{}, line {}: [{section}] {key} = {x} is not finite", self.name, e.line)),
            Value::Text(t) => Err(format!("{}, line {}: [{section}] {key} = {t:?} is not a number", self.name, e.line)),
        }
    }

    /// A text value (quotes off), if present.
    pub fn text(&self, section: &str, key: &str) -> Option<&str> {
        match self.entry(section, key).map(|e| &e.value) {
            Some(Value::Text(t)) => Some(t),
            _ => None,
        }
    }

    /// The SI factor of the file's unit of `kind` (`[UNITS]`; SI where the file names none): an error
    /// naming the key, the file and the line for a unit it cannot convert.
    pub fn unit_factor(&self, kind: UnitKind) -> Result<f64, String> {
        let Some(e) = self.entry("UNITS", kind.key()) else { return Ok(1.0) };
        let written = match &e.value {
            Value::Text(t) => t.clone(),
            Value::Number(x) => x.to_string(),
        };
        kind.factor(&normalise_unit(&written)).ok_or_else(|| {
            format!(
                "{}, line {}: [UNITS] {} = {written:?}: a unit this model cannot convert",
                self.name,
                e.line,
                kind.key()
            )
        })
    }

    /// The format: `PAC2002`, or `MF61`/`MF62` from `FITTYP` (61, 62), in `[MODEL]`.
    pub fn format(&self) -> Result<TirFormat, String> {
        if let Some(f) = self.text("MODEL", "PROPERTY_FILE_FORMAT") {
            match f.to_ascii_uppercase().as_str() {
                "PAC2002" => return Ok(TirFormat::Pac2002),
                "MF_61" | "MF61" | "MF6.1" => return Ok(TirFormat::Mf61),
                "MF_62" | "MF62" | "MF6.2" => return Ok(TirFormat::Mf62),
                _ => {}
            }
        }
        match self.number_or("MODEL", "FITTYP", 0.0)? as i64 {
            // MF-Tyre 5.x (5, 6; 21 as MFeval takes it): PAC2002's equations.
            5 | 6 | 21 => Ok(TirFormat::Pac2002),
            61 => Ok(TirFormat::Mf61),
            62 => Ok(TirFormat::Mf62),
            _ => Err(format!(
                "{}: [MODEL] names neither PROPERTY_FILE_FORMAT = 'PAC2002' nor FITTYP = 5/6/21 (MF 5.x) or 61/62 \
                 (found {:?}, {:?}): a format this model does not read",
                self.name,
                self.text("MODEL", "PROPERTY_FILE_FORMAT"),
                self.entry("MODEL", "FITTYP").map(|e| &e.value)
            )),
        }
    }
}

/// The property-file formats read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum TirFormat {
    Pac2002,
    Mf61,
    Mf62,
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: &str = "$ comment\n[UNITS]\nLENGTH = 'meter' $m\nANGLE = 'Radians'\nFORCE='kilonewton'\n\
        [MODEL]\nPROPERTY_FILE_FORMAT = 'PAC2002'\nLONGVL = 16.7 $ speed\n[SHAPE]\n{radial width}\n 1.0 0.0\n 1.0 0.4\n\
        [VERTICAL]\nFNOMIN = 35000\nVERTICAL_STIFFNESS = abc\n";

    #[test]
    fn reads_keys_units_tables_and_names_errors() {
        let f = TirFile::parse("t.tir", SMALL).unwrap();
        assert_eq!(f.format().unwrap(), TirFormat::Pac2002);
        assert_eq!(f.number("MODEL", "LONGVL").unwrap(), 16.7);
        assert_eq!(f.unit_factor(UnitKind::Angle).unwrap(), 1.0);
        assert_eq!(f.unit_factor(UnitKind::Force).unwrap(), 1e3);
        assert_eq!(f.unit_factor(UnitKind::Mass).unwrap(), 1.0, "SI where the file names none");
        assert_eq!(f.tables["SHAPE"], vec![vec![1.0, 0.0], vec![1.0, 0.4]]);
        assert!(f.warnings.iter().any(|w| w.contains("[SHAPE]")));
        let e = f.number("VERTICAL", "VERTICAL_STIFFNESS").unwrap_err();
        assert!(e.contains("t.tir") && e.contains("line 15") && e.contains("VERTICAL_STIFFNESS"), "{e}");
        let e = f.number("VERTICAL", "VERTICAL_DAMPING").unwrap_err();
        assert!(e.contains("t.tir, line 13") && e.contains("VERTICAL_DAMPING") && e.contains("missing"), "{e}");
        let e = f.number("STRUCTURAL", "PCFX1").unwrap_err();
        assert!(e.contains("t.tir") && e.contains("PCFX1") && e.contains("no [STRUCTURAL] section"), "{e}");
        assert_eq!(f.number_or("VERTICAL", "VERTICAL_DAMPING", 0.0).unwrap(), 0.0);
    }

    #[test]
    fn bad_files_are_named_errors() {
        let unit = TirFile::parse("u.tir", "[UNITS]\nLENGTH = 'furlong'\n").unwrap();
        let e = unit.unit_factor(UnitKind::Length).unwrap_err();
        assert!(e.contains("u.tir, line 2") && e.contains("furlong"), "{e}");
        for (text, needle) in [
            ("[MODEL]\nLONGVL =\n", "LONGVL has no value"),
            ("[MODEL\nLONGVL = 1\n", "without ']'"),
            ("LONGVL = 1\n", "before the first"),
            ("[MODEL]\nNAME = 'abc\n", "unterminated"),
            ("", "no [SECTION]"),
            ("[SHAPE]\n{a b}\n1.0 x\n", "not numbers"),
        ] {
            let e = TirFile::parse("b.tir", text).unwrap_err();
            assert!(e.contains("b.tir") && e.contains(needle), "{text:?}: {e}");
        }
        let f = TirFile::parse("f.tir", "[MODEL]\nPROPERTY_FILE_FORMAT = 'MF_52'\n").unwrap();
        assert!(f.format().unwrap_err().contains("does not read"));
        assert_eq!(TirFile::parse("f.tir", "[MODEL]\nFITTYP = 62\n").unwrap().format().unwrap(), TirFormat::Mf62);
    }
}
