//! `tetprep INPUT -o PREFIX`: surface scan in, `PREFIX.node/.ele/.face` out (and `PREFIX.vtk`
//! with `--vtk`), stats after every run. Errors go to stderr with a non-zero exit; nothing
//! is written unless meshing succeeded, and every file is written atomically.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, ValueEnum};
use tetrasim::mesh::io::{read_surface, write_surface, write_tetgen, write_vtk};
use tetrasim::mesh::shapes::Shape;
use tetrasim::prep::{prep_surface, Mesher, PrepOptions};
use tetrasim::SurfaceMesh;

/// Converts a triangle surface (PLY, OBJ, OFF, STL) into a tetrahedral mesh: repairs it
/// (welds, drops degenerate/duplicate faces, orients, fills holes), simplifies it when the
/// target needs it, meshes it with TetGen or the voxel mesher and prints the mesh's stats.
#[derive(Debug, Parser)]
#[command(version)]
struct Args {
    /// The surface file (.ply, .obj, .off, .stl).
    #[arg(required_unless_present = "shape")]
    input: Option<PathBuf>,
    /// Mesh a surface made by code instead of reading one (the shapes in meshes/).
    #[arg(long, value_enum, conflicts_with = "input")]
    shape: Option<Shape>,
    /// Also write the input surface (after --scale) to this file (.ply, .obj, .off, .stl).
    #[arg(long)]
    save_surface: Option<PathBuf>,
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
    /// Aim for about this many tets (within 25 %). Keeps the surface as given (TetGen -Y)
    /// and simplifies it first when it has more than N/4 faces.
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
    let mut progress = |stage: &str| eprintln!("tetprep: {stage}");
    let surface = match (&args.input, args.shape) {
        (_, Some(shape)) => shape.surface(),
        (Some(path), None) => {
            progress(&format!("reading {}", path.display()));
            read_surface(path)?
        }
        (None, None) => {
            return Err(tetrasim::Error::param(
                "input",
                "give an input file or --shape",
            ))
        }
    };
    if let Some(path) = &args.save_surface {
        let scaled = SurfaceMesh {
            vertices: surface.vertices.iter().map(|p| *p * args.scale).collect(),
            triangles: surface.triangles.clone(),
        };
        write_surface(path, &scaled)?;
        progress(&format!("wrote the surface to {}", path.display()));
    }
    let name = match (&args.input, args.shape) {
        (Some(path), _) => path.display().to_string(),
        (None, shape) => format!(
            "--shape {}",
            shape
                .and_then(|s| s.to_possible_value())
                .map(|v| v.get_name().to_string())
                .unwrap_or_default()
        ),
    };
    let mut out = prep_surface(&surface, &options, &mut progress).map_err(|e| match e {
        tetrasim::Error::Mesh(m) => tetrasim::Error::Mesh(format!("{name}: {m}")),
        tetrasim::Error::Meshing(m) => tetrasim::Error::Meshing(format!("{name}: {m}")),
        e => e,
    })?;
    out.stats.input = Some(name);
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
