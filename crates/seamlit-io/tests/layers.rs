//! Imports run one way inside seamlit-io: every module imports only modules of lower layers
//! (or of its own), never the other way, so that the folders show the design and no two
//! modules import each other. The layers are [`LAYERS`], lowest first; ARCHITECTURE.md
//! ("Inside seamlit-io") draws the same order.
//!
//! The check is a scan of the `crate::` and `super::` paths in src/ (comments and the
//! `#[cfg(test)] mod tests` at the end of a file left out): each path is resolved to the
//! module it names (a name re-exported at the crate root, such as `crate::IoError`, to the
//! module that defines it, through lib.rs's `pub use`; a name defined in lib.rs itself to the
//! top layer), and that module's layer must not be above the importer's.

use std::collections::BTreeMap;
use std::path::Path;

/// The layers, lowest first: a module may import from its own layer and from those above it
/// in this list, never from one below. Each layer is a module with everything in it (its
/// submodules import each other freely); `lib` is lib.rs, the entry points.
const LAYERS: &[&str] = &[
    // What goes wrong, the options, and the pieces every format shares.
    "gltf::error",
    "fbx::error",
    "usd::error",
    "error",
    "options",
    "paths",
    "files",
    "check",
    // What a loaded file becomes: the asset, with the sources the pass-through writers keep.
    "gltf::json",
    "gltf::source",
    "obj::source",
    "usd::source",
    "animation",
    "asset",
    "pose",
    "skins",
    "motion",
    "texture",
    // glTF: below the reader and the writers, the container, URIs and references; then the
    // decoders, the reader, the pass-through writer, the generic writer.
    "gltf::glb",
    "gltf::uri",
    "gltf::references",
    "gltf::decode",
    "gltf::read",
    "gltf::passthrough",
    "gltf::write",
    // OBJ, in the same order.
    "obj::polygon",
    "obj::parse",
    "obj::mtl",
    "obj::read",
    "obj::passthrough",
    "obj::write",
    // FBX: the reader (ufbx's scene to an asset); no writer.
    "fbx::read",
    // USD: the reader (openusd's composed stage to an asset), then the `.usda` writer, which
    // reads the stage again to place the normals on its meshes.
    "usd::read",
    "usd::write",
    // The formats' public functions, and the entry points.
    "gltf",
    "obj",
    "fbx",
    "usd",
    "newell",
    "lib",
];

/// One import that runs the wrong way: the file, the path as written, the two layers.
#[derive(Debug, PartialEq, Eq)]
struct BackEdge {
    file: String,
    path: String,
    from: String,
    to: String,
}

/// The source files, as (path below src/, text).
fn sources() -> Vec<(String, String)> {
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
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut out = Vec::new();
    walk(&root, &root, &mut out);
    out
}

/// The module path of a file below src/: `gltf/read/scene.rs` -> `gltf::read::scene`,
/// `lib.rs` -> ``.
fn module_of(file: &str) -> String {
    let stem = file.strip_suffix(".rs").unwrap_or(file);
    match stem {
        "lib" => String::new(),
        _ => stem.trim_end_matches("/mod").replace('/', "::"),
    }
}

/// The layer of a module path (`lib` for the crate root), or `None` when no layer holds it.
fn layer_of(module: &str) -> Option<&'static str> {
    if module.is_empty() {
        return Some("lib");
    }
    LAYERS
        .iter()
        .copied()
        .filter(|layer| module == *layer || module.starts_with(&format!("{layer}::")))
        .max_by_key(|layer| layer.len())
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

