//! Materials enough to render: a mesh's `material:binding` (its own, else its nearest
//! ancestor's) names a Material whose `outputs:surface` is a UsdPreviewSurface shader; its
//! `diffuseColor` (a value, or a UsdUVTexture's `file`), `opacity`, `metallic`, `roughness`
//! and `emissiveColor` become a metallic-roughness [`Material`]. A texture is read from the
//! file its asset path resolves to (relative to the layer that authored it), inside the
//! stage's folder or an asset root ([`seamlit_asset::LoadOptions::asset_roots`]), or from inside the
//! `.usdz` package that holds it.

use super::resolver::Reach;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use openusd::ar::Resolver as _;
use openusd::{ar, sdf, usd};

use super::{f32_of, value};
use seamlit_asset::files::Files;
use seamlit_asset::{AlphaMode, Material, Texture, TextureRef, TextureSource};

/// The materials and textures read so far, by prim path and resolved file.
pub(super) struct Materials<'s> {
    stage: &'s usd::Stage,
    file: &'s Path,
    /// Where textures may come from (the stage's reach).
    reach: Reach,
    /// Where the stage's files are read from.
    files: &'s Files,
    pub list: Vec<Material>,
    pub textures: Vec<Texture>,
    by_path: HashMap<String, usize>,
    texture_by_path: HashMap<String, Option<usize>>,
}

impl<'s> Materials<'s> {
    pub(super) fn new(
        stage: &'s usd::Stage,
        file: &'s Path,
        asset_roots: &[PathBuf],
        files: &'s Files,
    ) -> Self {
        Self {
            stage,
            file,
            reach: Reach::of(file, asset_roots),
            files,
            list: Vec::new(),
            textures: Vec::new(),
            by_path: HashMap::new(),
            texture_by_path: HashMap::new(),
        }
    }

    /// The material bound to the prim at `path` (its own binding, else its nearest
    /// ancestor's), read on first use.
    pub(super) fn bound(
        &mut self,
        path: &sdf::Path,
        warnings: &mut Vec<String>,
    ) -> anyhow::Result<Option<usize>> {
        let mut at = Some(path.clone());
        while let Some(p) = at {
            if p.is_abs_root() {
                break;
            }
            let targets = self.stage.prim(p.clone()).relationship("material:binding").targets()?;
            if let Some(target) = targets.first() {
                return self.material(target, warnings).map(Some);
            }
            at = p.parent();
        }
        Ok(None)
    }

    /// The material of each triangle of the mesh at `mesh` (`triangle_faces` its triangles'
    /// faces, of `faces`) by its `materialBind` GeomSubsets (`subsets`, its GeomSubset
    /// children): a face in a subset with a `material:binding` of its own has that material,
    /// other faces the mesh's (`None`). `None` when no face has a material of a subset. A
    /// subset that cannot be used (indices out of range or not an int array, a face in two
    /// subsets, an `elementType` other than `face`, a binding on a subset of another family)
    /// is one warning naming the layer and the mesh; its faces keep the mesh's material (a
    /// face in two subsets the first's).
    pub(super) fn subsets(
        &mut self,
        mesh: &sdf::Path,
        subsets: &[sdf::Path],
        (triangle_faces, faces): (&[u32], usize),
        warnings: &mut Vec<String>,
    ) -> anyhow::Result<Option<Vec<Option<usize>>>> {
        let mut face_material: Vec<Option<usize>> = vec![None; faces];
        let mut problems: Vec<String> = Vec::new();
        for subset in subsets {
            let token = |name: &str| -> anyhow::Result<Option<String>> {
                Ok(match value(&self.stage.attribute(subset.append_property(name)?))? {
                    Some(sdf::Value::Token(t)) => Some(t.as_str().to_owned()),
                    Some(sdf::Value::String(s)) => Some(s),
                    _ => None,
                })
            };
            let name = subset.name().unwrap_or_default().to_owned();
            let family = token("familyName")?.unwrap_or_default();
            let binding = self.stage.prim(subset.clone()).relationship("material:binding");
            let Some(target) = binding.targets()?.first().cloned() else { continue };
            if family != "materialBind" {
                problems.push(format!(
                    "{name} binds a material but its family is {family:?}, not \"materialBind\""
                ));
                continue;
            }
            let element = token("elementType")?.unwrap_or_else(|| "face".to_owned());
            if element != "face" {
                problems.push(format!("{name} has elementType {element:?}, not \"face\""));
                continue;
            }
            let indices = match value(&self.stage.attribute(subset.append_property("indices")?))? {
                Some(sdf::Value::IntVec(v)) => v,
                None => Vec::new(),
                Some(_) => {
                    problems.push(format!("{name}'s indices are not an int array"));
                    continue;
                }
            };
            let material = self.material(&target, warnings)?;
            let (mut outside, mut overlapping) = (0usize, 0usize);
            for &index in &indices {
                match usize::try_from(index).ok().and_then(|f| face_material.get_mut(f)) {
                    None => outside += 1,
                    Some(Some(_)) => overlapping += 1,
                    Some(slot) => *slot = Some(material),
                }
            }
            if outside > 0 {
                problems
                    .push(format!("{name} has {outside} indices outside the mesh's {faces} faces"));
            }
            if overlapping > 0 {
                let faces = if overlapping == 1 { "face" } else { "faces" };
                problems
                    .push(format!("{name} has {overlapping} {faces} that an earlier subset holds"));
            }
        }
        if !problems.is_empty() {
            warnings.push(format!(
                "{}: mesh <{}>: GeomSubsets not used as bound: {}; those faces are drawn with the mesh's material (a face in two subsets with the first's)",
                self.file.display(),
                mesh.as_str(),
                problems.join("; ")
            ));
        }
        if face_material.iter().all(Option::is_none) {
            return Ok(None);
        }
        let triangles = triangle_faces
            .iter()
            .map(|&f| face_material.get(f as usize).copied().flatten())
            .collect();
        Ok(Some(triangles))
    }

