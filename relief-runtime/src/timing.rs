//! Paired timing statistics (a leaf): the ratio of two pipelines' mean frame times from
//! blocks timed alternately in one run, with its 95 % interval.
//!
//! The protocol ([`crate::gpu::paired_blocks`]) times pipeline A and pipeline B in blocks,
//! A B, B A, A B, … : each pair of adjacent blocks is one observation, and the order inside a
//! pair alternates so that a steady drift (a machine warming up, a load that creeps in) adds
//! as much to A in one pair as it adds to B in the next. A load that lasts longer than a pair
//! slows both blocks of the pair alike and cancels in the pair's ratio.
//!
//! The estimator: for pair i, `r_i = a_i / b_i`, the ratio of the two blocks' mean frame
//! times. The log-ratios `ln r_i` are averaged; their mean `m` with a Student t interval
//! `m ± t(0.975, n − 1) · s / √n` (s the sample standard deviation of the n log-ratios) gives
//! the ratio `exp(m)` (the geometric mean of the pair ratios) and its interval
//! `[exp(m − h), exp(m + h)]`. Under the model the protocol assumes, where a load multiplies
//! both blocks of a pair by the same factor, `exp(m)` estimates the ratio of the two
//! pipelines' mean frame times on an unloaded machine; logs make the interval symmetric in
//! "×" and "÷" and keep it positive. See `docs/timing.md`.

/// A ratio of mean frame times with its 95 % interval.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ratio {
    /// The estimate: the geometric mean of the pair ratios.
    pub ratio: f64,
    /// Lower end of the 95 % interval (NaN with fewer than two pairs).
    pub lo: f64,
    /// Upper end of the 95 % interval (NaN with fewer than two pairs).
    pub hi: f64,
    /// Pairs of blocks behind the estimate.
    pub pairs: u32,
}

/// The two-sided 95 % quantile of Student's t, `t(0.975, df)`; `df` = 0 gives infinity (no
/// interval from one observation). Exact to three decimals from a table up to 30 degrees of
/// freedom, the Cornish–Fisher expansion of t about the normal quantile beyond (error below
/// 1e-4 there).
pub(crate) fn t975(df: u32) -> f64 {
    const TABLE: [f64; 30] = [
        12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145, 2.131,
        2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042,
    ];
    match df {
        0 => f64::INFINITY,
        1..=30 => TABLE[df as usize - 1],
        _ => t975_expansion(df as f64),
    }
}

/// The Cornish–Fisher expansion of `t(0.975, ν)` in powers of 1/ν (Abramowitz & Stegun
/// 26.7.5), about the normal quantile z = 1.959964.
fn t975_expansion(nu: f64) -> f64 {
    let z: f64 = 1.959_963_985;
    let (z3, z5, z7) = (z.powi(3), z.powi(5), z.powi(7));
    z + (z3 + z) / (4.0 * nu)
        + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * nu * nu)
        + (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / (384.0 * nu.powi(3))
}

/// The ratio of A's to B's mean frame time from paired blocks: `a[i]` and `b[i]` are the
/// mean frame times (any unit, the same for both) of the two blocks of pair i. Pairs beyond
/// the shorter list are ignored. A block time that is not a positive finite number (a block
/// below the timer's resolution reads 0) makes the whole estimate NaN: it is not dropped.
pub(crate) fn paired_ratio(a: &[f64], b: &[f64]) -> Ratio {
    let n = a.len().min(b.len());
    let logs: Vec<f64> = a
        .iter()
        .zip(b)
        .map(|(x, y)| if *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite() { (x / y).ln() } else { f64::NAN })
        .collect();
    let pairs = n as u32;
    if n == 0 {
        return Ratio { ratio: f64::NAN, lo: f64::NAN, hi: f64::NAN, pairs };
    }
    let m = logs.iter().sum::<f64>() / n as f64;
    if n < 2 {
        return Ratio { ratio: m.exp(), lo: f64::NAN, hi: f64::NAN, pairs };
    }
    let var = logs.iter().map(|l| (l - m).powi(2)).sum::<f64>() / (n - 1) as f64;
    let h = t975(pairs - 1) * (var / n as f64).sqrt();
    Ratio { ratio: m.exp(), lo: (m - h).exp(), hi: (m + h).exp(), pairs }
}

