//! UsdSkel skin bindings (UsdSkelBindingAPI): which skeleton skins a mesh, by which joints and
//! weights, from which bind space.
//!
//! A mesh under a `SkelRoot`, with `SkelBindingAPI` applied and `primvars:skel:jointIndices`
//! and `primvars:skel:jointWeights`, is skinned by the skeleton its `skel:skeleton` names (its
//! own, else that of its nearest ancestor with `SkelBindingAPI`, as pxr reads bindings only
//! there). Its joint indices index its own `skel:joints` (its own, else inherited) where authored, else
//! the skeleton's `joints`; both primvars hold `elementSize` influences per point (vertex
//! interpolation) or for the whole mesh (constant). Skinning puts the points in the
//! skeleton's space through `primvars:skel:geomBindTransform` (identity unauthored), and
//! there the skeleton's world matrix places them: the mesh's own transform does not. At the
//! bind pose every skinning matrix is the identity, so a skinned mesh's rest points are
//! `points * geomBindTransform * world(skeleton)` (checked against pxr's
//! `UsdSkelSkinningQuery::ComputeSkinnedPoints` in the tests): seamlit welds them there, as it
//! welds a glTF skin in its bind pose.
//!
//! Joints are named across the stage by an id per (skeleton, joint path), so that meshes that
//! list the joints of one skeleton in different orders compare their influences.
//! A binding that cannot be used (a missing skeleton, joint indices out of range, counts that
//! do not fit) is a warning naming the mesh: the mesh is then read unskinned at its own
//! transform, as USD itself draws a mesh whose skinning is invalid.

use std::collections::HashMap;

use glam::DMat4;
use openusd::{sdf, usd};

use super::value;
use crate::source::SkinInfluences;

/// The value of a check that found the binding usable, or, from the enclosing function, the
/// reason it is not (`Ok(Err(reason))`: the caller warns).
macro_rules! usable {
    ($check:expr) => {
        match $check {
            Ok(value) => value,
            Err(reason) => return Ok(Err(reason)),
        }
    };
}

/// The API schema a prim's skin binding properties are read on (pxr ignores them elsewhere:
/// a mesh without it is not skinned, an ancestor without it binds no skeleton).
const BINDING_API: &str = "SkelBindingAPI";

/// The skin bindings of a stage's meshes, and the joints they name.
pub(super) struct Skels<'s> {
    stage: &'s usd::Stage,
    /// Per skeleton prim: its joints' ids in its order, or why it cannot be used.
    skeletons: HashMap<String, Result<Vec<u32>, String>>,
    /// Every joint named so far as (skeleton prim, joint path); a joint's id is its index.
    pub joints: Vec<(String, String)>,
    ids: HashMap<(String, String), u32>,
}

/// A mesh's skin binding, read and checked but for the number of points.
pub(super) struct Binding {
    /// The skeleton's world matrix (before the up axis).
    pub skeleton_world: DMat4,
    /// `primvars:skel:geomBindTransform`: the mesh's points to the skeleton's space.
    pub geom_bind: DMat4,
    pub influences: SkinInfluences,
}

impl Binding {
    /// Why the binding does not fit a mesh of `points` points, if it does not.
    pub fn misfit(&self, points: usize) -> Option<String> {
        let i = &self.influences;
        let elements = if i.constant { 1 } else { points };
        let expected = elements * i.element_size;
        (i.indices.len() != expected).then(|| {
            format!(
                "{} joint indices and weights for {elements} elements of {} influences",
                i.indices.len(),
                i.element_size
            )
        })
    }

    /// Point `p`'s influences as (joint id, weight), `element_size` of them.
    pub fn of_point(&self, p: usize) -> impl Iterator<Item = (u32, f32)> + '_ {
        let joints = &self.influences.joints;
        self.influences.of_point(p).map(|(i, w)| (joints[i as usize], w))
    }
}

impl<'s> Skels<'s> {
    pub(super) fn new(stage: &'s usd::Stage) -> Self {
        Self { stage, skeletons: HashMap::new(), joints: Vec::new(), ids: HashMap::new() }
    }

    /// The skin binding of the mesh `prim`: `Ok(None)` for a mesh without joint influences,
    /// `Ok(Some(Err(reason)))` for one whose binding cannot be used (the caller warns).
    /// `world` gives a prim's world matrix.
    ///
    /// # Errors
    ///
    /// What openusd gave reading the values.
    pub(super) fn binding(
        &mut self,
        prim: &usd::Prim,
        world: &mut impl FnMut(&sdf::Path) -> anyhow::Result<DMat4>,
    ) -> anyhow::Result<Option<Result<Binding, String>>> {
        let indices = value(&prim.attribute("primvars:skel:jointIndices"))?;
        let weights = value(&prim.attribute("primvars:skel:jointWeights"))?;
        let (Some(indices), Some(weights)) = (indices, weights) else { return Ok(None) };
        Ok(Some(self.checked(prim, indices, weights, world)?))
    }

