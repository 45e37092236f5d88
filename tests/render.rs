//! Offscreen rendering on lavapipe with the validation layer on: the object covers a sane
//! share of the picture, the floor and background have their colours, a falling object's
//! image moves down, the volume colour mode turns squashed tets blue and stretched ones red,
//! and `render_methods` writes the frames, GIF and sheet it is asked for. Pixels are checked
//! by tolerance, never byte for byte.

mod gpu_support;

use std::sync::Arc;

use tetrasim::backend::vulkan::{DrawBuffers, EngineOptions, VulkanBackend};
use tetrasim::gpu::{Buffer, Context, ContextOptions};
use tetrasim::params::{Method, SimParams};
use tetrasim::render::legend::LegendLayout;
use tetrasim::render::style::{BACKGROUND_RGB, FLOOR_RGB, GRID_RGB};
use tetrasim::render::{ColourMode, Image, RenderOptions, Renderer};
use tetrasim::{Backend, Model};
use tetrasim_cli::render_session::{render_methods, Outputs, RenderJob};

const W: u32 = 160;
const H: u32 = 120;

fn context() -> Arc<Context> {
    Arc::new(
        Context::new(&ContextOptions {
            validation: true,
            ..Default::default()
        })
        .unwrap(),
    )
}

fn options(colour: ColourMode) -> RenderOptions {
    RenderOptions {
        width: W,
        height: H,
        colour,
        ..Default::default()
    }
}

fn assert_no_messages(ctx: &Context) {
    let messages = ctx.validation_messages();
    assert!(
        messages.is_empty(),
        "{} validation messages:\n{}",
        messages.len(),
        messages.join("\n")
    );
}

/// Pixels of the clay-coloured object in the flat mode: clearly warmer than the grey floor,
/// background and shadow.
fn object_pixels(image: &Image) -> Vec<(u32, u32)> {
    (0..image.height)
        .flat_map(|y| (0..image.width).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let [r, _, b] = image.pixel(x, y).unwrap();
            i32::from(r) - i32::from(b) > 30
        })
        .collect()
}

fn count(image: &Image, keep: impl Fn([i32; 3]) -> bool) -> usize {
    (0..image.height)
        .flat_map(|y| (0..image.width).map(move |x| (x, y)))
        .filter(|&(x, y)| keep(image.pixel(x, y).unwrap().map(i32::from)))
        .count()
}

fn mean(image: &Image, xs: std::ops::Range<u32>, ys: std::ops::Range<u32>) -> [f64; 3] {
    let mut sum = [0.0; 3];
    let mut n = 0.0;
    for y in ys {
        for x in xs.clone() {
            let p = image.pixel(x, y).unwrap();
            for c in 0..3 {
                sum[c] += f64::from(p[c]);
            }
            n += 1.0;
        }
    }
    sum.map(|s| s / n)
}

/// The model's positions with `f` applied, as a vec4-per-node GPU buffer.
fn positions_buffer(
    ctx: &Arc<Context>,
    model: &Model,
    f: impl Fn(glam::DVec3) -> glam::DVec3,
) -> Buffer {
    let data: Vec<[f32; 4]> = model
        .positions
        .iter()
        .map(|&p| {
            let q = f(p);
            [q.x as f32, q.y as f32, q.z as f32, 1.0]
        })
        .collect();
    Buffer::with_data(ctx, "test positions", bytemuck::cast_slice(&data)).unwrap()
}

