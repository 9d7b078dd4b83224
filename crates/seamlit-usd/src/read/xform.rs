//! World transforms from the xformOps (UsdGeomXformable): each prim's `xformOpOrder` composed
//! into its local matrix, times its parent's world matrix unless the order starts with
//! `!resetXformStack!`; and what hides a prim from a render (`visibility` invisible, `purpose`
//! guide or proxy, both inherited). Values are the default, else the earliest time sample.
//!
//! USD writes matrices for row vectors (`p' = p M`, translation in the last row) and lists
//! ops outermost first; glam's are for column vectors, so a USD matrix read in its storage
//! order is the glam matrix, and the local matrix is `op0 * op1 * ...`.

use std::collections::HashMap;

use anyhow::{Context, bail};
use glam::{DMat4, DQuat, DVec3};
use openusd::{sdf, usd};

use super::value;

/// World matrices and render visibility, computed once per prim.
pub(super) struct Xforms<'s> {
    stage: &'s usd::Stage,
    world: HashMap<String, DMat4>,
    /// Per prim: hidden from renders, and its computed purpose.
    shown: HashMap<String, (bool, String)>,
}

impl<'s> Xforms<'s> {
    pub(super) fn new(stage: &'s usd::Stage) -> Self {
        Self { stage, world: HashMap::new(), shown: HashMap::new() }
    }

    /// The prim's local-to-world matrix.
    pub(super) fn world(&mut self, path: &sdf::Path) -> anyhow::Result<DMat4> {
        if path.is_abs_root() {
            return Ok(DMat4::IDENTITY);
        }
        if let Some(m) = self.world.get(path.as_str()) {
            return Ok(*m);
        }
        let prim = self.stage.prim(path.clone());
        let (local, reset) = local(&prim)?;
        let parent = match path.parent() {
            Some(parent) if !reset => self.world(&parent)?,
            _ => DMat4::IDENTITY,
        };
        let m = parent * local;
        self.world.insert(path.as_str().to_owned(), m);
        Ok(m)
    }

    /// Whether the prim is hidden from a render: it or an ancestor is `invisible`, or its
    /// purpose (its own, else its parent's) is `guide` or `proxy` (the render purpose and the
    /// default one are drawn).
    pub(super) fn hidden(&mut self, path: &sdf::Path) -> anyhow::Result<bool> {
        Ok(self.visibility(path)?.0)
    }

    fn visibility(&mut self, path: &sdf::Path) -> anyhow::Result<(bool, String)> {
        if path.is_abs_root() {
            return Ok((false, "default".to_owned()));
        }
        if let Some(v) = self.shown.get(path.as_str()) {
            return Ok(v.clone());
        }
        let (parent_hidden, parent_purpose) = match path.parent() {
            Some(parent) => self.visibility(&parent)?,
            None => (false, "default".to_owned()),
        };
        let prim = self.stage.prim(path.clone());
        let token = |name: &str| -> anyhow::Result<Option<String>> {
            Ok(value(&prim.attribute(name))?.and_then(|v| match v {
                sdf::Value::Token(t) => Some(t.as_str().to_owned()),
                sdf::Value::String(s) => Some(s),
                _ => None,
            }))
        };
        let invisible = token("visibility")?.as_deref() == Some("invisible");
        let purpose = token("purpose")?.unwrap_or(parent_purpose);
        let hidden = parent_hidden || invisible || purpose == "guide" || purpose == "proxy";
        let v = (hidden, purpose);
        self.shown.insert(path.as_str().to_owned(), v.clone());
        Ok(v)
    }
}

/// The prim's local matrix from its `xformOpOrder`, and whether the order resets the stack
/// (ops before a `!resetXformStack!` are ignored, as USD does).
fn local(prim: &usd::Prim) -> anyhow::Result<(DMat4, bool)> {
    let Some(order) = prim.attribute("xformOpOrder").get::<sdf::Value>()? else {
        return Ok((DMat4::IDENTITY, false));
    };
    let names: Vec<String> = match order {
        sdf::Value::TokenVec(v) => v.iter().map(|t| t.as_str().to_owned()).collect(),
        sdf::Value::StringVec(v) => v,
        other => bail!("xformOpOrder is not a token array: {other:?}"),
    };
    let mut m = DMat4::IDENTITY;
    let mut reset = false;
    for name in &names {
        if name == "!resetXformStack!" {
            m = DMat4::IDENTITY;
            reset = true;
            continue;
        }
        m *= op(prim, name).with_context(|| format!("xformOp {:?}", shortened(name)))?;
    }
    Ok((m, reset))
}

/// `name`, cut after 60 characters (with "..."): a corrupted file's token can be its whole rest.
fn shortened(name: &str) -> String {
    match name.char_indices().nth(60) {
        Some((at, _)) => format!("{}...", &name[..at]),
        None => name.to_owned(),
    }
}

