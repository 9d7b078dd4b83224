//! The `.usda` output: a layer of opinions over the input stage, USD's own non-destructive
//! way. It sublayers the input by its path relative to the output, repeats the root layer's
//! stage metadata (USD reads `upAxis`, `metersPerUnit`, `defaultPrim` from the root layer
//! only), and holds an `over` per mesh whose normals seamlit changed, authoring there only
//! `primvars:normals` (faceVarying, its values and `primvars:normals:indices`, so that the
//! weaker layer's indices never apply) and, where the input has a plain `normals` attribute,
//! a block of it (`primvars:normals` wins over it anyway; the block keeps tools that read
//! `normals` from reading the old values). A skinned mesh whose influences
//! [`seamlit_asset::match_skin_seams`] changed also gets its `primvars:skel:jointIndices` and
//! `primvars:skel:jointWeights` (per point, in its own joint order) and, where that order
//! had to grow, its `skel:joints`.
//!
//! The text is written here, not by openusd's usda writer (which writes `apiSchemas`
//! without brackets, `uniform rel`, and other text Pixar's USD does not read): it is a small
//! document of a fully known shape. Meshes that are subdivision surfaces get no normals
//! (renderers ignore them). Meshes inside instances cannot be overridden per instance: each
//! prototype mesh is written once, at the site the reader found for it (`read/instance.rs`),
//! with the normals its instances agree on (`prototype_over`). A mesh whose points or
//! normals are time-sampled keeps the input's normals (a value here would hold for every
//! frame).

mod corners;

use std::fmt::{self, Write as _};
use std::io;
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

use glam::Vec3;
use rayon::prelude::*;
use seamlit_mesh::Object;

use crate::source::{MeshSource, SkinSource, StageSource, UsdSource};
use corners::CornerNormals;
use seamlit_asset::Asset;
use seamlit_asset::LoadOptions;
use seamlit_asset::error::IoError;
use seamlit_asset::error::usd::UsdOutput;

/// Writes `asset` (loaded from a USD stage) as a `.usda` layer over that stage at `path`.
/// Returns the warnings: meshes whose normals are not written, and why.
///
/// # Errors
///
/// [`IoError::UsdOutput`] when the asset did not come from USD or no longer matches its
/// stage or holds a normal that is not finite; the errors of reading the stage again;
/// [`IoError::Io`] when writing fails.
pub(crate) fn save(asset: &Asset, path: &Path) -> Result<Vec<String>, IoError> {
    let layer = prepare(asset, path)?;
    let sublayer = relative(&layer.input, path);
    seamlit_asset::files::write_with(path, |out| layer.write(&sublayer, out))?;
    Ok(layer.warnings)
}

/// Writes `asset` as [`save`] does, but the layer in USD's binary crate format (`.usdc`):
/// the data the same text parses to ([`Layer::data`]), written by openusd's crate writer
/// (patched in vendor/openusd so that Pixar's USD reads it: PATCHES.md).
///
/// # Errors
///
/// Those of [`save`]; [`IoError::UsdOutput`] with [`UsdOutput::Usdc`] when openusd cannot
/// parse or write the layer.
pub(crate) fn save_usdc(asset: &Asset, path: &Path) -> Result<Vec<String>, IoError> {
    let layer = prepare(asset, path)?;
    let refuse = |e: anyhow::Error| IoError::UsdOutput {
        path: path.to_path_buf(),
        kind: UsdOutput::Usdc { reason: format!("{e:#}") },
    };
    let mut data = layer.data(&relative(&layer.input, path)).map_err(refuse)?;
    element_sizes_as_ints(&mut data);
    let mut bytes = io::Cursor::new(Vec::new());
    openusd::usdc::CrateWriter::write(&data, &mut bytes).map_err(refuse)?;
    seamlit_asset::files::write(path, bytes.get_ref())?;
    Ok(layer.warnings)
}

