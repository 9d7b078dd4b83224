//! The workspace's shape, held by tests (ARCHITECTURE.md draws the same):
//!
//! - **Crates depend only downward.** Each crate has a layer ([`LAYERS`]); a crate's
//!   `[dependencies]` name only seamlit crates of lower layers. Crates of one layer never
//!   depend on each other, so no format crate depends on another format, and the renderer
//!   (beside the formats) depends on the asset crate, never on a format or on seamlit-io.
//! - **No import circle inside a crate.** Within each crate's `src/`, no two modules of one
//!   folder import each other, directly or through others of that folder (a module importing
//!   its parent's or its children's items is not a circle: they are one room).
//! - **No room too large.** No source file over [`MOST_FILE_LINES`] lines, no function
//!   over [`MOST_FUNCTION_LINES`] (test modules aside), and no crate holding more than a
//!   quarter of the workspace's source lines.
//!
//! The checks read the files as text: `crate::` and `super::` paths (in `use` trees and in
//! code) resolved to the module they name, a name re-exported at a crate's root to the
//! module that defines it.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The crates by layer, lowest first: a crate may depend only on crates of lower layers.
const LAYERS: &[&[&str]] = &[
    // Geometry, and the helpers tests and benchmark generators share.
    &["seamlit-mesh", "seamlit-testkit"],
    // What a file becomes, whatever its format.
    &["seamlit-asset"],
    // One crate per format, and the renderer: each knows the asset, none the others.
    &["seamlit-gltf", "seamlit-obj", "seamlit-fbx", "seamlit-usd", "seamlit-render"],
    // The front door that picks a format by extension.
    &["seamlit-io"],
    // Scenes, and the Python package.
    &["seamlit-scene", "seamlit-py"],
    // The programs: the command line, the web page's module, the benchmarks' helper.
    &["seamlit", "seamlit-web", "seamlit-bench"],
];

/// The most lines a source file may have.
const MOST_FILE_LINES: usize = 900;

/// The most lines a function may have, from its `fn` line to its closing brace.
const MOST_FUNCTION_LINES: usize = 80;

/// The workspace's root folder.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Every crate of the workspace: its package name and its folder.
fn crates() -> Vec<(String, PathBuf)> {
    let mut folders: Vec<PathBuf> = std::fs::read_dir(root().join("crates"))
        .expect("crates/ is readable")
        .map(|e| e.expect("an entry of crates/").path())
        .filter(|p| p.join("Cargo.toml").is_file())
        .collect();
    folders.push(root().join("bench"));
    folders.sort();
    folders
        .into_iter()
        .map(|folder| {
            let manifest = std::fs::read_to_string(folder.join("Cargo.toml")).unwrap();
            let name = manifest
                .lines()
                .find_map(|l| l.strip_prefix("name = \""))
                .and_then(|l| l.strip_suffix('"'))
                .unwrap_or_else(|| panic!("{}: no package name", folder.display()));
            (name.to_owned(), folder)
        })
        .collect()
}

/// The seamlit crates a manifest's `[dependencies]` section names (not dev- or
/// build-dependencies: tests may reach anywhere).
fn dependencies(manifest: &str) -> BTreeSet<String> {
    let mut in_dependencies = false;
    let mut names = BTreeSet::new();
    for line in manifest.lines().map(str::trim) {
        if line.starts_with('[') {
            in_dependencies = line == "[dependencies]";
            continue;
        }
        let name = line.split(['.', '=', ' ']).next().unwrap_or_default();
        if in_dependencies && name.starts_with("seamlit-") {
            names.insert(name.to_owned());
        }
    }
    names
}

/// The layer of a crate, or `None` for one [`LAYERS`] does not name.
fn layer(name: &str) -> Option<usize> {
    LAYERS.iter().position(|layer| layer.contains(&name))
}

