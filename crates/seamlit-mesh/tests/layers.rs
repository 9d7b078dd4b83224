//! The layering ARCHITECTURE.md states: a user who only wants repaired models depends on
//! seamlit-mesh and seamlit-io and never compiles the GPU stack. Checked on Cargo.lock: the
//! packages each of the two can reach (dev-dependencies included, so this over-approximates)
//! contain no wgpu, winit or egui.

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
    for library in ["seamlit-mesh", "seamlit-io", "seamlit-py"] {
        let reach = reachable(&graph, library);
        assert!(reach.len() > 5, "{library}: {reach:?}");
        for gpu in ["wgpu", "winit", "egui", "seamlit-render", "naga"] {
            assert!(!reach.contains(gpu), "{library} reaches {gpu}");
        }
    }
}
