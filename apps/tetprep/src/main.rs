//! `tetprep INPUT -o PREFIX`: surface scan in, `PREFIX.node/.ele/.face` out (and `PREFIX.vtk`
//! with `--vtk`), stats after every run. Output folders are made (and bad output paths
//! refused) before any work; errors go to stderr with a non-zero exit; nothing is written
//! unless meshing succeeded, and every file is written atomically.

mod output;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, ValueEnum};
use output::{output_prefix, with_ext, MadeFolders};
use tetmesh::mesh::io::{read_surface, write_surface, write_tetgen, write_vtk, SurfaceFormat};
use tetmesh::mesh::shapes::Shape;
use tetmesh::prep::{prep_surface, Mesher, PrepOptions, StageTime};

/// Converts a triangle surface (PLY, OBJ, OFF, STL) into a tetrahedral mesh: repairs it
/// (welds, drops degenerate/duplicate faces, orients, fills holes), simplifies it when the
/// target needs it, meshes it with TetGen or the voxel mesher and prints the mesh's stats.
#[derive(Debug, Parser)]
#[command(version, allow_negative_numbers = true)]
struct Args {
    /// The surface file (.ply, .obj, .off, .stl).
    #[arg(required_unless_present = "shape")]
    input: Option<PathBuf>,
    /// Mesh a surface made by code instead of reading one (the shapes in meshes/).
    #[arg(long, value_enum, conflicts_with = "input")]
    shape: Option<Shape>,
    /// Also write the surface that went into the mesher to this file (.ply, .obj, .off,
    /// .stl): the input after --scale, repair and, when --target-tets needs it,
    /// simplification. Missing folders are made.
    #[arg(long, value_name = "FILE")]
    save_surface: Option<PathBuf>,
    /// Output prefix: writes PREFIX.node, PREFIX.ele, PREFIX.face (and PREFIX.vtk with
    /// --vtk). A tet-mesh extension (.node, .ele, .face, .vtk, .vtu, .msh, .mesh) is dropped,
    /// so `-o out/bunny.node` also writes out/bunny.node, out/bunny.ele, out/bunny.face.
    /// Missing folders (`out/` here) are made before any work starts.
    #[arg(short, long, value_name = "PREFIX")]
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
    /// and simplifies it first when it has more than N/2 faces.
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
    /// Keep the mesher's numbering of nodes and tets (by default both are renumbered along a
    /// Morton curve, so a tet's nodes sit together in memory: about twice as fast to
    /// simulate on large meshes).
    #[arg(long)]
    keep_order: bool,
    /// Also write PREFIX.vtk (legacy VTK, for ParaView).
    #[arg(long)]
    vtk: bool,
    /// Write the stats as JSON to FILE (its folder is made first), or print them on stdout
    /// instead of the table when no FILE (or `-`) is given; stage lines go to stderr.
    #[arg(long, num_args = 0..=1, default_missing_value = "-", value_name = "FILE")]
    json: Option<PathBuf>,
}

fn run(args: &Args, made: &mut MadeFolders) -> tetmesh::Result<()> {
    let options = PrepOptions {
        quality: (args.quality != 0.0).then_some(args.quality),
        max_volume: args.max_volume,
        preserve_surface: args.preserve_surface,
        target_tets: args.target_tets,
        scale: args.scale,
        mesher: args.mesher,
        fallback: args.fallback,
        keep_order: args.keep_order,
        ..Default::default()
    };
    // Everything that can be refused without reading or meshing is checked first, and the
    // output folders exist before any work starts.
    options.validate()?;
    let prefix = output_prefix(&args.output)?;
    if let Some(path) = &args.save_surface {
        SurfaceFormat::from_path(path)
            .map_err(|e| tetmesh::Error::param("save-surface", e.to_string()))?;
    }
    made.make_parent_of(&prefix, "output")?;
    if let Some(path) = &args.save_surface {
        made.make_parent_of(path, "save-surface")?;
    }
    if let Some(path) = args.json.as_deref().filter(|p| *p != Path::new("-")) {
        if path.is_dir() {
            return Err(tetmesh::Error::param(
                "json",
                format!("{} is a folder; give a file name", path.display()),
            ));
        }
        made.make_parent_of(path, "json")?;
    }
    for dir in made.made() {
        eprintln!("tetprep: made the folder {}", dir.display());
    }
    let mut progress = |stage: &str| eprintln!("tetprep: {stage}");
    let read_started = std::time::Instant::now();
    let surface = match (&args.input, args.shape) {
        (_, Some(shape)) => shape.surface(),
        (Some(path), None) => {
            progress(&format!("reading {}", path.display()));
            read_surface(path)?
        }
        (None, None) => {
            return Err(tetmesh::Error::param(
                "input",
                "give an input file or --shape",
            ))
        }
    };
    let read_time = read_started.elapsed();
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
        tetmesh::Error::Mesh(m) => tetmesh::Error::Mesh(format!("{name}: {m}")),
        tetmesh::Error::Meshing(m) => tetmesh::Error::Meshing(format!("{name}: {m}")),
        e => e,
    })?;
    out.stats.input = Some(name);
    if args.input.is_some() {
        let seconds = read_time.as_secs_f64();
        out.stats.times.insert(
            0,
            StageTime {
                stage: "read".into(),
                seconds,
            },
        );
        out.stats.total_seconds += seconds;
    }
    let mut written = vec![];
    write_tetgen(&prefix, &out.mesh)?;
    written.push(format!("{}.{{node,ele,face}}", prefix.display()));
    if args.vtk {
        let vtk = with_ext(&prefix, "vtk");
        write_vtk(&vtk, &out.mesh, None)?;
        written.push(vtk.display().to_string());
    }
    if let Some(path) = &args.save_surface {
        write_surface(path, &out.surface)?;
        written.push(format!(
            "{} (the meshed surface, {} faces)",
            path.display(),
            out.surface.triangles.len()
        ));
    }
    eprintln!("tetprep: wrote {}", written.join(", "));
    let json = || {
        serde_json::to_string_pretty(&out.stats)
            .map_err(|e| tetmesh::Error::param("json", e.to_string()))
    };
    match args.json.as_deref() {
        Some(path) if path == Path::new("-") => println!("{}", json()?),
        Some(path) => {
            let text = json()?;
            tetmesh::mesh::io::write_atomic(path, |w| writeln!(w, "{text}"))?;
            eprintln!("tetprep: stats written to {}", path.display());
            println!("{}", out.stats);
        }
        None => println!("{}", out.stats),
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    let mut made = MadeFolders::default();
    match run(&args, &mut made) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            if !made.made().is_empty() {
                made.remove_empty();
                eprintln!("tetprep: removed the folders it made (those still empty)");
            }
            eprintln!("tetprep: error: {e}");
            ExitCode::FAILURE
        }
    }
}