/// Every dependency that does not run downward, as `"a -> b"`, and every crate without a layer.
fn upward(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<String> {
    let mut wrong = Vec::new();
    for (name, deps) in graph {
        let Some(from) = layer(name) else {
            wrong.push(format!("{name} is in no layer of LAYERS: give it one"));
            continue;
        };
        for dep in deps {
            match layer(dep) {
                Some(to) if to < from => {}
                Some(_) => wrong.push(format!("{name} -> {dep}")),
                None => wrong.push(format!("{name} -> {dep}, which is in no layer of LAYERS")),
            }
        }
    }
    wrong
}

/// The workspace's crate graph: each crate with the seamlit crates it depends on.
fn crate_graph() -> BTreeMap<String, BTreeSet<String>> {
    crates()
        .into_iter()
        .map(|(name, folder)| {
            let manifest = std::fs::read_to_string(folder.join("Cargo.toml")).unwrap();
            (name, dependencies(&manifest))
        })
        .collect()
}

#[test]
fn crates_depend_only_downward() {
    let graph = crate_graph();
    assert!(graph.len() >= 12, "found only {} crates", graph.len());
    assert_eq!(
        graph["seamlit-gltf"],
        BTreeSet::from(["seamlit-asset".into(), "seamlit-mesh".into()])
    );
    let wrong = upward(&graph);
    assert!(wrong.is_empty(), "dependencies against the layers:\n  {}", wrong.join("\n  "));
}

// --- Modules ----------------------------------------------------------------------------

/// A crate's source files below `src/`, as (path below src/, text).
fn sources(src: &Path) -> Vec<(String, String)> {
    fn walk(dir: &Path, root: &Path, out: &mut Vec<(String, String)>) {
        let mut entries: Vec<_> =
            std::fs::read_dir(dir).expect("src/ is readable").map(|e| e.unwrap().path()).collect();
        entries.sort();
        for path in entries {
            if path.is_dir() {
                walk(&path, root, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let name = path.strip_prefix(root).unwrap().to_string_lossy().replace('\\', "/");
                out.push((name, std::fs::read_to_string(&path).unwrap()));
            }
        }
    }
    let mut out = Vec::new();
    walk(src, src, &mut out);
    out
}

/// The module path of a file below src/: `read/stage.rs` -> `read::stage`; `lib.rs` and
/// `main.rs` -> ``.
fn module_of(file: &str) -> String {
    let stem = file.strip_suffix(".rs").unwrap_or(file);
    match stem {
        "lib" | "main" => String::new(),
        _ => stem.trim_end_matches("/mod").replace('/', "::"),
    }
}

/// The code of a file without comments and without its test module.
fn code(text: &str) -> String {
    let text = match text.find("#[cfg(test)]\nmod tests") {
        Some(at) => &text[..at],
        None => text,
    };
    text.lines()
        .map(|line| line.find("//").map_or(line, |at| &line[..at]))
        .collect::<Vec<_>>()
        .join("\n")
}

/// Every path of a `use` tree, expanded: `crate::{a, b::{c, d}}` -> `crate::a`, `crate::b::c`,
/// `crate::b::d`.
fn expand(tree: &str) -> Vec<String> {
    let tree: String = tree.chars().filter(|c| !c.is_whitespace()).collect();
    let Some(open) = tree.find('{') else { return vec![tree] };
    let (prefix, rest) = tree.split_at(open);
    let inner = &rest[1..rest.len() - 1];
    let mut parts = Vec::new();
    let (mut depth, mut start) = (0, 0);
    for (i, c) in inner.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&inner[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&inner[start..]);
    parts
        .into_iter()
        .filter(|p| !p.is_empty())
        .flat_map(|p| expand(p).into_iter().map(move |e| format!("{prefix}{e}")))
        .collect()
}

/// A `use` tree without its renames (`a as b` -> `a`).
fn without_renames(tree: &str) -> String {
    let words: Vec<&str> = tree.split_whitespace().collect();
    let mut out = String::new();
    let mut i = 0;
    while i < words.len() {
        if words[i] == "as" {
            let name = words.get(i + 1).copied().unwrap_or_default();
            out.push_str(name.trim_start_matches(|c: char| c.is_ascii_alphanumeric() || c == '_'));
            i += 2;
        } else {
            out.push_str(words[i]);
            i += 1;
        }
    }
    out
}

/// The `crate::` and `super::` paths of a file's code, as written (`use` trees expanded).
fn paths(code: &str) -> Vec<String> {
    let mut found = Vec::new();
    let mut rest = String::new();
    let mut statement: Option<String> = None;
    for line in code.lines() {
        let trimmed = line.trim_start();
        let after_visibility = ["pub(crate) ", "pub(super) ", "pub "]
            .iter()
            .find_map(|v| trimmed.strip_prefix(v))
            .unwrap_or(trimmed);
        if statement.is_none() && after_visibility.starts_with("use ") {
            statement = Some(String::new());
        }
        let Some(text) = &mut statement else {
            rest.push_str(line);
            rest.push('\n');
            continue;
        };
        text.push_str(line);
        text.push(' ');
        if line.contains(';') {
            let text = statement.take().unwrap_or_default();
            let tree = text.split_once("use ").map_or("", |(_, t)| t);
            let tree = tree.split(';').next().unwrap_or_default();
            found.extend(
                expand(&without_renames(tree))
                    .into_iter()
                    .filter(|p| p.starts_with("crate::") || p.starts_with("super::")),
            );
        }
    }
    let bytes = rest.as_bytes();
    for start in ["crate::", "super::"] {
        let mut from = 0;
        while let Some(at) = rest[from..].find(start).map(|a| from + a) {
            from = at + start.len();
            let before = at.checked_sub(1).map(|b| bytes[b]);
            if before.is_some_and(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b':') {
                continue;
            }
            let end = rest[at..]
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == ':'))
                .map_or(rest.len(), |e| at + e);
            found.push(rest[at..end].trim_end_matches(':').to_owned());
        }
    }
    found
}

