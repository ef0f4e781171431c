//! History columns: the one table of what a scene's history records (name, label, unit).
//! The model writes its rows in [`SimModel::history_columns`](super::SimModel) order; the
//! history CSV, the workbench's Scene screen, the history figure and the paper's rows read
//! them through [`HistoryColumn`], never by a string of their own.

/// Declares [`HistoryColumn`], its [`HistoryColumn::ALL`] list and [`HistoryColumn::info`] from
/// one table, so a column is added in one line and the list cannot miss it.
macro_rules! history_columns {
    ($($(#[$doc:meta])* $column:ident => ($name:literal, $label:literal, $unit:literal, $energy:expr),)*) => {
        /// One column of a scene's history.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum HistoryColumn {
            $($(#[$doc])* $column,)*
        }

        impl HistoryColumn {
            /// Every column, in the table's order.
            pub const ALL: [HistoryColumn; [$($name),*].len()] = [$(HistoryColumn::$column),*];

            pub fn info(self) -> ColumnInfo {
                match self {
                    $(HistoryColumn::$column => ColumnInfo {
                        name: $name,
                        label: $label,
                        unit: $unit,
                        energy: $energy,
                    },)*
                }
            }
        }
    };
}

history_columns! {
    T => ("t", "time", "s", None),
    /// Flexible column deformation u and its rate.
    U => ("u", "u", "m", None),
    UDot => ("u_dot", "u̇", "m/s", None),
    Theta => ("theta", "θ", "rad", None),
    ThetaDot => ("theta_dot", "θ̇", "rad/s", None),
    GroundAccel => ("ground_accel", "ag", "m/s²", None),
    /// The horizontal coordinate X the device acts on, and Ẋ.
    X => ("x", "X", "m", None),
    XDot => ("x_dot", "Ẋ", "m/s", None),
    FlywheelAVel => ("flywheel_a_vel", "flywheel a", "m/s", None),
    FlywheelBVel => ("flywheel_b_vel", "flywheel b", "m/s", None),
    ClutchForceA => ("clutch_force_a", "clutch a", "N", None),
    ClutchForceB => ("clutch_force_b", "clutch b", "N", None),
    DeviceForce => ("device_force", "Fd", "N", None),
    EInput => ("e_input", "input work", "J", Some(EnergyRole::Input)),
    EStructure => ("e_structure", "structure (kinetic + potential)", "J", Some(EnergyRole::Stored)),
    EInerter => ("e_inerter", "flywheels + clutch spring", "J", Some(EnergyRole::Stored)),
    EColumnDamping => ("e_column_damping", "column damping", "J", Some(EnergyRole::Dissipated)),
    EDeviceDamping => ("e_device_damping", "device damping", "J", Some(EnergyRole::Dissipated)),
    EFriction => ("e_friction", "friction", "J", Some(EnergyRole::Dissipated)),
    EImpact => ("e_impact", "impacts", "J", Some(EnergyRole::Dissipated)),
    EDisengagement => ("e_disengagement", "disengagement", "J", Some(EnergyRole::Dissipated)),
    EReset => ("e_reset", "clutch resets", "J", Some(EnergyRole::Dissipated)),
}

/// Where an energy column goes in a balance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnergyRole {
    Input,
    Stored,
    Dissipated,
}

/// What the table says about one column.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ColumnInfo {
    /// The CSV header and the name a history is read by.
    pub name: &'static str,
    /// Legend label.
    pub label: &'static str,
    pub unit: &'static str,
    /// For an energy term, its place in the balance.
    pub energy: Option<EnergyRole>,
}

impl HistoryColumn {
    /// The device columns every rocking model records after its coordinates.
    pub const DEVICE: [HistoryColumn; 8] = {
        use HistoryColumn::*;
        [
            GroundAccel,
            X,
            XDot,
            FlywheelAVel,
            FlywheelBVel,
            ClutchForceA,
            ClutchForceB,
            DeviceForce,
        ]
    };

    /// The energy partition's terms, in the order of [`super::Energy::terms`].
    pub const ENERGY: [HistoryColumn; 9] = {
        use HistoryColumn::*;
        [
            EInput,
            EStructure,
            EInerter,
            EColumnDamping,
            EDeviceDamping,
            EFriction,
            EImpact,
            EDisengagement,
            EReset,
        ]
    };

    pub fn name(self) -> &'static str {
        self.info().name
    }

    pub fn label(self) -> &'static str {
        self.info().label
    }

    pub fn energy(self) -> Option<EnergyRole> {
        self.info().energy
    }

    /// The column of this name, if the table has one.
    pub fn from_name(name: &str) -> Option<HistoryColumn> {
        Self::ALL.into_iter().find(|c| c.name() == name)
    }
}

impl std::fmt::Display for HistoryColumn {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Names are unique and read back to their column; the device and energy lists are
    /// in the table.
    #[test]
    fn names_round_trip() {
        let mut names: Vec<_> = HistoryColumn::ALL.iter().map(|c| c.name()).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), HistoryColumn::ALL.len());
        for c in HistoryColumn::ALL {
            assert_eq!(HistoryColumn::from_name(c.name()), Some(c));
        }
        assert_eq!(HistoryColumn::from_name("nope"), None);
        let energy: Vec<_> = HistoryColumn::ALL
            .into_iter()
            .filter(|c| c.energy().is_some())
            .collect();
        assert_eq!(energy, HistoryColumn::ENERGY);
    }
}
