//! Files made by other tools, through the binary (issue 27): an MTL with statements seamlit
//! cannot use loads with the right colours and one warning; an OBJ with Latin-1 names loads,
//! its OBJ output keeps those lines byte for byte and its glTF output has the names as
//! characters; NUL bytes and binary garbage are still refused with exit status 2.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn seamlit(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_seamlit"))
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("the binary runs")
}

fn lines(o: &Output, prefix: &str) -> Vec<String> {
    let stderr = String::from_utf8_lossy(&o.stderr);
    stderr.lines().filter(|l| l.starts_with(prefix)).map(str::to_owned).collect()
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

#[test]
fn an_mtl_with_ks_0_and_a_spectral_ka_loads_with_its_colours_and_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "m.mtl", b"newmtl grey\nKa spectral x.rfl\nKd 0.25\nKs 0\n");
    let input = write(dir.path(), "m.obj", format!("mtllib m.mtl\nusemtl grey\n{QUAD}").as_bytes());
    let output = dir.path().join("out.gltf");
    let o = seamlit(&["fix", input.to_str().unwrap(), "-o", output.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let warnings = lines(&o, "warning: ");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains("m.mtl:2: `Ka spectral x.rfl`"), "{warnings:?}");
    let pbr = &json(&output)["materials"][0]["pbrMetallicRoughness"];
    assert_eq!(pbr["baseColorFactor"], serde_json::json!([0.25, 0.25, 0.25, 1.0]));
}

#[test]
fn latin_1_names_load_and_keep_their_bytes_in_obj_and_their_characters_in_gltf() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "m.mtl", b"newmtl Bl\xe5\nKd 0 0 1\n");
    let obj: &[u8] = b"mtllib m.mtl\r\ng R\xf8d_tr\xe6\r\nusemtl Bl\xe5\r\nv 0 0 0\r\nv 1 0 0\r\n\
v 1 1 0\r\nv 0 1 0\r\nf 1 2 3 4\r\n";
    let input = write(dir.path(), "old.obj", obj);
    let out = tempfile::tempdir().unwrap();
    let obj_out = out.path().join("old.obj");
    let gltf_out = out.path().join("old.gltf");
    for output in [&obj_out, &gltf_out] {
        let o = seamlit(&["fix", input.to_str().unwrap(), "-o", output.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        let warnings = lines(&o, "warning: ");
        assert_eq!(warnings.len(), 2, "one for the OBJ, one for the MTL: {warnings:?}");
    }
    let written = std::fs::read(&obj_out).unwrap();
    let kept: Vec<&[u8]> = written.split_inclusive(|&b| b == b'\n').take(3).collect();
    assert_eq!(kept, [&b"mtllib m.mtl\r\n"[..], b"g R\xf8d_tr\xe6\r\n", b"usemtl Bl\xe5\r\n"]);
    assert_eq!(std::fs::read(out.path().join("m.mtl")).unwrap(), b"newmtl Bl\xe5\nKd 0 0 1\n");
    let gltf = json(&gltf_out);
    assert_eq!(gltf["materials"][0]["name"], "Blå");
    assert_eq!(
        gltf["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"],
        serde_json::json!([0.0, 0.0, 1.0, 1.0])
    );
    let nodes = gltf["nodes"].as_array().unwrap();
    assert!(nodes.iter().any(|n| n["name"] == "Rød_træ"), "{nodes:?}");
}

#[test]
fn nul_bytes_and_binary_garbage_are_still_refused_with_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    // Bytes of no text encoding, without a NUL: a deterministic scramble.
    let garbage: Vec<u8> = (0u32..4096)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13).to_le_bytes()[0])
        .map(|b| if b == 0 { 0xff } else { b })
        .collect();
    let with_garbage = [b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".as_slice(), &garbage].concat();
    for (name, bytes) in [
        ("nul.obj", b"o a\nv 0 0 0\nv 1 0\x00 0\nv 0 1 0\nf 1 2 3\n".to_vec()),
        ("garbage.obj", with_garbage),
    ] {
        let path = write(dir.path(), name, &bytes);
        let output = dir.path().join(format!("{name}.glb"));
        let o = seamlit(&["fix", path.to_str().unwrap(), "-o", output.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{name}: {}", String::from_utf8_lossy(&o.stderr));
        let errors = lines(&o, "error: ");
        assert_eq!(errors.len(), 1, "{errors:?}");
        assert!(errors[0].contains(name), "{errors:?}");
        assert!(!output.exists());
    }
}
