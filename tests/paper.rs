//! The paper's results-section claims, one test per claim, named after its figure. Each check
//! (rocklab::paper, which also writes PAPER.md through `rocklab paper`) states its margin
//! in its claim text; a test fails with the paper's statement and rocklab's measurement.

use rocklab::paper::{self, Agreement, Claim};

fn assert_agrees(check: fn() -> anyhow::Result<Claim>) {
    let c = check().expect("the check's scenes run");
    println!("{}: {}\n  rocklab: {}", c.figure, c.claim, c.rocklab);
    assert_eq!(
        c.verdict,
        Agreement::Agrees,
        "{} — {}\n  paper: {}\n  rocklab: {}",
        c.figure,
        c.claim,
        c.paper,
        c.rocklab
    );
}

#[test]
fn fig3_restitution_grows_with_sigma() {
    assert_agrees(paper::fig3_restitution_grows_with_sigma);
}

#[test]
fn fig5_dirac_converges_to_housner() {
    assert_agrees(paper::fig5_dirac_converges_to_housner);
}

#[test]
fn fig5_wide_dirac_removes_spikes() {
    assert_agrees(paper::fig5_wide_dirac_removes_spikes);
}

#[test]
fn s9_fig8_protected_blocks_accelerate_less() {
    assert_agrees(paper::s9_protected_blocks_accelerate_less);
}

#[test]
fn fig8_11_peak_ordering() {
    assert_agrees(paper::fig8_peak_ordering);
}

#[test]
fn fig8_9_sequential_decays_faster() {
    assert_agrees(paper::fig8_sequential_decays_faster);
}

#[test]
fn fig12_bare_overturning_boundary() {
    assert_agrees(paper::fig12_bare_overturning_boundary);
}

#[test]
fn fig12_mechanistic_marginally_below_sequential() {
    assert_agrees(paper::fig12_mechanistic_marginally_below_sequential);
}

#[test]
fn fig12_mechanistic_accelerations_larger() {
    assert_agrees(paper::fig12_mechanistic_accelerations_larger);
}

#[test]
fn fig14_inerter_cuts_uplift_clutches_more() {
    assert_agrees(paper::fig14_inerter_cuts_uplift_clutches_more);
}

#[test]
fn fig15_clutched_energy_does_not_flow_back() {
    assert_agrees(paper::fig15_clutched_energy_does_not_flow_back);
}

#[test]
fn fig18_stiffness_not_determinant() {
    assert_agrees(paper::fig18_stiffness_not_determinant);
}

#[test]
fn fig19_operational_damping_immaterial() {
    assert_agrees(paper::fig19_operational_damping_immaterial);
}

#[test]
fn fig19_supplemental_damping_halves_rotation() {
    assert_agrees(paper::fig19_supplemental_damping_halves_rotation);
}

#[test]
fn fig21_strong_friction_cuts_response() {
    assert_agrees(paper::fig21_strong_friction_cuts_response);
}

#[test]
fn fig23_play_leaves_peaks_raises_accelerations() {
    assert_agrees(paper::fig23_play_leaves_peaks_raises_accelerations);
}

#[test]
fn fig24_mechanistic_below_sequential() {
    assert_agrees(paper::fig24_mechanistic_below_sequential);
}

#[test]
fn fig24_accelerations_and_overturning() {
    assert_agrees(paper::fig24_accelerations_and_overturning);
}

/// Every check above is in the command's list (so PAPER.md shows it), and the claims listed
/// without a check say why.
#[test]
fn paper_md_lists_every_check() {
    assert_eq!(paper::CHECKS.len(), 18);
    for c in paper::not_checked() {
        assert!(matches!(c.verdict, Agreement::NotChecked(why) if !why.is_empty()));
    }
}
