//! `rocklab plot`: the paper's figures from a results file.

use super::UsageError;
use crate::report::{self, FigureOptions, FigureSize, ImageFormat, PlotChoice};
use anyhow::Context;
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug, Clone)]
pub struct PlotArgs {
    /// Results file (results.json) or the directory holding it.
    pub results: PathBuf,
    /// Write SVG figures into this directory.
    #[arg(long, required_unless_present = "png")]
    pub svg: Option<PathBuf>,
    /// Write PNG figures into this directory (both --svg and --png: both formats).
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Figure size WIDTHxHEIGHT with a unit: 160x80mm, 6.3x3.2in, 16x8cm, 1200x600px
    /// (default: a size that suits the figure's panels).
    #[arg(long, value_parser = FigureSize::parse)]
    pub size: Option<FigureSize>,
    /// PNG resolution in dots per inch (SVG is resolution independent).
    #[arg(long, default_value_t = 300.0, value_parser = parse_dpi)]
    pub dpi: f64,
    /// Largest PNG, in megapixels, that --size and --dpi may ask for (each megapixel takes
    /// 3 MB of memory while it is drawn; at most 2000).
    #[arg(long, default_value_t = report::MAX_MEGAPIXELS, value_parser = parse_megapixels)]
    pub max_megapixels: f64,
    /// Draw only the series that match, as `compare --a/--b` selects: a device kind or label
    /// with parameter values in the study's syntax, e.g. `mechanistic`, `bare`,
    /// `mechanistic(k_theta: 3.0, play: [0.0, 0.005])`, `sequential(record: landers)`.
    /// Repeat for more series.
    #[arg(long, value_name = "SELECTOR")]
    pub select: Vec<String>,
    /// With --b: the overturning maps of A and B compared cell by cell (maps-difference.*):
    /// where both survive, only B survives, only A survives, both overturn; paired as
    /// `compare --a/--b` pairs, e.g. --a sequential --b mechanistic.
    #[arg(long, value_name = "SELECTOR", requires = "b")]
    pub a: Option<String>,
    /// With --a: the variant compared with A in maps-difference.* (it may be a grid: one
    /// panel per member).
    #[arg(long, value_name = "SELECTOR", requires = "a")]
    pub b: Option<String>,
    /// One row of panels per value of this parameter (study field, CSV name or label:
    /// `play`, `k_theta`, `kθ`).
    #[arg(long, value_name = "PARAM")]
    pub facet: Option<String>,
    /// Record suites: each device's mean ± one standard deviation over the records (a band)
    /// instead of one line per record.
    #[arg(long)]
    pub band: bool,
    /// Most series in one panel.
    #[arg(long, default_value_t = report::MAX_SERIES)]
    pub max_series: usize,
    /// Also plot the histories of this scene (its index in the study; rerun from its stored
    /// scene).
    #[arg(long)]
    pub scene: Option<usize>,
}

fn parse_dpi(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if (30.0..=2400.0).contains(&v) => Ok(v),
        _ => Err(format!(
            "--dpi {text}: give a number between 30 and 2400, e.g. 300"
        )),
    }
}

/// A PNG of `--size` at `--dpi` must fit in `--max-megapixels`: checked before the results
/// are read or anything is drawn (each figure checks its own size again, default sizes too).
fn check_pixels(args: &PlotArgs) -> Result<(), UsageError> {
    let (Some(size), Some(_)) = (args.size, &args.png) else {
        return Ok(());
    };
    let options = FigureOptions {
        size: Some(size),
        ..figure_options(args, ImageFormat::Png)
    };
    match options.canvas(size, "a figure") {
        Ok(_) => Ok(()),
        Err(e) => Err(UsageError::new(e.to_string())),
    }
}

fn figure_options(args: &PlotArgs, format: ImageFormat) -> FigureOptions {
    FigureOptions {
        format,
        size: args.size,
        dpi: args.dpi,
        max_megapixels: args.max_megapixels,
    }
}

fn parse_megapixels(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v > 0.0 && v <= report::MEGAPIXELS_CEILING => Ok(v),
        _ => Err(format!(
            "--max-megapixels {text}: give a number above 0 and at most {} (the most a PNG \
             can be drawn at)",
            report::MEGAPIXELS_CEILING
        )),
    }
}

