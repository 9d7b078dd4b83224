//! Every WGSL file of the crate parses and validates with naga.

use std::path::Path;

#[test]
fn every_wgsl_file_parses_and_validates() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut checked = 0;
    for entry in std::fs::read_dir(&src).expect("read src/") {
        let path = entry.expect("list src/").path();
        if path.extension().is_none_or(|e| e != "wgsl") {
            continue;
        }
        let text = std::fs::read_to_string(&path).expect("read a shader");
        let module = naga::front::wgsl::parse_str(&text)
            .unwrap_or_else(|e| panic!("{}: {}", path.display(), e.emit_to_string(&text)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}: {}", path.display(), e.emit_to_string(&text)));
        checked += 1;
    }
    assert!(checked >= 1, "no .wgsl files found in {}", src.display());
}

/// `shadow.wgsl` repeats `mesh.wgsl`'s `Object` (group 2's uniforms, `ObjectRaw` in
/// scene.rs), since each shader is a file of its own: the two stay the same struct, member for
/// member (names, types and offsets).
#[test]
fn the_shadow_pass_reads_the_object_uniforms_as_the_mesh_shader_does() {
    let object = |file: &str| -> Vec<(String, u32, String)> {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("src").join(file);
        let text = std::fs::read_to_string(&path).expect("read a shader");
        let module = naga::front::wgsl::parse_str(&text).expect("parse a shader");
        let (_, ty) = module
            .types
            .iter()
            .find(|(_, ty)| ty.name.as_deref() == Some("Object"))
            .unwrap_or_else(|| panic!("{file} has no struct Object"));
        let naga::TypeInner::Struct { members, .. } = &ty.inner else {
            panic!("{file}: Object is not a struct");
        };
        members
            .iter()
            .map(|m| {
                let name = m.name.clone().unwrap_or_default();
                (name, m.offset, format!("{:?}", module.types[m.ty].inner))
            })
            .collect()
    };
    let mesh = object("mesh.wgsl");
    assert!(mesh.len() >= 2, "{mesh:?}");
    assert_eq!(object("shadow.wgsl"), mesh);
}
