//! `seamlit-bench flip`: the mean FLIP error between two pictures of the same size (NVIDIA's
//! FLIP through the `nv-flip` crate, as wgpu's image tests use it), and the pictures with the
//! error map side by side.

use std::path::{Path, PathBuf};

use anyhow::{Context as _, bail};
use image::{RgbImage, imageops};

/// `seamlit-bench flip`.
#[derive(Debug, clap::Args)]
pub struct FlipArgs {
    /// The reference picture (PNG).
    reference: PathBuf,
    /// The picture compared with it, of the same size.
    test: PathBuf,
    /// Write reference | test | FLIP error map (magma: black is no difference) here.
    #[arg(long, value_name = "OUT.png")]
    side_by_side: Option<PathBuf>,
}

/// Prints the mean FLIP error and writes the side-by-side picture when asked.
///
/// # Errors
/// A picture that cannot be read, pictures of different sizes, or an output not written.
pub fn run(args: &FlipArgs) -> anyhow::Result<()> {
    let reference = read(&args.reference)?;
    let test = read(&args.test)?;
    if reference.dimensions() != test.dimensions() {
        bail!(
            "{}: {}x{}, but {} is {}x{}",
            args.test.display(),
            test.width(),
            test.height(),
            args.reference.display(),
            reference.width(),
            reference.height()
        );
    }
    let (w, h) = reference.dimensions();
    let error = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(w, h, reference.as_raw()),
        nv_flip::FlipImageRgb8::with_data(w, h, test.as_raw()),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    let mean = nv_flip::FlipPool::from_image(&error).mean();
    println!("{mean:.4}");
    if let Some(out) = &args.side_by_side {
        let map = error.apply_color_lut(&nv_flip::magma_lut());
        let map = RgbImage::from_raw(w, h, map.to_vec()).context("FLIP error map size")?;
        let mut sheet = RgbImage::new(w * 3, h);
        for (i, picture) in [&reference, &test, &map].into_iter().enumerate() {
            imageops::replace(&mut sheet, picture, i64::from(w) * i as i64, 0);
        }
        sheet.save(out).with_context(|| format!("{}: writing", out.display()))?;
    }
    Ok(())
}

fn read(path: &Path) -> anyhow::Result<RgbImage> {
    Ok(image::open(path).with_context(|| format!("{}: reading", path.display()))?.to_rgb8())
}
