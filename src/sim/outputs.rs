//! Output channels: the CLI's CSV columns, reused by name as the FMU's output variables.

/// The one table of the output channels, in CSV order (SI; ISO 8855: x forward, y left, z up): each row
/// is a channel's name in the code and its column name. `Channel` and `OUTPUT_NAMES` are generated from it,
/// so code names a channel (`Channel::Ay`) and never writes its column number.
macro_rules! output_table {
    ($($channel:ident = $name:literal,)*) => {
        /// An output channel; `index()` is its column in `OUTPUT_NAMES` (and in `Outputs::values`).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[repr(usize)]
        pub enum Channel {
            $($channel,)*
        }

        impl Channel {
            /// Every channel, in column order.
            pub const ALL: [Channel; [$($name),*].len()] = [$(Channel::$channel,)*];
        }

        /// Column names, in CSV order.
        pub const OUTPUT_NAMES: [&str; Channel::ALL.len()] = [$($name,)*];
    };
}

output_table! {
    Time = "time",
    X = "x",
    Y = "y",
    Z = "z",
    Roll = "roll",
    Pitch = "pitch",
    Yaw = "yaw",
    Vx = "vx",
    Vy = "vy",
    Vz = "vz",
    RollRate = "roll_rate",
    PitchRate = "pitch_rate",
    YawRate = "yaw_rate",
    Ax = "ax",
    Ay = "ay",
    Az = "az",
    RackDisplacement = "rack_displacement",
    SteerFl = "steer_fl",
    SteerFr = "steer_fr",
    WheelZFl = "wheel_z_fl",
    WheelZFr = "wheel_z_fr",
    WheelZRl = "wheel_z_rl",
    WheelZRr = "wheel_z_rr",
    WheelSpinFl = "wheel_spin_fl",
    WheelSpinFr = "wheel_spin_fr",
    WheelSpinRl = "wheel_spin_rl",
    WheelSpinRr = "wheel_spin_rr",
    TireFxFl = "tire_fx_fl",
    TireFxFr = "tire_fx_fr",
    TireFxRl = "tire_fx_rl",
    TireFxRr = "tire_fx_rr",
    TireFyFl = "tire_fy_fl",
    TireFyFr = "tire_fy_fr",
    TireFyRl = "tire_fy_rl",
    TireFyRr = "tire_fy_rr",
    TireFzFl = "tire_fz_fl",
    TireFzFr = "tire_fz_fr",
    TireFzRl = "tire_fz_rl",
    TireFzRr = "tire_fz_rr",
    KappaFl = "kappa_fl",
    KappaFr = "kappa_fr",
    KappaRl = "kappa_rl",
    KappaRr = "kappa_rr",
    AlphaFl = "alpha_fl",
    AlphaFr = "alpha_fr",
    AlphaRl = "alpha_rl",
    AlphaRr = "alpha_rr",
    ConstraintResidual = "constraint_residual",
    NewtonIterations = "newton_iterations",
}

impl Channel {
    /// The per-wheel channels, each in the wheel order fl, fr, rl, rr.
    pub const WHEEL_Z: [Channel; 4] = [Channel::WheelZFl, Channel::WheelZFr, Channel::WheelZRl, Channel::WheelZRr];
    pub const WHEEL_SPIN: [Channel; 4] =
        [Channel::WheelSpinFl, Channel::WheelSpinFr, Channel::WheelSpinRl, Channel::WheelSpinRr];
    /// Tire force per component (x, y, z), each per wheel.
    pub const TIRE_FORCE: [[Channel; 4]; 3] = [
        [Channel::TireFxFl, Channel::TireFxFr, Channel::TireFxRl, Channel::TireFxRr],
        [Channel::TireFyFl, Channel::TireFyFr, Channel::TireFyRl, Channel::TireFyRr],
        [Channel::TireFzFl, Channel::TireFzFr, Channel::TireFzRl, Channel::TireFzRr],
    ];
    pub const KAPPA: [Channel; 4] = [Channel::KappaFl, Channel::KappaFr, Channel::KappaRl, Channel::KappaRr];
    pub const ALPHA: [Channel; 4] = [Channel::AlphaFl, Channel::AlphaFr, Channel::AlphaRl, Channel::AlphaRr];

