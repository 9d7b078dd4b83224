//! An independent reader of glTF and GLB files for the tests: plain byte handling and
//! serde_json, no seamlit and no gltf crate, so that what a test compares is what the file
//! holds.

use std::path::{Path, PathBuf};

use serde_json::Value;

use super::usize_of;

/// A glTF or GLB file: the JSON and each buffer's bytes.
pub struct File {
    /// The document.
    pub json: Value,
    /// Each buffer's bytes: the GLB `BIN` chunk, a `data:` URI's or a file's; empty for a
    /// meshopt fallback buffer (no data of its own).
    pub buffers: Vec<Vec<u8>>,
    /// The file's folder (relative URIs).
    pub folder: PathBuf,
}

/// The JSON chunk and, when there is one, the BIN chunk of GLB `bytes`; checks the header's
/// length and the chunk types.
pub fn glb_chunks(bytes: &[u8]) -> (Value, Option<Vec<u8>>) {
    let word =
        |at: usize| usize_of(u64::from(u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap())));
    assert_eq!(&bytes[..4], b"glTF");
    assert_eq!(word(8), bytes.len(), "GLB length");
    let json_length = word(12);
    assert_eq!(&bytes[16..20], b"JSON");
    let json: Value = serde_json::from_slice(&bytes[20..20 + json_length]).unwrap();
    let at = 20 + json_length;
    let bin = (at < bytes.len()).then(|| {
        assert_eq!(&bytes[at + 4..at + 8], b"BIN\0");
        bytes[at + 8..at + 8 + word(at)].to_vec()
    });
    (json, bin)
}

/// The JSON chunk of a GLB file.
pub fn glb_json(path: &Path) -> Value {
    glb_chunks(&std::fs::read(path).unwrap()).0
}

/// Reads a `.gltf` (with its buffers) or `.glb`.
pub fn read(path: &Path) -> File {
    let bytes = std::fs::read(path).unwrap();
    let (json, mut bin) = if bytes.starts_with(b"glTF") {
        glb_chunks(&bytes)
    } else {
        (serde_json::from_slice(&bytes).unwrap(), None)
    };
    let folder = path.parent().unwrap().to_path_buf();
    let fallback = |buffer: &Value| {
        buffer["extensions"].as_object().is_some_and(|e| {
            e.iter()
                .any(|(name, e)| name.ends_with("_meshopt_compression") && e["fallback"] == true)
        })
    };
    let buffers = json["buffers"]
        .as_array()
        .map(|buffers| {
            buffers
                .iter()
                .map(|buffer| {
                    let data = match buffer["uri"].as_str() {
                        Some(uri) if uri.starts_with("data:") => {
                            base64::decode(uri.split_once(";base64,").unwrap().1).unwrap()
                        }
                        Some(uri) => std::fs::read(folder.join(uri)).unwrap(),
                        None if fallback(buffer) => return Vec::new(),
                        None => bin.take().expect("a BIN chunk for the buffer without uri"),
                    };
                    assert!(data.len() >= buffer["byteLength"].as_u64().map(usize_of).unwrap());
                    data
                })
                .collect()
        })
        .unwrap_or_default();
    File { json, buffers, folder }
}

/// Bytes per component of a `componentType`.
pub fn component_size(component_type: u64) -> usize {
    match component_type {
        5120 | 5121 => 1,
        5122 | 5123 => 2,
        _ => 4,
    }
}

use seamlit_testkit::components;

impl File {
    /// A buffer view's bytes.
    pub fn view(&self, index: usize) -> &[u8] {
        let view = &self.json["bufferViews"][index];
        let offset = view["byteOffset"].as_u64().map_or(0, usize_of);
        let length = view["byteLength"].as_u64().map(usize_of).unwrap();
        &self.buffers[view["buffer"].as_u64().map(usize_of).unwrap()][offset..offset + length]
    }

    /// An accessor's elements, each as its bytes (sparse substitution applied; matrices of
    /// components under 4 bytes, which need column padding, are not read).
    pub fn elements(&self, index: usize) -> Vec<Vec<u8>> {
        let a = &self.json["accessors"][index];
        let size = component_size(a["componentType"].as_u64().unwrap())
            * components(a["type"].as_str().unwrap());
        let count = a["count"].as_u64().map(usize_of).unwrap();
        let mut out = vec![vec![0u8; size]; count];
        if let Some(view) = a["bufferView"].as_u64().map(usize_of) {
            let stride =
                self.json["bufferViews"][view]["byteStride"].as_u64().map_or(size, usize_of);
            let offset = a["byteOffset"].as_u64().map_or(0, usize_of);
            let data = self.view(view);
            for (k, e) in out.iter_mut().enumerate() {
                e.copy_from_slice(&data[offset + k * stride..offset + k * stride + size]);
            }
        }
        if let Some(sparse) = a.get("sparse") {
            let n = sparse["count"].as_u64().map(usize_of).unwrap();
            let index_size = component_size(sparse["indices"]["componentType"].as_u64().unwrap());
            let indices =
                self.view(sparse["indices"]["bufferView"].as_u64().map(usize_of).unwrap());
            let values = self.view(sparse["values"]["bufferView"].as_u64().map(usize_of).unwrap());
            for k in 0..n {
                let mut word = [0u8; 4];
                word[..index_size].copy_from_slice(&indices[k * index_size..(k + 1) * index_size]);
                out[u32::from_le_bytes(word) as usize] = values[k * size..(k + 1) * size].to_vec();
            }
        }
        out
    }
}
