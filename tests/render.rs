//! Offscreen rendering on lavapipe with the validation layer on: the object covers a sane
//! share of the picture, the floor and background have their colours, a falling object's
//! image moves down, the volume colour mode turns squashed tets blue and stretched ones red,
//! a collider is drawn in steel grey where it projects (and moves with its motion), and
//! `render_methods` writes the frames, GIF and sheet it is asked for. Pixels are checked by
//! tolerance, never byte for byte.

mod gpu_support;

use std::sync::Arc;

use glam::DVec3;
use tetrasim::backend::vulkan::{DrawBuffers, EngineOptions, VulkanBackend};
use tetrasim::collider::{Collider, Motion};
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
        let image = renderer
            .render(
                sim.draw_buffers(),
                false,
                f64::from(k * 120) * params.frame_time(),
            )
            .unwrap();
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
    let rest = renderer.render(at(&rest), false, 0.0).unwrap();
    let squashed = renderer.render(at(&squashed), false, 0.0).unwrap();
    let stretched = renderer.render(at(&stretched), true, 0.0).unwrap();
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
    let err = renderer
        .render(at(&short), false, 0.0)
        .unwrap_err()
        .to_string();
    assert!(err.contains("too short") && err.contains("nodes"), "{err}");
    // Another model's springs (fewer than this model's) are refused the same way.
    let springs = DrawBuffers {
        springs: &short,
        ..sim.draw_buffers()
    };
    let err = renderer
        .render(springs, false, 0.0)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("too short") && err.contains("springs"),
        "{err}"
    );
    assert_no_messages(&ctx);
}

/// Pixels of a collider: the cool steel grey (blue above red), neither the warm floor and
/// clay object nor the near-white background.
fn steel(c: [i32; 3]) -> bool {
    c[2] - c[0] >= 10 && c[1] >= c[0] && c[2] <= 215
}

fn steel_pixels(image: &Image, xs: std::ops::Range<u32>, ys: std::ops::Range<u32>) -> usize {
    ys.flat_map(|y| xs.clone().map(move |x| (x, y)))
        .filter(|&(x, y)| steel(image.pixel(x, y).unwrap().map(i32::from)))
        .count()
}

/// Where the world point `p` lands in a `W` x `H` picture of `renderer`'s scene.
fn pixel_of(renderer: &Renderer, p: glam::Vec3) -> (u32, u32) {
    let clip = renderer.scene().view_proj(W as f32 / H as f32) * p.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    (
        ((ndc.x + 1.0) * 0.5 * W as f32) as u32,
        ((ndc.y + 1.0) * 0.5 * H as f32) as u32,
    )
}

/// A box model and a ball collider of radius 0.15 m beside it, 0.1 m above the floor.
fn box_and_ball(motion: Motion) -> (Model, Model, DVec3) {
    let model = gpu_support::box_model([4, 3, 2], 0.1);
    let (_, hi) = tetrasim::mesh::bounds_of(&model.positions).unwrap();
    let centre = DVec3::new(hi.x + 0.35, 0.25, 0.0);
    let ball = Collider::sphere(centre, 0.15).moving(motion);
    let with = model.clone().with_colliders([ball]).unwrap();
    (model, with, centre)
}

#[test]
fn a_collider_is_drawn_in_steel_grey_where_it_projects() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let ctx = context();
    let (bare, with, centre) = box_and_ball(Motion::Fixed);
    let sim =
        VulkanBackend::with_context(ctx.clone(), &bare, &SimParams::default(), Some(64)).unwrap();
    let mut drawn = Renderer::new(&ctx, &with, &options(ColourMode::Flat)).unwrap();
    // The same camera without the collider.
    let same_camera = RenderOptions {
        camera: Some(drawn.scene().camera),
        ..options(ColourMode::Flat)
    };
    let mut without = Renderer::new(&ctx, &bare, &same_camera).unwrap();
    let a = drawn.render(sim.draw_buffers(), false, 0.0).unwrap();
    let b = without.render(sim.draw_buffers(), false, 0.0).unwrap();
    let (x, y) = pixel_of(&drawn, centre.as_vec3());
    assert!(
        x > 8 && x < W - 8 && y > 8 && y < H - 8,
        "the ball is at ({x}, {y})"
    );
    let window = |image: &Image| steel_pixels(image, x - 3..x + 4, y - 3..y + 4);
    assert!(
        window(&a) >= 40,
        "{} of 49 steel pixels at the ball",
        window(&a)
    );
    assert_eq!(window(&b), 0, "steel pixels without the collider");
    let all = |image: &Image| steel_pixels(image, 0..W, 0..H);
    assert!(all(&a) > 100, "{} steel pixels", all(&a));
    assert!(all(&b) < 5, "{} steel pixels without the collider", all(&b));
    // The object is still drawn, in its own colour.
    assert!(object_pixels(&a).len() > 200);
    assert_no_messages(&ctx);
}