pub fn run(args: &PlotArgs) -> anyhow::Result<()> {
    check_pixels(args)?;
    let results_path = super::compare::resolve_results(&args.results);
    let results = report::load_results(&results_path)?;
    // A fragility study's report sits beside its results.
    let fragility_path =
        crate::fsutil::parent_dir(&results_path).join(report::fragility::FRAGILITY_JSON);
    let fragility = match fragility_path.exists() {
        true => Some(report::fragility::read_fragility_json(&fragility_path)?),
        false => None,
    };
    // And its seismic risk (`rocklab risk` or a study's risk section), if computed.
    let risk = report::risk::read_risk(crate::fsutil::parent_dir(&results_path));
    let mut targets = Vec::new();
    if let Some(d) = &args.svg {
        targets.push((d.clone(), ImageFormat::Svg));
    }
    if let Some(d) = &args.png {
        targets.push((d.clone(), ImageFormat::Png));
    }
    if targets.is_empty() {
        return Err(UsageError::new("give --svg DIR and/or --png DIR").into());
    }
    let choice = PlotChoice {
        select: args.select.clone(),
        facet: args.facet.clone(),
        band: args.band,
        max_series: args.max_series,
    };
    let spectra = report::spectra(&results);
    let maps = report::maps(&results);
    // Rerun the scene once, whatever the number of formats.
    let scene = match args.scene {
        None => None,
        Some(index) => {
            let outcome = results
                .outcomes
                .iter()
                .find(|o| o.point.index == index)
                .ok_or_else(|| {
                    UsageError::new(format!(
                        "--scene {index}: no such scene in this results file ({} scenes, indices {}…{})",
                        results.outcomes.len(),
                        results.outcomes.first().map_or(0, |o| o.point.index),
                        results.outcomes.last().map_or(0, |o| o.point.index)
                    ))
                })?;
            // The whole history, not just until no peak can change, resampled on a uniform
            // grid from the dense output (smooth curves at the stored result's tolerance).
            let scene = crate::sim::history_scene(&outcome.point.scene);
            // Under the sweep's guard: a scene that panics fails here as it did in the sweep.
            let library = crate::excitation::library::global()?;
            let (result, history) = crate::sweep::guarded(|| {
                crate::sim::run_history(&scene, library, &crate::sim::Sampling::Auto)
            })
            .map_err(|e| anyhow::anyhow!("scene {index} failed: {e}"))?;
            let mut title = report::scene_title(&outcome.point);
            if result.overturned {
                title.push_str(" (overturned)");
            }
            Some((index, scene, title, history))
        }
    };
    let mut written = Vec::new();
    for (dir, format) in targets {
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("cannot create output directory {}", dir.display()))?;
        let options = figure_options(args, format);
        // A design study's scenes are the search's probes: its figure is the design chart.
        if let Some(path) = report::plot_design(&dir, &options, &results)? {
            written.push(path);
            continue;
        }
        written.extend(report::plot_spectra(
            &dir, &options, &results, &spectra, &choice,
        )?);
        written.extend(report::plot_maps(&dir, &options, &results, &maps, &choice)?);
        if let Some(f) = &fragility {
            written.extend(report::fragility::plot_fragility(&dir, &options, f)?);
        }
        if let Some(risk) = &risk {
            written.extend(report::plot_risk(&dir, &options, risk)?);
        }
        if let (Some(a), Some(b)) = (&args.a, &args.b) {
            match report::plot_map_differences(&dir, &options, &maps, a, b)? {
                Some(path) => written.push(path),
                None => eprintln!("--a/--b: these results hold no overturning maps to compare"),
            }
        }
        if let Some((index, scene, title, history)) = &scene {
            let path = dir.join(format!("scene-{index}.{}", format.extension()));
            report::plot_history(&path, &options, title, scene, history)?;
            written.push(path);
        }
    }
    if written.is_empty() {
        anyhow::bail!("no figure written (see the messages above)");
    }
    for path in &written {
        println!("{}", path.display());
    }
    Ok(())
}