/// Retags every `elementSize` (the skin primvars') as an `int`: openusd's text parser reads an
/// untyped metadata integer as an `int64`, its crate writer writes that type, and Pixar's USD
/// takes a primvar's `elementSize` only as an `int` (an `int64` one reads as 1: UsdSkel then
/// finds its joint indices mis-sized and skins nothing).
fn element_sizes_as_ints(data: &mut openusd::sdf::Data) {
    use openusd::sdf::Value;
    let paths: Vec<openusd::sdf::Path> = data
        .iter()
        .filter(|(_, spec)| matches!(spec.get("elementSize"), Some(Value::Int64(_))))
        .map(|(path, _)| path.clone())
        .collect();
    for path in paths {
        if let Some(size) = data.spec_mut(&path).and_then(|spec| spec.get_mut("elementSize"))
            && let Value::Int64(n) = *size
        {
            *size = Value::Int(i32::try_from(n).unwrap_or(i32::MAX));
        }
    }
}

/// The override layer for `asset`, but for the asset path by which it sublayers the input
/// (which depends on where the layer is written: beside the output, or inside a package).
pub(crate) struct Layer {
    /// The input stage's root layer.
    pub input: PathBuf,
    /// The stage's meshes and metadata, as read.
    stage: Arc<StageSource>,
    /// The meshes overridden, in the order of the stage's meshes.
    overs: Vec<MeshOver>,
    /// Meshes whose normals are not written, and why.
    pub warnings: Vec<String>,
}

impl Layer {
    /// The layer's text, sublayering the input at `sublayer` (an asset path).
    pub fn text(&self, sublayer: &str) -> String {
        let mut text = String::new();
        // Writing to a String does not fail.
        let _ = document(&mut text, sublayer, self, Arrays::Written);
        text
    }

    /// The layer as openusd's data, for its crate writer: the document with its arrays left
    /// empty, parsed by openusd, and the arrays then put in as values. That is the data the
    /// whole text parses to (a float's shortest text reads back as the same float; the
    /// parser keeps the type the text declares), without formatting and parsing every
    /// number: the 1M-triangle teapot's layer is 40 MB of them.
    ///
    /// # Errors
    ///
    /// openusd's, where it cannot parse the document; an over or array missing from what it
    /// parsed; an index past `i32::MAX` (`int[]`).
    pub fn data(&self, sublayer: &str) -> anyhow::Result<openusd::sdf::Data> {
        use openusd::sdf::Value;
        let mut text = String::new();
        let _ = document(&mut text, sublayer, self, Arrays::Empty);
        let mut data = openusd::usda::parse(&text)?;
        for over in &self.overs {
            let prim = prim_path(&over.prim);
            let mut put = |property: &str, value: Value| -> anyhow::Result<()> {
                let path = openusd::sdf::Path::new(&format!("{prim}.{property}"))?;
                let slot = data
                    .spec_mut(&path)
                    .and_then(|spec| spec.get_mut("default"))
                    .ok_or_else(|| anyhow::anyhow!("<{path}> has no value to set"))?;
                *slot = value;
                Ok(())
            };
            if let Some(normals) = &over.normals {
                let values = normals.values.iter().map(|n| openusd::gf::vec3f(n.x, n.y, n.z));
                put("primvars:normals", Value::Vec3fVec(values.collect()))?;
                put("primvars:normals:indices", Value::IntVec(ints(&normals.indices)?))?;
            }
            if let Some(skin) = &over.skin {
                put("primvars:skel:jointIndices", Value::IntVec(ints(&skin.indices)?))?;
                put("primvars:skel:jointWeights", Value::FloatVec(skin.weights.clone()))?;
            }
        }
        Ok(data)
    }

    /// Writes the layer's text to `out` as it is made, sublayering the input at `sublayer`.
    ///
    /// # Errors
    ///
    /// The error `out` gave.
    pub fn write(&self, sublayer: &str, out: &mut dyn io::Write) -> io::Result<()> {
        let mut text = IoText { out, error: None };
        match document(&mut text, sublayer, self, Arrays::Written) {
            Ok(()) => Ok(()),
            Err(fmt::Error) => Err(text.error.unwrap_or_else(|| io::Error::other("formatting"))),
        }
    }
}

/// What the layer authors on one mesh.
struct MeshOver {
    /// An index into the stage's meshes (for a prototype's, its first instance's copy).
    mesh: usize,
    /// The prim the `over` is written at: the mesh's, or for an instance's mesh the
    /// prototype's site in the root layer stack.
    prim: String,
    /// Its normals at each face corner, where they changed.
    normals: Option<CornerNormals>,
    /// Its skin influences, where they changed.
    skin: Option<SkinOver>,
}