#[test]
fn a_moving_collider_is_drawn_where_it_is_at_the_pictures_time() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let ctx = context();
    // Rising at 0.5 m/s: 0.2 m higher after 0.4 s.
    let up = Motion::Velocity {
        linear: DVec3::new(0.0, 0.5, 0.0),
        angular: DVec3::ZERO,
    };
    let (bare, with, centre) = box_and_ball(up);
    let sim =
        VulkanBackend::with_context(ctx.clone(), &bare, &SimParams::default(), Some(64)).unwrap();
    let mut renderer = Renderer::new(&ctx, &with, &options(ColourMode::Flat)).unwrap();
    let centroid = |image: &Image| {
        let pixels: Vec<(u32, u32)> = (0..H)
            .flat_map(|y| (0..W).map(move |x| (x, y)))
            .filter(|&(x, y)| steel(image.pixel(x, y).unwrap().map(i32::from)))
            .collect();
        assert!(pixels.len() > 100, "{} steel pixels", pixels.len());
        let n = pixels.len() as f64;
        (
            pixels.iter().map(|p| f64::from(p.0)).sum::<f64>() / n,
            pixels.iter().map(|p| f64::from(p.1)).sum::<f64>() / n,
        )
    };
    let start = renderer.render(sim.draw_buffers(), false, 0.0).unwrap();
    let later = renderer.render(sim.draw_buffers(), false, 0.4).unwrap();
    let (x0, y0) = centroid(&start);
    let (x1, y1) = centroid(&later);
    let (_, expected) = pixel_of(&renderer, (centre + DVec3::new(0.0, 0.2, 0.0)).as_vec3());
    let (_, first) = pixel_of(&renderer, centre.as_vec3());
    assert!(y1 < y0 - 5.0, "the ball rose from row {y0:.1} to {y1:.1}");
    assert!(
        (y0 - f64::from(first)).abs() < 3.0 && (y1 - f64::from(expected)).abs() < 3.0,
        "rows {y0:.1}, {y1:.1}; projected centres {first}, {expected}"
    );
    assert!((x1 - x0).abs() < 3.0, "columns {x0:.1} -> {x1:.1}");
    // Rendering t = 0 again puts it back.
    let again = renderer.render(sim.draw_buffers(), false, 0.0).unwrap();
    assert!((centroid(&again).1 - y0).abs() < 0.5);
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
        physics: None,
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

/// A PNG written by the renderer, back as an [`Image`].
fn read_png(path: &std::path::Path) -> Image {
    let mut decoder =
        png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::ALPHA);
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgba);
    buf.truncate(info.buffer_size());
    Image {
        width: info.width,
        height: info.height,
        rgba: buf,
    }
}

#[test]
fn render_methods_steps_on_the_cpu_and_draws_its_state() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let ctx = context();
    let model = gpu_support::box_model([4, 3, 2], 0.1);
    let params = SimParams {
        method: Method::Volume,
        iterations: 2,
        floor: false,
        ..SimParams::default()
    };
    let dir = tempfile::tempdir().unwrap();
    let frames = 240;
    let job = RenderJob {
        frames,
        methods: vec![Method::Volume],
        render: options(ColourMode::Flat),
        outputs: Outputs {
            frames_dir: Some(dir.path().to_path_buf()),
            every: frames,
            ..Default::default()
        },
        engine: EngineOptions::default(),
        physics: Some("cpu-ref".into()),
        progress: false,
    };
    let report = render_methods(&ctx, &model, &params, &job).unwrap();
    // The same run on cpu-ref alone: the same volumes (the CPU stepped).
    let mut cpu = tetrasim::create_backend("cpu-ref", &model, &params).unwrap();
    let mut sim = tetrasim::sim::Simulation::new(&model, &params);
    for _ in 0..frames {
        sim.advance(cpu.as_mut(), true).unwrap();
    }
    let m = &report.methods[0];
    assert_eq!(m.frames_run, frames);
    assert_eq!(m.final_volume_pct, sim.last_volume_pct().unwrap());
    // The last picture shows the CPU's state: the box has fallen 0.29 m (in 0.24 s).
    let row = |frame: u32| {
        let image = read_png(&dir.path().join(format!("volume_{frame:05}.png")));
        let object = object_pixels(&image);
        object.iter().map(|&(_, y)| f64::from(y)).sum::<f64>() / object.len() as f64
    };
    assert!(
        row(frames) > row(0) + 8.0,
        "rows {} -> {}",
        row(0),
        row(frames)
    );
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
