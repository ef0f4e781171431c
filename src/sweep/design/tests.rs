//! The design search's unit tests: probes at the parameter, and a bisection that always ends.

use super::*;
use crate::scene::Device;

#[test]
fn sigma_zero_is_the_bare_structure_and_clutch_fields_are_set() {
    let study = Study::builtin_default();
    let points = study.expand().unwrap();
    let mech = points
        .iter()
        .find(|p| p.scene.device.name() == "mechanistic")
        .unwrap();
    let bare = with_parameter(&mech.scene, DesignParameter::Sigma, 0.0);
    assert_eq!(bare.device, Device::None);
    let s = with_parameter(&mech.scene, DesignParameter::Sigma, 0.7);
    assert_eq!(s.device.sigma(), 0.7);
    let f = with_parameter(&mech.scene, DesignParameter::Friction, 0.3);
    let Device::Mechanistic(c) = &f.device else {
        panic!("mechanistic stays mechanistic")
    };
    assert_eq!(c.friction, 0.3);
    assert_eq!(c.sigma, mech.scene.device.sigma());
}

/// Issue 43 (F2): a bracket with no f64 between its ends (the resolution asked for is finer
/// than f64's) ends the bisection at its passing end instead of probing an end again forever.
#[test]
fn a_bracket_f64_cannot_split_ends_the_bisection() {
    let text = include_str!("../../../studies/design_sigma_rigid.ron")
        .replace("resolution: 0.01", "resolution: 1e-300");
    // Validation refuses such a resolution; the search must end even without it.
    let study = Study::parse_ron(&text, "tiny.ron").unwrap();
    let mut search = Search::new(&study).unwrap();
    let (lo, hi) = (1.0, f64::from_bits(1.0f64.to_bits() + 1));
    let mut state = State {
        phase: Phase::Bisect,
        lo,
        hi,
        probes: Vec::new(),
        pending: Vec::new(),
        status: DesignStatus::Incomplete,
    };
    let at = search.add_probe(0, &mut state, lo);
    state.probes[at].eval = Some(Evaluation {
        pass: false,
        worst: 0,
        verdict: SceneVerdict::Overturned,
        fit: None,
    });
    state.pending = vec![at];
    search.states[0] = state;
    search.advance(0);
    let state = &search.states[0];
    assert_eq!(state.phase, Phase::Verify);
    assert_eq!(state.hi, hi);
    // Every value it asks for next lies above the answer, none at the failing end.
    for &i in &state.pending {
        assert!(state.probes[i].value >= hi, "{}", state.probes[i].value);
    }
}
