//! What `tetrasim tradeoff` concludes: Pareto fronts, the cheapest setting per volume-error
//! budget, substeps against iterations at equal cost and equal work, and the Markdown report
//! (the files are written by [`super::tradeoff_files`]).

use std::fmt::Write as _;

use super::tradeoff::TradeoffRecord;

/// Volume-error budgets [%] the report answers "cheapest setting" for.
pub const VOLUME_BUDGETS: [f64; 6] = [10.0, 5.0, 2.0, 1.0, 0.5, 0.2];

/// Local volume error budgets [%] of the "which solver for which budget" table (the global
/// volume constraint holds the total, so the local error tells the solvers apart).
pub const LOCAL_BUDGETS: [f64; 6] = [2.0, 1.0, 0.5, 0.25, 0.15, 0.1];

/// Cost ratio within which two settings count as "equal cost".
pub const EQUAL_COST_RATIO: f64 = 1.5;

fn setting(r: &TradeoffRecord) -> String {
    format!(
        "{} it {} ss {} omega {}",
        r.series(),
        r.iterations,
        r.substeps,
        r.omega
    )
}

fn pos(e: Option<f64>) -> String {
    e.map_or("-".to_string(), |e| format!("{e:.2e}"))
}

/// The Pareto front of (cost, volume error), cheapest first, as a table.
pub fn front_table(records: &[TradeoffRecord]) -> String {
    let mut front: Vec<&TradeoffRecord> = records.iter().filter(|r| r.pareto_volume).collect();
    front.sort_by(|a, b| a.ms_per_frame.total_cmp(&b.ms_per_frame));
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<9} {:<22} {:>4} {:>3} {:>5} {:>10} {:>10} {:>9} {:>9} {:>9} {:>9}",
        "method",
        "solver",
        "it",
        "ss",
        "omega",
        "ms/frame",
        "vol err %",
        "min vol%",
        "local %",
        "pos rms",
        "pos max"
    );
    for r in front {
        let _ = writeln!(
            out,
            "{:<9} {:<22} {:>4} {:>3} {:>5} {:>10.3} {:>10.3} {:>9.2} {:>9.3} {:>9} {:>9}",
            r.method,
            r.solver,
            r.iterations,
            r.substeps,
            r.omega,
            r.ms_per_frame,
            r.volume_error_pct,
            r.min_volume_pct,
            r.avg_local_error_pct,
            pos(r.pos_rms_rel),
            pos(r.pos_max_rel)
        );
    }
    out
}

/// The cheapest run (lowest median ms per frame) whose volume error is at most `budget` %.
pub fn cheapest_for(records: &[TradeoffRecord], budget: f64) -> Option<&TradeoffRecord> {
    records
        .iter()
        .filter(|r| !r.diverged && r.volume_error_pct <= budget)
        .min_by(|a, b| a.ms_per_frame.total_cmp(&b.ms_per_frame))
}

/// The cheapest constraint-method run whose mean local volume error is at most `budget` %
/// and whose volume error is at most `budget` too.
pub fn cheapest_for_local(records: &[TradeoffRecord], budget: f64) -> Option<&TradeoffRecord> {
    records
        .iter()
        .filter(|r| !r.diverged && r.method != "mss" && r.method != "mss-node")
        .filter(|r| r.avg_local_error_pct <= budget && r.volume_error_pct <= budget)
        .min_by(|a, b| a.ms_per_frame.total_cmp(&b.ms_per_frame))
}

/// "Which solver for which budget": per [`LOCAL_BUDGETS`] entry, the cheapest setting.
pub fn local_budget_table(records: &[TradeoffRecord]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "| local error <= | setting | ms/frame | avg local % | volume error % | pos rms |"
    );
    let _ = writeln!(out, "| ---: | --- | ---: | ---: | ---: | ---: |");
    for budget in LOCAL_BUDGETS {
        match cheapest_for_local(records, budget) {
            Some(r) => {
                let _ = writeln!(
                    out,
                    "| {budget} % | {} | {:.3} | {:.3} | {:.3} | {} |",
                    setting(r),
                    r.ms_per_frame,
                    r.avg_local_error_pct,
                    r.volume_error_pct,
                    pos(r.pos_rms_rel)
                );
            }
            None => {
                let _ = writeln!(out, "| {budget} % | none of the settings | - | - | - | - |");
            }
        }
    }
    out
}