/// Checks `asset` against the stage it was loaded from and finds the normals to write.
///
/// # Errors
///
/// As [`save`], but for writing.
pub(crate) fn prepare(asset: &Asset, path: &Path) -> Result<Layer, IoError> {
    let refuse = |kind| IoError::UsdOutput { path: path.to_path_buf(), kind };
    let Some(input) = asset.source.as_deref().filter(|s| is_usd(s)) else {
        return Err(refuse(UsdOutput::NotFromUsd));
    };
    let stage = stage_of(asset, input)?;
    check_model(&asset.model.objects, &stage)
        .map_err(|reason| refuse(UsdOutput::ModelChanged { reason }))?;
    let mut warnings = Vec::new();
    let mut overs = Vec::new();
    // The instance proxies of each prototype mesh, in the order of the stage's meshes.
    let mut prototypes: Vec<(&str, Vec<usize>)> = Vec::new();
    // The corner normals of every mesh outside instances, side by side (the instances' are
    // agreed on below): most of the work of a large stage's layer.
    let corners: Vec<Option<CornerNormals>> = (asset.model.objects.par_iter())
        .zip(&stage.meshes)
        .map(|(object, mesh)| match mesh.instance {
            Some(_) => None,
            None => CornerNormals::of(object, mesh),
        })
        .collect();
    let meshes = asset.model.objects.iter().zip(&stage.meshes).zip(corners);
    for (m, ((object, mesh), normals)) in meshes.enumerate() {
        let skin = match &mesh.skin {
            Some(skin) if asset.skins_changed.objects.contains(&m) => {
                skin_over(object, mesh, skin, &stage.joints, path, &mut warnings)
            }
            _ => None,
        };
        if let Some(instance) = &mesh.instance {
            match prototypes.iter_mut().find(|(p, _)| *p == instance.prototype) {
                Some((_, copies)) => copies.push(m),
                None => prototypes.push((&instance.prototype, vec![m])),
            }
            continue;
        }
        let normals =
            changed_normals(normals, object, mesh, path, &mut warnings).map_err(refuse)?;
        if normals.is_some() || skin.is_some() {
            overs.push(MeshOver { mesh: m, prim: mesh.prim.clone(), normals, skin });
        }
    }
    let mut written: Vec<(String, usize)> = Vec::new();
    for (_, copies) in &prototypes {
        let Some(over) = prototype_over(&asset.model.objects, &stage, copies, path, &mut warnings)
            .map_err(refuse)?
        else {
            continue;
        };
        // Two prototypes (instances of one source with different arcs) cannot share a site.
        if let Some((_, other)) = written.iter().find(|(site, _)| *site == over.prim) {
            warnings.push(format!(
                "{}: mesh <{}>: the instances of two prototypes (<{}>, <{}>) compose their normals from <{}>, where they differ: its normals are not written",
                path.display(),
                stage.meshes[copies[0]].prim,
                stage.meshes[*other].prim,
                stage.meshes[copies[0]].prim,
                over.prim
            ));
            overs.retain(|o| o.prim != over.prim);
            continue;
        }
        written.push((over.prim.clone(), copies[0]));
        overs.push(over);
    }
    for (_, copies) in &prototypes {
        let instance = stage.meshes[copies[0]].instance.as_ref();
        let Some(site) = instance.and_then(|i| i.site.as_ref().ok()) else { continue };
        if overs.iter().any(|o| o.prim == *site && stage.meshes[o.mesh].instance.is_none()) {
            warnings.push(format!(
                "{}: mesh <{site}>: its normals, written there, are composed by {} too (they reference it)",
                path.display(),
                plural(copies.len(), "instance")
            ));
        }
    }
    Ok(Layer { input: input.to_path_buf(), stage, overs, warnings })
}

