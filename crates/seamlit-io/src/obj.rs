//! Wavefront OBJ (+ MTL) in, through tobj.
//!
//! Every `o` and `g` statement starts an object, keeping its name (tobj also starts one where
//! `usemtl` changes the material inside an object: both parts keep the name). Faces are
//! triangulated as fans; `vt` and `vn` are kept where every face of the object has them.
//! Material libraries are read with tobj and converted here, including the `-bm` (bump
//! multiplier), `-o` and `-s` options that tobj leaves in the texture name, and the `norm`
//! statement it does not know. Texture paths resolve against the `.mtl` file's folder.
//!
//! tobj reports errors without a line number; when it fails, a short diagnostic pass over the
//! text finds the line and says what is wrong there.

use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use seamlit_mesh::{Model, Object, VAxis};

use crate::{
    Asset, IoError, LoadOptions, Material, Texture, TextureRef, TextureSource, UvTransform,
};

/// A material library that could not be read: (referenced name, resolved path, error).
type MtlFailure = (String, PathBuf, MtlProblem);

#[derive(Debug)]
enum MtlProblem {
    Missing,
    Unreadable(std::io::Error),
    Syntax { line: usize, reason: String },
}

/// Reads an OBJ file and the material libraries and textures it refers to.
///
/// # Errors
///
/// [`IoError::Io`] / [`IoError::TooLarge`] for the file itself; [`IoError::Syntax`],
/// [`IoError::ReferenceOutOfRange`] and [`IoError::NotFinite`] with the line for a malformed
/// OBJ or MTL; [`IoError::MissingFile`] for a missing `.mtl` or texture when
/// `options.strict` is set (a warning otherwise); [`IoError::TooManyElements`] past
/// `options.max_elements`.
pub fn load(path: &Path, options: &LoadOptions) -> Result<Asset, IoError> {
    let text = crate::read_text(path, options)?;
    let folder = path.parent().unwrap_or(Path::new("")).to_path_buf();
    let failures: RefCell<Vec<MtlFailure>> = RefCell::new(Vec::new());
    // Material libraries, in the order they were read, with the folder their textures
    // resolve against.
    let libraries: RefCell<Vec<(PathBuf, usize)>> = RefCell::new(Vec::new());

    let tobj_options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let loader = |mtl: &Path| -> tobj::MTLLoadResult {
        let resolved = folder.join(mtl);
        let fail = |problem| {
            failures.borrow_mut().push((
                mtl.to_string_lossy().into_owned(),
                resolved.clone(),
                problem,
            ));
            Ok((Vec::new(), Default::default()))
        };
        let mtl_text = match std::fs::read(&resolved) {
            Ok(bytes) => String::from_utf8_lossy(&bytes).into_owned(),
            Err(err) if err.kind() == std::io::ErrorKind::NotFound => {
                return fail(MtlProblem::Missing);
            }
            Err(err) => return fail(MtlProblem::Unreadable(err)),
        };
        match tobj::load_mtl_buf(&mut mtl_text.as_bytes()) {
            Ok((materials, map)) => {
                libraries.borrow_mut().push((
                    resolved.parent().unwrap_or(Path::new("")).to_path_buf(),
                    materials.len(),
                ));
                Ok((materials, map))
            }
            Err(err) => {
                let (line, reason) = locate_mtl_error(&mtl_text).unwrap_or((0, err.to_string()));
                fail(MtlProblem::Syntax { line, reason })
            }
        }
    };
    let loaded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        tobj::load_obj_buf(&mut text.as_bytes(), &tobj_options, loader)
    }));
    let (models, materials) = match loaded {
        Ok(Ok(result)) => result,
        Ok(Err(err)) => {
            return Err(diagnose(path, &text).unwrap_or_else(|| IoError::Obj {
                path: path.to_path_buf(),
                reason: err.to_string(),
            }));
        }
        Err(_) => {
            return Err(diagnose(path, &text).unwrap_or_else(|| IoError::Obj {
                path: path.to_path_buf(),
                reason: "the OBJ reader failed".to_owned(),
            }));
        }
    };
    let materials = materials.unwrap_or_default();

    let mut warnings = Vec::new();
    for (name, resolved, problem) in failures.into_inner() {
        let line = find_statement_line(&text, "mtllib", &name);
        match problem {
            MtlProblem::Missing if options.strict => {
                return Err(IoError::MissingFile {
                    path: path.to_path_buf(),
                    what: "material library".to_owned(),
                    missing: resolved,
                    line,
                });
            }
            MtlProblem::Missing => warnings.push(format!(
                "{}{}: material library {} not found; its materials get defaults",
                path.display(),
                line.map(|l| format!(":{l}")).unwrap_or_default(),
                resolved.display()
            )),
            MtlProblem::Unreadable(source) => return Err(IoError::io(resolved, source)),
            MtlProblem::Syntax { line, reason } => {
                return Err(IoError::Syntax { path: resolved, line, reason });
            }
        }
    }

    let mut objects = Vec::with_capacity(models.len());
    for model in models {
        if let Some(object) = convert_model(model, materials.len(), path, options, &mut warnings)? {
            objects.push(object);
        }
    }
    if let Some(err) = check_finite(&objects, path, &text) {
        return Err(err);
    }

    let mut asset = Asset { model: Model { objects, v_axis: VAxis::Up }, ..Asset::default() };
    let mut texture_index: HashMap<PathBuf, usize> = HashMap::new();
    let libraries = libraries.into_inner();
    let mut library_of =
        libraries.iter().flat_map(|(folder, count)| std::iter::repeat_n(folder, *count));
    for material in &materials {
        let mtl_folder = library_of.next().cloned().unwrap_or_else(|| folder.clone());
        asset.materials.push(convert_material(
            material,
            &mtl_folder,
            &mut asset.textures,
            &mut texture_index,
        ));
    }
    asset.source = Some(path.to_path_buf());
    warnings.extend(crate::texture::decode_all(&mut asset.textures, path, options)?);
    asset.warnings = warnings;
    Ok(asset)
}

