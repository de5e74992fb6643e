//! Longitudinal control: a PI law on the speed error turned into wheel torques, the same law as the vehicle
//! model's own speed hold (rt-vehicle `model::vehicle`, docs/physics.md §8.2): T = m R0 [kp (V* − V) + ki z],
//! ż = V* − V. A positive T drives the four wheels equally; a negative one brakes them equally. The integral
//! stops while the torque is at a limit in the direction of the error (anti-windup).

use serde::{Deserialize, Serialize};

/// The controller's constants.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpeedControl {
    /// Vehicle mass m, kg.
    pub mass: f64,
    /// Wheel radius R0, m.
    pub wheel_radius: f64,
    /// Proportional gain kp, 1/s (acceleration asked per m/s of error).
    pub kp: f64,
    /// Integral gain ki, 1/s².
    pub ki: f64,
    /// Largest total drive torque, N·m (≥ 0).
    pub max_drive: f64,
    /// Largest total brake torque, N·m (≥ 0).
    pub max_brake: f64,
}

/// Torques on the four wheels (FL, FR, RL, RR), N·m: drive (signed as the vehicle's drive inputs) and brake
/// (≥ 0, opposing the spin).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WheelTorques {
    pub drive: [f64; 4],
    pub brake: [f64; 4],
}

impl SpeedControl {
    /// The total torque asked for the speed error `error` = V* − V and the integral `z`, before the limits.
    fn asked(&self, error: f64, z: f64) -> f64 {
        self.mass * self.wheel_radius * (self.kp * error + self.ki * z)
    }

    /// The wheel torques for the speed error `error` = V* − V (m/s) and the integral state `z` (m).
    pub fn torques(&self, error: f64, z: f64) -> WheelTorques {
        let total = self.asked(error, z).clamp(-self.max_brake, self.max_drive);
        if total >= 0.0 {
            WheelTorques { drive: [0.25 * total; 4], brake: [0.0; 4] }
        } else {
            WheelTorques { drive: [0.0; 4], brake: [-0.25 * total; 4] }
        }
    }

    /// ż: the error, or 0 while the torque is saturated in the error's direction.
    pub fn integral_rate(&self, error: f64, z: f64) -> f64 {
        let asked = self.asked(error, z);
        let saturated = (asked > self.max_drive && error > 0.0) || (asked < -self.max_brake && error < 0.0);
        if saturated {
            0.0
        } else {
            error
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const C: SpeedControl =
        SpeedControl { mass: 2000.0, wheel_radius: 0.5, kp: 5.0, ki: 2.0, max_drive: 8000.0, max_brake: 20000.0 };

    #[test]
    fn drives_when_slow_brakes_when_fast_and_saturates() {
        assert_eq!(C.torques(0.1, 0.0), WheelTorques { drive: [125.0; 4], brake: [0.0; 4] });
        assert_eq!(C.torques(-0.1, 0.0), WheelTorques { drive: [0.0; 4], brake: [125.0; 4] });
        assert_eq!(C.torques(10.0, 0.0).drive, [2000.0; 4]);
        assert_eq!(C.torques(-10.0, 0.0).brake, [5000.0; 4]);
        // Anti-windup: no integration into the limit, integration out of it.
        assert_eq!(C.integral_rate(10.0, 0.0), 0.0);
        assert_eq!(C.integral_rate(-10.0, 0.0), 0.0);
        assert_eq!(C.integral_rate(0.5, 0.0), 0.5);
        assert_eq!(C.integral_rate(-0.5, 100.0), -0.5);
    }
}
