//! Material libraries: the `.mtl` files an OBJ's `mtllib` statements name, resolved inside
//! the model's folder and read with tobj (after the checks for the lines it panics on or
//! misreads), their materials converted into seamlit's, including the `-bm` (bump
//! multiplier), `-o` and `-s` options that tobj leaves in the texture name ([`MapOptions`]),
//! and the `norm` statement it does not know. Texture paths resolve against the `.mtl`
//! file's folder.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::parse::names;
use seamlit_asset::LoadOptions;
use seamlit_asset::error::{IoError, Syntax};
use seamlit_asset::{Asset, Material, Texture, TextureRef, TextureSource, UvTransform};

mod usable;

/// The materials of an OBJ's libraries, in order: per material, the tobj material, its
/// library file and that file's folder as parts below the model's folder (for resolving its
/// texture paths); by name, the last definition (as in tobj); and whether a library is
/// missing.
#[derive(Default)]
pub(super) struct Libraries {
    pub(super) materials: Vec<(tobj::Material, PathBuf, Vec<String>)>,
    pub(super) by_name: HashMap<String, usize>,
    pub(super) missing: bool,
}

/// Reads the material libraries that the `mtllib` statements name (name, line).
///
/// # Errors
///
/// [`IoError::PathEscapes`] / [`IoError::LinkEscapes`] for a library outside the model's
/// folder, [`IoError::MissingFile`] for a missing one when `options.strict` is set (a
/// warning otherwise), [`IoError::Syntax`] for one tobj rejects, with its line (none that
/// [`usable`] lets through is known). A statement seamlit cannot use is a warning
/// ([`usable::warning`]), and so are names that are not UTF-8 ([`names::decode_lines`]).
pub(super) fn read_libraries(
    path: &Path,
    statements: &[(String, usize)],
    options: &LoadOptions,
    warnings: &mut Vec<String>,
) -> Result<Libraries, IoError> {
    let folder = path.parent().unwrap_or(Path::new(""));
    let mut libraries = Libraries::default();
    for (name, line) in statements {
        let parts =
            seamlit_asset::paths::inside(&[], name).ok_or_else(|| IoError::PathEscapes {
                path: path.to_path_buf(),
                line: Some(*line),
                what: "material library",
                reference: name.clone(),
            })?;
        // Read where it is on disk; named in messages and kept as decoded.
        let resolved = names::on_disk(folder, &parts);
        let named = parts.iter().fold(folder.to_path_buf(), |p, s| p.join(s));
        let sub = parts[..parts.len().saturating_sub(1)].to_vec();
        let Some(mtl_bytes) = read_library(path, folder, name, *line, &resolved, options)? else {
            warnings.push(format!(
                "{}:{line}: material library {} not found; its materials get defaults",
                path.display(),
                resolved.display()
            ));
            libraries.missing = true;
            continue;
        };
        let (mtl_text, legacy) = names::decode_lines(&mtl_bytes);
        warnings.extend(legacy.map(|line| names::legacy_warning(&named, line)));
        let mtl = usable::usable(&mtl_text);
        warnings.extend(usable::warning(&named, &mtl.unusable));
        let mtl_text = mtl.text;
        let (library, _) = read_mtl(&mtl_text).map_err(|err| {
            let (line, kind) = locate_mtl_error(&mtl_text)
                .unwrap_or((0, Syntax::MaterialLibrary { tobj: err.to_string() }));
            IoError::Syntax { path: named.clone(), line, kind }
        })?;
        for material in library {
            libraries.by_name.insert(material.name.clone(), libraries.materials.len());
            libraries.materials.push((material, resolved.clone(), sub.clone()));
        }
    }
    Ok(libraries)
}

