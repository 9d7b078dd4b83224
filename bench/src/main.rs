//! `seamlit-bench`: what `bench/peers.sh` needs beyond the `seamlit` binary.
//!
//! - `input MODEL OUT.glb` writes a benchmark input: the model as loaded, with its normals and
//!   tangents dropped, so that every tool computes them from the same positions and UVs.
//! - `teapot N OUT.glb` writes the demo teapot (32 Bezier patches tessellated N x N each, UVs,
//!   the brick normal map, Y up) without normals.
//! - `reference IN OUT.glb` runs the paper's brute-force algorithm
//!   (`seamlit_mesh::reference::fix`, O(V x F)) and writes the result.
//! - `render OUT.png FILE...` renders each file *as it is* (its own normals and tangents, no
//!   fix) and puts the pictures side by side; `seamlit render` always fixes first.
//! - `flip REFERENCE.png TEST.png [--side-by-side OUT.png]` prints the mean FLIP error of
//!   TEST against REFERENCE (NVIDIA's FLIP, the `nv-flip` crate) and writes reference | test |
//!   error map (bench/sample-viewer/compare.sh).
//! - `skinned OUT.gltf [--rings R --segments S --joints J]` writes a skinned, morphed,
//!   animated two-object character (`skinned.rs`), the animation benchmarks' input.
//! - `assjson IN.assjson OUT.glb` converts Assimp's JSON dump, which keeps the tangents that
//!   Assimp's glTF 2 exporter drops.

mod assjson;
mod flip;
mod render;
mod skinned;

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context as _;
use clap::{Parser, Subcommand};
use seamlit_io::{Asset, LoadOptions, SaveOptions};

/// Helpers for bench/peers.sh.
#[derive(Debug, Parser)]
#[command(name = "seamlit-bench", max_term_width = 100)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Write MODEL without normals and tangents (a benchmark input).
    Input {
        /// Any model seamlit reads (.obj, .gltf, .glb, Newell patches).
        model: PathBuf,
        /// Where to write (.glb, .gltf or .obj).
        output: PathBuf,
    },
    /// Write the demo teapot, N x N quads per patch (2 N^2 x 32 triangles), without normals.
    Teapot {
        /// Quads per patch side.
        #[arg(value_parser = clap::value_parser!(u32).range(1..=1024))]
        n: u32,
        /// Where to write (.glb, .gltf or .obj).
        output: PathBuf,
    },
    /// Run the paper's reference algorithm on IN and write OUT.
    Reference {
        /// Any model seamlit reads.
        input: PathBuf,
        /// Where to write (.glb, .gltf or .obj).
        output: PathBuf,
    },
    /// Convert Assimp's JSON dump (`-fassjson`), tangents included, to OUT (.glb, .gltf, .obj).
    Assjson {
        /// The `.assjson` file.
        input: PathBuf,
        /// Where to write.
        output: PathBuf,
    },
    /// Write a skinned, morphed, animated two-object character (2 S triangles).
    Skinned {
        /// Where to write (.gltf; its buffer goes beside it as NAME.bin).
        output: PathBuf,
        /// Rings of vertices up the tube.
        #[arg(long, default_value_t = 1001)]
        rings: usize,
        /// Segments around it.
        #[arg(long, default_value_t = 500)]
        segments: usize,
        /// Joints in the chain up the tube.
        #[arg(long, default_value_t = 64)]
        joints: usize,
    },
    /// Render each FILE with its own normals and tangents, side by side, one row per view.
    Render(render::RenderArgs),
    /// Print the mean FLIP error of TEST against REFERENCE; optionally write the pictures and
    /// the error map side by side.
    Flip(flip::FlipArgs),
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("seamlit-bench: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Input { model, output } => {
            let mut asset = seamlit_io::load(&model, &LoadOptions::DEFAULT)?;
            strip(&mut asset);
            save(&asset, &output)
        }
        Command::Teapot { n, output } => {
            let mut asset = seamlit_scene::demo::teapot_asset(n)?;
            strip(&mut asset);
            save(&asset, &output)
        }
        Command::Reference { input, output } => {
            let mut asset = seamlit_io::load(&input, &LoadOptions::DEFAULT)?;
            asset.model = seamlit_mesh::reference::fix(&asset.model)
                .with_context(|| format!("{}: reference fix", input.display()))?;
            save(&asset, &output)
        }
        Command::Assjson { input, output } => save(&assjson::load(&input)?, &output),
        Command::Skinned { output, rings, segments, joints } => {
            skinned::write(&skinned::Shape { rings, segments, joints }, &output)
        }
        Command::Render(args) => render::run(&args),
        Command::Flip(args) => flip::run(&args),
    }
}

/// Drops every object's normals and tangents.
fn strip(asset: &mut Asset) {
    for object in &mut asset.model.objects {
        object.normals = None;
        object.tangents = None;
    }
}

fn save(asset: &Asset, output: &std::path::Path) -> anyhow::Result<()> {
    seamlit_io::save(asset, output, &SaveOptions::default())?;
    println!(
        "wrote {} ({} objects, {} triangles)",
        output.display(),
        asset.model.objects.len(),
        asset.model.triangle_count()
    );
    Ok(())
}
