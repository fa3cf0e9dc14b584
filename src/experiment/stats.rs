//! Statistics over independent runs: means with 95% confidence intervals.

/// The mean of a sample with a two-sided 95% confidence interval of the mean.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Summary {
    /// The sample mean (NaN for an empty sample).
    pub mean: f64,
    /// Lower end of the 95% confidence interval.
    pub(crate) ci_low: f64,
    /// Upper end of the 95% confidence interval.
    pub(crate) ci_high: f64,
    /// Sample size.
    pub n: usize,
}

/// Two-sided 95% quantiles of Student's t (the 0.975 quantile), degrees of
/// freedom 1 to 30, to 15 significant digits (computed with mpmath).
const T_975: [f64; 30] = [
    12.706_204_736_174_7,
    4.302_652_729_749_46,
    3.182_446_305_283_71,
    2.776_445_105_197_79,
    2.570_581_835_636_32,
    2.446_911_851_144_97,
    2.364_624_251_592_79,
    2.306_004_135_204_17,
    2.262_157_162_798_21,
    2.228_138_851_986_27,
    2.200_985_160_091_64,
    2.178_812_829_667_23,
    2.160_368_656_462_79,
    2.144_786_687_917_80,
    2.131_449_545_559_78,
    2.119_905_299_221_25,
    2.109_815_577_833_32,
    2.100_922_040_241_04,
    2.093_024_054_408_31,
    2.085_963_447_265_86,
    2.079_613_844_727_68,
    2.073_873_067_904_03,
    2.068_657_610_419_05,
    2.063_898_561_628_03,
    2.059_538_552_753_30,
    2.055_529_438_642_87,
    2.051_830_516_480_29,
    2.048_407_141_795_25,
    2.045_229_642_132_70,
    2.042_272_456_301_24,
];

/// The 0.975 quantile of the standard normal distribution.
const Z_975: f64 = 1.959_963_984_540_054;

/// The 0.975 quantile of Student's t distribution with `df` degrees of freedom:
/// the half-width factor of a two-sided 95% confidence interval.
///
/// Exact (to 15 significant digits) for `df` up to 30, from a table. Beyond,
/// the Cornish-Fisher expansion in `1/df` up to the fourth order (Abramowitz
/// and Stegun 26.7.5) is used; its absolute error is below 3e-8 at `df = 31`
/// and shrinks quickly (below 1e-10 from `df = 100`), converging to the normal
/// quantile 1.959964. `df = 0` has no quantile and gives infinity.
pub(crate) fn t_quantile_975(df: usize) -> f64 {
    match df {
        0 => f64::INFINITY,
        1..=30 => T_975[df - 1],
        _ => {
            let z = Z_975;
            let z2 = z * z;
            let z3 = z2 * z;
            let z5 = z3 * z2;
            let z7 = z5 * z2;
            let z9 = z7 * z2;
            let g1 = (z3 + z) / 4.0;
            let g2 = (5.0 * z5 + 16.0 * z3 + 3.0 * z) / 96.0;
            let g3 = (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / 384.0;
            let g4 = (79.0 * z9 + 776.0 * z7 + 1482.0 * z5 - 1920.0 * z3 - 945.0 * z) / 92160.0;
            let v = 1.0 / df as f64;
            z + v * (g1 + v * (g2 + v * (g3 + v * g4)))
        }
    }
}

/// The mean of `samples` and a two-sided 95% confidence interval of the mean,
/// `mean ± t(n-1) · s / √n` with `s` the sample standard deviation (n-1 in the
/// denominator) and `t` from `t_quantile_975`.
///
/// One sample gives a zero-width interval at that sample; no samples give NaN
/// for the mean and both ends with `n = 0`. Samples are used as given: a NaN
/// or infinite sample makes the mean and interval NaN or infinite.
pub(crate) fn summarize(samples: &[f64]) -> Summary {
    let n = samples.len();
    if n == 0 {
        return Summary {
            mean: f64::NAN,
            ci_low: f64::NAN,
            ci_high: f64::NAN,
            n,
        };
    }
    let count = n as f64;
    let mean = samples.iter().sum::<f64>() / count;
    if n == 1 {
        return Summary {
            mean,
            ci_low: mean,
            ci_high: mean,
            n,
        };
    }
    let squares: f64 = samples.iter().map(|x| (x - mean) * (x - mean)).sum();
    let sd = (squares / (count - 1.0)).sqrt();
    let half = t_quantile_975(n - 1) * sd / count.sqrt();
    Summary {
        mean,
        ci_low: mean - half,
        ci_high: mean + half,
        n,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_match_the_t_table() {
        let known = [
            (1, 12.706),
            (2, 4.303),
            (5, 2.571),
            (10, 2.228),
            (19, 2.093),
            (30, 2.042),
            (31, 2.040),
            (40, 2.021),
            (60, 2.000),
            (120, 1.980),
            (199, 1.972),
            (1_000_000, 1.960),
        ];
        for (df, t) in known {
            let q = t_quantile_975(df);
            assert!((q - t).abs() < 1e-3, "df {df}: {q} vs {t}");
        }
        assert_eq!(t_quantile_975(0), f64::INFINITY);
    }

    #[test]
    fn the_approximation_joins_the_table_smoothly() {
        // Exact values (mpmath) just past the table and further out.
        for (df, exact) in [
            (31, 2.039_513_446_396_41),
            (40, 2.021_075_390_306_27),
            (100, 1.983_971_518_523_55),
        ] {
            assert!((t_quantile_975(df) - exact).abs() < 3e-8, "df {df}");
        }
        // Decreasing in the degrees of freedom, towards the normal quantile.
        let qs: Vec<f64> = (1..500).map(t_quantile_975).collect();
        assert!(qs.windows(2).all(|w| w[0] > w[1]));
        assert!(qs.iter().all(|&q| q > Z_975));
    }

    #[test]
    fn summary_by_hand() {
        // Mean 2.5, s = sqrt(5/3), t(3) = 3.182446: half-width 2.054260.
        let s = summarize(&[1.0, 2.0, 3.0, 4.0]);
        assert_eq!(s.n, 4);
        assert!((s.mean - 2.5).abs() < 1e-12);
        assert!((s.ci_low - 0.445_739_743).abs() < 1e-8, "{s:?}");
        assert!((s.ci_high - 4.554_260_257).abs() < 1e-8, "{s:?}");
        // Mean 5, s = sqrt(9), t(4) = 2.776445: half-width 3.724992.
        let s = summarize(&[2.0, 4.0, 4.0, 5.0, 10.0]);
        assert!((s.ci_low - 1.275_008_005).abs() < 1e-8, "{s:?}");
        assert!((s.ci_high - 8.724_991_995).abs() < 1e-8, "{s:?}");
    }

    #[test]
    fn degenerate_samples() {
        let one = summarize(&[3.5]);
        assert_eq!(
            one,
            Summary {
                mean: 3.5,
                ci_low: 3.5,
                ci_high: 3.5,
                n: 1
            }
        );
        let none = summarize(&[]);
        assert_eq!(none.n, 0);
        assert!(none.mean.is_nan() && none.ci_low.is_nan() && none.ci_high.is_nan());
        let constant = summarize(&[2.0; 10]);
        assert_eq!((constant.ci_low, constant.ci_high), (2.0, 2.0));
    }
}
