//! The layers of `host/src` and `kernel/src`, enforced (`docs/architecture.md`).
//!
//! The layer of every top-level module (a folder or a file under `src/`) is read from the
//! tables of `docs/architecture.md`, so the drawing and the test cannot drift apart. Every
//! `crate::` path in the code of every `.rs` file (comments and string literals are skipped;
//! test code counts) names the top-level module it reaches: directly, through a re-export of
//! the crate root (`lib.rs`), or through an exported macro. An import fails the test when it
//! runs up a layer or closes a cycle between modules of one layer, unless it is one of the
//! [`ALLOWED`] entries, each named with its reason. An entry that no longer occurs fails the
//! test too, so the list can only shrink.
//!
//! A module of the table whose folder does not exist (yet) is tolerated; a module of the
//! source that no table places fails the test.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// An import that breaks the layers today and is known: the crate (`host` or `kernel`), the
/// importing and the imported top-level module, and why it is still there.
struct Allowed {
    krate: &'static str,
    from: &'static str,
    to: &'static str,
    reason: &'static str,
}

/// The known violations. Remove an entry when its import goes (the test says when).
const ALLOWED: &[Allowed] = &[];

/// The module a file belongs to: its first path component under `src` (`.rs` removed).
fn top_module(src: &Path, file: &Path) -> Option<String> {
    let relative = file.strip_prefix(src).ok()?;
    let first = relative.components().next()?.as_os_str().to_str()?;
    Some(first.strip_suffix(".rs").unwrap_or(first).to_string())
}

/// Every `.rs` file under `dir`, sorted.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// The crate's top-level modules: folders and files under `src` but the crate roots.
fn modules(src: &Path) -> BTreeSet<String> {
    fs::read_dir(src)
        .unwrap_or_else(|e| panic!("{}: {e}", src.display()))
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.is_dir() || path.extension().is_some_and(|e| e == "rs"))
        .filter_map(|path| top_module(src, &path))
        .filter(|name| name != "lib" && name != "main")
        .collect()
}