/// The object's normals at its mesh's face corners ([`CornerNormals::of`]) where they are
/// to be written: changed, finite, on a mesh that is neither a subdivision surface nor inside
/// an instance (those get a warning).
fn changed_normals(
    normals: Option<CornerNormals>,
    object: &Object,
    mesh: &MeshSource,
    path: &Path,
    warnings: &mut Vec<String>,
) -> Result<Option<CornerNormals>, UsdOutput> {
    let Some(normals) = normals else { return Ok(None) };
    if !normals.is_finite() {
        return Err(UsdOutput::NotFinite { object: object.name.clone() });
    }
    if mesh.corner_normals.as_ref().is_some_and(|old| normals.same_bits(old)) {
        return Ok(None);
    }
    if let Some(scheme) = &mesh.subdivision {
        warnings.push(format!(
            "{}: mesh <{}> is a subdivision surface (subdivisionScheme {scheme}): no normals are written on it (renderers ignore them)",
            path.display(),
            mesh.prim
        ));
        return Ok(None);
    }
    if let Some(why) = time_sampled(mesh) {
        warnings.push(format!("{}: mesh <{}>: {why}", path.display(), mesh.prim));
        return Ok(None);
    }
    if mesh.instance_proxy {
        warnings.push(format!(
            "{}: mesh <{}> is inside an instance, whose prims a layer cannot override one by one: its normals are not written",
            path.display(),
            mesh.prim
        ));
        return Ok(None);
    }
    Ok(Some(normals))
}

/// The largest angle, in degrees, between two instances' normals of one face corner that
/// still counts as the same: `f32` rounding through different instance transforms (the
/// usd-wg teapots, 0.3 units across, up to 2.7 from the origin, turned and scaled, differ by
/// up to 0.07 degrees at their tiniest faces), far below a seam's degrees.
const SAME_NORMAL_DEGREES: f32 = 0.25;

/// The `over` of one prototype mesh, from its instance proxies `copies` (indices into the
/// stage's meshes and the objects), written where the stage lets one layer change every
/// instance (the site the reader found). At each face corner it authors the normal every
/// instance was given; where they were given different ones (a seam with a mesh outside the
/// instances, different in each), the input's normal (without one, the instances' mean), with
/// one warning. `None`, with a warning, where nothing can be written: a subdivision surface,
/// no site (an external reference), or a site that is also a mesh outside instances.
fn prototype_over(
    objects: &[Object],
    stage: &StageSource,
    copies: &[usize],
    path: &Path,
    warnings: &mut Vec<String>,
) -> Result<Option<MeshOver>, UsdOutput> {
    let first = &stage.meshes[copies[0]];
    let Some(instance) = &first.instance else { return Ok(None) };
    let mut all = Vec::with_capacity(copies.len());
    for &m in copies {
        let Some(normals) = CornerNormals::of(&objects[m], &stage.meshes[m]) else {
            return Ok(None);
        };
        if !normals.is_finite() {
            return Err(UsdOutput::NotFinite { object: objects[m].name.clone() });
        }
        all.push(normals.expanded());
    }
    let (normals, differ) = agreed_normals(&all, first.corner_normals.as_deref());
    let normals = CornerNormals::from_values(&normals);
    if first.corner_normals.as_ref().is_some_and(|old| normals.same_bits(old)) {
        return Ok(None);
    }
    let named = format!(
        "{}: mesh <{}> (the prototype of {}, <{}> among them)",
        path.display(),
        instance.site.as_deref().unwrap_or(&first.prim),
        plural(copies.len(), "instance"),
        instance.instance
    );
    if let Some(scheme) = &first.subdivision {
        warnings.push(format!(
            "{named} is a subdivision surface (subdivisionScheme {scheme}): no normals are written on it (renderers ignore them)"
        ));
        return Ok(None);
    }
    if let Some(why) = time_sampled(first) {
        warnings.push(format!("{named}: {why}"));
        return Ok(None);
    }
    let site = match &instance.site {
        Ok(site) => site.clone(),
        Err(why) => {
            warnings.push(format!("{named}: its normals are not written: {why}"));
            return Ok(None);
        }
    };
    if let Some(other) = stage.meshes.iter().find(|m| m.root_sites.contains(&site)) {
        warnings.push(format!(
            "{named}: its normals are not written: mesh <{}>, outside instances, composes from <{site}> too and would change with them",
            other.prim
        ));
        return Ok(None);
    }
    if differ > 0 {
        let kept = if first.corner_normals.is_some() {
            "the input's normals are kept there"
        } else {
            "the instances' mean is written there"
        };
        warnings.push(format!(
            "{named}: at {differ} face corners its instances were given different normals (seams with meshes outside the instances, different in each, which one prototype cannot close): {kept}"
        ));
    }
    Ok(Some(MeshOver { mesh: copies[0], prim: site, normals: Some(normals), skin: None }))
}

/// `count` `thing`s, in English.
fn plural(count: usize, thing: &str) -> String {
    if count == 1 { format!("1 {thing}") } else { format!("{count} {thing}s") }
}

