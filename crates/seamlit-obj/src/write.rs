//! Wavefront OBJ (+ MTL) out: the generic writer, for assets that did not come from OBJ or
//! whose model no longer lines up with the OBJ it came from (an OBJ that does goes through
//! `passthrough.rs`, which keeps the input file). No tangents are written: OBJ has no statement
//! for them.
//!
//! Each object becomes an `o` block with its `usemtl`, `v`, `vt` and `vn` lines and faces
//! `f v/vt/vn`; vertex colours go on the `v` lines (`v x y z r g b`, and `a` where it is not
//! 1). OBJ has no transforms: positions (and normals) are moved into model space.
//! Smoothing groups go out as `s N` / `s off` wherever the group changes; where some objects
//! have groups, those without get one number of their own (one above the largest used), which
//! is what `None` means.
//! Numbers are written with Rust's shortest round-trip formatting, so reading the file back
//! gives the same bits. Texture coordinates are flipped (`v' = 1 - v`) when the model's V runs
//! down (glTF), since OBJ's runs up. Materials go to `NAME.mtl` and the textures they use are
//! written beside it.

use std::collections::HashSet;
use std::fmt::Write as _;
use std::path::Path;

use glam::{Mat3, Mat4};
use seamlit_mesh::VAxis;

use seamlit_asset::files::Destination;
use seamlit_asset::{Asset, IoError, Material, TextureRef};

/// The `s` statement in force while faces are written, and the group of objects without
/// groups.
struct SmoothingState {
    /// `None` before the first `s` (and for files without groups).
    current: Option<u32>,
    /// The number written for objects without groups; `None` where no object has groups.
    ungrouped: Option<u32>,
}

impl SmoothingState {
    fn new<'a>(objects: impl IntoIterator<Item = &'a seamlit_mesh::Object>) -> Self {
        let mut any = false;
        let mut largest = 0;
        for groups in objects.into_iter().filter_map(|o| o.smoothing_groups.as_ref()) {
            any = true;
            largest = groups.iter().copied().fold(largest, u32::max);
        }
        Self { current: None, ungrouped: any.then(|| largest.saturating_add(1)) }
    }

    /// Writes an `s` line before triangle `t` of `object` where its group differs from the
    /// one in force.
    fn write(&mut self, out: &mut String, object: &seamlit_mesh::Object, t: usize) {
        let Some(ungrouped) = self.ungrouped else { return };
        let group = object.smoothing_groups.as_ref().map_or(ungrouped, |g| g[t]);
        if self.current != Some(group) {
            self.current = Some(group);
            let _ = match group {
                0 => writeln!(out, "s off"),
                g => writeln!(out, "s {g}"),
            };
        }
    }
}

/// Writes `asset` as OBJ at `path`, with `STEM.mtl` and the textures beside it, to `to`.
pub(crate) fn save(asset: &Asset, path: &Path, to: &mut Destination) -> Result<(), IoError> {
    for object in &asset.model.objects {
        seamlit_asset::check::check_object(object, path)?;
    }
    let stem =
        path.file_stem().map_or_else(|| "model".to_owned(), |s| s.to_string_lossy().into_owned());
    let names = MaterialNames::new(asset);
    let mut mtl = MtlWriter {
        mtl: String::new(),
        asset,
        path,
        stem: &stem,
        texture_files: vec![None; asset.textures.len()],
        side_files: Vec::new(),
    };
    if !asset.materials.is_empty() {
        // The model's materials, then the default for parts that have none (if any do).
        let default = names.needs_default.then(Material::default);
        let all = names.names.iter().chain(default.iter().map(|_| &names.default));
        for (m, name) in asset.materials.iter().chain(&default).zip(all) {
            mtl.material(name, m)?;
        }
    }
    let obj = write_obj(asset, (!mtl.mtl.is_empty()).then_some(&names), &stem);
    let folder = path.parent().unwrap_or(Path::new(""));
    for (name, bytes) in &mtl.side_files {
        to.write(&folder.join(name), bytes)?;
    }
    if !mtl.mtl.is_empty() {
        to.write(&folder.join(format!("{stem}.mtl")), mtl.mtl.as_bytes())?;
    }
    to.write(path, obj.as_bytes())
}

