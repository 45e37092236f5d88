//! `tetrasim soak`: a long run that watches itself. It steps a scene (the bundled sphere by
//! default) as `run` does and samples, at regular frames, the process's resident memory,
//! the device memory the allocator holds (`vulkan`), the total energy and the volume;
//! it fails (exit 1) when memory grows by more than `--growth` after the warm-up, the
//! energy rises above its start, the volume leaves its band or the run diverges. Its
//! figures are on its last line (`scripts/soak.sh`, docs/SOAK.md).

use std::time::Instant;

use tetrasim::backend::{Backend, State};
use tetrasim::params::{Method, SimParams};
use tetrasim::physics::elastic_energy;
use tetrasim::problem::Problem;
use tetrasim::schedule::family::ElasticNodes;
use tetrasim::sim::{BackendFactory, Simulation};

use super::output_flags::{output_flags, refuse_given};
use super::RunArgs;

/// Frames of a soak given no `--frames` nor scene.
const DEFAULT_FRAMES: u32 = 100_000;

/// Arguments of `tetrasim soak`.
#[derive(Debug, clap::Args)]
pub struct SoakArgs {
    /// The scene and physics, as for `run` (default: the bundled sphere dropped on the
    /// floor; `--frames` default 100000); outputs are refused.
    #[command(flatten)]
    pub run: RunArgs,
    /// Samples over the run (memory, energy, volume), evenly spaced.
    #[arg(long, default_value_t = 100)]
    pub samples: u32,
    /// Share of the run before memory is compared (allocators and caches settle).
    #[arg(long, default_value_t = 0.1)]
    pub warm_up: f64,
    /// Largest memory growth allowed after the warm-up [%].
    #[arg(long, default_value_t = 1.0)]
    pub growth: f64,
    /// Largest distance of the volume from the rest volume [%].
    #[arg(long, default_value_t = 5.0)]
    pub volume_band: f64,
}

/// The soak's bounds.
#[derive(Debug, Clone, Copy)]
struct Bounds {
    /// [`SoakArgs::warm_up`].
    warm_up: f64,
    /// [`SoakArgs::growth`] [%].
    growth: f64,
    /// [`SoakArgs::volume_band`] [%].
    volume_band: f64,
    /// The energy's rounding allowance [J]: 1 % of the body's weight times a centimetre.
    energy_slack: f64,
}

/// What one sample measured.
#[derive(Debug, Clone, Copy)]
struct Sample {
    frame: u32,
    resident: u64,
    device: Option<u64>,
    energy: f64,
    volume_pct: f64,
}

/// Runs the soak of every method the arguments select.
pub fn execute(args: SoakArgs) -> anyhow::Result<()> {
    refuse_outputs(&args.run)?;
    if args.samples < 2 || !(0.0..1.0).contains(&args.warm_up) {
        return Err(tetrasim::Error::param(
            "samples",
            "soak needs at least 2 samples and a warm-up share in [0, 1)",
        )
        .into());
    }
    let (scene, methods) = args.run.scene_and_methods()?;
    let backend = args.run.backend.as_deref().unwrap_or("cpu");
    let staged = args.run.stage(&scene)?;
    let frames = match args.run.solver.frames.is_none() && args.run.scene.is_none() {
        true => DEFAULT_FRAMES,
        false => staged.frames,
    };
    let gpu = args.run.gpu.engine_options();
    crate::runner::preflight(backend, &staged.model, &staged.params, &methods, 0, &gpu)?;
    let mut failed = Vec::new();
    for method in methods {
        let params = SimParams {
            method,
            ..staged.params.clone()
        };
        let problem = Problem::new(&staged.model, &params)?;
        let mut engine = BackendFactory::new(gpu.clone()).create(backend, &problem)?;
        let started = Instant::now();
        let (samples, diverged) = soak(&args, &problem, engine.as_mut(), frames)?;
        let mass: f64 = problem.model.mass.iter().sum();
        let bounds = Bounds {
            warm_up: args.warm_up,
            growth: args.growth,
            volume_band: args.volume_band,
            energy_slack: 0.01 * mass * problem.params.gravity.length() * 0.01,
        };
        let verdict = match diverged {
            // "diverged at frame F, substep S ...: why".
            Some(divergence) => Err(divergence),
            None => judge(&bounds, &samples),
        };
        let line = summary(&samples, args.warm_up, started.elapsed().as_secs_f64());
        let name = format!("{} {} {}", staged.label, engine.name(), method.name());
        match &verdict {
            Ok(()) => println!("soak {name}: {line}: PASS"),
            Err(why) => {
                println!("soak {name}: {line}: FAIL ({why})");
                failed.push(name);
            }
        }
    }
    match failed.is_empty() {
        true => Ok(()),
        false => anyhow::bail!("soak failed: {}", failed.join(", ")),
    }
}