/// `source` with comments removed and string and character literals emptied.
fn code_only(source: &str) -> String {
    let bytes = source.as_bytes();
    let mut out = String::with_capacity(source.len());
    let mut i = 0;
    let identifier = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
    while i < bytes.len() {
        let rest = &source[i..];
        if rest.starts_with("//") {
            i += rest.find('\n').unwrap_or(rest.len());
        } else if rest.starts_with("/*") {
            let mut depth = 0;
            while i < bytes.len() {
                if source[i..].starts_with("/*") {
                    depth += 1;
                    i += 2;
                } else if source[i..].starts_with("*/") {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
        } else if (rest.starts_with("r\"") || rest.starts_with("r#") || rest.starts_with("br"))
            && (i == 0 || !identifier(bytes[i - 1]))
            && rest
                .trim_start_matches(['b', 'r'])
                .trim_start_matches('#')
                .starts_with('"')
        {
            let prefix = rest.len() - rest.trim_start_matches(['b', 'r']).len();
            let hashes = rest[prefix..].len() - rest[prefix..].trim_start_matches('#').len();
            let close = format!("\"{}", "#".repeat(hashes));
            let body = prefix + hashes + 1;
            i += body
                + rest[body..]
                    .find(&close)
                    .map_or(rest.len() - body, |e| e + close.len());
            out.push_str("\"\"");
        } else if bytes[i] == b'"' {
            i += 1;
            while i < bytes.len() && bytes[i] != b'"' {
                i += if bytes[i] == b'\\' { 2 } else { 1 };
            }
            i += 1;
            out.push_str("\"\"");
        } else if bytes[i] == b'\'' && rest.len() > 3 && bytes[i + 1] == b'\\' {
            // An escaped character literal: `'\n'`, `'\''`, `'\u{..}'`.
            i += 3 + rest[3..].find('\'').map_or(rest.len() - 3, |e| e + 1);
        } else if bytes[i] == b'\'' && rest.chars().nth(2) == Some('\'') {
            i += 1 + rest[1..].chars().next().map_or(0, char::len_utf8) + 1;
        } else {
            let c = rest.chars().next().unwrap_or(' ');
            out.push(c);
            i += c.len_utf8();
        }
    }
    out
}

/// The first segment of every path after `crate::` in `code` (`crate::a::b` gives `a`;
/// `crate::{a::b, c}` gives `a` and `c`; `$crate::` counts).
fn crate_paths(code: &str) -> Vec<String> {
    let mut found = Vec::new();
    let identifier = |c: char| c.is_ascii_alphanumeric() || c == '_';
    for (at, _) in code.match_indices("crate::") {
        if code[..at].chars().next_back().is_some_and(identifier) {
            continue;
        }
        let rest = &code[at + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let mut depth = 1;
            let mut item = String::new();
            let mut items = Vec::new();
            for c in group.chars() {
                match c {
                    '{' => depth += 1,
                    '}' => depth -= 1,
                    ',' if depth == 1 => items.push(std::mem::take(&mut item)),
                    _ => {}
                }
                if depth == 0 {
                    items.push(std::mem::take(&mut item));
                    break;
                }
                if depth >= 1 && c != ',' {
                    item.push(c);
                }
            }
            for item in items {
                let first: String = item.trim().chars().take_while(|c| identifier(*c)).collect();
                if !first.is_empty() && first != "self" {
                    found.push(first);
                }
            }
        } else {
            let first: String = rest.chars().take_while(|c| identifier(*c)).collect();
            if !first.is_empty() {
                found.push(first);
            }
        }
    }
    found
}

/// Names the crate root re-exports (`pub use module::{A, B};` in `lib.rs`), with their module.
fn root_reexports(lib: &str) -> BTreeMap<String, String> {
    let mut names = BTreeMap::new();
    for statement in code_only(lib).split(';') {
        let Some(path) = statement.trim().strip_prefix("pub use ") else {
            continue;
        };
        let Some((module, rest)) = path.split_once("::") else {
            continue;
        };
        let last = rest.rsplit("::").next().unwrap_or(rest);
        for name in last.trim_matches(['{', '}', ' ', '\n']).split(',') {
            let name = name.split(" as ").last().unwrap_or(name).trim();
            if !name.is_empty() {
                names.insert(name.to_string(), module.trim().to_string());
            }
        }
    }
    names
}

/// Each top-level module's imports of other top-level modules, with a file that makes each.
type Edges = BTreeMap<(String, String), PathBuf>;

/// The import graph of the crate at `src`; the errors are paths it cannot resolve.
fn import_graph(src: &Path) -> (BTreeSet<String>, Edges, Vec<String>) {
    let modules = modules(src);
    let lib = fs::read_to_string(src.join("lib.rs")).unwrap_or_default();
    let mut targets = root_reexports(&lib);
    let files = rust_files(src);
    let mut code = BTreeMap::new();
    for file in &files {
        let text = code_only(&fs::read_to_string(file).unwrap());
        if let Some(module) = top_module(src, file) {
            for (at, _) in text.match_indices("macro_rules!") {
                let name: String = text[at + "macro_rules!".len()..]
                    .trim_start()
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                    .collect();
                targets.insert(name, module.clone());
            }
        }
        code.insert(file.clone(), text);
    }
    for module in &modules {
        targets.insert(module.clone(), module.clone());
    }
    let mut edges = Edges::new();
    let mut unresolved = Vec::new();
    for (file, text) in &code {
        let Some(from) = top_module(src, file) else {
            continue;
        };
        if from == "lib" || from == "main" {
            continue;
        }
        for name in crate_paths(text) {
            match targets.get(&name) {
                Some(to) if *to != from => {
                    edges
                        .entry((from.clone(), to.clone()))
                        .or_insert_with(|| file.clone());
                }
                Some(_) => {}
                None => unresolved.push(format!(
                    "{}: `crate::{name}` names no module, root re-export or macro",
                    file.display()
                )),
            }
        }
    }
    (modules, edges, unresolved)
}

/// The layers of a crate from the table under the `## ` heading of `docs/architecture.md`
/// that contains `heading`: rows `| <layer> | `module`, `module` | ... |`.
fn layers(document: &str, heading: &str) -> BTreeMap<String, usize> {
    let mut layers = BTreeMap::new();
    let mut inside = false;
    for line in document.lines() {
        if let Some(title) = line.strip_prefix("## ") {
            inside = title.contains(heading);
            continue;
        }
        if !inside || !line.starts_with('|') {
            continue;
        }
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        let Some(layer) = cells.get(1).and_then(|c| c.parse::<usize>().ok()) else {
            continue;
        };
        for name in cells.get(2).unwrap_or(&"").split('`').skip(1).step_by(2) {
            let name = name.trim_end_matches('/');
            assert!(
                layers.insert(name.to_string(), layer).is_none(),
                "docs/architecture.md places `{name}` twice"
            );
        }
    }
    assert!(
        !layers.is_empty(),
        "docs/architecture.md has no layer table under a `## ...{heading}...` heading"
    );
    layers
}

/// Every way the graph breaks the layers, but the allowed ones; and every allowed entry that
/// no longer occurs or is no violation.
fn check(
    krate: &str,
    layers: &BTreeMap<String, usize>,
    modules: &BTreeSet<String>,
    edges: &Edges,
    allowed: &[Allowed],
) -> Vec<String> {
    let mut errors = Vec::new();
    for module in modules {
        if !layers.contains_key(module) {
            errors.push(format!(
                "{krate}: module `{module}` is in no layer of docs/architecture.md"
            ));
        }
    }
    let is_allowed = |from: &str, to: &str| {
        allowed
            .iter()
            .any(|a| a.krate == krate && a.from == from && a.to == to)
    };
    let mut same_layer: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for ((from, to), file) in edges {
        let (Some(&low), Some(&high)) = (layers.get(from), layers.get(to)) else {
            continue;
        };
        if is_allowed(from, to) {
            continue;
        }
        if high > low {
            errors.push(format!(
                "{krate}: `{from}` (layer {low}) imports `{to}` (layer {high}), up a layer, in {}",
                file.display()
            ));
        } else if high == low {
            same_layer.entry(from).or_default().push(to);
        }
    }
    // A cycle needs an import up a layer or a cycle within one layer: search the latter.
    let mut state: BTreeMap<&str, u8> = BTreeMap::new();
    let mut path: Vec<&str> = Vec::new();
    fn visit<'a>(
        node: &'a str,
        graph: &BTreeMap<&'a str, Vec<&'a str>>,
        state: &mut BTreeMap<&'a str, u8>,
        path: &mut Vec<&'a str>,
        cycles: &mut Vec<String>,
    ) {
        state.insert(node, 1);
        path.push(node);
        for &next in graph.get(node).into_iter().flatten() {
            match state.get(next).copied().unwrap_or(0) {
                0 => visit(next, graph, state, path, cycles),
                1 => {
                    let start = path.iter().position(|n| *n == next).unwrap_or(0);
                    let mut cycle: Vec<&str> = path[start..].to_vec();
                    cycle.push(next);
                    cycles.push(cycle.join(" -> "));
                }
                _ => {}
            }
        }
        path.pop();
        state.insert(node, 2);
    }
    let mut cycles = Vec::new();
    let nodes: Vec<&str> = same_layer.keys().copied().collect();
    for node in nodes {
        if state.get(node).copied().unwrap_or(0) == 0 {
            visit(node, &same_layer, &mut state, &mut path, &mut cycles);
        }
    }
    for cycle in cycles {
        errors.push(format!("{krate}: import cycle within a layer: {cycle}"));
    }
    for entry in allowed.iter().filter(|a| a.krate == krate) {
        let key = (entry.from.to_string(), entry.to.to_string());
        let (from, to) = (layers.get(entry.from), layers.get(entry.to));
        if !edges.contains_key(&key) {
            errors.push(format!(
                "{krate}: allowed `{} -> {}` no longer occurs: remove it from ALLOWED ({})",
                entry.from, entry.to, entry.reason
            ));
        } else if from.is_some() && to.is_some() && to < from {
            errors.push(format!(
                "{krate}: allowed `{} -> {}` runs down a layer, which is no violation: remove it",
                entry.from, entry.to
            ));
        }
    }
    errors
}

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the workspace folder")
        .to_path_buf()
}