fn convert_model(
    model: tobj::Model,
    material_count: usize,
    path: &Path,
    options: &LoadOptions,
    warnings: &mut Vec<String>,
) -> Result<Option<Object>, IoError> {
    let mesh = model.mesh;
    if mesh.indices.len() < 3 {
        return Ok(None);
    }
    let vertex_count = mesh.positions.len() / 3;
    let triangle_count = mesh.indices.len() / 3;
    let too_many = vertex_count.max(triangle_count);
    if too_many > options.max_elements {
        return Err(IoError::TooManyElements {
            path: path.to_path_buf(),
            what: format!("object {:?}", model.name),
            limit: options.max_elements,
            actual: too_many,
        });
    }
    let positions: Vec<Vec3> =
        mesh.positions.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])).collect();
    let uvs = match mesh.texcoords.len() {
        0 => None,
        n if n == vertex_count * 2 => {
            Some(mesh.texcoords.chunks_exact(2).map(|t| Vec2::new(t[0], t[1])).collect())
        }
        _ => {
            warnings.push(format!("{}: object {:?}: some faces have texture coordinates and some do not; texture coordinates dropped", path.display(), model.name));
            None
        }
    };
    let normals = match mesh.normals.len() {
        0 => None,
        n if n == vertex_count * 3 => {
            Some(mesh.normals.chunks_exact(3).map(|n| Vec3::new(n[0], n[1], n[2])).collect())
        }
        _ => {
            warnings.push(format!(
                "{}: object {:?}: some faces have normals and some do not; normals dropped",
                path.display(),
                model.name
            ));
            None
        }
    };
    let triangles = mesh.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    Ok(Some(Object {
        name: model.name,
        positions,
        uvs,
        normals,
        tangents: None,
        triangles,
        transform: None,
        material: mesh.material_id.filter(|&m| m < material_count),
    }))
}

/// The first non-finite `v`, `vt` or `vn` value, if any object holds one.
fn check_finite(objects: &[Object], path: &Path, text: &str) -> Option<IoError> {
    let finite = objects.iter().all(|o| {
        o.positions.iter().all(|p| p.is_finite())
            && o.uvs.as_ref().is_none_or(|uvs| uvs.iter().all(|t| t.is_finite()))
            && o.normals.as_ref().is_none_or(|ns| ns.iter().all(|n| n.is_finite()))
    });
    if finite {
        return None;
    }
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let what = match words.next() {
            Some("v") => "vertex position",
            Some("vt") => "texture coordinate",
            Some("vn") => "vertex normal",
            _ => continue,
        };
        if let Some(bad) = words.find(|w| w.parse::<f32>().is_ok_and(|x| !x.is_finite())) {
            return Some(IoError::NotFinite {
                path: path.to_path_buf(),
                line: i + 1,
                what,
                text: bad.to_owned(),
            });
        }
    }
    Some(IoError::Obj {
        path: path.to_path_buf(),
        reason: "a vertex attribute is not finite".to_owned(),
    })
}