impl Ratio {
    /// The standard error of `ln ratio` behind the interval: its half-width in logs divided
    /// by `t(0.975, pairs − 1)`. NaN without an interval.
    pub(crate) fn log_se(&self) -> f64 {
        if self.pairs < 2 || !self.lo.is_finite() || !self.hi.is_finite() || self.lo <= 0.0 {
            return f64::NAN;
        }
        (self.hi.ln() - self.lo.ln()) / 2.0 / t975(self.pairs - 1)
    }

    /// `self ÷ other` for two ratios to one baseline measured independently (two cells of a
    /// sweep, each timed against the baseline in its own run): the baseline cancels, the
    /// log-ratios subtract and their variances add; the interval's t quantile takes the
    /// Welch–Satterthwaite degrees of freedom. `pairs` of the result is the smaller count.
    /// NaN bounds when either has none.
    pub fn over(&self, other: &Ratio) -> Ratio {
        let ratio = self.ratio / other.ratio;
        let pairs = self.pairs.min(other.pairs);
        let (sa, sb) = (self.log_se(), other.log_se());
        if !sa.is_finite() || !sb.is_finite() {
            return Ratio { ratio, lo: f64::NAN, hi: f64::NAN, pairs };
        }
        let (va, vb) = (sa * sa, sb * sb);
        let se = (va + vb).sqrt();
        let dof = |p: u32| (p.max(2) - 1) as f64;
        let nu = if va + vb > 0.0 {
            (va + vb).powi(2) / (va * va / dof(self.pairs) + vb * vb / dof(other.pairs))
        } else {
            dof(pairs)
        };
        let h = t975(nu.floor().max(1.0) as u32) * se;
        Ratio { ratio, lo: ratio * (-h).exp(), hi: ratio * h.exp(), pairs }
    }

    /// Whether the ratio exceeds `threshold`: `Some(true)` when the whole interval lies
    /// above it, `Some(false)` when the whole interval lies at or below it, `None` when the
    /// interval straddles it (not decided). Without an interval (fewer than two pairs, or a
    /// point value such as the dissertation's numbers), the estimate alone decides.
    pub fn above(&self, threshold: f64) -> Option<bool> {
        if !self.ratio.is_finite() {
            return None;
        }
        if !self.lo.is_finite() || !self.hi.is_finite() {
            return Some(self.ratio > threshold);
        }
        if self.lo > threshold {
            Some(true)
        } else if self.hi <= threshold {
            Some(false)
        } else {
            None
        }
    }

    /// A results row's `frame_ratio_to_baseline` with its interval (`_lo`, `_hi`) and
    /// `timing_pairs`; None for a row timed alone. Bounds the row lacks are NaN.
    pub fn to_baseline(m: &crate::results::Metrics) -> Option<Ratio> {
        Some(Ratio {
            ratio: m.frame_ratio_to_baseline?,
            lo: m.frame_ratio_to_baseline_lo.unwrap_or(f64::NAN),
            hi: m.frame_ratio_to_baseline_hi.unwrap_or(f64::NAN),
            pairs: m.timing_pairs,
        })
    }

    /// A point value without an interval (a mean frame time, a model cost).
    pub fn point(v: f64) -> Ratio {
        Ratio { ratio: v, lo: f64::NAN, hi: f64::NAN, pairs: 0 }
    }
}