    fn material(&mut self, path: &sdf::Path, warnings: &mut Vec<String>) -> anyhow::Result<usize> {
        if let Some(&i) = self.by_path.get(path.as_str()) {
            return Ok(i);
        }
        let name = path.name().unwrap_or_default().to_owned();
        let mut material = Material { name, ..Material::default() };
        if let Some(shader) = self.source(&path.append_property("outputs:surface")?)? {
            if self.shader_id(&shader)?.as_deref() == Some("UsdPreviewSurface") {
                self.preview_surface(&shader, &mut material, warnings)?;
            } else {
                warnings.push(format!(
                    "{}: material <{}>: its surface is not a UsdPreviewSurface; drawn with a default material",
                    self.file.display(),
                    path.as_str()
                ));
            }
        }
        self.list.push(material);
        let i = self.list.len() - 1;
        self.by_path.insert(path.as_str().to_owned(), i);
        Ok(i)
    }

    fn preview_surface(
        &mut self,
        shader: &sdf::Path,
        material: &mut Material,
        warnings: &mut Vec<String>,
    ) -> anyhow::Result<()> {
        let input = |name: &str| shader.append_property(format!("inputs:{name}"));
        let number = |name: &str, default: f32| -> anyhow::Result<f32> {
            Ok(match value(&self.stage.attribute(input(name)?))? {
                Some(sdf::Value::Float(f)) => f,
                Some(sdf::Value::Double(d)) => f32_of(d),
                _ => default,
            })
        };
        let metallic = number("metallic", 0.0)?.clamp(0.0, 1.0);
        let roughness = number("roughness", 0.5)?.clamp(0.0, 1.0);
        let opacity = number("opacity", 1.0)?.clamp(0.0, 1.0);
        let diffuse = input("diffuseColor")?;
        let mut base = color(value(&self.stage.attribute(diffuse.clone()))?, [0.18; 3]);
        if let Some(texture) = self.source(&diffuse)?
            && self.shader_id(&texture)?.as_deref() == Some("UsdUVTexture")
        {
            material.base_color_texture = self.texture(&texture, warnings)?;
            if material.base_color_texture.is_some() {
                base = [1.0; 3];
            }
        }
        let emissive = color(value(&self.stage.attribute(input("emissiveColor")?))?, [0.0; 3]);
        material.base_color = [base[0], base[1], base[2], opacity];
        material.metallic = metallic;
        material.roughness = roughness;
        material.specular = std::array::from_fn(|i| 0.04 + (base[i] - 0.04) * metallic);
        material.shininess = seamlit_asset::roughness_to_shininess(roughness);
        material.emissive = emissive;
        material.alpha_mode = if opacity < 1.0 { AlphaMode::Blend } else { AlphaMode::Opaque };
        Ok(())
    }

