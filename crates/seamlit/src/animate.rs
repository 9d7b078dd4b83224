//! Posing a model for `render`, `compare` and `view`: which animation (the command line's,
//! else a `[[model]]`'s own for its model, else the scene's `[render]`), at which time, and the
//! per-object poses the renderer takes (from `seamlit_io::pose`, the CPU's sampling of the
//! glTF animation).

use std::ops::Range;
use std::path::Path;

use seamlit_io::Asset;
use seamlit_io::pose::Pose;
use seamlit_render::ObjectPose;
use seamlit_scene::AnimationChoice;

use crate::cli::AnimationFlags;
use crate::failure::Failure;
use crate::prepare::Loaded;

/// The animation and time a picture is posed at.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Moment {
    /// An index into the asset's animations; `None`: the rest pose.
    pub animation: Option<usize>,
    /// Seconds into it.
    pub time: f32,
}

/// A `[[model]]` posed by its own `animation`: the merged asset's objects that are that
/// model's and the moment they are posed at (the animation an index into the merged asset's,
/// which moves only that model's nodes).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct OwnMoment {
    objects: Range<usize>,
    moment: Moment,
}

/// The moment the flags (else the scene) ask for, the animation resolved against `asset`'s.
///
/// # Errors
/// [`Failure::BadInput`] naming `input` and listing the animations the model has, for a name
/// or index it lacks.
pub(crate) fn moment(
    flags: &AnimationFlags,
    loaded: &Loaded,
    asset: &Asset,
    input: &Path,
) -> Result<Moment, Failure> {
    let render = &loaded.scene.render;
    let choice =
        flags.animation.as_deref().map(AnimationChoice::parse).or(render.animation.clone());
    let time = flags.time.or(render.time).unwrap_or(0.0);
    let animation = choice.map(|c| resolve(asset, &c, input)).transpose()?;
    Ok(Moment { animation, time })
}

/// The models that have their own `animation` key, unless the command line names one for all:
/// each with its objects in `asset` (the scene's models merged by `Scene::assemble`, which
/// concatenates objects and animations in model order) and its moment (its own `time`, else
/// the command line's or `[render]`'s, else 0).
///
/// # Errors
/// [`Failure::BadInput`] for an animation a model lacks (listing those it has);
/// [`Failure::Processing`] when `asset` is not laid out as the parts say.
pub(crate) fn own_moments(
    flags: &AnimationFlags,
    loaded: &Loaded,
    asset: &Asset,
    input: &Path,
) -> Result<Vec<OwnMoment>, Failure> {
    let mut own = Vec::new();
    let (mut object, mut animation) = (0, 0);
    for (model, part) in &loaded.parts {
        // As drawn: objects cut by their triangles' materials (`Loaded::build`).
        let objects = part.split_object_count();
        if flags.animation.is_none()
            && let Some(choice) = &model.animation
        {
            let local = resolve(part, choice, &model.path)?;
            let time = model.time.or(flags.time).or(loaded.scene.render.time).unwrap_or(0.0);
            own.push(OwnMoment {
                objects: object..object + objects,
                moment: Moment { animation: Some(animation + local), time },
            });
        }
        object += objects;
        animation += part.animations.len();
    }
    if object != asset.model.objects.len() || animation != asset.animations.len() {
        return Err(Failure::processing(format!(
            "{}: the merged scene has {} objects and {} animations, its models {object} and \
             {animation}: cannot place the models' own animations",
            input.display(),
            asset.model.objects.len(),
            asset.animations.len()
        )));
    }
    Ok(own)
}

/// The index of the animation `choice` names.
fn resolve(asset: &Asset, choice: &AnimationChoice, input: &Path) -> Result<usize, Failure> {
    let found = match choice {
        AnimationChoice::Index(i) => (*i < asset.animations.len()).then_some(*i),
        AnimationChoice::Name(name) => asset.animations.iter().position(|a| a.name == *name),
    };
    found.ok_or_else(|| {
        let asked = match choice {
            AnimationChoice::Index(i) => format!("animation {i}"),
            AnimationChoice::Name(name) => format!("animation {name:?}"),
        };
        let has = if asset.animations.is_empty() {
            "it has none".to_owned()
        } else {
            let list: Vec<String> = asset
                .animations
                .iter()
                .enumerate()
                .map(|(i, a)| format!("{i} {:?} ({:.2} s)", a.name, a.duration()))
                .collect();
            format!("it has {}", list.join(", "))
        };
        Failure::input(format!("{}: the model has no {asked}; {has}", input.display()))
    })
}

/// Each animation's name (or `animation N` where it has none) and length in seconds.
pub(crate) fn list(asset: &Asset) -> Vec<(String, f32)> {
    asset
        .animations
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let name = if a.name.is_empty() { format!("animation {i}") } else { a.name.clone() };
            (name, a.duration())
        })
        .collect()
}

/// The pose of every object of `asset` at `moment` (the rest pose without an animation:
/// skinned objects are drawn skinned by their nodes as authored, as the Khronos Sample
/// Viewer draws them), the nodes of each of `own` at its own moment; `None` for a model
/// with neither skins nor animations, which is drawn as it is.
pub(crate) fn poses(asset: &Asset, moment: Moment, own: &[OwnMoment]) -> Option<Vec<ObjectPose>> {
    if asset.skins.is_empty() && asset.animations.is_empty() {
        return None;
    }
    let at = |m: Moment| match m.animation {
        Some(a) => Pose::at(asset, a, m.time),
        None => Pose::rest(asset),
    };
    let pose = at(moment);
    let own_poses: Vec<(Range<usize>, Pose)> =
        own.iter().map(|o| (o.objects.clone(), at(o.moment))).collect();
    Some(
        (0..asset.model.objects.len())
            .map(|o| {
                let pose = own_poses.iter().find(|(r, _)| r.contains(&o)).map_or(&pose, |(_, p)| p);
                let joints = pose.joint_matrices(asset, o);
                // A skinned mesh's own node transform is ignored (glTF "Skins"): its joint
                // matrices place it in model space.
                let transform = if joints.is_some() {
                    glam::Mat4::IDENTITY
                } else {
                    pose.object_transform(asset, o)
                };
                ObjectPose {
                    transform,
                    joints,
                    morph_weights: pose.morph_weights(asset, o).to_vec(),
                }
            })
            .collect(),
    )
}
