//! The one integration-test binary (as ripgrep does): each tests/<name>.rs is a module, so the
//! library is linked once. `util` holds the helpers they share.

mod util;

mod adaptive;
mod angular_acceleration;
mod checkpoint;
mod cli_simulate;
mod compare;
mod conditioning;
mod design;
mod design_view;
mod exact_contact;
mod excitation;
mod figures;
mod flexible;
mod fragility_run;
mod fragility_views;
mod fuzz;
mod hard_cases;
mod lost_events;
mod paper;
mod quantities;
mod readme;
mod records_cli;
mod records_sim;
mod rigid;
mod robustness;
mod saving;
mod scene_history;
mod slurm;
mod strict_inputs;
mod studies;
mod study;
mod suites;
mod sweep;
mod tui;
mod tui_compare;
mod tui_results;
mod tui_run;
mod tui_saving;
mod tui_scene;
mod tui_smoke;
mod tui_study;
mod tui_workflow;