fn check_crate(krate: &str, heading: &str) {
    let root = workspace();
    let document = fs::read_to_string(root.join("docs/architecture.md")).unwrap();
    let layers = layers(&document, heading);
    let (modules, edges, mut errors) = import_graph(&root.join(krate).join("src"));
    errors.extend(check(krate, &layers, &modules, &edges, ALLOWED));
    assert!(
        errors.is_empty(),
        "the layers of docs/architecture.md are broken:\n{}",
        errors.join("\n")
    );
}

#[test]
fn the_host_crate_keeps_its_layers() {
    // GOAL: no import of host/src runs up a layer or closes a cycle between its top-level
    //       modules, beyond the named ALLOWED entries (and those all still occur).
    // SETUP: the `crate::` paths of every file of host/src; the host table of
    //        docs/architecture.md. REFERENCE: no error.
    check_crate("host", "host/src");
}

#[test]
fn calibrate_and_diagnose_do_not_import_each_other() {
    // GOAL: the two fitting front ends build on the fitting layer only (issue 49): a
    //       same-layer import between them (allowed by the layer rule while it closes no
    //       cycle) is refused here.
    // SETUP: the import graph of host/src. REFERENCE: neither edge exists.
    let (_, edges, _) = import_graph(&workspace().join("host/src"));
    for (from, to) in [("calibrate", "diagnose"), ("diagnose", "calibrate")] {
        if let Some(file) = edges.get(&(from.to_string(), to.to_string())) {
            panic!("{from} imports {to} (first in {})", file.display());
        }
    }
}