/// The line of the first `keyword argument` statement.
fn find_statement_line(text: &str, keyword: &str, argument: &str) -> Option<usize> {
    text.lines()
        .position(|l| {
            l.trim_start().strip_prefix(keyword).is_some_and(|rest| rest.trim() == argument)
        })
        .map(|i| i + 1)
}

/// Finds the line of an OBJ file that tobj rejected and says what is wrong with it.
///
/// Mirrors tobj's rules: `v` needs 3 numbers, `vt` 2, `vn` 3; face indices are one-based,
/// negative ones count back from the last element defined so far, and must refer to an
/// element that exists.
fn diagnose(path: &Path, text: &str) -> Option<IoError> {
    let (mut v, mut vt, mut vn) = (0usize, 0usize, 0usize);
    let syntax = |line: usize, reason: String| {
        Some(IoError::Syntax { path: path.to_path_buf(), line, reason })
    };
    for (i, line) in text.lines().enumerate() {
        let number = i + 1;
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else { continue };
        let numbers = |needed: usize, what: &str| -> Option<IoError> {
            let values: Vec<&str> = words.clone().take(needed).collect();
            if values.len() < needed {
                return syntax(
                    number,
                    format!(
                        "`{keyword}` needs {needed} numbers ({what}), found {}: {line:?}",
                        values.len()
                    ),
                );
            }
            values.iter().find(|w| w.parse::<f32>().is_err()).and_then(|bad| {
                syntax(number, format!("`{keyword}`: expected a number, found {bad:?}"))
            })
        };
        match keyword {
            "v" => {
                if let Some(err) = numbers(3, "x y z") {
                    return Some(err);
                }
                v += 1;
            }
            "vt" => {
                if let Some(err) = numbers(2, "u v") {
                    return Some(err);
                }
                vt += 1;
            }
            "vn" => {
                if let Some(err) = numbers(3, "x y z") {
                    return Some(err);
                }
                vn += 1;
            }
            "f" | "l" => {
                for corner in words {
                    for (slot, field) in corner.split('/').enumerate() {
                        if field.is_empty() && slot > 0 {
                            continue;
                        }
                        let (what, count) = match slot {
                            0 => ("vertex", v),
                            1 => ("texture coordinate", vt),
                            2 => ("normal", vn),
                            _ => {
                                return syntax(
                                    number,
                                    format!("face corner {corner:?} has more than three indices"),
                                );
                            }
                        };
                        let Ok(index) = field.parse::<i64>() else {
                            return syntax(
                                number,
                                format!(
                                    "face corner {corner:?}: expected an index, found {field:?}"
                                ),
                            );
                        };
                        let resolved = if index < 0 { count as i64 + index } else { index - 1 };
                        if resolved < 0 || resolved >= count as i64 {
                            return Some(IoError::ReferenceOutOfRange {
                                path: path.to_path_buf(),
                                line: number,
                                what,
                                index,
                                count,
                            });
                        }
                    }
                }
            }
            _ => {}
        }
    }
    None
}

/// Finds the line of an MTL file that tobj rejects, by giving it each line alone.
fn locate_mtl_error(text: &str) -> Option<(usize, String)> {
    text.lines().enumerate().find_map(|(i, line)| {
        let probe = format!("newmtl probe\n{line}\n");
        let is_newmtl = line.split_whitespace().next() == Some("newmtl");
        let probe = if is_newmtl { format!("{line}\n") } else { probe };
        tobj::load_mtl_buf(&mut probe.as_bytes())
            .err()
            .map(|err| (i + 1, format!("{err}: {:?}", line.trim())))
    })
}