/// The run's samples, the first before any frame, and its divergence if it diverged (the
/// run stops there).
fn soak(
    args: &SoakArgs,
    problem: &Problem,
    backend: &mut dyn Backend,
    frames: u32,
) -> anyhow::Result<(Vec<Sample>, Option<String>)> {
    let (model, params) = (&problem.model, &problem.params);
    let mut sim = Simulation::new(model, params);
    let every = (frames / args.samples).max(1);
    let elastic = (params.method == Method::NeoHookean).then(|| ElasticNodes::prepare(problem));
    let elastic = elastic.as_ref();
    let mut samples = vec![measure(problem, backend, elastic, 0)?];
    while sim.frames() < frames {
        let n = every.min(frames - sim.frames());
        sim.advance_frames(backend, n, &|_| false, &mut |_| {})?;
        if sim.stopped() {
            return Ok((samples, sim.divergence.clone()));
        }
        samples.push(measure(problem, backend, elastic, sim.frames())?);
        let last = samples[samples.len() - 1];
        if !last.energy.is_finite() || !last.volume_pct.is_finite() {
            break;
        }
    }
    Ok((samples, None))
}

/// One sample at `frame`.
fn measure(
    problem: &Problem,
    backend: &mut dyn Backend,
    elastic: Option<&ElasticNodes<f64>>,
    frame: u32,
) -> anyhow::Result<Sample> {
    let state = backend.state()?;
    let volume = backend.volume()?;
    let rest: f64 = problem.model.rest_volume.iter().sum();
    let device = backend.gpu_report()?.map(|r| r.memory_in_use);
    Ok(Sample {
        frame,
        resident: resident_bytes(),
        device,
        energy: energy(&state, problem, elastic),
        volume_pct: 100.0 * volume.volume / rest,
    })
}

/// Kinetic + gravitational (above `y = 0`) + elastic energy [J]: the springs' with their
/// stiffness, the finite elements' with their material (`elastic`; the volume constraints
/// store none).
fn energy(state: &State, problem: &Problem, elastic: Option<&ElasticNodes<f64>>) -> f64 {
    let (model, params) = (&problem.model, &problem.params);
    let x = &state.positions;
    let mut e: f64 = (x.iter().zip(&state.velocities).zip(&model.mass))
        .map(|((x, v), &m)| 0.5 * m * v.length_squared() - m * params.gravity.dot(*x))
        .sum();
    match elastic {
        Some(nodes) => {
            e += (model.tets.iter().zip(&nodes.tets))
                .map(|(tet, t)| elastic_energy(t, tet.map(|k| x[k as usize])))
                .sum::<f64>();
        }
        None => {
            let stiffness = &problem.material.spring_stiffness;
            e += (model.springs.iter().enumerate())
                .map(|(s, &[i, j])| {
                    let stretch = x[i as usize].distance(x[j as usize]) - model.rest_length[s];
                    0.5 * stiffness[s] * stretch * stretch
                })
                .sum::<f64>();
        }
    }
    e
}

/// The process's resident memory [bytes] (Linux's `/proc/self/statm`; 0 elsewhere).
fn resident_bytes() -> u64 {
    let pages = std::fs::read_to_string("/proc/self/statm")
        .ok()
        .and_then(|s| s.split_whitespace().nth(1)?.parse::<u64>().ok());
    pages.map_or(0, |p| p * 4096)
}

/// Why the samples fail the soak's bounds, if they do.
fn judge(args: &Bounds, samples: &[Sample]) -> Result<(), String> {
    let last = samples[samples.len() - 1];
    let frames = samples.iter().map(|s| s.frame).max().unwrap_or(0);
    if let Some(s) = samples
        .iter()
        .find(|s| !s.energy.is_finite() || !s.volume_pct.is_finite())
    {
        return Err(format!("not finite at frame {}", s.frame));
    }
    let settled = settled(samples, args.warm_up);
    let growth = |of: &dyn Fn(&Sample) -> Option<u64>| growth_pct(settled, of);
    if let Some(g) = growth(&|s| Some(s.resident)).filter(|&g| g > args.growth) {
        return Err(format!("resident memory grew {g:.2} % after the warm-up"));
    }
    if let Some(g) = growth(&|s| s.device).filter(|&g| g > args.growth) {
        return Err(format!("device memory grew {g:.2} % after the warm-up"));
    }
    let e0 = samples[0].energy;
    // Rounding allowed: 1 % of the start's energy, or of the body's weight times 1 cm.
    let allowed = (0.01 * e0.abs()).max(args.energy_slack);
    if let Some(s) = samples.iter().find(|s| s.energy > e0 + allowed) {
        return Err(format!(
            "the energy rose to {:.6e} J at frame {} (start {e0:.6e} J)",
            s.energy, s.frame
        ));
    }
    if let Some(s) = (samples.iter()).find(|s| (s.volume_pct - 100.0).abs() > args.volume_band) {
        return Err(format!(
            "the volume left its band: {:.3} % at frame {}",
            s.volume_pct, s.frame
        ));
    }
    if frames == 0 || last.frame < frames {
        return Err("no frame ran".into());
    }
    Ok(())
}