/// The names a crate root re-exports from its own modules: `IoError` -> `error`.
fn reexports(root: &str) -> BTreeMap<String, String> {
    let mut names = BTreeMap::new();
    for path in paths(&code(root).replace("pub use ", "use crate::")) {
        let segments: Vec<&str> = path.split("::").collect();
        if let [_, module @ .., name] = segments.as_slice()
            && !module.is_empty()
        {
            names.insert((*name).to_owned(), module.join("::"));
        }
    }
    names
}

/// The module a path names (as far as it names modules), from the file of module `module`;
/// `` for the crate root.
fn target(
    path: &str,
    module: &str,
    modules: &[String],
    reexports: &BTreeMap<String, String>,
) -> String {
    let mut segments: Vec<String> = Vec::new();
    let mut parts = path.split("::").peekable();
    if parts.next() != Some("crate") {
        // super::, relative to the file's own module.
        segments.extend(module.split("::").filter(|s| !s.is_empty()).map(str::to_owned));
        segments.pop();
        while parts.peek() == Some(&"super") {
            parts.next();
            segments.pop();
        }
    }
    segments.extend(parts.map(str::to_owned));
    for n in (1..=segments.len()).rev() {
        let prefix = segments[..n].join("::");
        if modules.contains(&prefix) {
            return prefix;
        }
    }
    match segments.first() {
        Some(name) => reexports.get(name).cloned().unwrap_or_default(),
        None => String::new(),
    }
}

/// For an import of `to` by `from`: the two distinct siblings (children of one folder) that
/// hold them, or `None` when one holds the other (a parent and its child are one room).
fn siblings(from: &str, to: &str) -> Option<(String, String)> {
    let a: Vec<&str> = from.split("::").filter(|s| !s.is_empty()).collect();
    let b: Vec<&str> = to.split("::").filter(|s| !s.is_empty()).collect();
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    if common == a.len() || common == b.len() {
        return None;
    }
    Some((a[..=common].join("::"), b[..=common].join("::")))
}

/// The import circles among sibling modules of one crate's files, each as its modules.
fn circles(files: &[(String, String)]) -> Vec<Vec<String>> {
    let modules: Vec<String> = files.iter().map(|(f, _)| module_of(f)).collect();
    let root = files.iter().find(|(f, _)| f == "lib.rs" || f == "main.rs");
    let reexports = reexports(root.map_or("", |(_, t)| t.as_str()));
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (file, text) in files {
        let module = module_of(file);
        for path in paths(&code(text)) {
            let to = target(&path, &module, &modules, &reexports);
            if let Some((a, b)) = siblings(&module, &to) {
                edges.entry(a).or_default().insert(b);
            }
        }
    }
    strongly_connected(&edges).into_iter().filter(|c| c.len() > 1).collect()
}

