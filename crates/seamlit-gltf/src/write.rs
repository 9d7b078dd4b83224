//! glTF 2.0 and GLB out, through gltf-json.
//!
//! Each object becomes a mesh of one triangle primitive (POSITION with min/max, NORMAL,
//! TANGENT, TEXCOORD_0 and _1, COLOR_0 as RGBA floats, indices as u16 where every index fits
//! below 65535, else u32, and the morph targets' POSITION, NORMAL and TANGENT deltas) named
//! after the object. The node hierarchy of the asset is rebuilt when it is consistent with
//! the objects' transforms (a node carrying several objects gets one child node per object);
//! otherwise each object gets a root node with its transform. Materials and the textures
//! they use are carried through: embedded in a GLB, written beside a `.gltf` (whose buffer
//! goes to `NAME.bin` beside it too).
//!
//! The glTF validator rejects non-unit normals and tangents and tangent signs other than
//! +-1: such values (only such) are normalised on the way out, a zero vector becoming +Z
//! (normal) or +X (tangent). Texture coordinates are flipped (`v' = 1 - v`) when the model's V
//! runs up (OBJ, Newell), since glTF's runs down.

use std::io::Write;
use std::path::Path;

use gltf_json as json;
use json::validation::{Checked, USize64};

use seamlit_asset::Asset;
use seamlit_asset::check::check_object;
use seamlit_asset::error::{InvalidAsset, IoError};
use seamlit_asset::files::Destination;
use seamlit_asset::files::safe_name;

mod animation;
mod bin;
mod deform;
mod material;
mod mesh;
mod nodes;

use bin::BinPart;
use deform::Deform;
use nodes::hierarchy_matches;

/// Writes `asset` as `.glb` (`binary`) or `.gltf` (+ `.bin` and images beside it).
///
/// The binary buffer is never assembled in memory: the JSON is built first with every buffer
/// view's offset computed from the lengths, then the vertex and index data are streamed from
/// the objects to the file (after the JSON chunk in a GLB, into `NAME.bin` beside a `.gltf`).
pub(crate) fn save(
    asset: &Asset,
    path: &Path,
    binary: bool,
    to: &mut Destination,
) -> Result<(), IoError> {
    for object in &asset.model.objects {
        check_object(object, path)?;
    }
    // glTF's indices are 32-bit: the nodes written (the asset's, or one per object) too.
    let nodes = asset.nodes.len() + asset.model.objects.len();
    if nodes >= u32::MAX as usize {
        return Err(IoError::TooManyElements {
            path: path.to_path_buf(),
            what: "the asset's nodes and objects".to_owned(),
            limit: u32::MAX as usize - 1,
            actual: nodes,
        });
    }
    let mut writer = Writer::new(path, binary);
    let textures = writer.textures(asset)?;
    for material in &asset.materials {
        let m = writer.material(material, &textures);
        writer.root.push(m);
    }
    let hierarchy = hierarchy_matches(asset);
    let deform = Deform::of(asset, hierarchy);
    let meshes: Vec<json::Index<json::Mesh>> = asset
        .model
        .objects
        .iter()
        .enumerate()
        .map(|(i, o)| writer.mesh(o, asset.model.v_axis, asset.materials.len(), &deform, i))
        .collect();
    let written = writer.nodes(asset, &meshes, hierarchy);
    if hierarchy {
        writer.skins(asset, &written);
        writer.animations(asset, &written, &deform);
    }
    writer.finish(to)
}

struct Writer<'a> {
    root: json::Root,
    /// The binary buffer's contents in order, each starting at a multiple of 4 bytes.
    pieces: Vec<BinPart<'a>>,
    /// The binary buffer's length so far.
    bin_len: usize,
    /// Files to write beside a `.gltf`: (file name, bytes).
    side_files: Vec<(String, Vec<u8>)>,
    path: &'a Path,
    binary: bool,
    stem: String,
}

impl<'a> Writer<'a> {
    /// A writer of an empty document (its `asset` member set) to `path`.
    fn new(path: &'a Path, binary: bool) -> Self {
        let stem = path
            .file_stem()
            .map_or_else(|| "model".to_owned(), |s| safe_name(&s.to_string_lossy()));
        let root = json::Root {
            asset: json::Asset {
                generator: Some("seamlit".to_owned()),
                version: "2.0".to_owned(),
                ..Default::default()
            },
            ..Default::default()
        };
        Self { root, pieces: Vec::new(), bin_len: 0, side_files: Vec::new(), path, binary, stem }
    }