    /// [`Self::binding`]'s checks, as named steps: the skeleton bound, the joint order, the
    /// primvars' layout, their values, the bind transform.
    fn checked(
        &mut self,
        prim: &usd::Prim,
        indices: sdf::Value,
        weights: sdf::Value,
        world: &mut impl FnMut(&sdf::Path) -> anyhow::Result<DMat4>,
    ) -> anyhow::Result<Result<Binding, String>> {
        let path = prim.path().clone();
        let skeleton = usable!(self.bound_skeleton(prim, &path)?);
        let skeleton_joints = usable!(self.skeleton(&skeleton)?);
        let (joints, own_order) = usable!(self.joint_order(&path, &skeleton, skeleton_joints)?);
        let (element_size, constant) = usable!(influence_layout(prim)?);
        let (indices, weights) = usable!(influence_values(indices, weights, joints.len()));
        let geom_bind = usable!(geom_bind_transform(prim)?);
        let skeleton_world = world(&skeleton)?;
        Ok(Ok(Binding {
            skeleton_world,
            geom_bind,
            influences: SkinInfluences {
                skeleton: skeleton.as_str().to_owned(),
                joints,
                own_order,
                element_size,
                constant,
                indices,
                weights,
            },
        }))
    }

    /// The skeleton that skins the mesh `prim` at `path`: it must be under a `SkelRoot`, with
    /// the binding API applied, and name one with `skel:skeleton` (its own or an ancestor's).
    fn bound_skeleton(
        &self,
        prim: &usd::Prim,
        path: &sdf::Path,
    ) -> anyhow::Result<Result<sdf::Path, String>> {
        if !self.under_skel_root(path)? {
            return Ok(Err("it is not under a SkelRoot, so USD does not skin it".to_owned()));
        }
        if !prim.has_api_schema(BINDING_API)? {
            return Ok(Err(format!("{BINDING_API} is not applied to it, so USD does not skin it")));
        }
        let skeleton = self.inherited(path, |p| {
            Ok(p.relationship("skel:skeleton").targets()?.into_iter().next())
        })?;
        Ok(skeleton.ok_or_else(|| {
            format!("no skel:skeleton is bound to it or an ancestor with {BINDING_API}")
        }))
    }

    /// The joints the mesh at `path` indexes, and whether that order is its own
    /// `skel:joints` (else the skeleton's, `skeleton_joints`).
    fn joint_order(
        &self,
        path: &sdf::Path,
        skeleton: &sdf::Path,
        skeleton_joints: Vec<u32>,
    ) -> anyhow::Result<Result<(Vec<u32>, bool), String>> {
        let tokens = match self.inherited(path, |p| value(&p.attribute("skel:joints")))? {
            None => return Ok(Ok((skeleton_joints, false))),
            Some(sdf::Value::TokenVec(tokens)) => tokens,
            Some(_) => return Ok(Err("its skel:joints is not a token array".to_owned())),
        };
        let mut ids = Vec::with_capacity(tokens.len());
        for t in &tokens {
            let key = (skeleton.as_str().to_owned(), t.as_str().to_owned());
            match self.ids.get(&key) {
                Some(&id) if skeleton_joints.contains(&id) => ids.push(id),
                _ => {
                    return Ok(Err(format!(
                        "its skel:joints names {:?}, not a joint of <{}>",
                        t.as_str(),
                        skeleton.as_str()
                    )));
                }
            }
        }
        Ok(Ok((ids, true)))
    }

    /// Whether a prim above `path` is a `SkelRoot`.
    fn under_skel_root(&self, path: &sdf::Path) -> anyhow::Result<bool> {
        let mut at = path.parent();
        while let Some(p) = at.filter(|p| !p.is_abs_root()) {
            if self.stage.prim(p.clone()).type_name()?.is_some_and(|t| t.as_str() == "SkelRoot") {
                return Ok(true);
            }
            at = p.parent();
        }
        Ok(false)
    }

    /// What `read` finds on the prim at `path`, else on its nearest ancestor that has it;
    /// only prims with [`BINDING_API`] applied count (USD reads a binding on no other).
    fn inherited<T>(
        &self,
        path: &sdf::Path,
        read: impl Fn(&usd::Prim) -> anyhow::Result<Option<T>>,
    ) -> anyhow::Result<Option<T>> {
        let mut at = Some(path.clone());
        while let Some(p) = at.filter(|p| !p.is_abs_root()) {
            let prim = self.stage.prim(p.clone());
            if prim.has_api_schema(BINDING_API)?
                && let Some(found) = read(&prim)?
            {
                return Ok(Some(found));
            }
            at = p.parent();
        }
        Ok(None)
    }