#[test]
fn the_kernel_keeps_its_layers() {
    // GOAL: the same for kernel/src's folders and files.
    // SETUP: kernel/src; the kernel table. REFERENCE: no error.
    check_crate("kernel", "kernel/src");
}

#[test]
fn the_scanner_reads_paths_and_skips_comments_and_strings() {
    // GOAL: the scanner sees every `crate::` path of the code and nothing else.
    // SETUP: a use group (nested), a plain path, a `$crate` path in a macro, a path in a
    //        comment, in a doc comment, in a string, in a raw string, after a char literal.
    // REFERENCE: a, b, c, d and e only.
    let source = r##"
        use crate::{a::{X, Y}, b, self};
        // crate::not_a_comment
        /// [`crate::not_a_doc`]
        /* crate::not_in /* nested */ crate::block */
        let s = "crate::not_a_string \" crate::still_not";
        let r = r#"crate::not_raw "# ;
        let q = '"'; let z = crate::c::f(q);
        macro_rules! m { () => { $crate::d::E }; }
        fn f<'a>(x: &'a str) -> crate::e::T<'a> { T(x) }
        let mycrate::x = 1;
    "##;
    let paths = crate_paths(&code_only(source));
    assert_eq!(paths, ["a", "b", "c", "d", "e"]);
    let lib = "pub mod a;\npub use a::{Alpha, Beta as B};\npub use b::c::Gamma;\n";
    let names = root_reexports(lib);
    assert_eq!(names.get("Alpha").map(String::as_str), Some("a"));
    assert_eq!(names.get("B").map(String::as_str), Some("a"));
    assert_eq!(names.get("Gamma").map(String::as_str), Some("b"));
}

#[test]
fn a_new_violation_or_a_stale_allowance_fails() {
    // GOAL: the checker refuses an import up a layer, a cycle within a layer, an unplaced
    //       module and an allowed entry that no longer occurs; it accepts an allowed one.
    // SETUP: layers low 0, mid 1, mid2 1, high 2 (and `absent`, a tolerated missing module);
    //        imports mid -> high (up), mid <-> mid2 (cycle), high -> low (fine), low -> high
    //        (up, allowed); allowed entries low -> high and low -> mid (stale); a module
    //        `stray` in no layer. REFERENCE: exactly those four errors.
    let layers: BTreeMap<String, usize> = [("low", 0), ("mid", 1), ("mid2", 1), ("high", 2)]
        .into_iter()
        .chain([("absent", 1)])
        .map(|(n, l)| (n.to_string(), l))
        .collect();
    let modules: BTreeSet<String> = ["low", "mid", "mid2", "high", "stray"]
        .into_iter()
        .map(String::from)
        .collect();
    let edges: Edges = [
        ("mid", "high"),
        ("mid", "mid2"),
        ("mid2", "mid"),
        ("high", "low"),
        ("low", "high"),
    ]
    .into_iter()
    .map(|(a, b)| {
        (
            (a.to_string(), b.to_string()),
            PathBuf::from(format!("{a}.rs")),
        )
    })
    .collect();
    let allowed = [
        Allowed {
            krate: "t",
            from: "low",
            to: "high",
            reason: "kept",
        },
        Allowed {
            krate: "t",
            from: "low",
            to: "mid",
            reason: "gone",
        },
    ];
    let errors = check("t", &layers, &modules, &edges, &allowed);
    assert_eq!(errors.len(), 4, "{errors:#?}");
    assert!(errors[0].contains("`stray` is in no layer"));
    assert!(errors[1].contains("`mid` (layer 1) imports `high` (layer 2)"));
    assert!(errors[2].contains("cycle within a layer: mid -> mid2 -> mid"));
    assert!(errors[3].contains("`low -> mid` no longer occurs"));
}