/// The bytes of the library `name` (on `line` of the OBJ at `path`), resolved to `resolved`
/// in the model's `folder`; `None` when it is missing and `options.strict` is not set.
///
/// # Errors
///
/// [`IoError::LinkEscapes`] where a symbolic link leads it out of the folder,
/// [`IoError::MissingFile`] (strict), [`IoError::Io`].
fn read_library(
    path: &Path,
    folder: &Path,
    name: &str,
    line: usize,
    resolved: &Path,
    options: &LoadOptions,
) -> Result<Option<Vec<u8>>, IoError> {
    // A symbolic link on the way must not lead out of the model's folder; the real path
    // is what is read. A missing file is left to the read below, which reports it.
    let real = match options.files.real_inside(folder, resolved) {
        Ok(real) => real,
        Err(seamlit_asset::paths::NotInside::Outside(target)) => {
            return Err(IoError::LinkEscapes {
                path: path.to_path_buf(),
                what: "material library".to_owned(),
                reference: name.to_owned(),
                target,
            });
        }
        Err(seamlit_asset::paths::NotInside::Io(_)) => resolved.to_path_buf(),
    };
    match options.files.read(&real) {
        Ok(bytes) => Ok(Some(bytes)),
        Err(err) if err.kind() == std::io::ErrorKind::NotFound => match options.strict {
            true => Err(IoError::MissingFile {
                path: path.to_path_buf(),
                what: "material library".to_owned(),
                missing: resolved.to_path_buf(),
                line: Some(line),
            }),
            false => Ok(None),
        },
        Err(err) => Err(IoError::io(resolved, err)),
    }
}

/// Warns of each `usemtl` name (name, line of first use) that no library defines.
pub(super) fn warn_unknown_materials(
    path: &Path,
    used: &[(String, usize)],
    by_name: &HashMap<String, usize>,
    warnings: &mut Vec<String>,
) {
    for (name, line) in used {
        if !by_name.contains_key(name) {
            warnings.push(format!(
                "{}:{line}: `usemtl {name}`: no material library of the file defines {}; \
                 its faces get the default material",
                path.display(),
                if name.is_empty() { "a material without a name" } else { "it" }
            ));
        }
    }
}

/// Converts the libraries' materials into the asset's, gathering their textures.
///
/// # Errors
///
/// [`IoError::PathEscapes`] for a texture path that leaves the model's folder.
pub(super) fn convert_materials(
    path: &Path,
    materials: &[(tobj::Material, PathBuf, Vec<String>)],
    asset: &mut Asset,
) -> Result<(), IoError> {
    let folder = path.parent().unwrap_or(Path::new(""));
    let mut texture_index: HashMap<PathBuf, usize> = HashMap::new();
    for (material, file, sub) in materials {
        let library = Library { model_folder: folder, file, sub };
        let material =
            convert_material(material, library, &mut asset.textures, &mut texture_index)?;
        asset.materials.push(material);
    }
    Ok(())
}

/// Finds the line of an MTL file that tobj rejects, by giving it each line alone.
fn locate_mtl_error(text: &str) -> Option<(usize, Syntax)> {
    text.lines().enumerate().find_map(|(i, line)| {
        let probe = format!("newmtl probe\n{line}\n");
        let is_newmtl = line.split_whitespace().next() == Some("newmtl");
        let probe = if is_newmtl { format!("{line}\n") } else { probe };
        read_mtl(&probe).err().map(|err| {
            (i + 1, Syntax::Material { tobj: err.to_string(), text: line.trim().to_owned() })
        })
    })
}

/// tobj's MTL reader, given text that [`usable`] has read first.
///
/// tobj 4.0.5 unwraps a colour statement (`Ka`, `Kd`, `Ks`, `Ke`) of fewer than three numbers
/// (`parse_float3`, found by the `obj` fuzz target: regression input
/// `tests/regressions/obj_mtl_colour_with_two_numbers.obj`); [`usable`] gives it none. Any
/// panic in tobj is caught and becomes an error all the same.
fn read_mtl(text: &str) -> tobj::MTLLoadResult {
    let text = name_unnamed(text);
    let (mut materials, mut names) =
        std::panic::catch_unwind(|| tobj::load_mtl_buf(&mut text.as_bytes()))
            .unwrap_or(Err(tobj::LoadError::MaterialParseError))?;
    for material in &mut materials {
        if material.name == UNNAMED {
            material.name.clear();
        }
    }
    if let Some(index) = names.remove(UNNAMED) {
        names.insert(String::new(), index);
    }
    Ok((materials, names))
}

/// The name given to materials that `newmtl` leaves unnamed while tobj reads them (tobj
/// refuses an empty name, and Blender 2.61 writes one): a name no file holds.
const UNNAMED: &str = "\u{0}seamlit: unnamed material\u{0}";