/// Converts a tobj material; texture paths resolve against `folder` (the `.mtl`'s).
fn convert_material(
    m: &tobj::Material,
    folder: &Path,
    textures: &mut Vec<Texture>,
    index: &mut HashMap<PathBuf, usize>,
) -> Material {
    let mut texture = |spec: &str| -> Option<(TextureRef, MapOptions)> {
        let options = MapOptions::parse(spec);
        if options.file.is_empty() {
            return None;
        }
        let file = folder.join(options.file.replace('\\', "/"));
        let texture = *index.entry(file.clone()).or_insert_with(|| {
            let name = file
                .file_name()
                .map_or_else(|| options.file.clone(), |n| n.to_string_lossy().into_owned());
            textures.push(Texture { name, source: TextureSource::File(file), image: None });
            textures.len() - 1
        });
        Some((TextureRef { texture, tex_coord: 0, transform: options.transform() }, options))
    };
    let diffuse = m.diffuse.unwrap_or([0.8, 0.8, 0.8]);
    let shininess = m.shininess.unwrap_or(32.0).max(0.0);
    let base_color_texture = m.diffuse_texture.as_deref().and_then(&mut texture).map(|(t, _)| t);
    let normal_spec =
        m.normal_texture.as_deref().or_else(|| m.unknown_param.get("norm").map(String::as_str));
    let normal = normal_spec.and_then(&mut texture);
    Material {
        name: m.name.clone(),
        base_color: [diffuse[0], diffuse[1], diffuse[2], m.dissolve.unwrap_or(1.0)],
        base_color_texture,
        normal_scale: normal.as_ref().map_or(1.0, |(_, o)| o.bump_multiplier),
        normal_texture: normal.map(|(t, _)| t),
        normal_green_down: false,
        specular: m.specular.unwrap_or([0.5, 0.5, 0.5]),
        shininess,
        metallic: 0.0,
        roughness: crate::shininess_to_roughness(shininess),
        double_sided: false,
    }
}

/// The options of an MTL texture statement (`map_Kd -o 0.5 0.5 file.png`).
#[derive(Debug, PartialEq)]
struct MapOptions {
    file: String,
    bump_multiplier: f32,
    offset: [f32; 2],
    scale: [f32; 2],
}

impl MapOptions {
    fn parse(spec: &str) -> Self {
        let mut out = Self {
            file: String::new(),
            bump_multiplier: 1.0,
            offset: [0.0, 0.0],
            scale: [1.0, 1.0],
        };
        let mut rest = spec.trim();
        while let Some(option) = rest.strip_prefix('-') {
            let (name, after) = option.split_once(char::is_whitespace).unwrap_or((option, ""));
            let mut words = after.trim_start();
            let mut take = |max: usize, numeric_only: bool| -> Vec<f32> {
                let mut values = Vec::new();
                while values.len() < max {
                    let (word, tail) = words.split_once(char::is_whitespace).unwrap_or((words, ""));
                    match word.parse::<f32>() {
                        Ok(x) if !word.is_empty() => values.push(x),
                        _ if !numeric_only && values.is_empty() && !word.is_empty() => {
                            values.push(f32::NAN);
                        }
                        _ => break,
                    }
                    words = tail.trim_start();
                }
                values
            };
            match name {
                "bm" => {
                    if let Some(&bm) = take(1, true).first() {
                        out.bump_multiplier = bm;
                    }
                }
                "o" => {
                    let v = take(3, true);
                    out.offset =
                        [v.first().copied().unwrap_or(0.0), v.get(1).copied().unwrap_or(0.0)];
                }
                "s" => {
                    let v = take(3, true);
                    out.scale =
                        [v.first().copied().unwrap_or(1.0), v.get(1).copied().unwrap_or(1.0)];
                }
                "t" => {
                    take(3, true);
                }
                "mm" => {
                    take(2, true);
                }
                // One argument, a word or a number: -blendu on, -clamp on, -imfchan r, -type sphere,
                // -boost 1, -texres 512, -cc on.
                _ => {
                    take(1, false);
                }
            }
            rest = words;
        }
        out.file = rest.to_owned();
        out
    }

    fn transform(&self) -> Option<UvTransform> {
        (self.offset != [0.0, 0.0] || self.scale != [1.0, 1.0]).then_some(UvTransform {
            offset: self.offset,
            rotation: 0.0,
            scale: self.scale,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::MapOptions;

    #[test]
    fn map_options_are_split_from_the_file_name() {
        let o = MapOptions::parse("-bm 0.25 -clamp on -o 0.5 0.25 textures/brick normal.png");
        assert_eq!(o.file, "textures/brick normal.png");
        assert_eq!(o.bump_multiplier, 0.25);
        assert_eq!(o.offset, [0.5, 0.25]);
        assert_eq!(o.scale, [1.0, 1.0]);
        let plain = MapOptions::parse("this diffuse texture has spaces.jpg");
        assert_eq!(plain.file, "this diffuse texture has spaces.jpg");
        assert_eq!(plain.bump_multiplier, 1.0);
    }
}
