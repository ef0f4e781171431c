//! `rocklab compare`: two device variants of one results file side by side, with the ratio
//! b/a per point and of the peaks.

use super::UsageError;
use crate::report::{self, Quantity, Spectrum};
use crate::study::fmt_num;
use clap::Args;
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(Args, Debug, Clone)]
pub struct CompareArgs {
    /// Results file (results.json) or the directory holding it.
    pub results: PathBuf,
    /// Group label (or a word of it) of the reference variant, e.g. `sequential`.
    #[arg(long)]
    pub a: String,
    /// Group label (or a word of it) compared against it, e.g. `mechanistic`.
    #[arg(long)]
    pub b: String,
    /// Quantity to compare (default: the study's first).
    #[arg(long)]
    pub quantity: Option<String>,
}

pub fn resolve_results(path: &std::path::Path) -> PathBuf {
    if path.is_dir() {
        path.join("results.json")
    } else {
        path.to_path_buf()
    }
}

pub fn run(args: &CompareArgs) -> anyhow::Result<()> {
    let results = report::load_results(&resolve_results(&args.results))?;
    let quantities = report::quantities(&results);
    let quantity = match &args.quantity {
        Some(name) => Quantity::from_name(name).ok_or_else(|| {
            let names: Vec<_> = Quantity::ALL.iter().map(|q| q.name()).collect();
            UsageError::new(format!(
                "unknown --quantity `{name}`; expected one of: {}",
                names.join(", ")
            ))
        })?,
        None => quantities[0],
    };
    let spectra: Vec<Spectrum> = report::spectra(&results)
        .into_iter()
        .filter(|s| s.quantity == quantity)
        .collect();
    let pairs = pair_spectra(&spectra, &args.a, &args.b);
    if pairs.is_empty() {
        let groups: Vec<&str> = spectra.iter().map(|s| s.group.as_str()).collect();
        return Err(UsageError::new(format!(
            "no spectra pair up as --a `{}` / --b `{}` for {}; groups in this file: {}",
            args.a,
            args.b,
            quantity.name(),
            groups.join(", ")
        ))
        .into());
    }
    for (a, b) in &pairs {
        print!("{}", side_by_side(a, b));
    }
    let peak_ratios: Vec<f64> = pairs
        .iter()
        .filter_map(|(a, b)| Some(peak(&b.ys)? / peak(&a.ys)?))
        .filter(|r| r.is_finite())
        .collect();
    if pairs.len() > 1 && !peak_ratios.is_empty() {
        let mean = peak_ratios.iter().sum::<f64>() / peak_ratios.len() as f64;
        println!(
            "\nover {} pairs: mean ratio of spectrum peaks b/a = {mean:.3} ({:+.1}%)",
            peak_ratios.len(),
            100.0 * (mean - 1.0)
        );
    }
    Ok(())
}

/// Whether `group` is `label`, or has it as a whole word.
fn names(group: &str, label: &str) -> bool {
    group == label || group.split([' ', '·']).any(|w| w == label)
}

/// Pairs (a, b) where b's group is a's group with the word `a` replaced by `b`.
pub fn pair_spectra<'s>(
    spectra: &'s [Spectrum],
    a: &str,
    b: &str,
) -> Vec<(&'s Spectrum, &'s Spectrum)> {
    spectra
        .iter()
        .filter(|s| names(&s.group, a))
        .filter_map(|sa| {
            let wanted = if sa.group == a {
                b.to_string()
            } else {
                sa.group
                    .split(' ')
                    .map(|w| if w == a { b } else { w })
                    .collect::<Vec<_>>()
                    .join(" ")
            };
            spectra
                .iter()
                .find(|sb| sb.group == wanted)
                .map(|sb| (sa, sb))
        })
        .collect()
}

pub fn side_by_side(a: &Spectrum, b: &Spectrum) -> String {
    let ratio = report::compare(a, b);
    let mut s = String::new();
    let _ = writeln!(s, "\n{} — {} vs {}", a.quantity.label(), a.group, b.group);
    let _ = writeln!(s, "  a {}", report::sparkline(&a.ys));
    let ys_b: Vec<Option<f64>> =
        a.xs.iter()
            .map(|x| b.xs.iter().position(|xb| xb == x).and_then(|i| b.ys[i]))
            .collect();
    let _ = writeln!(s, "  b {}", report::sparkline(&ys_b));
    let _ = writeln!(s, "  {:>10} {:>12} {:>12} {:>8}", a.axis, "a", "b", "b/a");
    let cell = |v: Option<f64>| v.map_or("—".to_string(), |v| format!("{v:.5}"));
    for (i, x) in a.xs.iter().enumerate() {
        let _ = writeln!(
            s,
            "  {:>10} {:>12} {:>12} {:>8}",
            fmt_num(*x),
            cell(a.ys[i]),
            cell(ys_b[i]),
            ratio[i].map_or("—".to_string(), |r| format!("{r:.3}"))
        );
    }
    let finite: Vec<f64> = ratio.iter().flatten().copied().collect();
    if let (Some(pa), Some(pb)) = (peak(&a.ys), peak(&ys_b)) {
        let _ = write!(s, "  peak a {pa:.5}, peak b {pb:.5}");
        if pa > 0.0 {
            let _ = write!(
                s,
                ": b/a = {:.3} ({:+.1}%)",
                pb / pa,
                100.0 * (pb / pa - 1.0)
            );
        }
    }
    if !finite.is_empty() {
        let mean = finite.iter().sum::<f64>() / finite.len() as f64;
        let _ = write!(s, "; mean ratio over {} points {mean:.3}", finite.len());
    }
    s.push('\n');
    s
}

/// Largest value of a spectrum, ignoring gaps.
fn peak(ys: &[Option<f64>]) -> Option<f64> {
    ys.iter().flatten().copied().reduce(f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spectrum(group: &str) -> Spectrum {
        Spectrum {
            quantity: Quantity::PeakRotationRatio,
            group: group.into(),
            axis: "ωn".into(),
            xs: vec![1.0],
            ys: vec![Some(1.0)],
        }
    }

    #[test]
    fn variants_pair_up_within_each_record_and_grid_point() {
        let spectra: Vec<Spectrum> = [
            "landers · sequential",
            "landers · mechanistic",
            "northridge · sequential",
            "northridge · mechanistic",
            "northridge · bare",
            "mechanistic kθ=3",
            "sequential kθ=3",
        ]
        .map(spectrum)
        .to_vec();
        let pairs: Vec<(&str, &str)> = pair_spectra(&spectra, "sequential", "mechanistic")
            .into_iter()
            .map(|(a, b)| (a.group.as_str(), b.group.as_str()))
            .collect();
        assert_eq!(
            pairs,
            [
                ("landers · sequential", "landers · mechanistic"),
                ("northridge · sequential", "northridge · mechanistic"),
                ("sequential kθ=3", "mechanistic kθ=3"),
            ]
        );
        // A word inside another word does not match.
        assert!(pair_spectra(&spectra, "sequent", "mechanistic").is_empty());
    }
}