/// Per face corner: the normal every copy has (the first copy's), else the input's where
/// there is one, else the copies' mean; and the number of corners where the copies differ.
fn agreed_normals(copies: &[Vec<Vec3>], input: Option<&[Vec3]>) -> (Vec<Vec3>, usize) {
    let cos_same = SAME_NORMAL_DEGREES.to_radians().cos();
    let same = |a: Vec3, b: Vec3| a.normalize_or_zero().dot(b.normalize_or_zero()) >= cos_same;
    let mut differ = 0;
    let normals = (0..copies[0].len())
        .map(|c| {
            let first = copies[0][c];
            if copies.iter().all(|n| same(n[c], first)) {
                return first;
            }
            differ += 1;
            match input {
                Some(input) => input[c],
                None => copies.iter().map(|n| n[c]).sum::<Vec3>().try_normalize().unwrap_or(first),
            }
        })
        .collect();
    (normals, differ)
}

/// Why normals written on `mesh` would replace the input's frames, where they would: its
/// points or its normals are time-sampled, and the layer writes one value, which holds for
/// every frame (USD takes the strongest layer's opinion, samples or default).
fn time_sampled(mesh: &MeshSource) -> Option<String> {
    let names = &mesh.time_sampled;
    if names.is_empty() {
        return None;
    }
    let which = names.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ");
    let frames = if names.iter().any(|n| n != "points") {
        "one value would replace its normals at every frame"
    } else {
        "normals fixed for one shape would hold for every frame"
    };
    Some(format!(
        "its {which} {} time-sampled, and {frames}: its normals are not written (kept as the input has them)",
        if names.len() == 1 { "is" } else { "are" }
    ))
}

/// Whether `path` names a USD file by its extension.
pub(crate) fn is_usd(path: &Path) -> bool {
    let extension = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    matches!(extension.as_deref(), Some("usda" | "usdc" | "usdz" | "usd"))
}

/// What the writer needs of the stage `asset` was loaded from: kept by the loader, else read
/// again as it was read (with the same folders allowed).
fn stage_of(asset: &Asset, input: &Path) -> Result<Arc<StageSource>, IoError> {
    let source = asset.document::<UsdSource>().cloned().unwrap_or_default();
    if let Some(stage) = source.stage {
        return Ok(stage);
    }
    let options = LoadOptions { asset_roots: source.asset_roots, ..LoadOptions::GEOMETRY };
    Ok(Arc::new(super::read::read(input, &options)?.1))
}

/// Why the model's objects are not the stage's meshes, if they are not.
fn check_model(objects: &[Object], stage: &StageSource) -> Result<(), String> {
    if objects.len() != stage.meshes.len() {
        return Err(format!(
            "{} objects, the stage has {} meshes",
            objects.len(),
            stage.meshes.len()
        ));
    }
    for (object, mesh) in objects.iter().zip(&stage.meshes) {
        if object.name != mesh.prim {
            return Err(format!("object {:?} is not mesh <{}>", object.name, mesh.prim));
        }
        if object.triangles.len() != mesh.triangle_corners.len() {
            return Err(format!(
                "object {:?} has {} triangles, the mesh {}",
                object.name,
                object.triangles.len(),
                mesh.triangle_corners.len()
            ));
        }
        let loaded = mesh
            .corner_vertex
            .iter()
            .filter(|&&v| v != u32::MAX)
            .max()
            .map_or(0, |&v| v as usize + 1);
        if object.input_vertex_count() != loaded {
            return Err(format!(
                "object {:?} has {} vertices, the mesh {loaded}",
                object.name,
                object.input_vertex_count()
            ));
        }
    }
    Ok(())
}

/// A prim of the override tree: its name, the mesh whose normals it authors (an index into
/// the layer's overs), its children.
#[derive(Default)]
struct Over {
    name: String,
    mesh: Option<usize>,
    children: Vec<Over>,
}

impl Over {
    fn at(&mut self, name: &str) -> &mut Over {
        let i = match self.children.iter().position(|c| c.name == name) {
            Some(i) => i,
            None => {
                self.children.push(Over { name: name.to_owned(), ..Over::default() });
                self.children.len() - 1
            }
        };
        &mut self.children[i]
    }

