//! One edit switches a study's excitation kind (pulse ↔ record, a record list ↔ a suite):
//! the fields that depend on the excitation follow, and each change is said in a short note.
//! The rule lives here so that the workbench, the CLI and Python share it (the workbench
//! edits studies; it owns no study rule).

use super::{Axis, ExcitationFamily, Layout, Study};

/// A study field's spelling of an axis (`frequency`, `scale`).
fn axis_name(axis: Axis) -> String {
    ron::to_string(&axis).unwrap_or_else(|_| format!("{axis:?}"))
}

impl Study {
    /// Make the fields that depend on the excitation fit it after its kind changed: a
    /// spectrum axis the excitation no longer has becomes its natural one (a pulse's
    /// frequency; a record's scale, or the first structure axis that varies), a map over an
    /// axis that is gone is dropped, and a fragility (and risk) section, which needs records,
    /// is dropped under a pulse. Returns one short note per change (none when all fit).
    pub fn follow_excitation(&mut self) -> Vec<String> {
        let Ok(layout) = Layout::of(self) else {
            return Vec::new();
        };
        let params = layout
            .variants
            .first()
            .map(|v| &v.params[..])
            .unwrap_or(&[]);
        let has = |axis: Axis| params.iter().any(|p| p.axis == Some(axis));
        let varies = |axis: Axis| params.iter().any(|p| p.axis == Some(axis) && p.varies());
        let pulse = matches!(self.excitation, ExcitationFamily::Pulse { .. });
        let mut notes = Vec::new();
        if !has(self.spectrum) {
            let natural = if pulse {
                Axis::Frequency
            } else {
                [
                    Axis::Scale,
                    Axis::Size,
                    Axis::P,
                    Axis::Alpha,
                    Axis::R0,
                    Axis::OmegaN,
                ]
                .into_iter()
                .chain([Axis::OmegaRatio, Axis::Xi])
                .find(|a| varies(*a))
                .unwrap_or(Axis::Scale)
            };
            notes.push(format!(
                "spectrum {} → {}",
                axis_name(self.spectrum),
                axis_name(natural)
            ));
            self.spectrum = natural;
        }
        if let Some(map) = self.map
            && !(has(map.x) && has(map.y))
        {
            self.map = None;
            notes.push("map dropped (its axes are gone)".into());
        }
        if pulse && self.fragility.is_some() {
            self.fragility = None;
            self.risk = None;
            notes.push("fragility dropped (it needs records)".into());
        }
        notes
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::MapAxes;

    #[test]
    fn a_pulse_study_switched_to_a_record_follows_in_one_step() {
        let mut study = Study::builtin_default();
        study.map = Some(MapAxes {
            x: Axis::Frequency,
            y: Axis::Amplitude,
            refine: None,
        });
        let mut switched = study.clone();
        switched.excitation =
            ron::from_str("record(names: [\"landers\"], scale: [0.5, 1.0])").unwrap();
        // As edited, the study is refused: its spectrum and map name the pulse's axes.
        assert!(switched.expand().is_err());
        let notes = switched.follow_excitation();
        assert_eq!(
            notes,
            [
                "spectrum frequency → scale",
                "map dropped (its axes are gone)"
            ]
        );
        assert_eq!(switched.spectrum, Axis::Scale);
        assert!(switched.map.is_none());
        // Back to a pulse: the frequency axis returns, and nothing else is said.
        let mut back = switched.clone();
        back.excitation = study.excitation.clone();
        assert_eq!(back.follow_excitation(), ["spectrum scale → frequency"]);
        assert_eq!(back.spectrum, Axis::Frequency);
        // A study that fits says nothing and is unchanged.
        let mut same = Study::builtin_default();
        assert!(same.follow_excitation().is_empty());
        assert_eq!(same, Study::builtin_default());
    }
}
