//! `seamlit render`: a scene or model to a PNG, and with `--frames N` the frame timing.

use seamlit_render::FrameDescriptor;

use crate::cli::RenderArgs;
use crate::draw::{Gpu, Look, check_png, frame_settings};
use crate::failure::{Classify, Failure};
use crate::picture::save_png;
use crate::prepare::{FixOverride, drawn_bounds, pick_camera};
use crate::table::count;

/// Runs `seamlit render`.
///
/// # Errors
/// Bad input (files, camera name) before any GPU work; processing failures after.
pub(crate) fn run(args: &RenderArgs) -> Result<(), Failure> {
    check_png(&args.output)?;
    let loaded = args.scene.load()?;
    let fix = FixOverride { mode: args.mode.map(Into::into), flags: args.scene.fix.clone() };
    let asset = loaded.build(&fix)?;
    let (flags, input) = (&args.scene.animation, &args.scene.input);
    let moment = crate::animate::moment(flags, &loaded, &asset, input)?;
    let own = crate::animate::own_moments(flags, &loaded, &asset, input)?;
    let poses = crate::animate::poses(&asset, moment, &own);
    let bounds = drawn_bounds(&asset, poses.as_deref());
    let size = args.scene.view.size;
    let aspect = size.0 as f32 / size.1 as f32;
    let cameras = loaded.cameras(bounds, aspect);
    let camera = pick_camera(&cameras, args.scene.view.camera.as_deref(), &args.scene.input)?;
    let settings = frame_settings(&args.scene.view, &loaded);
    let environment = Look::new(&args.scene.view, &loaded).read_environment()?;
    let mut gpu = Gpu::open()?;
    gpu.set_environment(environment.as_ref())?;
    let (scene, image) = gpu.render(&asset, poses.as_deref(), &camera, bounds, &settings, size)?;
    save_png(&image, &args.output).processing()?;
    println!(
        "wrote {} ({}x{}, camera {:?}, {}, {})",
        args.output.display(),
        size.0,
        size.1,
        camera.name,
        count(asset.model.objects.len(), "object"),
        count(asset.model.triangle_count(), "triangle")
    );
    if let Some(frames) = args.frames.filter(|n| *n > 0) {
        let view = camera.view(aspect, Some(bounds));
        let times = gpu
            .renderer
            .time_frames(
                &gpu.ctx,
                &FrameDescriptor {
                    scene: &scene,
                    camera: &view,
                    settings: &settings,
                    size: (size.0, size.1),
                },
                frames,
            )
            .processing()?;
        let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
        println!(
            "{frames} frames at {}x{} on {}: mean {:.2} ms, median {:.2} ms, min {:.2} ms ({:.1} frames/s)",
            size.0,
            size.1,
            gpu.ctx.describe(),
            ms(times.mean()),
            ms(times.median()),
            ms(times.min()),
            1e3 / ms(times.mean()).max(1e-9)
        );
    }
    Ok(())
}