    /// Its column in `OUTPUT_NAMES`.
    pub const fn index(self) -> usize {
        self as usize
    }

    /// Its column name.
    pub const fn name(self) -> &'static str {
        OUTPUT_NAMES[self as usize]
    }

    /// The channel of a column name.
    pub fn from_name(name: &str) -> Option<Channel> {
        Channel::ALL.iter().copied().find(|c| c.name() == name)
    }

    /// Whether it is read straight from the state (time, pose, velocities, rack position: no evaluation of
    /// the model needed) rather than from an evaluation (accelerations, wheels, tires).
    pub const fn from_state(self) -> bool {
        use Channel::*;
        matches!(
            self,
            Time | X | Y | Z | Roll | Pitch | Yaw | Vx | Vy | Vz | RollRate | PitchRate | YawRate | RackDisplacement
        )
    }
}

/// The scene CSV holds the channels through `alpha_rr`; the last two are FMU diagnostics:
/// max |Φ| over the subsystems at the last evaluation (m), Newton iterations of the last evaluation.
pub const CSV_COLUMNS: usize = Channel::AlphaRr.index() + 1;

/// Whether output `index` is read straight from the state (`Channel::from_state`).
pub const fn from_state(index: usize) -> bool {
    Channel::ALL[index].from_state()
}

/// One sample of every output channel, indexed like `OUTPUT_NAMES`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outputs {
    pub values: [f64; OUTPUT_NAMES.len()],
}

impl Default for Outputs {
    fn default() -> Self {
        Outputs { values: [0.0; OUTPUT_NAMES.len()] }
    }
}

/// Outputs are read by `Channel`, never by a name (a name from outside, such as a study's metric, is parsed
/// once by `Channel::from_name`, where it can be refused with its cause).
impl std::ops::Index<Channel> for Outputs {
    type Output = f64;

    fn index(&self, channel: Channel) -> &f64 {
        &self.values[channel.index()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_channels_are_the_columns_in_order() {
        for (i, channel) in Channel::ALL.iter().enumerate() {
            assert_eq!((channel.index(), Channel::from_name(channel.name())), (i, Some(*channel)));
        }
        assert_eq!(OUTPUT_NAMES[CSV_COLUMNS - 1], "alpha_rr");
        assert_eq!((CSV_COLUMNS, OUTPUT_NAMES.len()), (47, 49));
        let per_wheel = [Channel::WHEEL_Z, Channel::WHEEL_SPIN, Channel::KAPPA, Channel::ALPHA];
        for (group, wheel) in
            per_wheel.iter().chain(&Channel::TIRE_FORCE).flat_map(|g| g.iter().zip(["fl", "fr", "rl", "rr"]))
        {
            assert!(group.name().ends_with(wheel), "{group:?}");
        }
        for (component, group) in ["tire_fx", "tire_fy", "tire_fz"].iter().zip(Channel::TIRE_FORCE) {
            assert!(group.iter().all(|c| c.name().starts_with(component)), "{group:?}");
        }
    }

    #[test]
    fn the_state_outputs_are_the_pose_the_velocities_and_the_rack() {
        let state: Vec<&str> = (0..OUTPUT_NAMES.len()).filter(|&i| from_state(i)).map(|i| OUTPUT_NAMES[i]).collect();
        assert_eq!(
            state,
            [
                "time",
                "x",
                "y",
                "z",
                "roll",
                "pitch",
                "yaw",
                "vx",
                "vy",
                "vz",
                "roll_rate",
                "pitch_rate",
                "yaw_rate",
                "rack_displacement"
            ]
        );
    }
}
