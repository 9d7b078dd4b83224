//! `seamlit_mesh::fix` and `report` on arbitrary models: positions that include NaN,
//! infinities, huge and tiny values; indices in and out of range; optional UVs, normals,
//! tangents (of the right length or not) and transforms; every mode, weighting, tolerance,
//! tangent method and normal policy. Errors are fine; panics, hangs and runaway memory are not.
#![no_main]

use arbitrary::{Arbitrary, Unstructured};
use glam::{Mat4, Vec2, Vec3, Vec4};
use libfuzzer_sys::fuzz_target;
use seamlit_mesh::{
    FixOptions, Mode, Model, NormalPolicy, Object, ReportOptions, TangentMethod, VAxis, Weighting,
    WeldTolerance,
};

/// A float biased toward the values that break geometry code.
fn float(u: &mut Unstructured<'_>) -> arbitrary::Result<f32> {
    Ok(match u.int_in_range(0u8..=15)? {
        0 => f32::NAN,
        1 => f32::INFINITY,
        2 => f32::NEG_INFINITY,
        3 => f32::MAX,
        4 => -f32::MAX,
        5 => f32::MIN_POSITIVE,
        6 => 1e-30,
        7 => 0.0,
        8 => -0.0,
        9 => 1e30,
        10 => f32::from_bits(u32::arbitrary(u)?),
        // Small grid values: coincident positions, shared edges, degenerate triangles.
        _ => f32::from(u.int_in_range(-4i8..=4)?) * 0.5,
    })
}

fn vec2(u: &mut Unstructured<'_>) -> arbitrary::Result<Vec2> {
    Ok(Vec2::new(float(u)?, float(u)?))
}

fn vec3(u: &mut Unstructured<'_>) -> arbitrary::Result<Vec3> {
    Ok(Vec3::new(float(u)?, float(u)?, float(u)?))
}

/// An attribute array: usually one per vertex, sometimes of a wrong length.
fn attribute<T>(
    u: &mut Unstructured<'_>,
    vertices: usize,
    mut one: impl FnMut(&mut Unstructured<'_>) -> arbitrary::Result<T>,
) -> arbitrary::Result<Option<Vec<T>>> {
    if !u.arbitrary::<bool>()? {
        return Ok(None);
    }
    let len = if u.ratio(1u8, 8u8)? { u.int_in_range(0..=vertices + 2)? } else { vertices };
    (0..len).map(|_| one(u)).collect::<arbitrary::Result<Vec<T>>>().map(Some)
}

fn object(u: &mut Unstructured<'_>, index: usize) -> arbitrary::Result<Object> {
    let vertices = u.int_in_range(0..=48usize)?;
    let positions = (0..vertices).map(|_| vec3(u)).collect::<arbitrary::Result<Vec<_>>>()?;
    let triangles_len = u.int_in_range(0..=64usize)?;
    let bound = u32::try_from(vertices).unwrap_or(u32::MAX);
    let mut triangles = Vec::with_capacity(triangles_len);
    for _ in 0..triangles_len {
        let mut t = [0u32; 3];
        for i in &mut t {
            // Mostly valid indices; sometimes just past the end or anything at all.
            *i = match u.int_in_range(0u8..=15)? {
                0 => u32::arbitrary(u)?,
                1 => bound,
                _ => u.int_in_range(0..=bound.saturating_sub(1))?,
            };
        }
        triangles.push(t);
    }
    let uvs = attribute(u, vertices, vec2)?;
    let normals = attribute(u, vertices, vec3)?;
    let tangents = attribute(u, vertices, |u| {
        Ok(Vec4::from((vec3(u)?, if u.arbitrary::<bool>()? { 1.0 } else { -1.0 })))
    })?;
    let colors = attribute(u, vertices, |u| Ok(Vec4::from((vec3(u)?, 1.0))))?;
    let transform = if u.ratio(1u8, 4u8)? {
        Some(Mat4::from_cols_array(&std::array::from_fn(|_| float(u).unwrap_or(0.0))))
    } else {
        None
    };
    Ok(Object {
        name: format!("o{index}"),
        positions,
        uvs,
        uvs1: None,
        normals,
        tangents,
        colors,
        triangles,
        transform,
        material: None,
        smoothing_groups: None,
        split_from: Vec::new(),
        skin: Vec::new(),
        morph_targets: Vec::new(),
    })
}

fn options(u: &mut Unstructured<'_>) -> arbitrary::Result<FixOptions> {
    Ok(FixOptions {
        mode: *u.choose(&[Mode::Flat, Mode::Object, Mode::Model])?,
        weld_tolerance: match u.int_in_range(0u8..=2)? {
            0 => WeldTolerance::Relative(float(u)?),
            1 => WeldTolerance::Absolute(float(u)?),
            _ => WeldTolerance::Exact,
        },
        weighting: *u.choose(&[
            Weighting::Angle,
            Weighting::Area,
            Weighting::AngleArea,
            Weighting::Uniform,
        ])?,
        crease_angle_deg: float(u)?,
        tangents: *u.choose(&[
            TangentMethod::None,
            TangentMethod::Seamlit,
            TangentMethod::Mikktspace,
        ])?,
        tangent_angle_deg: float(u)?,
        split_mirrored: u.arbitrary()?,
        // Drawn last, in `build`, so that older inputs decode to the models they did.
        normals: NormalPolicy::Recompute,
    })
}

fn build(data: &[u8]) -> arbitrary::Result<(Model, FixOptions)> {
    let mut u = Unstructured::new(data);
    let options = options(&mut u)?;
    let count = u.int_in_range(0..=4usize)?;
    let mut objects =
        (0..count).map(|i| object(&mut u, i)).collect::<arbitrary::Result<Vec<_>>>()?;
    let v_axis = if u.arbitrary::<bool>()? { VAxis::Up } else { VAxis::Down };
    // Exhausted input chooses the first: `recompute`, what older inputs ran.
    let normals =
        *u.choose(&[NormalPolicy::Recompute, NormalPolicy::Auto, NormalPolicy::Keep])?;
    // Smoothing groups last, so that inputs found before they existed decode as they did
    // (an exhausted input gives none): usually one per triangle, sometimes a wrong length.
    for object in &mut objects {
        let triangles = object.triangles.len();
        object.smoothing_groups = attribute(&mut u, triangles, |u| u.int_in_range(0u32..=3))?;
    }
    Ok((Model { objects, v_axis }, FixOptions { normals, ..options }))
}

fuzz_target!(|data: &[u8]| {
    let Ok((model, options)) = build(data) else { return };
    let _ = seamlit_mesh::fix(&model, &options);
    let _ = seamlit_mesh::report(&model, &ReportOptions::from(&options));
});
