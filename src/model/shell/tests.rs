//! Unit tests of the rocking shell.

use super::*;
use crate::excitation::Gravity;
use crate::model::SimModel;
use crate::model::rigid::RigidModel;
use crate::presets::{mechanistic, rigid_fig8};
use crate::scene::Structure;
use crate::solver::OdeSystem;

/// The closed-form event rates are the event functions' derivatives along the solution:
/// central differences along the tangent agree, for a clutch engaged on one side, play
/// taken up on the other, resettable and not, about either pivot.
#[test]
fn closed_form_event_rates_match_differences_along_the_solution() {
    let scene = rigid_fig8(mechanistic());
    let Structure::Rigid(block) = &scene.structure else {
        unreachable!()
    };
    // Fig. 8's sine pulse, A = 1.5 g tan α at ω = 4p (the model reads a_g only).
    let motion = Motion::pulse(crate::excitation::Pulse::new(
        crate::excitation::PulseShape::Sine,
        1.5 * Gravity::STANDARD.g() * block.alpha.tan(),
        4.0 * scene.structure.p(),
    ));
    let device = DeviceModel::new(
        &scene.device,
        block.mass,
        scene.structure.p(),
        motion.gravity().g(),
    );
    for (rotation, fly) in [
        (0.3 * block.alpha, [0.004, 0.02, -0.003, -0.05]),
        (-0.2 * block.alpha, [-0.001, -0.3, 0.002, 0.1]),
        (0.5 * block.alpha, [0.05, 0.4, 0.06, 0.2]),
    ] {
        let mut model = RigidModel::new(block, device, scene.impact, &motion, rotation);
        let mut y = [0.0; 10];
        model.start(&mut y);
        y[1] = 0.7 * rotation.signum();
        y[2..6].copy_from_slice(&fly);
        let t = 0.1;
        let mut f = [0.0; 10];
        model.rhs(t, &y, &mut f);
        let m = OdeSystem::<10>::event_count(&model);
        let (mut g, mut rates) = ([0.0; MAX_EVENTS], [0.0; MAX_EVENTS]);
        assert!(model.events_with_rates(t, &y, &f, &mut g[..m], &mut rates[..m]));
        let at = |eps: f64| {
            let mut ge = [0.0; MAX_EVENTS];
            let ye: [f64; 10] = std::array::from_fn(|i| y[i] + eps * f[i]);
            model.events(t + eps, &ye, &mut ge[..m]);
            ge
        };
        let mut direct = [0.0; MAX_EVENTS];
        model.events(t, &y, &mut direct[..m]);
        let eps = 1e-6;
        let (ahead, behind) = (at(eps), at(-eps));
        for i in 0..m {
            assert_eq!(
                g[i],
                direct[i],
                "value of {}",
                SimModel::<10>::event_name(&model, i)
            );
            let difference = (ahead[i] - behind[i]) / (2.0 * eps);
            assert!(
                (rates[i] - difference).abs() <= 1e-6 * (1.0 + difference.abs()),
                "{}: closed form {} vs difference {difference}",
                SimModel::<10>::event_name(&model, i),
                rates[i]
            );
        }
    }
}
