use super::*;

/// Each parameter of a Latin hypercube of N draws has exactly one draw in each of its N
/// equal-probability strata [k/N, (k+1)/N).
#[test]
fn a_latin_hypercube_puts_one_draw_in_each_stratum() {
    for n in [1, 2, 7, 64, 500] {
        let u = uniforms(Sampling::LatinHypercube, 7, n, 3);
        assert_eq!(u.len(), n);
        for j in 0..3 {
            let mut strata: Vec<usize> = u.iter().map(|row| (row[j] * n as f64) as usize).collect();
            strata.sort_unstable();
            assert_eq!(strata, (0..n).collect::<Vec<_>>(), "n = {n}, parameter {j}");
            assert!(u.iter().all(|row| row[j] > 0.0 && row[j] < 1.0));
        }
    }
    // Monte Carlo leaves strata empty and doubles others (at N = 500 all N strata filled
    // once has probability N!/N^N ≈ 0).
    let u = uniforms(Sampling::MonteCarlo, 7, 500, 1);
    let mut strata: Vec<usize> = u.iter().map(|row| (row[0] * 500.0) as usize).collect();
    strata.sort_unstable();
    strata.dedup();
    assert!(strata.len() < 500);
}

#[test]
fn the_same_seed_draws_the_same_values_and_another_seed_others() {
    for sampling in [Sampling::MonteCarlo, Sampling::LatinHypercube] {
        let a = uniforms(sampling, 7, 40, 2);
        assert_eq!(a, uniforms(sampling, 7, 40, 2));
        let b = uniforms(sampling, 8, 40, 2);
        let same = a.iter().zip(&b).filter(|(x, y)| x == y).count();
        assert_eq!(same, 0, "{sampling:?}: seeds 7 and 8 share {same} draws");
    }
    // A draw's uniforms do not depend on how many draws follow it (Monte Carlo): draw i is
    // stream i of the seed.
    let few = uniforms(Sampling::MonteCarlo, 3, 5, 2);
    let many = uniforms(Sampling::MonteCarlo, 3, 50, 2);
    assert_eq!(few[..], many[..5]);
}

/// Mean and standard deviation of `xs`.
fn moments(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
    (mean, var.sqrt())
}

/// Monte Carlo draws of 40 000 have the stated mean and sd within 4 standard errors (the
/// CLT: se(mean) = σ/√N, se(sd) ≈ σ/√(2N) for a normal); fixed seed, so no flakiness.
#[test]
fn sample_moments_converge_to_the_stated_distributions() {
    let n = 40_000;
    let u: Vec<f64> = uniforms(Sampling::MonteCarlo, 11, n, 1)
        .into_iter()
        .map(|r| r[0])
        .collect();
    let within = |got: f64, want: f64, se: f64, what: &str| {
        assert!(
            (got - want).abs() < 4.0 * se,
            "{what}: {got} vs {want} (se {se})"
        );
    };
    let nf = n as f64;
    // α ~ N(14°, 1°): far from its range's ends, so the truncation changes nothing visible.
    let (mean, sd) = (14f64.to_radians(), 1f64.to_radians());
    let d = Distribution::Normal { mean, sd };
    let xs: Vec<f64> = u
        .iter()
        .map(|&u| d.value(u, Range::of(Param::Alpha)))
        .collect();
    let (m, s) = moments(&xs);
    within(m, mean, sd / nf.sqrt(), "normal mean");
    within(s, sd, sd / (2.0 * nf).sqrt(), "normal sd");
    // size ~ LN(ln 2, 0.1²): ln x has mean ln 2 and sd 0.1.
    let d = Distribution::Lognormal {
        median: 2.0,
        beta: 0.1,
    };
    let ln: Vec<f64> = (u.iter())
        .map(|&u| d.value(u, Range::of(Param::Size)).ln())
        .collect();
    let (m, s) = moments(&ln);
    within(m, 2f64.ln(), 0.1 / nf.sqrt(), "lognormal ln-mean");
    within(s, 0.1, 0.1 / (2.0 * nf).sqrt(), "lognormal β");
    // r ~ U(0.8, 0.95): mean 0.875, sd 0.15/√12; se(sd) ≈ sd·√(0.8/(4N)) (excess kurtosis −1.2).
    let d = Distribution::Uniform { lo: 0.8, hi: 0.95 };
    let xs: Vec<f64> = (u.iter())
        .map(|&u| d.value(u, Range::of(Param::Restitution)))
        .collect();
    let (m, s) = moments(&xs);
    let sd = 0.15 / 12f64.sqrt();
    within(m, 0.875, sd / nf.sqrt(), "uniform mean");
    within(s, sd, sd * (0.8 / (4.0 * nf)).sqrt(), "uniform sd");
    assert!(xs.iter().all(|x| (0.8..=0.95).contains(x)));
}