    /// The ids of the joints of the skeleton at `path`, in its order, read on first use.
    fn skeleton(&mut self, path: &sdf::Path) -> anyhow::Result<Result<Vec<u32>, String>> {
        if let Some(known) = self.skeletons.get(path.as_str()) {
            return Ok(known.clone());
        }
        let prim = self.stage.prim(path.clone());
        let kind = prim.type_name()?;
        let read = if kind.as_ref().is_none_or(|t| t.as_str() != "Skeleton") {
            Err(format!("its skel:skeleton <{}> is not a Skeleton", path.as_str()))
        } else {
            match value(&prim.attribute("joints"))? {
                Some(sdf::Value::TokenVec(tokens)) if !tokens.is_empty() => {
                    Ok(tokens.iter().map(|t| self.id(path.as_str(), t.as_str())).collect())
                }
                _ => Err(format!("its skeleton <{}> has no joints", path.as_str())),
            }
        };
        self.skeletons.insert(path.as_str().to_owned(), read.clone());
        Ok(read)
    }

    fn id(&mut self, skeleton: &str, joint: &str) -> u32 {
        let key = (skeleton.to_owned(), joint.to_owned());
        if let Some(&id) = self.ids.get(&key) {
            return id;
        }
        #[expect(clippy::cast_possible_truncation, reason = "joints are far fewer than u32::MAX")]
        let id = self.joints.len() as u32;
        self.joints.push(key.clone());
        self.ids.insert(key, id);
        id
    }
}

/// The influences' `elementSize` (1 to 64) and whether they are constant (one element for
/// the whole mesh) rather than per point: the same for both primvars.
fn influence_layout(prim: &usd::Prim) -> anyhow::Result<Result<(usize, bool), String>> {
    let layout = |name: &str| -> anyhow::Result<(Option<i64>, Option<String>)> {
        let attribute = prim.attribute(name);
        let size = match attribute.get_metadata::<sdf::Value>("elementSize")? {
            Some(sdf::Value::Int(n)) => Some(i64::from(n)),
            Some(sdf::Value::Int64(n)) => Some(n),
            Some(sdf::Value::Uint(n)) => Some(i64::from(n)),
            _ => None,
        };
        let interpolation = match attribute.get_metadata::<sdf::Value>("interpolation")? {
            Some(sdf::Value::Token(t)) => Some(t.as_str().to_owned()),
            Some(sdf::Value::String(s)) => Some(s),
            _ => None,
        };
        Ok((size, interpolation))
    };
    let of_indices = layout("primvars:skel:jointIndices")?;
    let of_weights = layout("primvars:skel:jointWeights")?;
    if of_indices != of_weights {
        return Ok(Err(format!(
            "its skel:jointIndices and skel:jointWeights differ in elementSize or interpolation ({of_indices:?}, {of_weights:?})"
        )));
    }
    let (size, interpolation) = of_indices;
    let element_size = match size.unwrap_or(1) {
        n @ 1..=64 => usize::try_from(n).unwrap_or(1),
        n => return Ok(Err(format!("its skel:jointIndices has elementSize {n}"))),
    };
    let constant = match interpolation.as_deref() {
        Some("constant") => true,
        Some("vertex" | "varying") | None => false,
        Some(other) => return Ok(Err(format!("its skel:jointIndices has {other} interpolation"))),
    };
    Ok(Ok((element_size, constant)))
}

/// The joint indices and weights, checked: an int and a float array of one length, every
/// index one of the `joints`, every weight finite.
fn influence_values(
    indices: sdf::Value,
    weights: sdf::Value,
    joints: usize,
) -> Result<(Vec<i32>, Vec<f32>), String> {
    let (sdf::Value::IntVec(indices), sdf::Value::FloatVec(weights)) = (indices, weights) else {
        return Err(
            "its skel:jointIndices is not an int array or its skel:jointWeights not a float array"
                .to_owned(),
        );
    };
    if indices.len() != weights.len() {
        return Err(format!(
            "{} skel:jointIndices, {} skel:jointWeights",
            indices.len(),
            weights.len()
        ));
    }
    if let Some(bad) = indices.iter().find(|&&i| i < 0 || i as usize >= joints) {
        return Err(format!("skel:jointIndices holds {bad}, for {joints} joints"));
    }
    if !weights.iter().all(|w| w.is_finite()) {
        return Err("a skel:jointWeights value is not finite".to_owned());
    }
    Ok((indices, weights))
}

/// `primvars:skel:geomBindTransform` (else the older `skel:geomBindTransform`), the identity
/// where neither is authored; `Err` with the reason where it cannot be used.
fn geom_bind_transform(prim: &usd::Prim) -> anyhow::Result<Result<DMat4, String>> {
    for name in ["primvars:skel:geomBindTransform", "skel:geomBindTransform"] {
        match value(&prim.attribute(name))? {
            Some(sdf::Value::Matrix4d(m)) => {
                let m = DMat4::from_cols_array(&m.0);
                if m.is_finite() && m.determinant() != 0.0 {
                    return Ok(Ok(m));
                }
                return Ok(Err(format!("its {name} is singular or not finite")));
            }
            Some(_) => return Ok(Err(format!("its {name} is not a matrix4d"))),
            None => {}
        }
    }
    Ok(Ok(DMat4::IDENTITY))
}
