//! Wavefront OBJ (+ MTL) out: the generic writer, for assets that did not come from OBJ or
//! whose model no longer lines up with the OBJ it came from (an OBJ that does goes through
//! `obj_pass`, which keeps the input file). No tangents are written: OBJ has no statement
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

use crate::{Asset, IoError, Material, TextureRef};

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

/// Writes `asset` as OBJ at `path`, with `STEM.mtl` and the textures beside it.
pub(crate) fn save(asset: &Asset, path: &Path) -> Result<(), IoError> {
    for object in &asset.model.objects {
        crate::gltf_write::check_object(object, path)?;
    }
    let folder = path.parent().unwrap_or(Path::new(""));
    let stem =
        path.file_stem().map_or_else(|| "model".to_owned(), |s| s.to_string_lossy().into_owned());
    let one_line = |s: &str| s.replace(['\n', '\r'], " ").trim().to_owned();

    // Material names: unique, non-empty, one line; plus a default for objects without one
    // when others have one (OBJ's `usemtl` would otherwise carry over).
    let mut taken = HashSet::new();
    let mut material_names: Vec<String> = Vec::with_capacity(asset.materials.len());
    for (i, m) in asset.materials.iter().enumerate() {
        let mut name = one_line(&m.name);
        if name.is_empty() {
            name = format!("material{i}");
        }
        while !taken.insert(name.clone()) {
            name.push_str(&format!("_{i}"));
        }
        material_names.push(name);
    }
    let objects = &asset.model.objects;
    let valid_material =
        |o: &seamlit_mesh::Object| o.material.filter(|&m| m < asset.materials.len());
    let needs_default = objects.iter().any(|o| valid_material(o).is_some())
        && objects.iter().any(|o| valid_material(o).is_none());
    let default_name = {
        let mut name = "seamlit_default".to_owned();
        while taken.contains(&name) {
            name.push('_');
        }
        name
    };

    let mut mtl = String::new();
    let mut side_files: Vec<(String, Vec<u8>)> = Vec::new();
    let mut texture_files: Vec<Option<String>> = vec![None; asset.textures.len()];
    if !asset.materials.is_empty() {
        // The model's materials, then the default for parts that have none (if any do).
        let default = needs_default.then(Material::default);
        let names = material_names.iter().chain(default.iter().map(|_| &default_name));
        for (m, name) in asset.materials.iter().chain(&default).zip(names) {
            write_material(
                &mut mtl,
                name,
                m,
                asset,
                path,
                &stem,
                &mut texture_files,
                &mut side_files,
            )?;
        }
    }

    let mut out =
        String::with_capacity(asset.model.triangle_count() * 40 + asset.model.vertex_count() * 60);
    out.push_str("# written by seamlit\n");
    if !mtl.is_empty() {
        let _ = writeln!(out, "mtllib {stem}.mtl");
    }
    let (mut v_base, mut vt_base, mut vn_base) = (1usize, 1usize, 1usize);
    let mut smoothing = SmoothingState::new(objects);
    for object in objects {
        let name = one_line(&object.name);
        let _ = writeln!(out, "o {}", if name.is_empty() { "object" } else { &name });
        if !mtl.is_empty() {
            let material = valid_material(object)
                .map_or(default_name.as_str(), |m| material_names[m].as_str());
            if valid_material(object).is_some() || needs_default {
                let _ = writeln!(out, "usemtl {material}");
            }
        }
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
                let v = match asset.model.v_axis {
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
        let (has_vt, has_vn) = (object.uvs.is_some(), object.normals.is_some());
        for (k, t) in object.triangles.iter().enumerate() {
            smoothing.write(&mut out, object, k);
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
        let n = object.positions.len();
        v_base += n;
        vt_base += if has_vt { n } else { 0 };
        vn_base += if has_vn { n } else { 0 };
    }

    for (name, bytes) in &side_files {
        crate::atomic::write(&folder.join(name), bytes)?;
    }
    if !mtl.is_empty() {
        crate::atomic::write(&folder.join(format!("{stem}.mtl")), mtl.as_bytes())?;
    }
    crate::atomic::write(path, out.as_bytes())
}

#[expect(clippy::too_many_arguments, reason = "one call site; the state is the writer's")]
fn write_material(
    mtl: &mut String,
    name: &str,
    m: &Material,
    asset: &Asset,
    path: &Path,
    stem: &str,
    texture_files: &mut [Option<String>],
    side_files: &mut Vec<(String, Vec<u8>)>,
) -> Result<(), IoError> {
    let [r, g, b, a] = m.base_color;
    let [sr, sg, sb] = m.specular;
    let _ = writeln!(
        mtl,
        "newmtl {name}\nKd {r} {g} {b}\nKs {sr} {sg} {sb}\nNs {}\nd {a}",
        m.shininess
    );
    let mut file_of = |r: &TextureRef| -> Result<Option<String>, IoError> {
        let Some(texture) = asset.textures.get(r.texture) else { return Ok(None) };
        if let Some(file) = &texture_files[r.texture] {
            return Ok(Some(file.clone()));
        }
        let Some((bytes, mime)) = crate::gltf_write::encoded(texture, path)? else {
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
        let file = format!("{stem}_{}_{base}.{extension}", r.texture);
        side_files.push((file.clone(), bytes));
        texture_files[r.texture] = Some(file.clone());
        Ok(Some(file))
    };
    let options = |r: &TextureRef| {
        r.transform.map_or_else(String::new, |t| {
            format!("-o {} {} -s {} {} ", t.offset[0], t.offset[1], t.scale[0], t.scale[1])
        })
    };
    if let Some(r) = &m.base_color_texture
        && let Some(file) = file_of(r)?
    {
        let _ = writeln!(mtl, "map_Kd {}{file}", options(r));
    }
    if let Some(r) = &m.normal_texture
        && let Some(file) = file_of(r)?
    {
        let bm =
            if m.normal_scale == 1.0 { String::new() } else { format!("-bm {} ", m.normal_scale) };
        let _ = writeln!(mtl, "map_Bump {bm}{}{file}", options(r));
    }
    mtl.push('\n');
    Ok(())
}