#[test]
fn a_falling_box_moves_down_over_a_floor_of_the_right_colour() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let ctx = context();
    let model = gpu_support::box_model([4, 3, 2], 0.1);
    let params = SimParams {
        method: Method::Mss,
        floor: false,
        ..SimParams::default()
    };
    let mut sim = VulkanBackend::with_context(ctx.clone(), &model, &params, Some(64)).unwrap();
    let mut renderer = Renderer::new(&ctx, &model, &options(ColourMode::Flat)).unwrap();
    let mut centroids = Vec::new();
    for k in 0..3 {
        if k > 0 {
            for _ in 0..120 {
                sim.step_frame().unwrap();
            }
        }
        let image = renderer.render(sim.draw_buffers(), false).unwrap();
        let object = object_pixels(&image);
        let share = object.len() as f64 / f64::from(W * H);
        assert!(
            (0.02..0.45).contains(&share),
            "frame {k}: the object covers {:.1} % of the image",
            100.0 * share
        );
        let cy = object.iter().map(|&(_, y)| f64::from(y)).sum::<f64>() / object.len() as f64;
        centroids.push(cy);
        if k == 0 {
            // Background above the horizon, floor at the bottom (between grid and floor grey).
            let top = mean(&image, 0..W, 0..4);
            for c in 0..3 {
                assert!(
                    (top[c] - f64::from(BACKGROUND_RGB[c])).abs() < 8.0,
                    "background {top:?}"
                );
            }
            let bottom = mean(&image, W / 2 - 10..W / 2 + 10, H - 6..H);
            for c in 0..3 {
                let (lo, hi) = (f64::from(GRID_RGB[c]) - 6.0, f64::from(FLOOR_RGB[c]) + 6.0);
                assert!(
                    (lo..hi).contains(&bottom[c]),
                    "floor {bottom:?} not within grid {GRID_RGB:?} .. floor {FLOOR_RGB:?}"
                );
            }
        }
    }
    // Free fall of 0.12 s and then 0.24 s: 0.07 m, then 0.28 m further down.
    assert!(centroids[1] > centroids[0] + 1.5, "{centroids:?}");
    assert!(centroids[2] > centroids[1] + 4.0, "{centroids:?}");
    assert_no_messages(&ctx);
}

#[test]
fn volume_colours_show_squashed_blue_and_stretched_red() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let ctx = context();
    let model = gpu_support::box_model([4, 3, 2], 0.1);
    let mut renderer = Renderer::new(&ctx, &model, &options(ColourMode::Volume)).unwrap();
    // The tets and rest volumes come from a simulation of the model; the positions are ours.
    let sim =
        VulkanBackend::with_context(ctx.clone(), &model, &SimParams::default(), Some(64)).unwrap();
    let at = |positions| DrawBuffers {
        positions,
        ..sim.draw_buffers()
    };
    let base = model
        .positions
        .iter()
        .map(|p| p.y)
        .fold(f64::INFINITY, f64::min);
    let scaled = |s: f64| move |p: glam::DVec3| glam::DVec3::new(p.x, base + s * (p.y - base), p.z);
    let blue = |c: [i32; 3]| c[2] - c[0] > 40;
    let red = |c: [i32; 3]| c[0] - c[2] > 40;

    let [rest, squashed, stretched] =
        [1.0, 0.6, 1.4].map(|s| positions_buffer(&ctx, &model, scaled(s)));
    let rest = renderer.render(at(&rest), false).unwrap();
    let squashed = renderer.render(at(&squashed), false).unwrap();
    let stretched = renderer.render(at(&stretched), true).unwrap();
    let pixels = f64::from(W * H);
    let share = |image: &Image, keep: &dyn Fn([i32; 3]) -> bool| count(image, keep) as f64 / pixels;
    assert!(
        share(&rest, &blue) < 0.002 && share(&rest, &red) < 0.002,
        "the rest shape is coloured"
    );
    assert!(
        share(&squashed, &blue) > 0.02,
        "squashed: {:.3} blue",
        share(&squashed, &blue)
    );
    assert!(share(&squashed, &red) < 0.002);
    assert!(
        share(&stretched, &red) > 0.02,
        "stretched: {:.3} red",
        share(&stretched, &red)
    );

    // The legend (drawn in the last render): red at the top of its bar, blue at the bottom.
    let [x0, y0, x1, y1] = LegendLayout::for_size(W, H).bar;
    let top = stretched
        .pixel((x0 + x1) / 2, y0 + 3)
        .unwrap()
        .map(i32::from);
    let bottom = stretched
        .pixel((x0 + x1) / 2, y1 - 4)
        .unwrap()
        .map(i32::from);
    assert!(
        red(top) && blue(bottom),
        "legend top {top:?}, bottom {bottom:?}"
    );

    let short = Buffer::with_data(&ctx, "too short", &[0u8; 32]).unwrap();
    let err = renderer.render(at(&short), false).unwrap_err().to_string();
    assert!(err.contains("too short") && err.contains("nodes"), "{err}");
    // Another model's springs (fewer than this model's) are refused the same way.
    let springs = DrawBuffers {
        springs: &short,
        ..sim.draw_buffers()
    };
    let err = renderer.render(springs, false).unwrap_err().to_string();
    assert!(
        err.contains("too short") && err.contains("springs"),
        "{err}"
    );
    assert_no_messages(&ctx);
}