/// A setting with several substeps against the single-substep setting of the same method
/// (omega 1) whose measured cost is closest.
#[derive(Debug, Clone, PartialEq)]
pub struct EqualCostPair<'a> {
    /// The setting with `substeps > 1`.
    pub substeps: &'a TradeoffRecord,
    /// The setting with one substep and more iterations.
    pub iterations: &'a TradeoffRecord,
}

impl EqualCostPair<'_> {
    /// Whether the substep setting has the smaller volume error.
    pub fn substeps_win_volume(&self) -> bool {
        self.substeps.volume_error_pct < self.iterations.volume_error_pct
    }

    /// Whether the substep setting has the smaller RMS position error (`None`: not known).
    pub fn substeps_win_position(&self) -> Option<bool> {
        Some(self.substeps.pos_rms_rel? < self.iterations.pos_rms_rel?)
    }
}

/// Every equal-cost pair (costs within [`EQUAL_COST_RATIO`]) of the constraint methods.
pub fn equal_cost_pairs(records: &[TradeoffRecord]) -> Vec<EqualCostPair<'_>> {
    let usable = |r: &&TradeoffRecord| !r.diverged && r.omega == 1.0 && r.ms_per_frame > 0.0;
    let mut pairs = Vec::new();
    for s in records.iter().filter(usable).filter(|r| r.substeps > 1) {
        let closest = records
            .iter()
            .filter(usable)
            .filter(|r| {
                r.substeps == 1
                    && r.method == s.method
                    && r.solver == s.solver
                    && r.iterations > s.iterations
            })
            .min_by(|a, b| {
                let d = |r: &TradeoffRecord| (r.ms_per_frame / s.ms_per_frame).ln().abs();
                d(a).total_cmp(&d(b))
            });
        if let Some(i) = closest {
            let ratio = i.ms_per_frame / s.ms_per_frame;
            if (1.0 / EQUAL_COST_RATIO..=EQUAL_COST_RATIO).contains(&ratio) {
                pairs.push(EqualCostPair {
                    substeps: s,
                    iterations: i,
                });
            }
        }
    }
    pairs
}

/// Every pair of a setting with several substeps and the one-substep setting of the same
/// method (omega 1) with as many iterations per frame (`iterations x substeps` equal): equal
/// work in the constraint passes, whatever the timing noise.
pub fn equal_work_pairs(records: &[TradeoffRecord]) -> Vec<EqualCostPair<'_>> {
    let usable = |r: &&TradeoffRecord| !r.diverged && r.omega == 1.0;
    records
        .iter()
        .filter(usable)
        .filter(|s| s.substeps > 1 && s.method != "mss" && s.method != "mss-node")
        .filter_map(|s| {
            records
                .iter()
                .filter(usable)
                .find(|r| {
                    r.substeps == 1
                        && r.method == s.method
                        && r.solver == s.solver
                        && r.iterations == s.iterations * s.substeps
                })
                .map(|i| EqualCostPair {
                    substeps: s,
                    iterations: i,
                })
        })
        .collect()
}