/// Tarjan's strongly connected components of a graph.
fn strongly_connected(edges: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct State<'a> {
        edges: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on_stack: BTreeSet<&'a str>,
        out: Vec<Vec<String>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a str) {
        let n = s.index.len();
        s.index.insert(v, n);
        s.low.insert(v, n);
        s.stack.push(v);
        s.on_stack.insert(v);
        for w in s.edges.get(v).into_iter().flatten() {
            if !s.index.contains_key(w.as_str()) {
                visit(s, w);
                let low = s.low[w.as_str()].min(s.low[v]);
                s.low.insert(v, low);
            } else if s.on_stack.contains(w.as_str()) {
                let low = s.index[w.as_str()].min(s.low[v]);
                s.low.insert(v, low);
            }
        }
        if s.low[v] == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack.remove(w);
                component.push(w.to_owned());
                if w == v {
                    break;
                }
            }
            component.sort();
            s.out.push(component);
        }
    }
    let mut state = State {
        edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in edges.keys() {
        if !state.index.contains_key(v.as_str()) {
            visit(&mut state, v);
        }
    }
    state.out
}

#[test]
fn no_crate_has_an_import_circle() {
    let mut found = Vec::new();
    for (name, folder) in crates() {
        let files = sources(&folder.join("src"));
        for circle in circles(&files) {
            found.push(format!("{name}: {}", circle.join(" <-> ")));
        }
    }
    assert!(found.is_empty(), "modules that import each other:\n  {}", found.join("\n  "));
}

// --- Sizes ------------------------------------------------------------------------------

/// The functions of a file's code (test module aside) longer than [`MOST_FUNCTION_LINES`],
/// as `name (N lines)`.
fn long_functions(text: &str) -> Vec<String> {
    let code = code(text);
    let lines: Vec<&str> = code.lines().collect();
    let mut long = Vec::new();
    for (start, line) in lines.iter().enumerate() {
        let Some(name) = fn_name(line) else { continue };
        if let Some(end) = body_end(&lines, start) {
            let n = end - start + 1;
            if n > MOST_FUNCTION_LINES {
                long.push(format!("{name} ({n} lines, from line {})", start + 1));
            }
        }
    }
    long
}

/// The name of the function a line starts, if it starts one.
fn fn_name(line: &str) -> Option<&str> {
    let words: Vec<&str> = line.split_whitespace().collect();
    let at = words.iter().position(|w| *w == "fn")?;
    let before_ok = words[..at].iter().all(|w| {
        w.starts_with("pub") || ["const", "async", "unsafe", "extern", "\"C\""].contains(w)
    });
    let name = words.get(at + 1)?;
    let name = name.split(['(', '<']).next()?;
    (before_ok && !name.is_empty()).then_some(name)
}

/// The line on which the body of the function starting at `start` closes; `None` for a
/// declaration without a body.
fn body_end(lines: &[&str], start: usize) -> Option<usize> {
    let mut depth = 0usize;
    let mut opened = false;
    for (i, line) in lines.iter().enumerate().skip(start) {
        let mut chars = line.chars().peekable();
        while let Some(c) = chars.next() {
            match c {
                '"' => {
                    while let Some(d) = chars.next() {
                        match d {
                            '\\' => {
                                chars.next();
                            }
                            '"' => break,
                            _ => {}
                        }
                    }
                }
                '\'' => {
                    // A character literal ('{', '\n') or a lifetime ('a).
                    let literal: String = chars.clone().take(3).collect();
                    if literal.starts_with('\\') {
                        chars.nth(2);
                    } else if literal.chars().nth(1) == Some('\'') {
                        chars.nth(1);
                    }
                }
                '{' => {
                    depth += 1;
                    opened = true;
                }
                '}' => {
                    depth = depth.saturating_sub(1);
                    if opened && depth == 0 {
                        return Some(i);
                    }
                }
                ';' if !opened => return None,
                _ => {}
            }
        }
    }
    None
}