    /// Writes the document: its buffer (when anything was put in it), the side files and
    /// `NAME.bin` beside a `.gltf`, then the `.gltf` or the GLB.
    fn finish(mut self, to: &mut Destination) -> Result<(), IoError> {
        let (path, binary) = (self.path, self.binary);
        let bin_uri = (!binary && self.bin_len > 0).then(|| format!("{}.bin", self.stem));
        if self.bin_len > 0 {
            let buffer = json::Buffer {
                byte_length: USize64::from(self.bin_len),
                name: None,
                uri: bin_uri.clone(),
                extensions: None,
                extras: Default::default(),
            };
            self.root.push(buffer);
        }
        let json_bytes =
            serde_json::to_vec_pretty(&self.root).map_err(|e| IoError::InvalidAsset {
                path: path.to_path_buf(),
                object: String::new(),
                kind: InvalidAsset::Json { source: e },
            })?;
        let folder = path.parent().unwrap_or(Path::new(""));
        for (name, bytes) in &self.side_files {
            to.write(&folder.join(name), bytes)?;
        }
        if let Some(uri) = bin_uri {
            to.write_with(&folder.join(uri), |out| self.write_bin(out))?;
        }
        if !binary {
            return to.write(path, &json_bytes);
        }
        let bin = (self.bin_len > 0).then_some(self.bin_len);
        crate::glb::write(to, path, json_bytes, bin, |out| self.write_bin(out))
    }

    /// Appends a piece to the binary buffer (4-byte aligned) as a buffer view.
    fn view(
        &mut self,
        piece: BinPart<'a>,
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::buffer::View> {
        let offset = self.bin_len.next_multiple_of(4);
        let length = piece.len();
        self.bin_len = offset + length;
        self.pieces.push(piece);
        self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(length),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: target.map(Checked::Valid),
            extensions: None,
            extras: Default::default(),
        })
    }

    /// Writes the binary buffer: every piece, each padded with zeros to a multiple of 4.
    fn write_bin(&self, out: &mut dyn Write) -> std::io::Result<()> {
        let mut written = 0usize;
        for piece in &self.pieces {
            let padding = written.next_multiple_of(4) - written;
            out.write_all(&[0; 3][..padding])?;
            piece.write(out)?;
            written += padding + piece.len();
        }
        debug_assert_eq!(written, self.bin_len);
        Ok(())
    }

    fn accessor(
        &mut self,
        piece: BinPart<'a>,
        count: usize,
        component: json::accessor::ComponentType,
        type_: json::accessor::Type,
        target: json::buffer::Target,
        min_max: Option<(Vec<f32>, Vec<f32>)>,
    ) -> json::Index<json::Accessor> {
        let view = self.view(piece, Some(target));
        self.push_accessor(view, count, component, type_, min_max)
    }

    /// Floats that are not vertex attributes (inverse bind matrices, animation times and
    /// values): a view without a target.
    fn data_accessor(
        &mut self,
        values: Vec<f32>,
        count: usize,
        type_: json::accessor::Type,
        min_max: Option<(Vec<f32>, Vec<f32>)>,
    ) -> json::Index<json::Accessor> {
        let view = self.view(BinPart::Floats(values), None);
        self.push_accessor(view, count, json::accessor::ComponentType::F32, type_, min_max)
    }

    /// An accessor of a whole view.
    fn push_accessor(
        &mut self,
        view: json::Index<json::buffer::View>,
        count: usize,
        component: json::accessor::ComponentType,
        type_: json::accessor::Type,
        min_max: Option<(Vec<f32>, Vec<f32>)>,
    ) -> json::Index<json::Accessor> {
        let (min, max) = match min_max {
            Some((min, max)) => (
                Some(json::Value::from(min.iter().map(|&x| f64::from(x)).collect::<Vec<_>>())),
                Some(json::Value::from(max.iter().map(|&x| f64::from(x)).collect::<Vec<_>>())),
            ),
            None => (None, None),
        };
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Checked::Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Checked::Valid(type_),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// A float vertex attribute of `count` elements.
    fn float_accessor(
        &mut self,
        piece: BinPart<'a>,
        count: usize,
        type_: json::accessor::Type,
        min_max: Option<(Vec<f32>, Vec<f32>)>,
    ) -> json::Index<json::Accessor> {
        self.accessor(
            piece,
            count,
            json::accessor::ComponentType::F32,
            type_,
            json::buffer::Target::ArrayBuffer,
            min_max,
        )
    }
}
