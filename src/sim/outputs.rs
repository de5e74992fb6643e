//! Output channels: the CLI's CSV columns, reused by name as the FMU's output variables.

/// Column names, in CSV order (SI; ISO 8855: x forward, y left, z up).
pub const OUTPUT_NAMES: [&str; 49] = [
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
    "ax",
    "ay",
    "az",
    "rack_displacement",
    "steer_fl",
    "steer_fr",
    "wheel_z_fl",
    "wheel_z_fr",
    "wheel_z_rl",
    "wheel_z_rr",
    "wheel_spin_fl",
    "wheel_spin_fr",
    "wheel_spin_rl",
    "wheel_spin_rr",
    "tire_fx_fl",
    "tire_fx_fr",
    "tire_fx_rl",
    "tire_fx_rr",
    "tire_fy_fl",
    "tire_fy_fr",
    "tire_fy_rl",
    "tire_fy_rr",
    "tire_fz_fl",
    "tire_fz_fr",
    "tire_fz_rl",
    "tire_fz_rr",
    "kappa_fl",
    "kappa_fr",
    "kappa_rl",
    "kappa_rr",
    "alpha_fl",
    "alpha_fr",
    "alpha_rl",
    "alpha_rr",
    "constraint_residual",
    "newton_iterations",
];

/// The scene CSV holds the first 47 channels (through `alpha_rr`); the last two are FMU diagnostics:
/// max |Φ| over the subsystems at the last evaluation (m), Newton iterations of the last evaluation.
pub const CSV_COLUMNS: usize = 47;

/// Whether output `index` is read straight from the state (time, pose, velocities, rack position: no
/// evaluation of the model needed) rather than from an evaluation (accelerations, wheels, tires).
pub const fn from_state(index: usize) -> bool {
    index <= 12 || index == 16
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

impl Outputs {
    pub fn index(name: &str) -> Option<usize> {
        OUTPUT_NAMES.iter().position(|n| *n == name)
    }

    pub fn get(&self, name: &str) -> Option<f64> {
        Self::index(name).map(|i| self.values[i])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