/// The MTL text with every `newmtl` that gives no name given [`UNNAMED`].
fn name_unnamed(text: &str) -> std::borrow::Cow<'_, str> {
    let unnamed = |line: &str| line.trim() == "newmtl";
    if !text.lines().any(unnamed) {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 64);
    for line in text.lines() {
        out.push_str(line);
        if unnamed(line) {
            out.push(' ');
            out.push_str(UNNAMED);
        }
        out.push('\n');
    }
    std::borrow::Cow::Owned(out)
}

/// Where a material came from: the `.mtl` file and its folder below the model's folder.
struct Library<'a> {
    model_folder: &'a Path,
    file: &'a Path,
    sub: &'a [String],
}

/// Converts a tobj material; texture paths resolve against the `.mtl`'s folder and may not
/// leave the model's folder.
///
/// # Errors
///
/// [`IoError::PathEscapes`] for a texture path that leaves the model's folder.
fn convert_material(
    m: &tobj::Material,
    library: Library<'_>,
    textures: &mut Vec<Texture>,
    index: &mut HashMap<PathBuf, usize>,
) -> Result<Material, IoError> {
    let mut texture = |spec: &str| -> Result<Option<(TextureRef, MapOptions)>, IoError> {
        let options = MapOptions::parse(spec);
        if options.file.is_empty() {
            return Ok(None);
        }
        let parts = seamlit_asset::paths::inside(library.sub, &options.file).ok_or_else(|| {
            IoError::PathEscapes {
                path: library.file.to_path_buf(),
                line: None,
                what: "texture",
                reference: options.file.clone(),
            }
        })?;
        let file = names::on_disk(library.model_folder, &parts);
        let texture = *index.entry(file.clone()).or_insert_with(|| {
            // The name as decoded (the file may be found under other bytes: `names.rs`).
            let name = parts.last().cloned().unwrap_or_else(|| options.file.clone());
            textures.push(Texture { name, source: TextureSource::File(file), image: None });
            textures.len() - 1
        });
        Ok(Some((TextureRef { texture, tex_coord: 0, transform: options.transform() }, options)))
    };
    let diffuse = m.diffuse.unwrap_or([0.8, 0.8, 0.8]);
    let shininess = m.shininess.unwrap_or(32.0).max(0.0);
    let base_color_texture =
        m.diffuse_texture.as_deref().map(&mut texture).transpose()?.flatten().map(|(t, _)| t);
    let normal_spec =
        m.normal_texture.as_deref().or_else(|| m.unknown_param.get("norm").map(String::as_str));
    let normal = normal_spec.map(&mut texture).transpose()?.flatten();
    Ok(Material {
        name: m.name.clone(),
        base_color: [diffuse[0], diffuse[1], diffuse[2], m.dissolve.unwrap_or(1.0)],
        base_color_texture,
        normal_scale: normal.as_ref().map_or(1.0, |(_, o)| o.bump_multiplier),
        normal_texture: normal.map(|(t, _)| t),
        normal_green_down: false,
        specular: m.specular.unwrap_or([0.5, 0.5, 0.5]),
        shininess,
        metallic: 0.0,
        roughness: seamlit_asset::shininess_to_roughness(shininess),
        double_sided: false,
        ..Material::default()
    })
}

/// The options of an MTL texture statement (`map_Kd -o 0.5 0.5 file.png`).
#[derive(Debug, PartialEq)]
pub(crate) struct MapOptions {
    pub(crate) file: String,
    bump_multiplier: f32,
    offset: [f32; 2],
    scale: [f32; 2],
    /// Whether it has an option the MTL specification does not list (skipped with one
    /// argument, unless that is the last word: the file).
    pub(crate) unknown: bool,
}

impl MapOptions {
    pub(crate) fn parse(spec: &str) -> Self {
        let mut out = Self {
            file: String::new(),
            bump_multiplier: 1.0,
            offset: [0.0, 0.0],
            scale: [1.0, 1.0],
            unknown: false,
        };
        let mut rest = spec.trim();
        while let Some(option) = rest.strip_prefix('-') {
            let (name, after) = option.split_once(char::is_whitespace).unwrap_or((option, ""));
            let mut words = after.trim_start();
            // An option of no argument before the file: the last word is the file.
            let last_word = !words.contains(char::is_whitespace);
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
                "blendu" | "blendv" | "boost" | "cc" | "clamp" | "imfchan" | "texres" | "type" => {
                    take(1, false);
                }
                _ if last_word => out.unknown = true,
                // An option the specification does not list: one argument, a word or a number.
                _ => {
                    out.unknown = true;
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