/// The samples after the warm-up share of the run.
fn settled(samples: &[Sample], warm_up: f64) -> &[Sample] {
    let frames = samples[samples.len() - 1].frame;
    let start = (samples.iter())
        .position(|s| f64::from(s.frame) >= warm_up * f64::from(frames))
        .unwrap_or(samples.len() - 1);
    &samples[start..]
}

/// Growth [%] of a measure over `samples`: its largest value against its first.
fn growth_pct(samples: &[Sample], of: &dyn Fn(&Sample) -> Option<u64>) -> Option<f64> {
    let first = of(samples.first()?)?;
    let most = samples.iter().filter_map(of).max()?;
    (first > 0).then(|| 100.0 * (most as f64 - first as f64) / first as f64)
}

/// The figures of a soak on one line.
fn summary(samples: &[Sample], warm_up: f64, wall_s: f64) -> String {
    let mib = |b: u64| b as f64 / (1024.0 * 1024.0);
    let settled = settled(samples, warm_up);
    let (first, last) = (settled[0], samples[samples.len() - 1]);
    let pct = |of: &dyn Fn(&Sample) -> Option<u64>| growth_pct(settled, of).unwrap_or(0.0);
    let device = match (first.device, last.device) {
        (Some(a), Some(b)) => format!(
            "device memory {:.2} -> {:.2} MiB (+{:.2} %)",
            mib(a),
            mib(b),
            pct(&|s| s.device)
        ),
        _ => "no device memory".to_string(),
    };
    let energy =
        |f: fn(f64, f64) -> f64| samples.iter().map(|s| s.energy).fold(samples[0].energy, f);
    let volume = |f: fn(f64, f64) -> f64| {
        (samples.iter().map(|s| s.volume_pct)).fold(samples[0].volume_pct, f)
    };
    format!(
        "{} frames in {wall_s:.1} s, resident memory {:.2} -> {:.2} MiB (+{:.2} %), {device}, \
         energy {:.6e} J at start, {:.6e} to {:.6e} J, volume {:.3} to {:.3} %",
        last.frame,
        mib(first.resident),
        mib(last.resident),
        pct(&|s| Some(s.resident)),
        samples[0].energy,
        energy(f64::min),
        energy(f64::max),
        volume(f64::min),
        volume(f64::max),
    )
}

/// `run`'s output flags, which a soak does not write, are refused by name.
fn refuse_outputs(args: &RunArgs) -> tetrasim::Result<()> {
    let why = "`soak` writes nothing but its report; use it with `tetrasim run`";
    refuse_given(&output_flags(args), why)
}

#[cfg(test)]
mod tests {
    use super::*;

    const BOUNDS: Bounds = Bounds {
        warm_up: 0.1,
        growth: 1.0,
        volume_band: 5.0,
        energy_slack: 1e-3,
    };

    /// 11 samples 100 frames apart; `resident(k)` and `device(k)` at sample `k`.
    fn run(resident: impl Fn(u32) -> u64, device: impl Fn(u32) -> Option<u64>) -> Vec<Sample> {
        (0..=10)
            .map(|k| Sample {
                frame: 100 * k,
                resident: resident(k),
                device: device(k),
                energy: 1.0 - 0.01 * f64::from(k),
                volume_pct: 100.0,
            })
            .collect()
    }

    #[test]
    fn memory_that_settles_in_the_warm_up_passes() {
        // Doubles before frame 100 (the warm-up), then flat.
        let samples = run(|k| if k == 0 { 1000 } else { 2000 }, |_| Some(500));
        assert_eq!(judge(&BOUNDS, &samples), Ok(()));
    }

    #[test]
    fn memory_that_creeps_after_the_warm_up_fails() {
        let creeping = run(|k| 1000 + 3 * u64::from(k), |_| None);
        let why = judge(&BOUNDS, &creeping).unwrap_err();
        assert!(why.starts_with("resident memory grew 2.69 %"), "{why}");
        let device = run(|_| 1000, |k| Some(500 + 10 * u64::from(k)));
        let why = judge(&BOUNDS, &device).unwrap_err();
        assert!(why.starts_with("device memory grew"), "{why}");
    }

    #[test]
    fn energy_volume_and_non_finite_values_fail() {
        let mut samples = run(|_| 1000, |_| None);
        samples[5].energy = 1.02;
        assert!(judge(&BOUNDS, &samples)
            .unwrap_err()
            .contains("energy rose"));
        let mut samples = run(|_| 1000, |_| None);
        samples[7].volume_pct = 94.0;
        assert!(judge(&BOUNDS, &samples)
            .unwrap_err()
            .contains("left its band"));
        let mut samples = run(|_| 1000, |_| None);
        samples[3].energy = f64::NAN;
        assert!(judge(&BOUNDS, &samples)
            .unwrap_err()
            .contains("not finite at frame 300"));
    }
}
