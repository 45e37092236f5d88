//! `tetprep INPUT -o PREFIX`: surface scan in, `PREFIX.node/.ele/.face` out (and `PREFIX.vtk`
//! with `--vtk`), stats after every run. Errors go to stderr with a non-zero exit; nothing
//! is written unless meshing succeeded, and every file is written atomically.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use tetrasim::mesh::io::{write_tetgen, write_vtk};
use tetrasim::prep::{prep_file, Mesher, PrepOptions};

/// Converts a triangle surface (PLY, OBJ, OFF, STL) into a tetrahedral mesh: repairs it
/// (welds, drops degenerate/duplicate faces, orients, fills holes), simplifies it when the
/// target needs it, meshes it with TetGen or the voxel mesher and prints the mesh's stats.
#[derive(Debug, Parser)]
#[command(version)]
struct Args {
    /// The surface file (.ply, .obj, .off, .stl).
    input: PathBuf,
    /// Output prefix: writes PREFIX.node, PREFIX.ele, PREFIX.face.
    #[arg(short, long)]
    output: PathBuf,
    /// TetGen radius-edge ratio bound (>= 1; 0 turns the bound off).
    #[arg(long, default_value_t = 2.0)]
    quality: f64,
    /// Largest tet volume, in the scaled input unit cubed.
    #[arg(long, conflicts_with = "target_tets")]
    max_volume: Option<f64>,
    /// Keep the surface as given: no Steiner points on it (TetGen -Y).
    #[arg(long)]
    preserve_surface: bool,
    /// Aim for about this many tets (within 25 %).
    #[arg(long)]
    target_tets: Option<usize>,
    /// Multiply the input coordinates by this factor first.
    #[arg(long, default_value_t = 1.0)]
    scale: f64,
    /// The mesher.
    #[arg(long, value_enum, default_value_t = Mesher::Tetgen)]
    mesher: Mesher,
    /// When TetGen fails, use the voxel mesher (with a warning).
    #[arg(long)]
    fallback: bool,
    /// Also write PREFIX.vtk (legacy VTK, for ParaView).
    #[arg(long)]
    vtk: bool,
    /// Print the stats as JSON on stdout (stage lines still go to stderr).
    #[arg(long)]
    json: bool,
}

fn run(args: &Args) -> tetrasim::Result<()> {
    let options = PrepOptions {
        quality: (args.quality != 0.0).then_some(args.quality),
        max_volume: args.max_volume,
        preserve_surface: args.preserve_surface,
        target_tets: args.target_tets,
        scale: args.scale,
        mesher: args.mesher,
        fallback: args.fallback,
        ..Default::default()
    };
    let out = prep_file(&args.input, &options, &mut |stage| {
        eprintln!("tetprep: {stage}")
    })?;
    let mut written = vec![];
    write_tetgen(&args.output, &out.mesh)?;
    written.push(format!("{}.{{node,ele,face}}", args.output.display()));
    if args.vtk {
        let vtk = PathBuf::from(format!("{}.vtk", args.output.display()));
        write_vtk(&vtk, &out.mesh, None)?;
        written.push(vtk.display().to_string());
    }
    eprintln!("tetprep: wrote {}", written.join(", "));
    if args.json {
        let json = serde_json::to_string_pretty(&out.stats)
            .map_err(|e| tetrasim::Error::param("json", e.to_string()))?;
        println!("{json}");
    } else {
        println!("{}", out.stats);
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tetprep: error: {e}");
            ExitCode::FAILURE
        }
    }
}