    /// Writes the prim and its children; a mesh's properties are made as they are written
    /// (one mesh's text at a time in memory).
    fn write(
        &self,
        out: &mut impl fmt::Write,
        depth: usize,
        layer: &Layer,
        arrays: Arrays,
    ) -> fmt::Result {
        let pad = "    ".repeat(depth);
        writeln!(out, "{pad}over \"{}\"\n{pad}{{", self.name)?;
        if let Some(k) = self.mesh {
            let over = &layer.overs[k];
            let mut body = over.normals.as_ref().map_or_else(String::new, |normals| {
                normals_text(normals, layer.stage.meshes[over.mesh].plain_normals, arrays)
            });
            if let Some(skin) = &over.skin {
                body.push_str(&skin.text(arrays));
            }
            for line in body.lines() {
                writeln!(out, "{pad}    {line}")?;
            }
        }
        for (k, child) in self.children.iter().enumerate() {
            if k > 0 || self.mesh.is_some() {
                out.write_char('\n')?;
            }
            child.write(out, depth + 1, layer, arrays)?;
        }
        writeln!(out, "{pad}}}")
    }
}

/// Whether a document's arrays are written out, or left empty (`[]`) for their values to be
/// put in afterwards ([`Layer::data`]).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Arrays {
    Written,
    Empty,
}

/// Writes the layer's text to `out`.
fn document(
    out: &mut impl fmt::Write,
    sublayer: &str,
    layer: &Layer,
    arrays: Arrays,
) -> fmt::Result {
    out.write_str("#usda 1.0\n(\n")?;
    for (key, value) in &layer.stage.metadata {
        writeln!(out, "    {key} = {value}")?;
    }
    writeln!(out, "    subLayers = [\n        @{sublayer}@\n    ]\n)\n")?;
    let mut root = Over::default();
    for (k, over) in layer.overs.iter().enumerate() {
        let mut node = &mut root;
        for name in over.prim.split('/').filter(|n| !n.is_empty()) {
            node = node.at(name);
        }
        node.mesh = Some(k);
    }
    for (k, prim) in root.children.iter().enumerate() {
        if k > 0 {
            out.write_char('\n')?;
        }
        prim.write(out, 0, layer, arrays)?;
    }
    Ok(())
}

/// [`fmt::Write`] onto an [`io::Write`], keeping the I/O error that stopped it.
struct IoText<'w> {
    out: &'w mut dyn io::Write,
    error: Option<io::Error>,
}

impl fmt::Write for IoText<'_> {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        self.out.write_all(s.as_bytes()).map_err(|e| {
            self.error = Some(e);
            fmt::Error
        })
    }
}

/// `indices` as an `int[]`'s values.
fn ints<T: Copy + TryInto<i32>>(indices: &[T]) -> anyhow::Result<Vec<i32>> {
    indices
        .iter()
        .map(|&i| i.try_into().map_err(|_| anyhow::anyhow!("an index past the range of int")))
        .collect()
}

/// The prim path of an over written at `prim` (the names between its slashes, as
/// [`document`] nests them).
fn prim_path(prim: &str) -> String {
    prim.split('/').filter(|n| !n.is_empty()).fold(String::new(), |path, name| path + "/" + name)
}

/// The properties of one mesh's override.
fn normals_text(normals: &CornerNormals, block_plain: bool, arrays: Arrays) -> String {
    // Left empty, the values are put in by `Layer::data`.
    let (values, indices) = match arrays {
        Arrays::Written => (&normals.values[..], &normals.indices[..]),
        Arrays::Empty => (&[][..], &[][..]),
    };
    let mut out = String::from("normal3f[] primvars:normals = [");
    push_list(&mut out, values, |s, v| {
        let _ = write!(s, "({}, {}, {})", v.x, v.y, v.z);
    });
    out.push_str("] (\n    interpolation = \"faceVarying\"\n)\nint[] primvars:normals:indices = [");
    push_list(&mut out, indices, |s, &i| s.push_str(itoa::Buffer::new().format(i)));
    out.push_str("]\n");
    if block_plain {
        out.push_str("normal3f[] normals = None\n");
    }
    out
}

/// Items written per parallel task by [`push_list`].
const LIST_CHUNK: usize = 1 << 14;

