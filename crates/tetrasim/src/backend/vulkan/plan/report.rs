//! The plan as text: what `tetrasim plan` prints.

use std::fmt::Write as _;

use super::*;

/// Surface nodes per invocation of MINRES's one workgroup per global row from which `plan`
/// says the model leaves that loop out: on horse86m (95 per invocation) it may add up to
/// about 25 us per MINRES iteration on an H200 (docs/GPU.md, "MINRES's object rows in one
/// workgroup"); the bunny's 13 stay inside the pass's other work.
const MINRES_LOOP_NOTED: u32 = 32;

impl EnginePlan {
    /// The plan as text (what `tetrasim plan` prints).
    pub fn render(&self) -> String {
        let mut out = String::new();
        let c = self.counts;
        let springs = match (self.springs, self.schedule.warm_start) {
            (SpringKind::Explicit, _) => "",
            (SpringKind::Implicit, false) => " with implicit springs",
            (SpringKind::Implicit, true) => " with warm-started implicit springs",
        };
        let _ = writeln!(
            out,
            "method {}{springs}: {} nodes, {} springs, {} tets; {} substeps x {} iterations, \
             workgroup {}",
            self.method,
            c.nodes,
            c.springs,
            c.tets,
            self.schedule.substeps,
            self.schedule.iterations,
            self.workgroup_size
        );
        let _ = writeln!(out, "per time step: {}", self.step_list().join(" -> "));
        if self.schedule.split {
            let _ = writeln!(
                out,
                "split contact: the passes before split_velocity run twice per time step, the \
                 velocity solve then the full solve"
            );
        }
        let sized: Vec<String> = self
            .passes
            .iter()
            .filter(|p| {
                p.workgroup_size != self.workgroup_size || p.lanes() > 1 || p.solves_blocks()
            })
            .map(|p| match (p.lanes(), self.block_shape(p)) {
                (_, Some(b)) => format!(
                    "{} {} ({} blocks, {} colours at most)",
                    p.label(),
                    p.workgroup_size,
                    b.blocks,
                    b.colours
                ),
                (1, None) => format!("{} {}", p.label(), p.workgroup_size),
                (lanes, None) => format!("{} {} ({lanes} a node)", p.label(), p.workgroup_size),
            })
            .collect();
        if !sized.is_empty() {
            let _ = writeln!(out, "workgroups sized to the work: {}", sized.join(", "));
        }
        let frame: Vec<String> = self
            .passes
            .iter()
            .filter(|p| p.stage.repeat == Repeat::Frame)
            .map(PassPlan::label)
            .collect();
        let _ = writeln!(
            out,
            "per frame, after the last step: {} -> copy {} B to the host",
            frame.join(" -> "),
            self.readback_bytes()
        );
        if self.upload_bytes() > 0 {
            let _ = writeln!(
                out,
                "per frame, before its submit: write {} B of collider poses ({} colliders x {} \
                 substeps)",
                self.upload_bytes(),
                self.counts.colliders,
                self.schedule.substeps
            );
        }
        let _ = writeln!(
            out,
            "{:<22} {:>14} {:>10}",
            "buffer", "device bytes", "readback"
        );
        for b in &self.buffers {
            let _ = writeln!(
                out,
                "{:<22} {:>14} {:>10}",
                b.id.name(),
                b.bytes,
                b.readback_bytes
            );
        }
        let _ = writeln!(
            out,
            "total device memory {} B ({:.2} MiB); dispatches per frame {}",
            self.device_bytes(),
            self.device_bytes() as f64 / (1024.0 * 1024.0),
            self.dispatches_per_frame()
        );
        // Each pass's predicted time per run and share of the frame on each modelled GPU.
        let labels: Vec<String> = self.passes.iter().map(PassPlan::label).collect();
        let width = labels.iter().map(String::len).max().unwrap_or(0).max(22);
        let _ = write!(
            out,
            "{:<width$} {:>6} {:>14}",
            "pass", "runs", "bytes per run"
        );
        for gpu in GPU_PROFILES {
            let _ = write!(out, "   {} us per run, % of frame", gpu.name);
        }
        let _ = writeln!(out);
        for (p, label) in self.passes.iter().zip(&labels) {
            let runs = self.runs_per_frame(p);
            let _ = write!(
                out,
                "{label:<width$} {:>6} {:>14}",
                runs,
                self.pass_bytes(p)
            );
            for gpu in GPU_PROFILES {
                let us = gpu.dispatch_us(self, p);
                let share = 0.1 * f64::from(runs) * us / gpu.frame_ms(self);
                let _ = write!(out, " {us:>10.2} {share:>5.1}");
            }
            let _ = writeln!(out);
        }
        let _ = writeln!(
            out,
            "estimated bytes moved per frame {} ({:.2} MiB)",
            self.bytes_per_frame(),
            self.bytes_per_frame() as f64 / (1024.0 * 1024.0)
        );
        let _ = writeln!(
            out,
            "memory-bound time per frame at peak bandwidth (bytes / bandwidth; dispatch and \
             latency costs come on top):"
        );
        for (gpu, bandwidth) in PEAK_BANDWIDTH {
            let _ = writeln!(
                out,
                "  {gpu:<28} {:>7.0} GB/s {:>10.1} us",
                bandwidth / 1e9,
                1e6 * self.bytes_per_frame() as f64 / bandwidth
            );
        }
        let blocks = self.passes.iter().any(|p| p.solves_blocks());
        // A loop the model cannot see, where it may be long enough to matter (the bunny's
        // 13 nodes per invocation stay inside the pass's other work).
        let tail = match self.minres_object_loop() {
            Some((nodes, each)) if each >= MINRES_LOOP_NOTED => format!(
                "; not counted: MINRES's global row, {nodes} surface nodes summed by one \
                 workgroup per object ({each} per invocation) in minres_rows and each \
                 minres_product, docs/GPU.md"
            ),
            _ => String::new(),
        };
        for gpu in GPU_PROFILES {
            let _ = writeln!(
                out,
                "predicted GPU time per frame on {} (cost model: {} us per dispatch, occupancy, \
                 bytes, atomics; docs/GPU.md): {:.3} ms{}{tail}",
                gpu.name,
                gpu.dispatch_us,
                gpu.frame_ms(self),
                match blocks {
                    true => format!(
                        " (block passes at an assumed {} ns per colour, not yet measured)",
                        gpu.block_colour_ns
                    ),
                    false => String::new(),
                }
            );
        }
        out
    }