/// The `crate::` and `super::` paths of a file's code, as written (`use` trees expanded,
/// `as` renames left out).
fn paths(code: &str) -> Vec<String> {
    let mut found = Vec::new();
    // `use` statements first, each from a line that starts with it (after a visibility) to
    // its `;`, their trees expanded; the rest of the code is scanned for paths after.
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
        match &mut statement {
            Some(text) => {
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
            None => {
                rest.push_str(line);
                rest.push('\n');
            }
        }
    }
    // Then every other path in the code.
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

/// A `use` tree without its renames (`a as b` -> `a`).
fn without_renames(tree: &str) -> String {
    let words: Vec<&str> = tree.split_whitespace().collect();
    let mut out = String::new();
    let mut i = 0;
    while i < words.len() {
        if words[i] == "as" {
            // Drop `as` and the new name, keeping whatever punctuation follows it.
            let name = words.get(i + 1).copied().unwrap_or_default();
            let tail = name.trim_start_matches(|c: char| c.is_ascii_alphanumeric() || c == '_');
            out.push_str(tail);
            i += 2;
        } else {
            out.push_str(words[i]);
            i += 1;
        }
    }
    out
}

/// The names lib.rs re-exports, with the module each comes from: `IoError` -> `error`.
fn reexports(lib: &str) -> BTreeMap<String, String> {
    let mut names = BTreeMap::new();
    for path in paths(&code(lib).replace("pub use ", "use crate::")) {
        let segments: Vec<&str> = path.split("::").collect();
        if let [_, module @ .., name] = segments.as_slice()
            && !module.is_empty()
        {
            names.insert((*name).to_owned(), module.join("::"));
        }
    }
    names
}

/// The module a path names (as far as it names modules), from the file of module `module`.
fn target(
    path: &str,
    module: &str,
    modules: &[String],
    reexports: &BTreeMap<String, String>,
) -> String {
    let mut segments: Vec<String> = Vec::new();
    let mut parts = path.split("::").peekable();
    match parts.next() {
        Some("crate") => {}
        _ => {
            // super::, relative to the file's own module.
            segments.extend(module.split("::").filter(|s| !s.is_empty()).map(str::to_owned));
            segments.pop();
            while parts.peek() == Some(&"super") {
                parts.next();
                segments.pop();
            }
        }
    }
    segments.extend(parts.map(str::to_owned));
    // The longest prefix that is a module.
    for n in (1..=segments.len()).rev() {
        let prefix = segments[..n].join("::");
        if modules.contains(&prefix) {
            return prefix;
        }
    }
    // A name at the crate root: re-exported from its module, or lib.rs's own.
    match segments.first() {
        Some(name) if segments.len() == 1 || !modules.iter().any(|m| m == name) => {
            reexports.get(name).cloned().unwrap_or_default()
        }
        _ => String::new(),
    }
}

/// Every import of `files` that runs against [`LAYERS`]; panics on a module no layer holds.
fn back_edges(files: &[(String, String)]) -> Vec<BackEdge> {
    let modules: Vec<String> = files.iter().map(|(f, _)| module_of(f)).collect();
    let lib = files.iter().find(|(f, _)| f == "lib.rs").map_or("", |(_, t)| t.as_str());
    let reexports = reexports(lib);
    let rank = |layer: &str| LAYERS.iter().position(|l| *l == layer).unwrap_or(LAYERS.len());
    let mut edges = Vec::new();
    for (file, text) in files {
        let module = module_of(file);
        let from = layer_of(&module)
            .unwrap_or_else(|| panic!("{file}: module `{module}` is in no layer of LAYERS"));
        for path in paths(&code(text)) {
            let to = layer_of(&target(&path, &module, &modules, &reexports))
                .unwrap_or_else(|| panic!("{file}: `{path}` names a module in no layer"));
            if rank(to) > rank(from) {
                edges.push(BackEdge {
                    file: file.clone(),
                    path,
                    from: from.to_owned(),
                    to: to.to_owned(),
                });
            }
        }
    }
    edges
}

#[test]
fn imports_run_one_way() {
    let files = sources();
    assert!(files.len() > 20, "src/ holds {} files", files.len());
    let edges = back_edges(&files);
    assert!(
        edges.is_empty(),
        "imports against the layers (a module may import only from its own layer and lower ones; see LAYERS):\n{}",
        edges
            .iter()
            .map(|e| format!("  {}: `{}` ({} imports {})", e.file, e.path, e.from, e.to))
            .collect::<Vec<_>>()
            .join("\n")
    );
}

#[test]
fn every_layer_is_a_module() {
    let modules: Vec<String> = sources().iter().map(|(f, _)| module_of(f)).collect();
    for layer in LAYERS.iter().filter(|l| **l != "lib") {
        assert!(modules.iter().any(|m| m == layer), "LAYERS names `{layer}`, which is no module");
    }
}

#[test]
fn the_check_sees_a_back_edge() {
    // The real files, with the JSON helpers importing the reader and the URI module using a
    // name that lib.rs defines: both run upward.
    let mut files = sources();
    let json = files.iter_mut().find(|(f, _)| f == "gltf/json.rs").expect("gltf/json.rs");
    json.1.push_str("\nuse crate::gltf::read::{self as reader};\nfn f() { crate::gltf::passthrough::save(); }\n");
    let uri = files.iter_mut().find(|(f, _)| f == "gltf/uri.rs").expect("gltf/uri.rs");
    uri.1.push_str("\nfn g() { let _ = crate::SaveReport::default(); }\n");
    let edges = back_edges(&files);
    let found: Vec<(&str, &str, &str)> =
        edges.iter().map(|e| (e.file.as_str(), e.from.as_str(), e.to.as_str())).collect();
    assert_eq!(
        found,
        [
            ("gltf/json.rs", "gltf::json", "gltf::read"),
            ("gltf/json.rs", "gltf::json", "gltf::passthrough"),
            ("gltf/uri.rs", "gltf::uri", "lib"),
        ]
    );
}
