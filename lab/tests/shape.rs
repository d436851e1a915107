//! The shape of the published crates' sources (DESIGN §8), measured from
//! the files themselves: no import cycle between the modules of nh-core
//! and of nh-runtime, no non-test file of nh-core over 1,000 lines, no
//! non-test function over 120 lines. `cargo test -p nh-lab --test shape --
//! --nocapture` prints the figures (`NH_SHAPE_ROOT=DIR` measures the
//! checkout at DIR instead).
//!
//! An arrow runs from a module to each module it names in a `use` or a
//! path (`crate::a::b`, `super::c`, a child `d::`), resolved to the
//! deepest module that is a file. A child may use its ancestors (it lives
//! inside them: Rust gives it their private items), so an arrow from a
//! module to one of its ancestors is not counted; every other arrow is.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The crates whose module graphs are checked: (name, `src` folder).
const CRATES: [(&str, &str); 2] = [
    ("nh-core", "nh-macros/core/src"),
    ("nh-runtime", "nh-runtime/src"),
];

/// One source file as a module: its path in the crate (`["mechanics",
/// "kane"]`) and its text.
struct Module {
    path: Vec<String>,
    file: PathBuf,
    text: String,
}

/// The workspace, or the checkout `NH_SHAPE_ROOT` names (to measure
/// another revision with the same rules).
fn root() -> PathBuf {
    match std::env::var_os("NH_SHAPE_ROOT") {
        Some(r) => PathBuf::from(r),
        None => Path::new(env!("CARGO_MANIFEST_DIR")).join(".."),
    }
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .expect("a source folder")
        .flatten()
        .collect();
    entries.sort_by_key(|e| e.path());
    for e in entries {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// Whether a file holds tests only (`tests.rs`, `*/tests/*`).
fn is_test_file(p: &Path) -> bool {
    p.file_name().is_some_and(|n| n == "tests.rs")
        || p.components().any(|c| c.as_os_str() == "tests")
}

fn modules(src: &Path) -> Vec<Module> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    files
        .into_iter()
        .filter(|f| !is_test_file(f))
        .map(|f| {
            let rel = f.strip_prefix(src).expect("inside src").with_extension("");
            let mut path: Vec<String> = rel
                .iter()
                .map(|c| c.to_string_lossy().into_owned())
                .collect();
            if path.last().is_some_and(|l| l == "mod" || l == "lib") {
                path.pop();
            }
            let text = std::fs::read_to_string(&f).expect("readable");
            Module {
                path,
                file: f,
                text,
            }
        })
        .collect()
}

/// The text without comments and without `#[cfg(test)]` modules (their
/// imports are the tests').
fn code_of(text: &str) -> String {
    let mut out = String::new();
    let mut skip_depth: Option<usize> = None;
    let mut depth = 0usize;
    let mut test_next = false;
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        let t = code.trim();
        if skip_depth.is_none() && t == "#[cfg(test)]" {
            test_next = true;
            continue;
        }
        if test_next && t.starts_with("mod ") && t.ends_with('{') {
            skip_depth = Some(depth);
        }
        test_next = false;
        depth += code.matches('{').count();
        depth = depth.saturating_sub(code.matches('}').count());
        if let Some(d) = skip_depth {
            if depth <= d {
                skip_depth = None;
            }
            continue;
        }
        out.push_str(code);
        out.push('\n');
    }
    out
}

