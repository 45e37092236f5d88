//! Summaries of frame-time samples: median, percentiles and mean.

use serde::{Deserialize, Serialize};

/// Percentile `p` (0..=100) of `sorted` by linear interpolation between closest ranks
/// (NumPy's default); 0 for an empty slice.
pub fn percentile(sorted: &[f64], p: f64) -> f64 {
    match sorted.len() {
        0 => 0.0,
        1 => sorted[0],
        n => {
            let rank = (p.clamp(0.0, 100.0) / 100.0) * (n - 1) as f64;
            let lo = rank.floor() as usize;
            let hi = (lo + 1).min(n - 1);
            let frac = rank - lo as f64;
            sorted[lo] + (sorted[hi] - sorted[lo]) * frac
        }
    }
}

/// Median, 10th and 90th percentile and mean of frame times [ms].
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct FrameTimes {
    /// Median [ms].
    pub median: f64,
    /// 10th percentile [ms].
    pub p10: f64,
    /// 90th percentile [ms].
    pub p90: f64,
    /// Mean [ms].
    pub mean: f64,
    /// Number of samples.
    pub count: usize,
}

impl FrameTimes {
    /// Summarises `samples` [ms] (all zero when empty).
    pub fn of(samples: &[f64]) -> Self {
        let mut sorted: Vec<f64> = samples.iter().copied().filter(|v| v.is_finite()).collect();
        sorted.sort_by(f64::total_cmp);
        let mean = if sorted.is_empty() {
            0.0
        } else {
            sorted.iter().sum::<f64>() / sorted.len() as f64
        };
        FrameTimes {
            median: percentile(&sorted, 50.0),
            p10: percentile(&sorted, 10.0),
            p90: percentile(&sorted, 90.0),
            mean,
            count: sorted.len(),
        }
    }

    /// Frames per second at the median frame time (0 when there is none).
    pub fn fps(&self) -> f64 {
        if self.median > 0.0 {
            1e3 / self.median
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_interpolate_between_ranks() {
        let t = FrameTimes::of(&[5.0, 1.0, 3.0, 2.0, 4.0]);
        assert_eq!((t.median, t.mean, t.count), (3.0, 3.0, 5));
        assert!(
            (t.p10 - 1.4).abs() < 1e-12 && (t.p90 - 4.6).abs() < 1e-12,
            "{t:?}"
        );
        assert!((t.fps() - 1e3 / 3.0).abs() < 1e-9);
        let even = FrameTimes::of(&[1.0, 2.0, 3.0, 10.0]);
        assert_eq!(even.median, 2.5);
        assert_eq!(FrameTimes::of(&[]).fps(), 0.0);
    }
}
