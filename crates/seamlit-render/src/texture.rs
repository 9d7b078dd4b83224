//! Texture upload: RGBA8 images with a full mip chain built on the CPU, in the right colour
//! space (sRGB colour is averaged in linear light, normal maps as unit vectors).

use image::RgbaImage;
use seamlit_asset::{TextureFilter, TextureSampling, Wrap};
use wgpu::util::DeviceExt;

use crate::{GpuContext, RenderError};

/// How material textures are uploaded and sampled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TextureOptions {
    /// Build a full mip chain on the CPU (colour averaged in linear light, normals
    /// renormalised). Default `true`.
    pub mipmaps: bool,
    /// Largest anisotropic filtering ratio, 1 to 16 (1 = off). Default 16. On lavapipe
    /// anisotropic filtering is a large part of the frame time (BENCHMARKS.md, Rendering).
    pub anisotropy: u16,
}

impl TextureOptions {
    /// Mipmaps and 16x anisotropic filtering.
    pub const DEFAULT: Self = Self { mipmaps: true, anisotropy: 16 };
}

impl Default for TextureOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// How a texture's texels are to be read.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum TexelKind {
    /// sRGB-encoded colour (base colour).
    Color,
    /// Linear tangent-space normals, `rgb * 2 - 1`.
    Normal,
    /// Linear data (metallic-roughness, occlusion), averaged as it is.
    Data,
}

impl TexelKind {
    fn format(self) -> wgpu::TextureFormat {
        match self {
            Self::Color => wgpu::TextureFormat::Rgba8UnormSrgb,
            Self::Normal | Self::Data => wgpu::TextureFormat::Rgba8Unorm,
        }
    }
}

/// sRGB byte to linear value.
fn srgb_to_linear(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

/// Linear value to sRGB byte.
fn linear_to_srgb(l: f32) -> u8 {
    let l = l.clamp(0.0, 1.0);
    let c = if l <= 0.003_130_8 { l * 12.92 } else { 1.055 * l.powf(1.0 / 2.4) - 0.055 };
    unorm8(c)
}

fn unorm8(c: f32) -> u8 {
    // In range by the clamp, so the cast cannot truncate.
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "clamped to 0..=255"
    )]
    let b = (c.clamp(0.0, 1.0) * 255.0).round() as u8;
    b
}

/// The next mip level of `src`: each texel the average of a 2x2 block (clamped at odd edges).
#[must_use]
pub(crate) fn downsample(src: &RgbaImage, kind: TexelKind) -> RgbaImage {
    let (w, h) = src.dimensions();
    let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
    let lut: Vec<f32> = (0..=255u8).map(srgb_to_linear).collect();
    RgbaImage::from_fn(nw, nh, |x, y| {
        let mut sum = [0.0f32; 4];
        for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            let p = src.get_pixel((2 * x + dx).min(w - 1), (2 * y + dy).min(h - 1)).0;
            for c in 0..4 {
                sum[c] += match (kind, c) {
                    (TexelKind::Color, 0..=2) => lut[usize::from(p[c])],
                    (TexelKind::Normal, 0..=2) => f32::from(p[c]) / 255.0 * 2.0 - 1.0,
                    _ => f32::from(p[c]) / 255.0,
                };
            }
        }
        let avg = sum.map(|s| s / 4.0);
        match kind {
            TexelKind::Data => image::Rgba(avg.map(unorm8)),
            TexelKind::Color => image::Rgba([
                linear_to_srgb(avg[0]),
                linear_to_srgb(avg[1]),
                linear_to_srgb(avg[2]),
                unorm8(avg[3]),
            ]),
            TexelKind::Normal => {
                let n = glam::Vec3::from_slice(&avg[..3]).try_normalize().unwrap_or(glam::Vec3::Z);
                let e = |v: f32| unorm8(v * 0.5 + 0.5);
                image::Rgba([e(n.x), e(n.y), e(n.z), unorm8(avg[3])])
            }
        }
    })
}

/// An image to upload as a material texture (see [`upload`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct ImageUpload<'a> {
    /// The texture's name, for its label and errors.
    pub name: &'a str,
    pub image: &'a RgbaImage,
    /// How its texels are read: the texture's format and how mips average.
    pub kind: TexelKind,
    /// Build and upload the full mip chain.
    pub mipmaps: bool,
}