/// The module paths a module's code names: every `crate::…`, `super::…`
/// and child path, in `use` trees and in expressions.
fn named_paths(m: &Module) -> Vec<Vec<String>> {
    let code = code_of(&m.text);
    let mut out = Vec::new();
    // `use` trees, flattened: `use a::{b, c::d};` → a::b, a::c::d
    for stmt in code.split(';') {
        let s = stmt.trim();
        let Some(tree) = s
            .strip_prefix("use ")
            .or_else(|| s.split_once(" use ").map(|x| x.1))
        else {
            continue;
        };
        for p in flatten_use(tree) {
            out.push(p);
        }
    }
    // inline paths: crate::a::b, super::a
    let text = &code;
    for start in ["crate::", "super::"] {
        let mut from = 0;
        while let Some(i) = text[from..].find(start) {
            let at = from + i;
            from = at + start.len();
            if at > 0
                && (text[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_' || c == ':'))
            {
                continue;
            }
            let rest: String = text[at..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                .collect();
            out.push(
                rest.split("::")
                    .filter(|s| !s.is_empty())
                    .map(String::from)
                    .collect(),
            );
        }
    }
    out
}

fn flatten_use(tree: &str) -> Vec<Vec<String>> {
    let tree: String = tree.chars().filter(|c| !c.is_whitespace()).collect();
    let mut out = Vec::new();
    expand(&tree, &mut Vec::new(), &mut out);
    out
}

fn expand(tree: &str, prefix: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    if let Some(open) = tree.find('{') {
        let head: Vec<String> = tree[..open]
            .split("::")
            .filter(|s| !s.is_empty())
            .map(String::from)
            .collect();
        let inner = &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())];
        let n = prefix.len();
        prefix.extend(head);
        for part in split_top(inner) {
            expand(&part, prefix, out);
        }
        prefix.truncate(n);
    } else {
        let mut p = prefix.clone();
        p.extend(
            tree.split("::")
                .filter(|s| !s.is_empty())
                .map(|s| s.split(" as ").next().unwrap_or(s).to_string()),
        );
        out.push(p);
    }
}

fn split_top(s: &str) -> Vec<String> {
    let (mut parts, mut depth, mut cur) = (Vec::new(), 0, String::new());
    for c in s.chars() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(std::mem::take(&mut cur));
                continue;
            }
            _ => {}
        }
        cur.push(c);
    }
    if !cur.is_empty() {
        parts.push(cur);
    }
    parts
}

/// The deepest known module a path from module `from` names.
fn resolve(from: &[String], path: &[String], known: &BTreeSet<Vec<String>>) -> Option<Vec<String>> {
    let mut abs: Vec<String> = match path.first().map(String::as_str) {
        Some("crate") => Vec::new(),
        Some("super") => from[..from.len().saturating_sub(1)].to_vec(),
        Some("self") => from.to_vec(),
        Some(first) => {
            let mut child = from.to_vec();
            child.push(first.to_string());
            if !known.contains(&child) {
                return None; // an external crate or an item
            }
            from.to_vec()
        }
        None => return None,
    };
    let rest = match path.first().map(String::as_str) {
        Some("crate" | "self") => &path[1..],
        Some("super") => {
            let mut i = 1;
            while path.get(i).is_some_and(|s| s == "super") {
                abs.pop();
                i += 1;
            }
            &path[i..]
        }
        _ => path,
    };
    let mut best = abs.clone();
    for seg in rest {
        abs.push(seg.clone());
        if known.contains(&abs) {
            best = abs.clone();
        } else {
            break;
        }
    }
    Some(best)
}

/// The module graph's arrows, ancestors excluded.
fn arrows(mods: &[Module]) -> BTreeMap<Vec<String>, BTreeSet<Vec<String>>> {
    let known: BTreeSet<Vec<String>> = mods.iter().map(|m| m.path.clone()).collect();
    let mut graph = BTreeMap::new();
    for m in mods {
        let mut to = BTreeSet::new();
        for p in named_paths(m) {
            if let Some(target) = resolve(&m.path, &p, &known)
                && target != m.path
                && !m.path.starts_with(&target)
            {
                to.insert(target);
            }
        }
        graph.insert(m.path.clone(), to);
    }
    graph
}

/// The cycles of a graph (one per strongly connected component with more
/// than one module), by Tarjan's algorithm.
fn cycles(graph: &BTreeMap<Vec<String>, BTreeSet<Vec<String>>>) -> Vec<Vec<Vec<String>>> {
    struct State<'a> {
        graph: &'a BTreeMap<Vec<String>, BTreeSet<Vec<String>>>,
        index: BTreeMap<&'a Vec<String>, usize>,
        low: BTreeMap<&'a Vec<String>, usize>,
        stack: Vec<&'a Vec<String>>,
        on: BTreeSet<&'a Vec<String>>,
        out: Vec<Vec<Vec<String>>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a Vec<String>) {
        let i = s.index.len();
        s.index.insert(v, i);
        s.low.insert(v, i);
        s.stack.push(v);
        s.on.insert(v);
        for w in s.graph.get(v).into_iter().flatten() {
            let Some((w, _)) = s.graph.get_key_value(w) else {
                continue;
            };
            if !s.index.contains_key(w) {
                visit(s, w);
                let lw = s.low[w];
                let lv = s.low.get_mut(v).expect("visited");
                *lv = (*lv).min(lw);
            } else if s.on.contains(w) {
                let iw = s.index[w];
                let lv = s.low.get_mut(v).expect("visited");
                *lv = (*lv).min(iw);
            }
        }
        if s.low[v] == s.index[v] {
            let mut comp = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on.remove(w);
                comp.push(w.clone());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                s.out.push(comp);
            }
        }
    }
    let mut s = State {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in graph.keys() {
        if !s.index.contains_key(v) {
            visit(&mut s, v);
        }
    }
    s.out
}