/// A name on one line: line ends become spaces, the ends are trimmed.
fn one_line(s: &str) -> String {
    s.replace(['\n', '\r'], " ").trim().to_owned()
}

/// The materials' names in the `.mtl`: unique, non-empty, one line; plus a default for
/// objects without one when others have one (OBJ's `usemtl` would otherwise carry over).
struct MaterialNames {
    names: Vec<String>,
    default: String,
    needs_default: bool,
    /// How many materials the asset has (an object's index past them names none).
    count: usize,
}

impl MaterialNames {
    fn new(asset: &Asset) -> Self {
        let mut taken = HashSet::new();
        let mut names: Vec<String> = Vec::with_capacity(asset.materials.len());
        for (i, m) in asset.materials.iter().enumerate() {
            let mut name = one_line(&m.name);
            if name.is_empty() {
                name = format!("material{i}");
            }
            while !taken.insert(name.clone()) {
                name.push_str(&format!("_{i}"));
            }
            names.push(name);
        }
        let mut default = "seamlit_default".to_owned();
        while taken.contains(&default) {
            default.push('_');
        }
        let mut names = Self { names, default, needs_default: false, count: asset.materials.len() };
        let objects = &asset.model.objects;
        names.needs_default = objects.iter().any(|o| names.valid(o).is_some())
            && objects.iter().any(|o| names.valid(o).is_none());
        names
    }

    /// The object's material, if it names one of the asset's.
    fn valid(&self, object: &seamlit_mesh::Object) -> Option<usize> {
        object.material.filter(|&m| m < self.count)
    }

    /// The `usemtl` name for `object`, where one is written.
    fn usemtl(&self, object: &seamlit_mesh::Object) -> Option<&str> {
        match self.valid(object) {
            Some(m) => Some(&self.names[m]),
            None => self.needs_default.then_some(self.default.as_str()),
        }
    }
}

/// The OBJ text of `asset`: `mtllib` and `usemtl` lines where `names` is given.
fn write_obj(asset: &Asset, names: Option<&MaterialNames>, stem: &str) -> String {
    let model = &asset.model;
    let mut out = String::with_capacity(model.triangle_count() * 40 + model.vertex_count() * 60);
    out.push_str("# written by seamlit\n");
    if names.is_some() {
        let _ = writeln!(out, "mtllib {stem}.mtl");
    }
    let mut bases = [1usize; 3];
    let mut smoothing = SmoothingState::new(&model.objects);
    for object in &model.objects {
        let name = one_line(&object.name);
        let _ = writeln!(out, "o {}", if name.is_empty() { "object" } else { &name });
        if let Some(material) = names.and_then(|names| names.usemtl(object)) {
            let _ = writeln!(out, "usemtl {material}");
        }
        write_elements(&mut out, object, model.v_axis);
        write_faces(&mut out, object, bases, &mut smoothing);
        let n = object.positions.len();
        bases[0] += n;
        bases[1] += if object.uvs.is_some() { n } else { 0 };
        bases[2] += if object.normals.is_some() { n } else { 0 };
    }
    out
}

/// An object's `v` (with colours), `vt` and `vn` lines, in model space.
fn write_elements(out: &mut String, object: &seamlit_mesh::Object, v_axis: VAxis) {
    let transform = object.transform.filter(|&m| m != Mat4::IDENTITY);
    for (i, &p) in object.positions.iter().enumerate() {
        let p = transform.map_or(p, |m| m.transform_point3(p));
        let _ = write!(out, "v {} {} {}", p.x, p.y, p.z);
        if let Some(c) = object.colors.as_ref().map(|colors| colors[i]) {
            let _ = write!(out, " {} {} {}", c.x, c.y, c.z);
            if c.w != 1.0 {
                let _ = write!(out, " {}", c.w);
            }
        }
        out.push('\n');
    }
    if let Some(uvs) = &object.uvs {
        for t in uvs {
            let v = match v_axis {
                VAxis::Up => t.y,
                VAxis::Down => 1.0 - t.y,
            };
            let _ = writeln!(out, "vt {} {}", t.x, v);
        }
    }
    if let Some(normals) = &object.normals {
        let normal_matrix = transform.map(|m| Mat3::from_mat4(m).inverse().transpose());
        for &n in normals {
            let n = normal_matrix.map_or(n, |m| (m * n).normalize_or_zero());
            let _ = writeln!(out, "vn {} {} {}", n.x, n.y, n.z);
        }
    }
}

