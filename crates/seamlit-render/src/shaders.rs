//! The WGSL sources as the GPU gets them. WGSL has no include, so what two shaders share is a
//! file of its own put in front of each: `object.wgsl`, the per-object uniforms, and
//! `deform.wgsl`, morph targets and skinning, which the scene pass, the shadow pass and the
//! posed-vertex readback all apply.
//!
//! Invariant: every struct a shader reads from a buffer has the layout of the Rust struct that
//! fills it (`Frame` / `FrameRaw`, `Light` / `LightRaw`, `Material` / `MaterialRaw`,
//! `Object` / `ObjectRaw`, `Params` / `ParamsRaw`): the same size and each member at the
//! same offset, checked with naga by the test `gpu_structs_have_the_layout_of_their_rust_structs`.

/// The scene pass: meshes, the sky and the TBN lines (`mesh.wgsl`), with the PBR extension
/// layers (`layers.wgsl`) and the textures of transmission, volume, iridescence and
/// anisotropy (`extension_textures.wgsl`).
pub(crate) const MESH: Source = Source {
    label: "seamlit mesh.wgsl",
    text: concat!(
        include_str!("object.wgsl"),
        include_str!("deform.wgsl"),
        include_str!("mesh.wgsl"),
        include_str!("layers.wgsl"),
        include_str!("extension_textures.wgsl")
    ),
};

/// [`MESH`] for a device with fewer sampled textures a stage: those four extensions'
/// textures unbound (`extension_textures_unbound.wgsl`).
pub(crate) const MESH_WITHOUT_EXTENSION_TEXTURES: Source = Source {
    label: "seamlit mesh.wgsl (without extension textures)",
    text: concat!(
        include_str!("object.wgsl"),
        include_str!("deform.wgsl"),
        include_str!("mesh.wgsl"),
        include_str!("layers.wgsl"),
        include_str!("extension_textures_unbound.wgsl")
    ),
};

/// The scene pass's shader for a material layout with (`extension_textures`) or without
/// bindings 15 to 19 (`context.rs`).
pub(crate) fn mesh(extension_textures: bool) -> Source {
    if extension_textures { MESH } else { MESH_WITHOUT_EXTENSION_TEXTURES }
}

/// The shadow-map pass (`shadow.wgsl`).
pub(crate) const SHADOW: Source = Source {
    label: "seamlit shadow.wgsl",
    text: concat!(
        include_str!("object.wgsl"),
        include_str!("deform.wgsl"),
        include_str!("shadow.wgsl")
    ),
};

/// The posed-vertex readback's compute pass (`posed.wgsl`).
pub(crate) const POSED: Source = Source {
    label: "seamlit posed.wgsl",
    text: concat!(
        include_str!("object.wgsl"),
        include_str!("deform.wgsl"),
        include_str!("posed.wgsl")
    ),
};

/// The environment's prefiltering compute passes (`ibl.wgsl`).
pub(crate) const IBL: Source = Source { label: "seamlit ibl.wgsl", text: include_str!("ibl.wgsl") };

/// The transmission target's mips (`transmission.wgsl`).
pub(crate) const TRANSMISSION: Source =
    Source { label: "seamlit transmission.wgsl", text: include_str!("transmission.wgsl") };

/// One shader module's WGSL text.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Source {
    /// The module's debug label.
    label: &'static str,
    /// The composed WGSL.
    text: &'static str,
}

