//! `rocklab plot`: figures from a results file.

use super::UsageError;
use crate::report::{self, ImageFormat};
use anyhow::Context;
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug, Clone)]
pub struct PlotArgs {
    /// Results file (results.json) or the directory holding it.
    pub results: PathBuf,
    /// Write SVG figures into this directory.
    #[arg(long, conflicts_with = "png", required_unless_present = "png")]
    pub svg: Option<PathBuf>,
    /// Write PNG figures into this directory.
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Also plot the histories of this scene (its index in the study; rerun from its stored
    /// scene).
    #[arg(long)]
    pub scene: Option<usize>,
}

pub fn run(args: &PlotArgs) -> anyhow::Result<()> {
    let results = report::load_results(&super::compare::resolve_results(&args.results))?;
    let (dir, format) = match (&args.svg, &args.png) {
        (Some(d), _) => (d.clone(), ImageFormat::Svg),
        (None, Some(d)) => (d.clone(), ImageFormat::Png),
        (None, None) => return Err(UsageError::new("give --svg DIR or --png DIR").into()),
    };
    std::fs::create_dir_all(&dir)
        .with_context(|| format!("cannot create output directory {}", dir.display()))?;
    let name = results
        .study
        .as_ref()
        .map_or("results", |s| s.name.as_str());
    let mut written = report::plot_spectra(&dir, format, name, &report::spectra(&results))?;
    written.extend(report::plot_maps(&dir, format, &report::maps(&results))?);
    if let Some(index) = args.scene {
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
        // Under the sweep's guard: a scene that panics fails here as it did in the sweep.
        let library = crate::excitation::library::global()?;
        let (_, history) = crate::sweep::guarded(|| {
            crate::sim::run_with_history(&outcome.point.scene, library, true)
        })
        .map_err(|e| anyhow::anyhow!("scene {index} failed: {e}"))?;
        let history = history.context("no history recorded")?;
        let path = dir.join(format!(
            "scene-{index}.{}",
            if format == ImageFormat::Svg {
                "svg"
            } else {
                "png"
            }
        ));
        let title = report::scene_title(index, &outcome.point.group, &outcome.point.coords);
        report::plot_history(&path, format, &title, &history)?;
        written.push(path);
    }
    for path in &written {
        println!("{}", path.display());
    }
    Ok(())
}