/// Appends `items` to `out`, each as `write` puts it, separated by `", "`: chunks of them are
/// written side by side and appended in order, the same text as one pass. (The 1M-triangle
/// teapot's override layer is 40 MB of numbers: their formatting was most of writing it.)
fn push_list<T: Sync>(out: &mut String, items: &[T], write: impl Fn(&mut String, &T) + Sync) {
    let chunks: Vec<String> = items
        .par_chunks(LIST_CHUNK)
        .map(|chunk| {
            let mut text = String::new();
            for (k, item) in chunk.iter().enumerate() {
                if k > 0 {
                    text.push_str(", ");
                }
                write(&mut text, item);
            }
            text
        })
        .collect();
    for (k, chunk) in chunks.iter().enumerate() {
        if k > 0 {
            out.push_str(", ");
        }
        out.push_str(chunk);
    }
}

/// `input` as an asset path relative to the folder of `output` (`./` first; `/` between
/// parts), or absolute where no relative path exists (another drive).
fn relative(input: &Path, output: &Path) -> String {
    let absolute = |p: &Path| -> PathBuf {
        let folder = p.parent().filter(|f| !f.as_os_str().is_empty()).unwrap_or(Path::new("."));
        let folder = folder.canonicalize().unwrap_or_else(|_| folder.to_path_buf());
        folder.join(p.file_name().unwrap_or_default())
    };
    let (input, output) = (absolute(input), absolute(output));
    let from: Vec<Component<'_>> =
        output.parent().map(|p| p.components().collect()).unwrap_or_default();
    let to: Vec<Component<'_>> = input.components().collect();
    let common = from.iter().zip(&to).take_while(|(a, b)| a == b).count();
    if common == 0 {
        return input.display().to_string().replace('\\', "/");
    }
    let up = from.len() - common;
    let mut parts: Vec<String> = if up == 0 { vec![".".to_owned()] } else { Vec::new() };
    parts.extend(std::iter::repeat_n("..".to_owned(), up));
    parts.extend(to[common..].iter().map(|c| c.as_os_str().to_string_lossy().into_owned()));
    parts.join("/")
}

/// A skinned mesh's influences as the layer authors them (UsdSkelBindingAPI): its joint
/// indices and weights per point, and its `skel:joints` where it had to grow.
struct SkinOver {
    /// The mesh's `skel:joints`, where joints were added to it.
    joints: Option<Vec<String>>,
    element_size: usize,
    indices: Vec<u32>,
    weights: Vec<f32>,
}

impl SkinOver {
    /// The override's properties: vertex interpolation, `elementSize` per point.
    fn text(&self, arrays: Arrays) -> String {
        let mut out = String::new();
        if let Some(joints) = &self.joints {
            out.push_str("uniform token[] skel:joints = [");
            for (k, joint) in joints.iter().enumerate() {
                let sep = if k == 0 { "" } else { ", " };
                let quoted = joint.replace('\\', "\\\\").replace('"', "\\\"");
                let _ = write!(out, "{sep}\"{quoted}\"");
            }
            out.push_str("]\n");
        }
        let layout = format!(
            "] (\n    elementSize = {}\n    interpolation = \"vertex\"\n)\n",
            self.element_size
        );
        let (indices, weights) = match arrays {
            Arrays::Written => (&self.indices[..], &self.weights[..]),
            Arrays::Empty => (&[][..], &[][..]),
        };
        out.push_str("int[] primvars:skel:jointIndices = [");
        push_list(&mut out, indices, |s, &i| s.push_str(itoa::Buffer::new().format(i)));
        out.push_str(&layout);
        out.push_str("float[] primvars:skel:jointWeights = [");
        push_list(&mut out, weights, |s, w| {
            let _ = write!(s, "{w}");
        });
        out.push_str(&layout);
        out
    }
}

