//! The `lumis` command line: `lumis [render] [SCENE] ...`. Parses and dispatches; each
//! subcommand lives in its own module under `cli/`.

use clap::{ArgMatches, CommandFactory, FromArgMatches, Parser, Subcommand};
use std::path::PathBuf;

mod cli;

use cli::{hits, info, merge, render};

/// lumis: an offline Whitted-style ray tracer.
#[derive(Parser, Debug)]
#[command(version, about, args_conflicts_with_subcommands = true)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// With no subcommand, `lumis [SCENE] [OPTIONS]` renders, like `lumis render`.
    #[command(flatten)]
    render: render::RenderArgs,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render a scene (the default scene when none is given) to EXR and/or PNG.
    Render(Box<render::RenderArgs>),
    /// Print what a scene or model file holds (geometry, materials, lights, camera, bounds,
    /// warnings) without rendering.
    Info {
        /// Scene or model file.
        file: PathBuf,
        /// glTF files: draw every placement of a mesh as its own world-space copy (also each
        /// EXT_mesh_gpu_instancing instance) instead of making a mesh placed twice or more one
        /// prototype with an instance per placement. Objects keep their names either way.
        #[arg(long)]
        flatten_instances: bool,
    },
    /// Trace a batch of rays from an .npy file and write one hit record per ray (for
    /// cross-checks against other tracers).
    Hits(hits::HitsArgs),
    /// Assemble the tiles of a farm render (`lumis render --tile I/N`) into the image one
    /// render gives, bit for bit.
    Merge(merge::MergeArgs),
}

fn main() {
    let matches = Cli::command().get_matches();
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    // The render's header records its flags as given, read from the matches.
    let render_matches: &ArgMatches = matches.subcommand_matches("render").unwrap_or(&matches);
    let result = match &cli.command {
        Some(Command::Render(args)) => render::run(args, render_matches),
        Some(Command::Info {
            file,
            flatten_instances,
        }) => info::run(file, *flatten_instances),
        Some(Command::Hits(args)) => hits::run(args),
        Some(Command::Merge(args)) => merge::run(args),
        None => render::run(&cli.render, &matches),
    };
    if let Err(e) = result {
        if let Some(stop) = e.downcast_ref::<cli::interrupt::Interrupted>() {
            eprintln!("{stop}");
            std::process::exit(cli::interrupt::EXIT_INTERRUPTED);
        }
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