/// Zero dispersion draws the centre exactly, whatever the uniform.
#[test]
fn a_distribution_without_spread_draws_its_centre_exactly() {
    let alpha = 0.2443;
    for d in [
        Distribution::Normal {
            mean: alpha,
            sd: 0.0,
        },
        Distribution::Lognormal {
            median: alpha,
            beta: 0.0,
        },
        Distribution::Uniform {
            lo: alpha,
            hi: alpha,
        },
    ] {
        for u in [1e-12, 0.3, 0.999_999] {
            assert_eq!(
                d.value(u, Range::of(Param::Alpha)).to_bits(),
                alpha.to_bits()
            );
        }
    }
}

/// A restitution of N(0.97, 0.01) puts Φ(−3) = 0.13 % above 1: accepted and truncated (no draw
/// above 1, and the truncated draws keep their stratification); N(0.95, 0.05) puts 16 %
/// above 1 and is refused, naming the field.
#[test]
fn impossible_values_are_truncated_or_refused_by_the_stated_rule() {
    let range = Range::of(Param::Restitution);
    let tight = Distribution::Normal {
        mean: 0.97,
        sd: 0.01,
    };
    let outside = tight.mass_outside(range);
    assert!((outside - crate::stats::normal::cdf(-3.0)).abs() < 1e-12);
    assert!(check_distribution(Param::Restitution, &tight).is_ok());
    let n = 1000;
    let xs: Vec<f64> = uniforms(Sampling::LatinHypercube, 2, n, 1)
        .iter()
        .map(|r| tight.value(r[0], range))
        .collect();
    assert!(xs.iter().all(|&x| x > 0.0 && x <= 1.0));
    // The largest of N stratified draws sits in the top stratum of the truncated normal,
    // i.e. above its (1 − 1/N) quantile.
    let top = xs.iter().copied().fold(0.0, f64::max);
    let q = 0.97 + 0.01 * crate::stats::normal::quantile((1.0 - 1.0 / n as f64) * (1.0 - outside));
    assert!(top >= q && top <= 1.0, "{top} vs {q}");
    let wide = Distribution::Normal {
        mean: 0.95,
        sd: 0.05,
    };
    let e = check_distribution(Param::Restitution, &wide).unwrap_err();
    assert_eq!(e.field.as_deref(), Some("uncertain.restitution"));
    assert!(e.message.contains("15.8"), "{}", e.message);
    // A uniform must lie inside the range; sd < 0, lo > hi and a median ≤ 0 are refused.
    for (param, d, says) in [
        (
            Param::Restitution,
            Distribution::Uniform { lo: 0.8, hi: 1.2 },
            "outside",
        ),
        (
            Param::Alpha,
            Distribution::Normal {
                mean: 0.2,
                sd: -0.01,
            },
            "negative",
        ),
        (
            Param::Size,
            Distribution::Uniform { lo: 2.0, hi: 1.0 },
            "above",
        ),
        (
            Param::Size,
            Distribution::Lognormal {
                median: 0.0,
                beta: 0.1,
            },
            "not positive",
        ),
    ] {
        let e = check_distribution(param, &d).unwrap_err();
        assert!(e.message.contains(says), "{d:?}: {}", e.message);
    }
}