#[test]
fn no_file_or_function_is_too_long() {
    let mut found = Vec::new();
    for (name, folder) in crates() {
        for (file, text) in sources(&folder.join("src")) {
            let n = text.lines().count();
            if n > MOST_FILE_LINES {
                found.push(format!("{name}/src/{file}: {n} lines"));
            }
            for f in long_functions(&text) {
                found.push(format!("{name}/src/{file}: fn {f}"));
            }
        }
    }
    assert!(
        found.is_empty(),
        "over {MOST_FILE_LINES} lines a file or {MOST_FUNCTION_LINES} a function:\n  {}",
        found.join("\n  ")
    );
}

#[test]
fn no_crate_holds_a_quarter_of_the_source() {
    let lines: BTreeMap<String, usize> = crates()
        .into_iter()
        .map(|(name, folder)| {
            let n = sources(&folder.join("src")).iter().map(|(_, t)| t.lines().count()).sum();
            (name, n)
        })
        .collect();
    let total: usize = lines.values().sum();
    let large: Vec<String> = lines
        .iter()
        .filter(|&(_, &n)| 4 * n > total)
        .map(|(name, n)| format!("{name}: {n} of {total} lines"))
        .collect();
    assert!(large.is_empty(), "crates over a quarter of the source:\n  {}", large.join("\n  "));
}

/// Where `unsafe` is allowed: the workspace denies it (`Cargo.toml`), and only ufbx's thread
/// pool (a C interface of callbacks) opts out, in one module.
#[test]
fn unsafe_code_is_allowed_in_one_module_only() {
    let manifest = std::fs::read_to_string(root().join("Cargo.toml")).unwrap();
    assert!(
        manifest
            .lines()
            .any(|l| l == r#"unsafe_code = "deny""# || l == r#"unsafe_code = "forbid""#),
        "the workspace's lints no longer deny unsafe code"
    );
    let mut found = Vec::new();
    for (name, folder) in crates() {
        for (file, text) in sources(&folder.join("src")) {
            let opts_out = ["allow(unsafe_code)", "expect(unsafe_code)", "warn(unsafe_code)"];
            if opts_out.iter().any(|o| text.contains(o)) {
                found.push(format!("{name}/src/{file}"));
            }
        }
    }
    assert_eq!(found, ["seamlit-fbx/src/read.rs"], "files that allow unsafe code");
}

// --- The checks themselves --------------------------------------------------------------

#[test]
fn the_checks_see_a_planted_back_edge() {
    // A format crate depending on another, and the renderer on the front door.
    let mut graph = crate_graph();
    graph.get_mut("seamlit-gltf").unwrap().insert("seamlit-usd".into());
    graph.get_mut("seamlit-render").unwrap().insert("seamlit-io".into());
    graph.insert("seamlit-new".into(), BTreeSet::new());
    assert_eq!(
        upward(&graph),
        [
            "seamlit-gltf -> seamlit-usd",
            "seamlit-new is in no layer of LAYERS: give it one",
            "seamlit-render -> seamlit-io",
        ]
    );

    // The USD reader's resolver and stage importing each other again (as before issue 40),
    // one by a `use` tree, the other by a path in code; and a module that imports its
    // parent's items, which is no circle.
    let mut files = sources(&root().join("crates/seamlit-usd/src"));
    let append = |files: &mut Vec<(String, String)>, file: &str, text: &str| {
        files.iter_mut().find(|(f, _)| f == file).expect(file).1.push_str(text);
    };
    append(&mut files, "read/resolver.rs", "\nuse super::{stage::{guarded as g}, xform};\n");
    append(&mut files, "read/stage.rs", "\nfn f() { super::resolver::Confined::new(); }\n");
    append(&mut files, "read/mesh.rs", "\nfn g() { let _ = super::read; }\n");
    assert_eq!(circles(&files), [["read::resolver", "read::stage"]]);

    // A function of 81 lines, with braces in strings and characters that do not count.
    let body = "    let s = \"}}{\"; let c = '}';\n".repeat(79);
    assert_eq!(
        long_functions(&format!("fn long() {{\n{body}}}\n")),
        ["long (81 lines, from line 1)"]
    );
    assert!(long_functions(&format!("fn fits() {{\n{}}}\n", "    x();\n".repeat(78))).is_empty());
}
