//! The library's files import one another without a circle (issue 33): every `.rs` file under `src/` is a
//! node, and an edge goes from a file to each file whose module it names in a path (`use crate::…`,
//! `use super::…`, `crate::…`/`super::…`/`self::…` in code, a child module's name in its parent). Declaring a
//! child with `mod x;` is not an import. The binaries (`src/bin/`) are crates of their own and are left out.
//!
//! The check reads the source text with a small tokenizer (comments, strings and characters skipped), so it
//! needs no parser crate; a path is resolved to the longest module prefix that is a file, so naming an item
//! a parent `mod.rs` re-exports is an edge to that `mod.rs`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

#[derive(Debug, Clone, PartialEq)]
enum Token {
    Ident(String),
    PathSep,
    Open,
    Close,
    Comma,
    Semi,
    Other,
}

/// The tokens of a Rust source with the line each starts on; comments, string, byte-string, raw-string and
/// character literals become `Other` (their contents never read as paths or braces).
fn tokens(src: &str) -> Vec<(Token, usize)> {
    let c: Vec<char> = src.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    let count_lines = |from: usize, to: usize, line: &mut usize| {
        *line += c[from..to].iter().filter(|&&x| x == '\n').count();
    };
    while i < c.len() {
        let ch = c[i];
        let start = i;
        if ch == '/' && c.get(i + 1) == Some(&'/') {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
            continue;
        }
        if ch == '/' && c.get(i + 1) == Some(&'*') {
            let mut depth = 0;
            while i < c.len() {
                if c[i] == '/' && c.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if c[i] == '*' && c.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
            count_lines(start, i, &mut line);
            continue;
        }
        // Raw strings: r"…", r#"…"#, br#"…"#.
        let raw_at = if ch == 'r' {
            Some(i + 1)
        } else if ch == 'b' && c.get(i + 1) == Some(&'r') {
            Some(i + 2)
        } else {
            None
        };
        if let Some(mut j) = raw_at {
            let mut hashes = 0;
            while c.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if c.get(j) == Some(&'"') && (i == 0 || !is_ident_char(c[i - 1])) {
                j += 1;
                loop {
                    if j >= c.len() {
                        break;
                    }
                    if c[j] == '"' && (0..hashes).all(|h| c.get(j + 1 + h) == Some(&'#')) {
                        j += 1 + hashes;
                        break;
                    }
                    j += 1;
                }
                i = j;
                count_lines(start, i, &mut line);
                out.push((Token::Other, line));
                continue;
            }
        }
        if ch == '"' || (ch == 'b' && c.get(i + 1) == Some(&'"')) {
            i += if ch == 'b' { 2 } else { 1 };
            while i < c.len() && c[i] != '"' {
                i += if c[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
            count_lines(start, i.min(c.len()), &mut line);
            out.push((Token::Other, line));
            continue;
        }
        if ch == '\'' {
            // A character literal ('x', '\n', '\u{..}') or a lifetime ('a).
            if c.get(i + 1) == Some(&'\\') {
                i += 2;
                while i < c.len() && c[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if c.get(i + 2) == Some(&'\'') {
                i += 3;
            } else {
                i += 1;
                while i < c.len() && is_ident_char(c[i]) {
                    i += 1;
                }
            }
            out.push((Token::Other, line));
            continue;
        }
        if is_ident_start(ch) {
            while i < c.len() && is_ident_char(c[i]) {
                i += 1;
            }
            let word: String = c[start..i].iter().collect();
            out.push((Token::Ident(word.trim_start_matches("r#").to_string()), line));
            continue;
        }
        if ch.is_ascii_digit() {
            while i < c.len() && (is_ident_char(c[i]) || c[i] == '.') && !(c[i] == '.' && c.get(i + 1) == Some(&'.')) {
                i += 1;
            }
            out.push((Token::Other, line));
            continue;
        }
        if ch == '\n' {
            line += 1;
            i += 1;
            continue;
        }
        if ch.is_whitespace() {
            i += 1;
            continue;
        }
        let token = match ch {
            ':' if c.get(i + 1) == Some(&':') => {
                i += 1;
                Token::PathSep
            }
            '{' => Token::Open,
            '}' => Token::Close,
            ',' => Token::Comma,
            ';' => Token::Semi,
            _ => Token::Other,
        };
        i += 1;
        out.push((token, line));
    }
    out
}

fn is_ident_start(ch: char) -> bool {
    ch.is_alphabetic() || ch == '_'
}

fn is_ident_char(ch: char) -> bool {
    ch.is_alphanumeric() || ch == '_'
}

/// A path a file names: its segments as written and the line.
struct Named {
    segments: Vec<String>,
    /// The module the path is written in (the file's module and any inline `mod x { … }` around it).
    scope: Vec<String>,
    line: usize,
}

/// Every path in a file's tokens, `use` trees expanded (`use a::{b, c::d}` names `a::b` and `a::c::d`).
fn named_paths(toks: &[(Token, usize)], module: &[String]) -> Vec<Named> {
    let mut out = Vec::new();
    // The inline modules open at this point: (name, brace depth inside them).
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0;
    let mut i = 0;
    let scope_of = |inline: &[(String, usize)]| {
        let mut s = module.to_vec();
        s.extend(inline.iter().map(|(n, _)| n.clone()));
        s
    };
    while i < toks.len() {
        match &toks[i].0 {
            Token::Open => depth += 1,
            Token::Close => {
                if inline.last().is_some_and(|&(_, d)| d == depth) {
                    inline.pop();
                }
                depth -= 1;
            }
            Token::Ident(w) if w == "mod" => {
                if let (Some((Token::Ident(name), _)), Some((Token::Open, _))) = (toks.get(i + 1), toks.get(i + 2)) {
                    inline.push((name.clone(), depth + 1));
                    depth += 1;
                    i += 3;
                    continue;
                }
            }
            Token::Ident(w) if w == "use" => {
                let scope = scope_of(&inline);
                let mut j = i + 1;
                let mut trees = Vec::new();
                use_tree(toks, &mut j, Vec::new(), &mut trees);
                for (segments, line) in trees {
                    out.push(Named { segments, scope: scope.clone(), line });
                }
                i = j;
                continue;
            }
            Token::Ident(first) if !matches!(i.checked_sub(1).map(|k| &toks[k].0), Some(Token::PathSep)) => {
                if toks.get(i + 1).map(|t| &t.0) == Some(&Token::PathSep) {
                    let mut segments = vec![first.clone()];
                    let mut j = i + 1;
                    while let (Some((Token::PathSep, _)), Some((Token::Ident(w), _))) = (toks.get(j), toks.get(j + 1)) {
                        segments.push(w.clone());
                        j += 2;
                    }
                    out.push(Named { segments, scope: scope_of(&inline), line: toks[i].1 });
                    i = j;
                    continue;
                }
            }
            _ => {}
        }
        i += 1;
    }
    out
}

/// Reads one use tree from `toks[*j]`, appending each full path (prefix + tree) to `out`; stops after the
/// tree (before a `,`, `}` or at/after the `;`).
fn use_tree(toks: &[(Token, usize)], j: &mut usize, mut prefix: Vec<String>, out: &mut Vec<(Vec<String>, usize)>) {
    let line = toks.get(*j).map_or(0, |t| t.1);
    loop {
        match toks.get(*j).map(|t| &t.0) {
            Some(Token::Ident(w)) if w == "as" => {
                *j += 2;
            }
            Some(Token::Ident(w)) => {
                prefix.push(w.clone());
                *j += 1;
            }
            Some(Token::PathSep) | Some(Token::Other) => *j += 1,
            Some(Token::Open) => {
                *j += 1;
                loop {
                    match toks.get(*j).map(|t| &t.0) {
                        Some(Token::Close) => {
                            *j += 1;
                            break;
                        }
                        Some(Token::Comma) => *j += 1,
                        None => return,
                        _ => use_tree(toks, j, prefix.clone(), out),
                    }
                }
                return;
            }
            Some(Token::Semi) => {
                *j += 1;
                out.push((prefix, line));
                return;
            }
            Some(Token::Comma) | Some(Token::Close) | None => {
                out.push((prefix, line));
                return;
            }
        }
    }
}

/// The module path of a file under `src/` (`src/lib.rs` is the crate root, `x/mod.rs` is `x`).
fn module_of(rel: &Path) -> Vec<String> {
    let mut parts: Vec<String> = rel.iter().map(|p| p.to_string_lossy().into_owned()).collect();
    let last = parts.pop().unwrap();
    let stem = last.trim_end_matches(".rs");
    if stem != "mod" && stem != "lib" {
        parts.push(stem.to_string());
    }
    parts
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The file a path names: the longest prefix of its absolute module path that is a file's module, or None
/// for a path outside the crate (std, a dependency, a local item).
fn resolve(named: &Named, modules: &BTreeMap<Vec<String>, String>) -> Option<String> {
    let mut segs = named.segments.iter().peekable();
    let mut abs: Vec<String> = match segs.peek().map(|s| s.as_str()) {
        Some("crate") => {
            segs.next();
            Vec::new()
        }
        Some("self") => {
            segs.next();
            named.scope.clone()
        }
        Some("super") => {
            let mut base = named.scope.clone();
            while segs.peek().map(|s| s.as_str()) == Some("super") {
                segs.next();
                base.pop();
            }
            base
        }
        Some(first) => {
            // A child module named from its parent (`road::Road` in the module that declares `mod road;`).
            let mut child = named.scope.clone();
            child.push(first.to_string());
            if !modules.contains_key(&child) {
                return None;
            }
            named.scope.clone()
        }
        None => return None,
    };
    let mut best = modules.get(&abs).cloned();
    for s in segs {
        abs.push(s.clone());
        match modules.get(&abs) {
            Some(file) => best = Some(file.clone()),
            None => break,
        }
    }
    best
}

/// A circle in the graph, as its files in order (the first repeated at the end), if there is one.
fn find_cycle(edges: &BTreeMap<String, BTreeMap<String, usize>>) -> Option<Vec<String>> {
    // 0 unvisited, 1 on the stack, 2 done.
    fn visit(
        n: &str,
        edges: &BTreeMap<String, BTreeMap<String, usize>>,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(n.to_string(), 1);
        stack.push(n.to_string());
        for next in edges.get(n).into_iter().flat_map(|m| m.keys()) {
            match state.get(next.as_str()).copied().unwrap_or(0) {
                1 => {
                    let from = stack.iter().position(|s| s == next).unwrap();
                    let mut cycle = stack[from..].to_vec();
                    cycle.push(next.clone());
                    return Some(cycle);
                }
                0 => {
                    if let Some(c) = visit(next, edges, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(n.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for n in edges.keys() {
        if state.get(n.as_str()).copied().unwrap_or(0) == 0 {
            if let Some(c) = visit(n, edges, &mut state, &mut Vec::new()) {
                return Some(c);
            }
        }
    }
    None
}

/// The import graph of the library under `src/`: file → (imported file → first line naming it).
fn import_graph(src: &Path) -> BTreeMap<String, BTreeMap<String, usize>> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    files.retain(|f| !f.strip_prefix(src).unwrap().starts_with("bin"));
    let mut modules = BTreeMap::new();
    for f in &files {
        let rel = f.strip_prefix(src).unwrap();
        modules.insert(module_of(rel), format!("src/{}", rel.display()));
    }
    let mut edges: BTreeMap<String, BTreeMap<String, usize>> = BTreeMap::new();
    for f in &files {
        let rel = f.strip_prefix(src).unwrap();
        let me = format!("src/{}", rel.display());
        let text = std::fs::read_to_string(f).unwrap();
        let out = edges.entry(me.clone()).or_default();
        for named in named_paths(&tokens(&text), &module_of(rel)) {
            if let Some(target) = resolve(&named, &modules) {
                // A child naming its folder's `mod.rs` (or an ancestor's) sees its parent's namespace: not counted
                // (every folder's children do; the circles the issue names are between siblings and folders).
                let ancestor = target.strip_suffix("mod.rs").is_some_and(|dir| me.starts_with(dir));
                if target != me && !ancestor && !KNOWN.contains(&(me.as_str(), target.as_str())) {
                    out.entry(target).or_insert(named.line);
                }
            }
        }
    }
    edges
}

/// Imports that close a circle still, left for their own work (the lead's list): each is reported by
/// `known_circles_still_exist` once it is gone, so that the list only shrinks.
const KNOWN: [(&str, &str); 0] = [];

#[test]
fn no_import_circle() {
    let edges = import_graph(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src"));
    // The graph is not empty: the reader finds imports (a reader that found none would pass any source).
    let count: usize = edges.values().map(|m| m.len()).sum();
    assert!(count > 100, "only {count} imports found under src/: the reader is broken");
    if let Some(cycle) = find_cycle(&edges) {
        let steps: Vec<String> =
            cycle.windows(2).map(|w| format!("  {} (line {}) -> {}", w[0], edges[&w[0]][&w[1]], w[1])).collect();
        panic!("import circle among src/ files:\n{}", steps.join("\n"));
    }
}

/// The reader itself on small sources: the kinds of paths it must see, and what it must not read as one.
#[test]
fn reader_finds_the_paths_it_should() {
    let modules: BTreeMap<Vec<String>, String> =
        [(vec![], "lib"), (vec!["a"], "a/mod"), (vec!["a", "b"], "a/b"), (vec!["a", "c"], "a/c"), (vec!["d"], "d")]
            .into_iter()
            .map(|(m, f)| (m.into_iter().map(String::from).collect(), f.to_string()))
            .collect();
    let targets = |src: &str, module: &[&str]| -> BTreeSet<String> {
        let module: Vec<String> = module.iter().map(|s| s.to_string()).collect();
        named_paths(&tokens(src), &module).iter().filter_map(|n| resolve(n, &modules)).collect()
    };
    let set = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<BTreeSet<_>>();
    assert_eq!(targets("use super::c::X;", &["a", "b"]), set(&["a/c"]));
    assert_eq!(targets("use super::{c::X, Y};", &["a", "b"]), set(&["a/c", "a/mod"]));
    assert_eq!(targets("fn f() { crate::d::g(); }", &["a", "b"]), set(&["d"]));
    assert_eq!(targets("use crate::a::{self, b::Z as W};", &["d"]), set(&["a/mod", "a/b"]));
    assert_eq!(targets("mod b; fn f() -> b::T { todo!() }", &["a"]), set(&["a/b"]));
    // Inline test modules: `super` is the file itself.
    assert_eq!(targets("mod tests { use super::*; }", &["a", "b"]), set(&["a/b"]));
    // Not paths: comments, strings, characters, a `mod x;` declaration, std.
    assert_eq!(
        targets("// crate::d::x\n/* super::c */ const S: &str = \"crate::d\"; mod c; use std::fmt;", &["a", "b"]),
        set(&[])
    );
    assert_eq!(targets("const C: char = '{'; fn f<'a>() {} use crate::d::X;", &[]), set(&["d"]));
    assert_eq!(targets("const R: &str = r#\"crate::d \"{\"#; use crate::a::b::T;", &[]), set(&["a/b"]));
    let cyclic: BTreeMap<String, BTreeMap<String, usize>> = [("x", "y"), ("y", "z"), ("z", "x")]
        .iter()
        .map(|(a, b)| (a.to_string(), [(b.to_string(), 1)].into()))
        .collect();
    assert_eq!(find_cycle(&cyclic).unwrap(), ["x", "y", "z", "x"]);
    let acyclic: BTreeMap<String, BTreeMap<String, usize>> =
        [("x", "y"), ("y", "z")].iter().map(|(a, b)| (a.to_string(), [(b.to_string(), 1)].into())).collect();
    assert_eq!(find_cycle(&acyclic), None);
}

/// The imports `KNOWN` leaves out are still there (else delete them from the list).
#[test]
fn known_circles_still_exist() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    for (from, to) in KNOWN {
        let text = std::fs::read_to_string(src.join(from.strip_prefix("src/").unwrap())).unwrap();
        let module =
            to.strip_prefix("src/").unwrap().trim_end_matches(".rs").trim_end_matches("/mod").replace('/', "::");
        assert!(text.contains(&format!("crate::{module}")), "{from} no longer names {to}: remove it from KNOWN");
    }
}
