//! KHR_lights_punctual: the lights the nodes of the scene carry.

use glam::{Mat4, Vec3};

use super::material::json_f32;
use seamlit_asset::{PunctualKind, PunctualLight};

/// KHR_lights_punctual: the lights that the nodes of `scene` carry, placed by the nodes'
/// global transforms (a light shines down its node's -Z). Read from the raw extension JSON,
/// as `emissive_strength` is. A node naming a light that does not exist, or a light of an
/// unknown type, is left out with a warning.
pub(super) fn punctual_lights(
    document: &gltf::Document,
    scene: Option<&gltf::Scene<'_>>,
    warnings: &mut Vec<String>,
) -> Vec<PunctualLight> {
    let defs = document
        .extension_value("KHR_lights_punctual")
        .and_then(|e| e.get("lights"))
        .and_then(serde_json::Value::as_array);
    let mut out = Vec::new();
    let mut stack: Vec<(gltf::Node<'_>, Mat4)> =
        scene.map(|s| s.nodes().map(|n| (n, Mat4::IDENTITY)).collect()).unwrap_or_default();
    while let Some((node, parent)) = stack.pop() {
        let global = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        let index = node
            .extension_value("KHR_lights_punctual")
            .and_then(|e| e.get("light"))
            .and_then(serde_json::Value::as_u64);
        if let Some(index) = index {
            let def = defs.and_then(|d| d.get(usize::try_from(index).ok()?));
            match def.map(|d| punctual_light(d, global)) {
                Some(Ok(light)) => out.push(light),
                Some(Err(kind)) => warnings.push(format!(
                    "nodes[{}]: KHR_lights_punctual light {index} has the unknown type {kind:?}; left out",
                    node.index()
                )),
                None => warnings.push(format!(
                    "nodes[{}]: KHR_lights_punctual light {index} does not exist; left out",
                    node.index()
                )),
            }
        }
        stack.extend(node.children().map(|c| (c, global)));
    }
    out
}

/// One KHR_lights_punctual light definition at `global`, with the extension's defaults
/// (white, intensity 1, unlimited range, spot cones 0 and pi/4); `Err` with the type when it
/// is not directional, point or spot.
fn punctual_light(def: &serde_json::Value, global: Mat4) -> Result<PunctualLight, String> {
    let number = |v: &serde_json::Value, key: &str| v.get(key).and_then(json_f32);
    let spot = def.get("spot").unwrap_or(&serde_json::Value::Null);
    let kind = match def.get("type").and_then(serde_json::Value::as_str).unwrap_or_default() {
        "directional" => PunctualKind::Directional,
        "point" => PunctualKind::Point,
        "spot" => PunctualKind::Spot {
            inner_cone_angle: number(spot, "innerConeAngle").unwrap_or(0.0),
            outer_cone_angle: number(spot, "outerConeAngle").unwrap_or(std::f32::consts::FRAC_PI_4),
        },
        other => return Err(other.to_owned()),
    };
    let color = def
        .get("color")
        .and_then(serde_json::Value::as_array)
        .and_then(|c| Some([json_f32(c.first()?)?, json_f32(c.get(1)?)?, json_f32(c.get(2)?)?]))
        .unwrap_or([1.0; 3]);
    Ok(PunctualLight {
        name: def.get("name").and_then(serde_json::Value::as_str).unwrap_or_default().to_owned(),
        kind,
        color,
        intensity: number(def, "intensity").unwrap_or(1.0),
        position: global.transform_point3(Vec3::ZERO),
        direction: global.transform_vector3(Vec3::NEG_Z).try_normalize().unwrap_or(Vec3::NEG_Z),
        range: number(def, "range").filter(|r| *r > 0.0),
    })
}