    /// `10 x (a, b)`, `10 x 8 groups x (a, b)` with several constraint groups,
    /// `10 x (8 groups x (a, b), c)` with passes after the groups, and one such part per
    /// sweep, `10 x (8 groups x (s, b), 8 groups x (a, b), c)`: each sweep's pass followed
    /// by the passes of no sweep.
    fn iteration_label(&self, passes: &[&PassPlan], after: &[String]) -> String {
        let shared: Vec<String> = passes
            .iter()
            .filter(|p| p.stage.sweep.is_none())
            .map(|p| p.label())
            .collect();
        let parts: Vec<(usize, String)> = self
            .schedule
            .sweeps
            .iter()
            .enumerate()
            .map(|(index, sweep)| {
                let mut labels: Vec<String> = passes
                    .iter()
                    .filter(|p| p.stage.sweep == Some(index))
                    .map(|p| match p.stage.repeat {
                        Repeat::FirstIteration => format!("{} (first)", p.label()),
                        Repeat::LastIteration => format!("{} (last)", p.label()),
                        _ => p.label(),
                    })
                    .collect();
                labels.extend(shared.iter().cloned());
                let text = match sweep.groups.len() {
                    0 | 1 => labels.join(", "),
                    k => format!("{k} groups x ({})", labels.join(", ")),
                };
                (sweep.groups.len(), text)
            })
            .collect();
        let it = self.schedule.iterations;
        match (parts.as_slice(), after.is_empty()) {
            ([(0 | 1, part)], true) => format!("{it} x ({part})"),
            ([(_, part)], true) => format!("{it} x {part}"),
            _ => {
                let mut items: Vec<String> = parts.into_iter().map(|(_, text)| text).collect();
                items.extend(after.iter().cloned());
                format!("{it} x ({})", items.join(", "))
            }
        }
    }

    /// `4 x (8 groups x (inversion_floor#gather, constraint_apply#gather), global_volume_sum,
    /// global_volume)`: a restore pass's sweeps after the iterations, each group followed by
    /// the iteration's passes of no sweep (from `iteration`), each sweep by the global volume
    /// passes among the iteration's ends (`ends`).
    fn restore_label(&self, pass: &PassPlan, iteration: &[&PassPlan], ends: &[String]) -> String {
        let mut labels = vec![pass.label()];
        labels.extend(
            (iteration.iter())
                .filter(|p| p.stage.sweep.is_none())
                .map(|p| p.label()),
        );
        let groups = pass
            .stage
            .sweep
            .map_or(1, |s| self.schedule.sweeps[s].groups.len());
        let part = match groups {
            0 | 1 => labels.join(", "),
            k => format!("{k} groups x ({})", labels.join(", ")),
        };
        let global = (ends.iter()).filter(|l| l.starts_with("global_volume"));
        let items: Vec<String> = std::iter::once(part).chain(global.cloned()).collect();
        format!(
            "{} x ({})",
            self.schedule.inversion_sweeps,
            items.join(", ")
        )
    }

    /// Labels of one time step's passes (the iteration group written `N x (a, b)`).
    pub(super) fn step_list(&self) -> Vec<String> {
        let mut out = Vec::new();
        let mut group: Vec<&PassPlan> = Vec::new();
        let mut after: Vec<String> = Vec::new();
        // The iterations' passes stay for the restore label after MINRES's passes.
        let mut iteration: (Vec<&PassPlan>, Vec<String>) = (Vec::new(), Vec::new());
        let mut minres: Vec<String> = Vec::new();
        for p in self
            .passes
            .iter()
            .filter(|p| p.stage.repeat != Repeat::Frame)
        {
            if p.stage.repeat != Repeat::Minres && !minres.is_empty() {
                out.push(format!(
                    "{} x ({})",
                    self.schedule.minres,
                    minres.join(", ")
                ));
                minres.clear();
            }
            let iterates = p.stage.repeat.in_iterations() || p.stage.repeat == Repeat::IterationEnd;
            if !iterates && !group.is_empty() {
                out.push(self.iteration_label(&group, &after));
                iteration = (std::mem::take(&mut group), std::mem::take(&mut after));
            }
            match p.stage.repeat {
                r if r.in_iterations() => group.push(p),
                Repeat::IterationEnd => after.push(p.label()),
                Repeat::Minres => minres.push(p.label()),
                Repeat::Restore => out.push(self.restore_label(p, &iteration.0, &iteration.1)),
                _ => out.push(p.label()),
            }
            if p.stage.kind == PassKind::MinresForces && self.schedule.closes_minres() {
                // MINRES's close: the global volume constraints once more.
                out.extend(
                    (self.passes.iter())
                        .filter(|q| q.stage.kind.is_global_volume())
                        .map(|q| q.label()),
                );
            }
        }
        if !minres.is_empty() {
            out.push(format!(
                "{} x ({})",
                self.schedule.minres,
                minres.join(", ")
            ));
        }
        out
    }
}