/// The skinned `object`'s influences in its mesh's terms, where some point's differ from what
/// was read: per point, the influences of its first input vertex (every vertex of a point
/// has the same after matching), else as read; joints the mesh's order lacks appended to its
/// `skel:joints`. `None`, with a warning, where they cannot be written: a joint of another
/// skeleton, a mesh that uses its skeleton's order and names a joint outside it, a mesh
/// inside an instance.
fn skin_over(
    object: &Object,
    mesh: &MeshSource,
    skin: &SkinSource,
    joints: &[(String, String)],
    path: &Path,
    warnings: &mut Vec<String>,
) -> Option<SkinOver> {
    let warn = |warnings: &mut Vec<String>, why: &str| {
        warnings.push(format!(
            "{}: mesh <{}>: its matched skin influences are not written ({why})",
            path.display(),
            mesh.prim
        ));
    };
    if mesh.instance_proxy {
        warn(warnings, "it is inside an instance, whose prims a layer cannot override one by one");
        return None;
    }
    let mut order = skin.influences.joints.clone();
    let mut per_point: Vec<Option<Vec<(u32, f32)>>> = vec![None; skin.points];
    let mut changed = false;
    for (v, &p) in skin.vertex_point.iter().enumerate() {
        let slot = &mut per_point[p as usize];
        if slot.is_some() {
            continue;
        }
        let now: Vec<(u32, f32)> = object
            .skin
            .iter()
            .flat_map(|set| set.joints[v].into_iter().zip(set.weights[v]))
            .collect();
        let read = read_lanes(skin, p as usize);
        if same_influences(&now, &read, skin) {
            *slot = Some(read);
            continue;
        }
        changed = true;
        match local_lanes(now, &mut order, skin, joints) {
            Ok(lanes) => *slot = Some(lanes),
            Err(why) => {
                warn(warnings, &why);
                return None;
            }
        }
    }
    changed.then(|| SkinOver::from_points(per_point, &order, skin, joints))
}

/// Whether the influences `now` (joint ids and weights, after matching) are the point's
/// influences as `read` (in the mesh's order), bit for bit, but for trailing zero weights.
fn same_influences(now: &[(u32, f32)], read: &[(u32, f32)], skin: &SkinSource) -> bool {
    now.len() >= read.len()
        && now.iter().zip(read).all(|(a, b)| {
            a.0 == skin.influences.joints[b.0 as usize] && a.1.to_bits() == b.1.to_bits()
        })
        && now[read.len()..].iter().all(|&(_, w)| w == 0.0)
}

/// The influences `now` (joint ids) with a nonzero weight, as indices into the mesh's joint
/// `order`, which grows by the joints it lacks where the mesh has an order of its own; `Err`
/// with the reason where a joint cannot be named.
fn local_lanes(
    now: Vec<(u32, f32)>,
    order: &mut Vec<u32>,
    skin: &SkinSource,
    joints: &[(String, String)],
) -> Result<Vec<(u32, f32)>, String> {
    let mut lanes = Vec::new();
    for (joint, weight) in now.into_iter().filter(|&(_, w)| w > 0.0) {
        let local = match order.iter().position(|&j| j == joint) {
            Some(k) => k,
            None => {
                let (skeleton, name) = &joints[joint as usize];
                if !skin.influences.own_order || *skeleton != skin.influences.skeleton {
                    return Err(format!(
                        "joint {name:?} of <{skeleton}> is not one its skeleton <{}> lets it name",
                        skin.influences.skeleton
                    ));
                }
                order.push(joint);
                order.len() - 1
            }
        };
        #[expect(clippy::cast_possible_truncation, reason = "joints are far fewer than u32::MAX")]
        lanes.push((local as u32, weight));
    }
    Ok(lanes)
}

impl SkinOver {
    /// The override of every point: its matched influences where `per_point` has them, else
    /// as read, `elementSize` lanes each (the largest needed), and the grown joint `order`
    /// where it grew.
    fn from_points(
        per_point: Vec<Option<Vec<(u32, f32)>>>,
        order: &[u32],
        skin: &SkinSource,
        joints: &[(String, String)],
    ) -> Self {
        let element_size = per_point
            .iter()
            .flatten()
            .map(Vec::len)
            .max()
            .unwrap_or(0)
            .max(skin.influences.element_size);
        let mut out = Self {
            joints: (order.len() > skin.influences.joints.len())
                .then(|| order.iter().map(|&j| joints[j as usize].1.clone()).collect()),
            element_size,
            indices: Vec::with_capacity(skin.points * element_size),
            weights: Vec::with_capacity(skin.points * element_size),
        };
        for (p, lanes) in per_point.into_iter().enumerate() {
            let lanes = lanes.unwrap_or_else(|| read_lanes(skin, p));
            for k in 0..element_size {
                let (i, w) = lanes.get(k).copied().unwrap_or((0, 0.0));
                out.indices.push(i);
                out.weights.push(w);
            }
        }
        out
    }
}

/// Point `p`'s influences as read: (index into the mesh's joints, weight).
fn read_lanes(skin: &SkinSource, p: usize) -> Vec<(u32, f32)> {
    skin.influences.of_point(p).collect()
}