#[test]
fn render_methods_writes_frames_gif_and_sheet() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let ctx = context();
    let model = gpu_support::box_model([3, 2, 2], 0.1);
    let dir = tempfile::tempdir().unwrap();
    let (w, h) = (64, 48);
    let job = RenderJob {
        frames: 20,
        methods: vec![Method::Mss, Method::Volume],
        render: RenderOptions {
            width: w,
            height: h,
            ..Default::default()
        },
        outputs: Outputs {
            frames_dir: Some(dir.path().join("frames")),
            every: 10,
            gif: Some(dir.path().join("a.gif")),
            gif_every: Some(5),
            sheet: Some(dir.path().join("sheet.png")),
            sheet_columns: 3,
            meshes: None,
        },
        engine: EngineOptions {
            workgroup_size: Some(64),
            ..EngineOptions::default()
        },
        progress: false,
    };
    let params = SimParams {
        iterations: 2,
        ..SimParams::default()
    };
    let report = render_methods(&ctx, &model, &params, &job).unwrap();
    assert_eq!(report.methods.len(), 2);
    for m in &report.methods {
        assert_eq!(m.frames_run, 20);
        assert!(
            m.min_volume_pct > 50.0 && m.min_volume_pct <= 100.0,
            "{m:?}"
        );
    }
    let png_size = |path: &std::path::Path| {
        let reader = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()))
            .read_info()
            .unwrap();
        (reader.info().width, reader.info().height)
    };
    for method in ["mss", "volume"] {
        for frame in [0, 10, 20] {
            let path = dir
                .path()
                .join("frames")
                .join(format!("{method}_{frame:05}.png"));
            assert_eq!(png_size(&path), (w, h), "{}", path.display());
        }
    }
    let (sw, sh) = png_size(&dir.path().join("sheet.png"));
    assert!(sw > 3 * w && sh > 2 * h, "sheet {sw}x{sh}");
    let mut decoder = gif::DecodeOptions::new();
    decoder.set_color_output(gif::ColorOutput::RGBA);
    let mut reader = decoder
        .read_info(std::fs::File::open(dir.path().join("a.gif")).unwrap())
        .unwrap();
    assert_eq!(
        (u32::from(reader.width()), u32::from(reader.height())),
        (2 * w, h)
    );
    let mut frames = 0;
    while reader.read_next_frame().unwrap().is_some() {
        frames += 1;
    }
    assert_eq!(frames, 5, "GIF frames at 0, 5, 10, 15, 20");
    // Sheet frames 0, 10, 20 coincide with PNG frames: no frame is drawn more than twice
    // (with and without legend) per method.
    assert!(report.images <= 2 * 2 * 5, "{} images", report.images);
    assert!(report.render_s > 0.0 && report.step_s > 0.0);
    assert_no_messages(&ctx);
}

#[test]
fn the_cli_writes_a_sheet_and_names_bad_flags() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("box");
    let mesh = tetrasim::mesh::grid::box_tets(glam::DVec3::ZERO, 0.1, [3, 2, 2]);
    tetrasim::mesh::io::write_tetgen(&prefix, &mesh).unwrap();
    let sheet = dir.path().join("sheet.png");
    let tetrasim = || {
        let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_tetrasim"));
        c.args([
            "render",
            "--preset",
            "seed",
            "--frames",
            "4",
            "--iterations",
            "2",
            "--quiet",
        ])
        .arg("--mesh")
        .arg(&prefix);
        c
    };
    let output = tetrasim()
        .args([
            "--method",
            "all",
            "--size",
            "64x48",
            "--sheet-frames",
            "2",
            "--validation",
        ])
        .arg("--sheet")
        .arg(&sheet)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stdout}\n{stderr}");
    for method in ["mss", "distance", "volume"] {
        assert!(
            stdout.lines().any(|l| l.starts_with(method)),
            "no `{method}` row:\n{stdout}"
        );
    }
    assert!(!stderr.contains("validation:"), "{stderr}");
    let reader = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(&sheet).unwrap(),
    ))
    .read_info()
    .unwrap();
    assert!(reader.info().width > 2 * 64 && reader.info().height > 3 * 48);

    for (flags, expected) in [
        (vec!["--sheet", "x.png", "--size", "10x10"], "size"),
        (vec!["--sheet", "x.png", "--camera", "1,2,3"], "camera"),
        (vec![], "nothing to write"),
    ] {
        let output = tetrasim().args(&flags).output().unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{flags:?} succeeded");
        assert!(stderr.contains(expected), "{flags:?}: {stderr}");
    }
}