    /// The prim an attribute is connected to, if it is.
    fn source(&self, attribute: &sdf::Path) -> anyhow::Result<Option<sdf::Path>> {
        let connections = self.stage.attribute(attribute.clone()).connections()?;
        Ok(connections.first().map(sdf::Path::prim_path))
    }

    fn shader_id(&self, shader: &sdf::Path) -> anyhow::Result<Option<String>> {
        Ok(match value(&self.stage.attribute(shader.append_property("info:id")?))? {
            Some(sdf::Value::Token(t)) => Some(t.as_str().to_owned()),
            Some(sdf::Value::String(s)) => Some(s),
            _ => None,
        })
    }

    /// A UsdUVTexture's image, read on first use.
    fn texture(
        &mut self,
        shader: &sdf::Path,
        warnings: &mut Vec<String>,
    ) -> anyhow::Result<Option<TextureRef>> {
        let Some(sdf::Value::AssetPath(asset)) =
            value(&self.stage.attribute(shader.append_property("inputs:file")?))?
        else {
            return Ok(None);
        };
        let written = asset.asset_path().to_owned();
        let resolved = asset.resolved_path().map(str::to_owned);
        let key = resolved.clone().unwrap_or_else(|| written.clone());
        if let Some(&index) = self.texture_by_path.get(&key) {
            return Ok(index.map(|texture| TextureRef { texture, tex_coord: 0, transform: None }));
        }
        let name = written.rsplit(['/', '\\']).next().unwrap_or(&written).to_owned();
        let source = match &resolved {
            None => {
                warnings.push(format!(
                    "{}: texture @{written}@ (shader <{}>) is not found; using a neutral default",
                    self.file.display(),
                    shader.as_str()
                ));
                None
            }
            Some(resolved) if ar::is_package_relative_path(resolved) => {
                let bytes = match self.files {
                    Files::Disk => ar::DefaultResolver::new()
                        .open_asset(&ar::ResolvedPath::new(resolved.as_str()))
                        .and_then(|mut asset| asset.read_all()),
                    Files::Memory(_) => super::memory::read_resolved(self.files, resolved),
                };
                match bytes {
                    Ok(bytes) => {
                        let mime = if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
                            "image/jpeg"
                        } else {
                            "image/png"
                        };
                        let bytes = bytes.into();
                        Some(TextureSource::Embedded { mime_type: mime.to_owned(), bytes })
                    }
                    Err(e) => {
                        warnings.push(format!(
                            "{}: texture @{written}@ in the package cannot be read: {e}; using a neutral default",
                            self.file.display()
                        ));
                        None
                    }
                }
            }
            // In memory the resolver found it in the set: there are no links to follow.
            Some(resolved) if matches!(self.files, Files::Memory(_)) => {
                Some(TextureSource::File(PathBuf::from(resolved)))
            }
            Some(resolved) => match inside(&self.reach, Path::new(resolved)) {
                Ok(file) => Some(TextureSource::File(file)),
                Err(why) => {
                    warnings.push(format!(
                        "{}: texture @{written}@ is not used: {why}",
                        self.file.display()
                    ));
                    None
                }
            },
        };
        let index = source.map(|source| {
            self.textures.push(Texture { name, source, image: None });
            self.textures.len() - 1
        });
        self.texture_by_path.insert(key, index);
        Ok(index.map(|texture| TextureRef { texture, tex_coord: 0, transform: None }))
    }
}

/// `file` when it is a regular file within `reach` (by its canonical path), or when it is
/// missing (the texture decoder then warns that it is); otherwise why it is not used.
fn inside(reach: &Reach, file: &Path) -> Result<PathBuf, &'static str> {
    if !file.exists() {
        return Ok(file.to_path_buf());
    }
    let real = file.canonicalize().map_err(|_| "its path cannot be followed")?;
    if !reach.admits(&real) {
        return Err("it lies outside the stage's folder and the --asset-root folders");
    }
    if !real.is_file() {
        return Err("it is not a regular file");
    }
    Ok(real)
}

/// A `color3f` value, `default` where there is none.
fn color(value: Option<sdf::Value>, default: [f32; 3]) -> [f32; 3] {
    match value {
        Some(sdf::Value::Vec3f(c)) => [c.x, c.y, c.z],
        Some(sdf::Value::Vec3d(c)) => [f32_of(c.x), f32_of(c.y), f32_of(c.z)],
        _ => default,
    }
}
