//! The layering ARCHITECTURE.md states: a user who only wants repaired models depends on
//! seamlit-mesh and seamlit-io (and the asset and format crates below it) and never compiles
//! the GPU stack. Checked on Cargo.lock: the packages each of them can reach (dev-dependencies
//! included, so this over-approximates) contain no wgpu, winit or egui.

use std::collections::{HashMap, HashSet};

/// Package name -> the names it depends on, from Cargo.lock's `[[package]]` tables.
fn lock_graph(text: &str) -> HashMap<String, Vec<String>> {
    let mut graph: HashMap<String, Vec<String>> = HashMap::new();
    let mut current: Option<String> = None;
    let mut in_dependencies = false;
    for line in text.lines() {
        if line == "[[package]]" {
            current = None;
            in_dependencies = false;
        } else if let Some(name) = line.strip_prefix("name = ") {
            let name = name.trim_matches('"').to_owned();
            graph.entry(name.clone()).or_default();
            current = Some(name);
        } else if line == "dependencies = [" {
            in_dependencies = true;
        } else if line == "]" {
            in_dependencies = false;
        } else if in_dependencies && let Some(package) = &current {
            // ` "name"` or ` "name version"`.
            let dependency = line.trim().trim_matches(',').trim_matches('"');
            let name = dependency.split(' ').next().unwrap_or(dependency).to_owned();
            graph.entry(package.clone()).or_default().push(name);
        }
    }
    graph
}

fn reachable(graph: &HashMap<String, Vec<String>>, from: &str) -> HashSet<String> {
    let mut seen = HashSet::new();
    let mut stack = vec![from.to_owned()];
    while let Some(p) = stack.pop() {
        if seen.insert(p.clone()) {
            stack.extend(graph.get(&p).into_iter().flatten().cloned());
        }
    }
    seen
}

#[test]
fn the_geometry_and_file_crates_never_reach_the_gpu_stack() {
    let lock = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../Cargo.lock"))
        .expect("the workspace's Cargo.lock");
    let graph = lock_graph(&lock);
    // The parse works: the binary does reach them.
    let binary = reachable(&graph, "seamlit");
    for gpu in ["wgpu", "winit", "egui"] {
        assert!(binary.contains(gpu), "the parse lost {gpu} under the binary");
    }
    let libraries = [
        "seamlit-mesh",
        "seamlit-asset",
        "seamlit-gltf",
        "seamlit-obj",
        "seamlit-fbx",
        "seamlit-usd",
        "seamlit-io",
        "seamlit-py",
    ];
    for library in libraries {
        let reach = reachable(&graph, library);
        assert!(reach.len() > 5, "{library}: {reach:?}");
        for gpu in ["wgpu", "winit", "egui", "seamlit-render", "naga"] {
            assert!(!reach.contains(gpu), "{library} reaches {gpu}");
        }
    }
}

#[test]
fn the_gltf_and_obj_crates_never_reach_another_format_s_library() {
    // The web page builds glTF and OBJ for wasm32: no FBX C library, no USD parser.
    let lock = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../Cargo.lock"))
        .expect("the workspace's Cargo.lock");
    let graph = lock_graph(&lock);
    assert!(reachable(&graph, "seamlit-fbx").contains("ufbx"), "the parse lost ufbx");
    assert!(reachable(&graph, "seamlit-usd").contains("openusd"), "the parse lost openusd");
    for library in ["seamlit-asset", "seamlit-gltf", "seamlit-obj"] {
        let reach = reachable(&graph, library);
        for other in ["ufbx", "openusd", "tobj", "gltf"] {
            let own = (library == "seamlit-obj" && other == "tobj")
                || (library == "seamlit-gltf" && other == "gltf");
            assert!(own || !reach.contains(other), "{library} reaches {other}");
        }
    }
}

/// The modules of seamlit-mesh, lowest first: a module may import from modules before it in
/// this list (and from names re-exported at the crate root: the model's types, options and
/// errors), never from one after it. The pipeline's order: validate and weld, the per-face
/// and per-frame maths, the grouping and the one-pass smoothing, the report, MikkTSpace, the
/// morph deltas, the output writer, the repair, `fix`; the paper's reference beside it.
const MESH_LAYERS: &[&str] = &[
    "error",
    "index",
    "options",
    "model",
    "changes",
    "validate",
    "weld",
    "face",
    "frame",
    "group",
    "judge",
    "smooth",
    "skin",
    "report",
    "mikk",
    "morph",
    "out",
    "repair",
    "fix",
    "reference",
];

/// The `crate::module` paths a source file uses outside comments and its `mod tests`.
fn module_paths(source: &str) -> Vec<String> {
    let code = source.split("#[cfg(test)]\nmod tests").next().unwrap_or(source);
    let mut paths = Vec::new();
    for line in code.lines().filter(|l| !l.trim_start().starts_with("//")) {
        let mut rest = line;
        while let Some(at) = rest.find("crate::") {
            rest = &rest[at + "crate::".len()..];
            let name: String =
                rest.chars().take_while(|c| c.is_ascii_lowercase() || *c == '_').collect();
            if !name.is_empty() && rest[name.len()..].starts_with([':', ';', ',', '}', ' ']) {
                paths.push(name);
            }
        }
    }
    // `use crate::{a, b::c}` groups: the lowercase names inside the braces are modules too.
    for group in code.split("use crate::{").skip(1) {
        let inside = group.split("};").next().unwrap_or("");
        for item in inside.split(',') {
            let name = item.trim().split("::").next().unwrap_or("");
            if name.chars().next().is_some_and(|c| c.is_ascii_lowercase()) {
                paths.push(name.to_string());
            }
        }
    }
    paths
}

/// The imports of `module` (whose source is `source`) that run up the layers.
fn back_edges(module: &str, source: &str) -> Vec<String> {
    let rank = |m: &str| MESH_LAYERS.iter().position(|l| *l == m);
    let own = rank(module).unwrap_or_else(|| panic!("{module} is not in MESH_LAYERS"));
    module_paths(source)
        .into_iter()
        .filter(|m| m != module && rank(m).is_some_and(|r| r > own))
        .map(|m| format!("{module} imports {m}"))
        .collect()
}

/// The source of a module file, or of every `.rs` file under a module's folder.
fn source_of(path: &std::path::Path) -> String {
    if !path.is_dir() {
        return std::fs::read_to_string(path).unwrap();
    }
    let mut all = String::new();
    for entry in std::fs::read_dir(path).unwrap() {
        all += &source_of(&entry.unwrap().path());
    }
    all
}

#[test]
fn mesh_imports_run_one_way() {
    let src = concat!(env!("CARGO_MANIFEST_DIR"), "/src");
    let mut found = Vec::new();
    for entry in std::fs::read_dir(src).unwrap() {
        let path = entry.unwrap().path();
        let module = path.file_stem().unwrap().to_str().unwrap().to_string();
        if module == "lib" {
            continue;
        }
        // A module's folder (`mikk/`) holds its submodules: they are part of that layer.
        found.extend(back_edges(&module, &source_of(&path)));
    }
    assert!(found.is_empty(), "imports that run up the layers: {found:#?}");
}

#[test]
fn the_mesh_check_sees_a_back_edge() {
    let source = "use crate::frame::Linear;\nuse crate::{Model, fix::Out};\n// crate::repair\n";
    assert_eq!(back_edges("weld", source), ["weld imports frame", "weld imports fix"]);
    assert!(back_edges("fix", source).is_empty());
}