impl std::fmt::Display for Ratio {
    /// `1.234 [1.201, 1.268] (95 %, 25 pairs)`, or the estimate alone without an interval.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.lo.is_finite() && self.hi.is_finite() {
            write!(f, "{:.3} [{:.3}, {:.3}] (95 %, {} pairs)", self.ratio, self.lo, self.hi, self.pairs)
        } else {
            write!(f, "{:.3}", self.ratio)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator: uniform in [0, 1).
    fn uniform(state: &mut u64) -> f64 {
        *state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A standard normal draw (Box–Muller).
    fn normal(state: &mut u64) -> f64 {
        let (u, v) = (uniform(state).max(1e-300), uniform(state));
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }

    #[test]
    fn the_t_expansion_meets_the_table_and_tends_to_the_normal_quantile() {
        // Two independent computations agree where both apply (the table's values are
        // rounded to three decimals).
        for df in [20u32, 25, 30] {
            assert!(
                (t975_expansion(df as f64) - t975(df)).abs() < 1.5e-3,
                "df {df}: {} vs {}",
                t975_expansion(df as f64),
                t975(df)
            );
        }
        assert!((t975(40) - 2.021).abs() < 1e-3 && (t975(60) - 2.000).abs() < 1e-3 && (t975(120) - 1.980).abs() < 1e-3);
        assert!((t975(1_000_000) - 1.960).abs() < 1e-3);
        assert!(t975(0).is_infinite());
        // Decreasing in the degrees of freedom.
        for df in 1..200 {
            assert!(t975(df + 1) < t975(df), "df {df}");
        }
    }

    #[test]
    fn a_constant_ratio_is_recovered_exactly_under_a_common_load() {
        // B takes 1.5× A; every pair sees a load factor (1…3×) common to its two blocks.
        let mut s = 7u64;
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for _ in 0..20 {
            let load = 1.0 + 2.0 * uniform(&mut s);
            a.push(2.0 * load);
            b.push(3.0 * load);
        }
        let r = paired_ratio(&b, &a);
        assert!((r.ratio - 1.5).abs() < 1e-12 && (r.lo - 1.5).abs() < 1e-12 && (r.hi - 1.5).abs() < 1e-12, "{r:?}");
        assert_eq!(r.pairs, 20);
    }

    #[test]
    fn the_interval_covers_the_true_ratio_about_95_percent_of_the_time() {
        // 2000 simulated runs of 12 pairs: each block's time is the true time × a load common
        // to the pair × its own log-normal noise (5 %). The share of intervals that hold the
        // true ratio 1.3 must be 95 % within what 2000 Bernoulli trials allow (±1.5 % is 3
        // standard deviations).
        let mut s = 11u64;
        let (runs, pairs, truth) = (2000, 12, 1.3);
        let mut covered = 0;
        for _ in 0..runs {
            let (mut a, mut b) = (Vec::new(), Vec::new());
            for _ in 0..pairs {
                let load = (0.5 * normal(&mut s)).exp();
                a.push(truth * load * (0.05 * normal(&mut s)).exp());
                b.push(load * (0.05 * normal(&mut s)).exp());
            }
            let r = paired_ratio(&a, &b);
            covered += (r.lo <= truth && truth <= r.hi) as usize;
        }
        let share = covered as f64 / runs as f64;
        assert!((share - 0.95).abs() < 0.015, "coverage {share}");
    }

    #[test]
    fn a_quotient_of_two_independent_ratios_covers_about_95_percent() {
        // Two cells, each against the baseline in its own run (different loads, different
        // noise levels and pair counts); their quotient's interval holds the true 1.2.
        let mut s = 5u64;
        let runs = 2000;
        let mut covered = 0;
        for _ in 0..runs {
            let mut one = |truth: f64, pairs: usize, noise: f64| {
                let (mut a, mut b) = (Vec::new(), Vec::new());
                for _ in 0..pairs {
                    let load = (0.3 * normal(&mut s)).exp();
                    a.push(truth * load * (noise * normal(&mut s)).exp());
                    b.push(load * (noise * normal(&mut s)).exp());
                }
                paired_ratio(&a, &b)
            };
            let (x, y) = (one(1.8, 10, 0.04), one(1.5, 25, 0.08));
            let q = x.over(&y);
            covered += (q.lo <= 1.2 && 1.2 <= q.hi) as usize;
        }
        let share = covered as f64 / runs as f64;
        assert!((share - 0.95).abs() < 0.015, "coverage {share}");
    }

    #[test]
    fn bad_blocks_and_short_runs_say_so() {
        assert!(paired_ratio(&[1.0, 0.0, 1.0], &[1.0, 1.0, 1.0]).ratio.is_nan(), "a zero-time block is not dropped");
        assert!(paired_ratio(&[1.0, f64::NAN], &[1.0, 1.0]).ratio.is_nan());
        let one = paired_ratio(&[2.0], &[1.0]);
        assert_eq!(one.ratio, 2.0);
        assert!(one.lo.is_nan() && one.hi.is_nan());
        assert_eq!(one.above(1.5), Some(true), "a point decides alone");
        assert!(paired_ratio(&[], &[]).ratio.is_nan());
    }

    #[test]
    fn above_is_undecided_where_the_interval_straddles_the_threshold() {
        let r = Ratio { ratio: 1.04, lo: 0.98, hi: 1.10, pairs: 10 };
        assert_eq!(r.above(1.0), None);
        assert_eq!(r.above(0.95), Some(true));
        assert_eq!(r.above(1.10), Some(false));
        assert_eq!(r.above(1.2), Some(false));
        assert_eq!(Ratio::point(f64::NAN).above(1.0), None);
        assert_eq!(r.to_string(), "1.040 [0.980, 1.100] (95 %, 10 pairs)");
    }
}