/// The non-test functions of a file and their lengths in lines (from the
/// `fn` line to its closing brace at the same indentation).
fn functions(text: &str) -> Vec<(usize, usize, String)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut in_tests: Option<usize> = None;
    for (i, l) in lines.iter().enumerate() {
        let indent = l.len() - l.trim_start().len();
        if let Some(d) = in_tests {
            if indent <= d && l.trim_start().starts_with('}') {
                in_tests = None;
            }
            continue;
        }
        let t = l.trim_start();
        if t.starts_with("mod tests") || t.starts_with("mod sled_tests") {
            in_tests = Some(indent);
            continue;
        }
        let head = t
            .trim_start_matches("pub(crate) ")
            .trim_start_matches("pub(super) ")
            .trim_start_matches("pub ");
        let head = head
            .trim_start_matches("const ")
            .trim_start_matches("unsafe ");
        let Some(name) = head.strip_prefix("fn ") else {
            continue;
        };
        if l.trim_end().ends_with(';') {
            continue;
        }
        let name: String = name
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        let close = format!("{}}}", &l[..indent]);
        if let Some(len) = lines[i + 1..].iter().position(|m| m.trim_end() == close) {
            out.push((len + 2, i + 1, name));
        }
    }
    out
}

#[test]
fn no_import_cycle_between_the_modules_of_the_published_crates() {
    let mut found = Vec::new();
    for (name, src) in CRATES {
        let mods = modules(&root().join(src));
        let graph = arrows(&mods);
        let count: usize = graph.values().map(BTreeSet::len).sum();
        println!("{name}: {} modules, {count} arrows", graph.len());
        for c in cycles(&graph) {
            let names: Vec<String> = c
                .iter()
                .map(|p| format!("{name}::{}", p.join("::")))
                .collect();
            found.push(names.join(" ↔ "));
        }
    }
    assert!(found.is_empty(), "import cycles: {found:#?}");
}

#[test]
fn no_file_of_nh_core_over_a_thousand_lines() {
    let src = root().join("nh-macros/core/src");
    let mut sizes: Vec<(usize, PathBuf)> = modules(&src)
        .into_iter()
        .map(|m| (m.text.lines().count(), m.file))
        .collect();
    sizes.sort();
    for (n, f) in sizes.iter().rev().take(3) {
        println!("{n:5} {}", f.strip_prefix(&src).unwrap_or(f).display());
    }
    let over: Vec<_> = sizes.iter().filter(|(n, _)| *n > 1000).collect();
    assert!(over.is_empty(), "files over 1,000 lines: {over:?}");
}

#[test]
fn no_function_over_120_lines() {
    let mut all = Vec::new();
    for (name, src) in CRATES {
        for m in modules(&root().join(src)) {
            for (len, line, f) in functions(&m.text) {
                all.push((len, format!("{name}/{}:{line} {f}", m.path.join("/"))));
            }
        }
    }
    all.sort();
    for (len, at) in all.iter().rev().take(3) {
        println!("{len:4} {at}");
    }
    let over: Vec<_> = all.iter().filter(|(len, _)| *len > 120).collect();
    assert!(over.is_empty(), "functions over 120 lines: {over:?}");
}

/// The measures catch what they measure: a cycle through two modules, a
/// path into a child and a long function.
#[test]
fn the_measures_see_a_planted_cycle_and_a_long_function() {
    let module = |path: &[&str], text: &str| Module {
        path: path.iter().map(|s| s.to_string()).collect(),
        file: PathBuf::new(),
        text: text.to_string(),
    };
    let mods = [
        module(&[], "mod a;\nmod b;\n"),
        module(&["a"], "use crate::b::Thing;\nmod inner;\n"),
        module(&["a", "inner"], "use super::Up;\n"),
        module(&["b"], "fn f() { crate::a::g(); }\n"),
    ];
    let graph = arrows(&mods);
    assert_eq!(cycles(&graph).len(), 1, "{graph:?}");
    let inner: Vec<String> = vec!["a".into(), "inner".into()];
    assert!(
        graph[&inner].is_empty(),
        "a child's use of its parent is not an arrow"
    );
    let long = format!("fn long() {{\n{}}}\n", "    x();\n".repeat(130));
    assert_eq!(functions(&long), vec![(132, 1, "long".to_string())]);
}