impl Source {
    /// Compiles the module on `device`.
    pub(crate) fn module(self, device: &wgpu::Device) -> wgpu::ShaderModule {
        device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(self.label),
            source: wgpu::ShaderSource::Wgsl(self.text.into()),
        })
    }
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;
    use std::mem::offset_of;

    use super::*;
    use crate::environment::ParamsRaw;
    use crate::light::LightRaw;
    use crate::material::MaterialRaw;
    use crate::pose::SkinRaw;
    use crate::scene::ObjectRaw;
    use crate::settings::FrameRaw;

    const ALL: [Source; 6] =
        [MESH, MESH_WITHOUT_EXTENSION_TEXTURES, SHADOW, POSED, IBL, TRANSMISSION];

    fn parse(source: Source) -> naga::Module {
        let module = naga::front::wgsl::parse_str(source.text)
            .unwrap_or_else(|e| panic!("{}: {}", source.label, e.emit_to_string(source.text)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}: {}", source.label, e.emit_to_string(source.text)));
        module
    }

    #[test]
    fn every_shader_parses_and_validates() {
        for source in ALL {
            parse(source);
        }
    }

    /// A `.wgsl` file added to src/ but composed into no module would go unchecked.
    #[test]
    fn every_wgsl_file_is_part_of_a_module() {
        let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let mut files = 0;
        for entry in std::fs::read_dir(&src).expect("read src/") {
            let path = entry.expect("list src/").path();
            if path.extension().is_some_and(|e| e == "wgsl") {
                let text = std::fs::read_to_string(&path).expect("read a shader");
                let used = ALL.iter().any(|source| source.text.contains(text.as_str()));
                assert!(used, "{} is in no shader module of shaders.rs", path.display());
                files += 1;
            }
        }
        assert!(files >= ALL.len(), "{files} .wgsl files for {} modules", ALL.len());
    }

    /// The struct `name` of `source`: its size and each member's offset by name.
    fn wgsl_layout(source: Source, name: &str) -> (u32, BTreeMap<String, u32>) {
        let module = parse(source);
        let (_, ty) = module
            .types
            .iter()
            .find(|(_, ty)| ty.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("{}: no struct {name}", source.label));
        let naga::TypeInner::Struct { members, span } = &ty.inner else {
            panic!("{}: {name} is not a struct", source.label);
        };
        let offsets =
            members.iter().map(|m| (m.name.clone().unwrap_or_default(), m.offset)).collect();
        (*span, offsets)
    }

    /// A Rust struct's size and the offsets of the listed fields, by name.
    macro_rules! rust_layout {
        ($ty:ty { $($field:ident),+ $(,)? }) => {
            (
                u32::try_from(size_of::<$ty>()).expect("a small struct"),
                BTreeMap::from([$((stringify!($field).to_owned(), {
                    u32::try_from(offset_of!($ty, $field)).expect("a small struct")
                })),+]),
            )
        };
    }

    /// Padding members (`pad`, `pad0`...) are only counted in the size.
    fn without_padding(
        (size, offsets): (u32, BTreeMap<String, u32>),
    ) -> (u32, BTreeMap<String, u32>) {
        (size, offsets.into_iter().filter(|(name, _)| !name.starts_with("pad")).collect())
    }

    #[test]
    fn gpu_structs_have_the_layout_of_their_rust_structs() {
        let object = rust_layout!(ObjectRaw {
            model,
            normal,
            det_sign,
            object_id,
            flip_v,
            has_tangents,
            skin_sets,
            morph_targets,
            vertex_count,
        });
        let pairs = [
            (
                MESH,
                "Frame",
                rust_layout!(FrameRaw {
                    view_proj,
                    eye,
                    light_count,
                    ambient,
                    lighting_model,
                    debug_view,
                    flags,
                    normal_strength,
                    tbn_length,
                    exposure,
                    tone_mapping,
                    environment_intensity,
                    environment_max_lod,
                    inv_view_proj,
                    environment_rotation,
                    background_lod,
                    shadow_normal_offset,
                }),
            ),
            (
                MESH,
                "Light",
                rust_layout!(LightRaw {
                    position,
                    kind,
                    direction,
                    range,
                    color,
                    cos_inner,
                    cos_outer,
                    shadow,
                }),
            ),
            (
                MESH,
                "Material",
                rust_layout!(MaterialRaw {
                    base_color,
                    specular,
                    shininess,
                    base_uv,
                    normal_uv,
                    metallic_roughness_uv,
                    occlusion_uv,
                    emissive_uv,
                    emissive,
                    normal_scale,
                    metallic,
                    roughness,
                    occlusion_strength,
                    alpha_cutoff,
                    flags,
                    specular_uv,
                    specular_color_uv,
                    clearcoat_uv,
                    clearcoat_roughness_uv,
                    clearcoat_normal_uv,
                    sheen_color_uv,
                    sheen_roughness_uv,
                    f0_dielectric,
                    specular_weight,
                    sheen_color,
                    sheen_roughness,
                    clearcoat,
                    clearcoat_roughness,
                    clearcoat_normal_scale,
                    clearcoat_f0,
                    anisotropy,
                    transmission,
                    thickness,
                    attenuation_distance,
                    ior,
                    attenuation_color,
                    iridescence,
                    iridescence_ior,
                    iridescence_thickness,
                    dispersion,
                    transmission_uv,
                    thickness_uv,
                    iridescence_uv,
                    iridescence_thickness_uv,
                    anisotropy_uv,
                    iridescence_thickness_minimum,
                }),
            ),
            (MESH, "Object", object.clone()),
            (SHADOW, "Object", object.clone()),
            (POSED, "Object", object),
            (MESH, "SkinVertex", rust_layout!(SkinRaw { joints, weights })),
            (IBL, "Params", rust_layout!(ParamsRaw { size, kind, roughness, base_size, color })),
        ];
        for (source, name, rust) in pairs {
            assert_eq!(
                without_padding(wgsl_layout(source, name)),
                rust,
                "{}: {name} (size, member offsets) against its Rust struct",
                source.label
            );
        }
    }
}