/// Whether `name` is a USD property name: identifiers (a letter or `_`, then letters, digits
/// or `_`) joined by `:`.
fn is_property_name(name: &str) -> bool {
    name.split(':').all(|part| {
        let mut chars = part.chars();
        chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
    })
}

/// One xformOp's matrix (column vectors), inverted for `!invert!`.
fn op(prim: &usd::Prim, name: &str) -> anyhow::Result<DMat4> {
    let (inverted, attribute) = match name.strip_prefix("!invert!") {
        Some(rest) => (true, rest),
        None => (false, name),
    };
    let Some(kind) = attribute.strip_prefix("xformOp:").map(|k| k.split(':').next().unwrap_or(k))
    else {
        bail!("not an xformOp name");
    };
    // Checked before openusd is asked for it: a name that is no property name (a cut or
    // corrupted file's token) sent openusd's path handling into a loop (the `usd` fuzz target).
    if !is_property_name(attribute) {
        bail!("not a property name");
    }
    let Some(v) = value(&prim.attribute(attribute))? else {
        bail!("the attribute {attribute} has no value");
    };
    let m = match kind {
        "translate" => DMat4::from_translation(vec3(&v)?),
        "translateX" => DMat4::from_translation(DVec3::X * scalar(&v)?),
        "translateY" => DMat4::from_translation(DVec3::Y * scalar(&v)?),
        "translateZ" => DMat4::from_translation(DVec3::Z * scalar(&v)?),
        "scale" => DMat4::from_scale(vec3(&v)?),
        "scaleX" => DMat4::from_scale(DVec3::new(scalar(&v)?, 1.0, 1.0)),
        "scaleY" => DMat4::from_scale(DVec3::new(1.0, scalar(&v)?, 1.0)),
        "scaleZ" => DMat4::from_scale(DVec3::new(1.0, 1.0, scalar(&v)?)),
        "rotateX" => DMat4::from_rotation_x(scalar(&v)?.to_radians()),
        "rotateY" => DMat4::from_rotation_y(scalar(&v)?.to_radians()),
        "rotateZ" => DMat4::from_rotation_z(scalar(&v)?.to_radians()),
        "rotateXYZ" | "rotateXZY" | "rotateYXZ" | "rotateYZX" | "rotateZXY" | "rotateZYX" => {
            let angles = vec3(&v)?;
            // `rotateABC` turns about A first, then B, then C: R = R_C R_B R_A.
            kind[6..].chars().fold(DMat4::IDENTITY, |m, axis| {
                let r = match axis {
                    'X' => DMat4::from_rotation_x(angles.x.to_radians()),
                    'Y' => DMat4::from_rotation_y(angles.y.to_radians()),
                    _ => DMat4::from_rotation_z(angles.z.to_radians()),
                };
                r * m
            })
        }
        "orient" => DMat4::from_quat(quat(&v)?),
        "transform" => match v {
            sdf::Value::Matrix4d(m) => DMat4::from_cols_array(&m.0),
            other => bail!("a transform op needs a matrix4d, found {other:?}"),
        },
        other => bail!("unknown xformOp type {other:?}"),
    };
    if !m.is_finite() {
        bail!("the matrix is not finite");
    }
    if inverted {
        if m.determinant() == 0.0 {
            bail!("the matrix of an inverted op is singular");
        }
        return Ok(m.inverse());
    }
    Ok(m)
}

fn scalar(v: &sdf::Value) -> anyhow::Result<f64> {
    Ok(match v {
        sdf::Value::Double(d) => *d,
        sdf::Value::Float(f) => f64::from(*f),
        sdf::Value::Half(h) => f64::from(h.to_f32()),
        other => bail!("expected a number, found {other:?}"),
    })
}

fn vec3(v: &sdf::Value) -> anyhow::Result<DVec3> {
    Ok(match v {
        sdf::Value::Vec3d(a) => DVec3::new(a.x, a.y, a.z),
        sdf::Value::Vec3f(a) => DVec3::new(a.x.into(), a.y.into(), a.z.into()),
        sdf::Value::Vec3h(a) => {
            DVec3::new(a.x.to_f32().into(), a.y.to_f32().into(), a.z.to_f32().into())
        }
        other => bail!("expected three numbers, found {other:?}"),
    })
}

fn quat(v: &sdf::Value) -> anyhow::Result<DQuat> {
    let (w, x, y, z) = match v {
        sdf::Value::Quatd(q) => (q.w, q.x, q.y, q.z),
        sdf::Value::Quatf(q) => (q.w.into(), q.x.into(), q.y.into(), q.z.into()),
        sdf::Value::Quath(q) => {
            (q.w.to_f32().into(), q.x.to_f32().into(), q.y.to_f32().into(), q.z.to_f32().into())
        }
        other => bail!("expected a quaternion, found {other:?}"),
    };
    let q = DQuat::from_xyzw(x, y, z, w);
    if q.length_squared() == 0.0 {
        bail!("the quaternion is zero");
    }
    Ok(q.normalize())
}