/// An object's `f` lines (and `s` lines where the group changes); `bases` are the file's
/// one-based indices of its first `v`, `vt` and `vn`.
fn write_faces(
    out: &mut String,
    object: &seamlit_mesh::Object,
    bases: [usize; 3],
    smoothing: &mut SmoothingState,
) {
    let [v_base, vt_base, vn_base] = bases;
    let (has_vt, has_vn) = (object.uvs.is_some(), object.normals.is_some());
    for (k, t) in object.triangles.iter().enumerate() {
        smoothing.write(out, object, k);
        out.push('f');
        for &i in t {
            let i = i as usize;
            let _ = match (has_vt, has_vn) {
                (false, false) => write!(out, " {}", v_base + i),
                (true, false) => write!(out, " {}/{}", v_base + i, vt_base + i),
                (false, true) => write!(out, " {}//{}", v_base + i, vn_base + i),
                (true, true) => write!(out, " {}/{}/{}", v_base + i, vt_base + i, vn_base + i),
            };
        }
        out.push('\n');
    }
}

/// The `.mtl` text being written, and the texture files it names.
struct MtlWriter<'a> {
    mtl: String,
    asset: &'a Asset,
    /// The OBJ's path (for errors) and stem (for the textures' file names).
    path: &'a Path,
    stem: &'a str,
    /// Per texture of the asset, its file once written.
    texture_files: Vec<Option<String>>,
    /// Texture files to write beside the OBJ: name and bytes.
    side_files: Vec<(String, Vec<u8>)>,
}

impl MtlWriter<'_> {
    /// Writes material `m` as `newmtl name`, with its textures.
    fn material(&mut self, name: &str, m: &Material) -> Result<(), IoError> {
        let [r, g, b, a] = m.base_color;
        let [sr, sg, sb] = m.specular;
        let _ = writeln!(
            self.mtl,
            "newmtl {name}\nKd {r} {g} {b}\nKs {sr} {sg} {sb}\nNs {}\nd {a}",
            m.shininess
        );
        let options = |r: &TextureRef| {
            r.transform.map_or_else(String::new, |t| {
                format!("-o {} {} -s {} {} ", t.offset[0], t.offset[1], t.scale[0], t.scale[1])
            })
        };
        if let Some(r) = &m.base_color_texture
            && let Some(file) = self.file_of(r)?
        {
            let _ = writeln!(self.mtl, "map_Kd {}{file}", options(r));
        }
        if let Some(r) = &m.normal_texture
            && let Some(file) = self.file_of(r)?
        {
            let bm = if m.normal_scale == 1.0 {
                String::new()
            } else {
                format!("-bm {} ", m.normal_scale)
            };
            let _ = writeln!(self.mtl, "map_Bump {bm}{}{file}", options(r));
        }
        self.mtl.push('\n');
        Ok(())
    }

    /// The file of the texture `r` refers to, written on first use; `None` for a texture
    /// that does not exist or has no image.
    fn file_of(&mut self, r: &TextureRef) -> Result<Option<String>, IoError> {
        let Some(texture) = self.asset.textures.get(r.texture) else { return Ok(None) };
        if let Some(file) = &self.texture_files[r.texture] {
            return Ok(Some(file.clone()));
        }
        let Some((bytes, mime)) = seamlit_asset::texture::encoded(texture, self.path)? else {
            return Ok(None);
        };
        let extension = if mime == "image/png" { "png" } else { "jpg" };
        let base = Path::new(&texture.name)
            .file_stem()
            .map_or_else(|| format!("texture{}", r.texture), |s| s.to_string_lossy().into_owned());
        let base: String = base
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() || c == '_' || c == '-' { c } else { '_' })
            .collect();
        let file = format!("{}_{}_{base}.{extension}", self.stem, r.texture);
        self.side_files.push((file.clone(), bytes));
        self.texture_files[r.texture] = Some(file.clone());
        Ok(Some(file))
    }
}
