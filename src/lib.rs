//! rocklab: parametric seismic studies of rocking structures protected by clutched inerters.
//!
//! Data flows one way: scene → [`sim::run`] (model + excitation + solver) → result.
//! See docs/MODEL.md in the repository for the equations each module implements.

#[macro_use]
mod enum_all;

pub mod cli;
pub mod error;
pub mod excitation;
pub mod fsutil;
pub mod model;
pub mod numfmt;
pub mod paper;
pub mod presets;
pub mod report;
pub mod risk;
pub mod ron_syntax;
pub mod scene;
pub mod sim;
pub mod solver;
pub mod stats;
pub mod study;
pub mod sweep;
pub mod trig;
pub mod tui;

#[cfg(test)]
mod layering;