/// Uploads `upload.image`, with its full mip chain if `upload.mipmaps`, and returns a view
/// of it.
pub(crate) fn upload(
    ctx: &GpuContext,
    upload: &ImageUpload<'_>,
) -> Result<wgpu::TextureView, RenderError> {
    let ImageUpload { name, image, kind, mipmaps } = *upload;
    let (width, height) = image.dimensions();
    let max = ctx.device().limits().max_texture_dimension_2d;
    if width == 0 || height == 0 || width > max || height > max {
        return Err(RenderError::TextureTooLarge { name: name.to_owned(), width, height, max });
    }
    let mut levels = vec![image.clone()];
    while let Some(last) = levels.last().filter(|l| mipmaps && (l.width() > 1 || l.height() > 1)) {
        let next = downsample(last, kind);
        levels.push(next);
    }
    let data: Vec<u8> = levels.iter().flat_map(|l| l.as_raw().iter().copied()).collect();
    let texture = ctx.device().create_texture_with_data(
        ctx.queue(),
        &wgpu::TextureDescriptor {
            label: Some(name),
            size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            mip_level_count: u32::try_from(levels.len()).unwrap_or(1),
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: kind.format(),
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::MipMajor,
        &data,
    );
    Ok(texture.create_view(&wgpu::TextureViewDescriptor::default()))
}

/// A 1x1 texture of one texel.
pub(crate) fn solid(
    ctx: &GpuContext,
    name: &str,
    texel: [u8; 4],
    kind: TexelKind,
) -> Result<wgpu::TextureView, RenderError> {
    let image = RgbaImage::from_pixel(1, 1, image::Rgba(texel));
    upload(ctx, &ImageUpload { name, image: &image, kind, mipmaps: false })
}

/// The material sampler: repeat, trilinear, anisotropic as `options` say.
pub(crate) fn sampler(ctx: &GpuContext, options: &TextureOptions) -> wgpu::Sampler {
    ctx.device().create_sampler(&wgpu::SamplerDescriptor {
        label: Some("seamlit material sampler"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        address_mode_w: wgpu::AddressMode::Repeat,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        anisotropy_clamp: options.anisotropy.clamp(1, 16),
        ..Default::default()
    })
}

/// A material sampler for a glTF sampler: its wrapping and filters; without a mipmap filter
/// (glTF's minFilter NEAREST or LINEAR) only the full-size image is read. Anisotropic as
/// `options` say where every filter is linear (the only case the API allows it).
pub(crate) fn sampler_for(
    ctx: &GpuContext,
    options: &TextureOptions,
    sampling: &TextureSampling,
) -> wgpu::Sampler {
    let address = |wrap: Wrap| match wrap {
        Wrap::Repeat => wgpu::AddressMode::Repeat,
        Wrap::ClampToEdge => wgpu::AddressMode::ClampToEdge,
        Wrap::MirroredRepeat => wgpu::AddressMode::MirrorRepeat,
    };
    let filter = |f: TextureFilter| match f {
        TextureFilter::Nearest => wgpu::FilterMode::Nearest,
        TextureFilter::Linear => wgpu::FilterMode::Linear,
    };
    let mipmap_filter = match sampling.mipmap_filter {
        Some(TextureFilter::Nearest) | None => wgpu::MipmapFilterMode::Nearest,
        Some(TextureFilter::Linear) => wgpu::MipmapFilterMode::Linear,
    };
    let all_linear = sampling.mag_filter == TextureFilter::Linear
        && sampling.min_filter == TextureFilter::Linear
        && sampling.mipmap_filter == Some(TextureFilter::Linear);
    ctx.device().create_sampler(&wgpu::SamplerDescriptor {
        label: Some("seamlit material sampler (glTF sampler)"),
        address_mode_u: address(sampling.wrap[0]),
        address_mode_v: address(sampling.wrap[1]),
        address_mode_w: wgpu::AddressMode::Repeat,
        mag_filter: filter(sampling.mag_filter),
        min_filter: filter(sampling.min_filter),
        mipmap_filter,
        lod_max_clamp: if sampling.mipmap_filter.is_some() { 32.0 } else { 0.0 },
        anisotropy_clamp: if all_linear { options.anisotropy.clamp(1, 16) } else { 1 },
        ..Default::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colour_mips_average_in_linear_light() {
        // Black and white texels average to 50% linear grey, which is sRGB 188, not 128.
        let img = RgbaImage::from_fn(2, 1, |x, _| {
            if x == 0 { image::Rgba([0, 0, 0, 255]) } else { image::Rgba([255; 4]) }
        });
        let mip = downsample(&img, TexelKind::Color);
        assert_eq!(mip.dimensions(), (1, 1));
        assert_eq!(mip.get_pixel(0, 0).0, [188, 188, 188, 255]);
    }

    #[test]
    fn normal_mips_stay_unit_length() {
        // Two normals tilted +-45 degrees about Y average to +Z.
        let t = unorm8(std::f32::consts::FRAC_1_SQRT_2 * 0.5 + 0.5);
        let u = unorm8(-std::f32::consts::FRAC_1_SQRT_2 * 0.5 + 0.5);
        let img = RgbaImage::from_fn(2, 2, |x, _| {
            if x == 0 { image::Rgba([t, 128, t, 255]) } else { image::Rgba([u, 128, t, 255]) }
        });
        let mip = downsample(&img, TexelKind::Normal);
        let p = mip.get_pixel(0, 0).0;
        assert!(p[0].abs_diff(128) <= 1 && p[1].abs_diff(128) <= 1 && p[2] == 255, "{p:?}");
    }
}