fn pair_table(out: &mut String, pairs: &[EqualCostPair<'_>]) {
    let _ = writeln!(out, "| substeps setting | ms | vol err % | pos rms | iterations setting | ms | vol err % | pos rms | lower volume error |");
    let _ = writeln!(
        out,
        "| --- | ---: | ---: | ---: | --- | ---: | ---: | ---: | --- |"
    );
    for p in pairs {
        let (s, i) = (p.substeps, p.iterations);
        let _ = writeln!(
            out,
            "| {} | {:.3} | {:.3} | {} | {} | {:.3} | {:.3} | {} | {} |",
            setting(s),
            s.ms_per_frame,
            s.volume_error_pct,
            pos(s.pos_rms_rel),
            setting(i),
            i.ms_per_frame,
            i.volume_error_pct,
            pos(i.pos_rms_rel),
            if p.substeps_win_volume() {
                "substeps"
            } else {
                "iterations"
            }
        );
    }
    let _ = writeln!(out, "\n{}", verdict(pairs));
}

/// The Markdown report: front, cheapest settings per budget, substeps against iterations.
pub fn report(records: &[TradeoffRecord]) -> String {
    let mut out = String::new();
    let first = records.first();
    let _ = writeln!(
        out,
        "# Trade-off on {} ({} tets, {} springs), backend {}\n",
        first.map_or("?", |r| r.mesh.as_str()),
        first.map_or(0, |r| r.tets),
        first.map_or(0, |r| r.springs),
        first.map_or("?", |r| r.backend.as_str())
    );
    let diverged = records.iter().filter(|r| r.diverged).count();
    let _ = writeln!(
        out,
        "{} settings, {diverged} diverged. Cost: median ms per frame. Volume error: largest \
         |V/V0 - 1| over the frames. Position error: node distance to the method's converged \
         reference, over the bounding-box diagonal.\n",
        records.len()
    );
    let _ = writeln!(
        out,
        "## Pareto front (cost, volume error)\n\n```text\n{}```\n",
        front_table(records)
    );
    let _ = writeln!(out, "## Cheapest setting for a volume error budget\n");
    let _ = writeln!(
        out,
        "| volume error <= | setting | ms/frame | volume error % | pos rms |"
    );
    let _ = writeln!(out, "| ---: | --- | ---: | ---: | ---: |");
    for budget in VOLUME_BUDGETS {
        match cheapest_for(records, budget) {
            Some(r) => {
                let _ = writeln!(
                    out,
                    "| {budget} % | {} | {:.3} | {:.3} | {} |",
                    setting(r),
                    r.ms_per_frame,
                    r.volume_error_pct,
                    pos(r.pos_rms_rel)
                );
            }
            None => {
                let _ = writeln!(out, "| {budget} % | none of the settings | - | - | - |");
            }
        }
    }
    let _ = writeln!(
        out,
        "\n## Which solver for which budget (local volume error)\n\nThe cheapest setting whose \
         mean local volume error (`sum_t |V_t - V0_t| / sum_t V0_t`) and total volume error \
         are both within the budget.\n\n{}",
        local_budget_table(records)
    );
    let pairs = equal_cost_pairs(records);
    let _ = writeln!(
        out,
        "\n## Substeps or iterations at equal cost\n\nEach setting with several substeps \
         against the one-substep setting of the same method with more iterations whose \
         measured cost is closest (within a factor {EQUAL_COST_RATIO}).\n"
    );
    pair_table(&mut out, &pairs);
    let _ = writeln!(
        out,
        "\n### At equal work\n\nThe same question with cost counted as constraint iterations \
         per frame (`iterations x substeps` equal), which timing noise cannot move; a substep \
         also repeats the spring and integration passes, so it costs a little more.\n"
    );
    pair_table(&mut out, &equal_work_pairs(records));
    out
}

/// One sentence per method: how many equal-cost pairs substeps win on each error.
pub fn verdict(pairs: &[EqualCostPair<'_>]) -> String {
    if pairs.is_empty() {
        return "No pairs to compare: the sweep needs several substep counts and matching iteration counts.\n"
            .into();
    }
    let mut methods: Vec<&str> = pairs.iter().map(|p| p.substeps.method.as_str()).collect();
    methods.dedup();
    let mut out = String::new();
    for m in methods {
        let of: Vec<&EqualCostPair<'_>> = pairs.iter().filter(|p| p.substeps.method == m).collect();
        let vol = of.iter().filter(|p| p.substeps_win_volume()).count();
        let known: Vec<bool> = of
            .iter()
            .filter_map(|p| p.substeps_win_position())
            .collect();
        let posw = known.iter().filter(|&&w| w).count();
        let answer = if 2 * vol > of.len() {
            "substeps beat iterations"
        } else if 2 * vol < of.len() {
            "iterations beat substeps"
        } else {
            "neither wins"
        };
        let _ = writeln!(
            out,
            "- {m}: {answer} on volume error ({vol} of {} pairs); substeps have the \
             lower position error in {posw} of {}.",
            of.len(),
            known.len()
        );
    }
    out
}
