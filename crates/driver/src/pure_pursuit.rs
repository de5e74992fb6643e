//! A path-following driver on the rack: pure pursuit (Coulter, "Implementation of the Pure Pursuit Path
//! Tracking Algorithm", CMU-RI-TR-92-01, 1992), the geometric steering law of many vehicle-dynamics test
//! drivers. It aims the rear axle's circle at the point of the path one preview distance ahead:
//! δ = atan(2 L sin α / L_d), with α the angle between the heading and that point and L_d = v T_p. The
//! road-wheel angle is turned into rack travel by the vehicle's steering gain at design, and clamped at the
//! rack's travel limit.

use crate::path::Path;
use serde::{Deserialize, Serialize};

/// What the driver sees of the vehicle: CM position (x, y) in the ground frame, m; yaw ψ, rad; forward speed,
/// m/s; yaw rate, rad/s.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Motion {
    pub x: f64,
    pub y: f64,
    pub yaw: f64,
    pub speed: f64,
    pub yaw_rate: f64,
}

/// The driver's constants.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PurePursuit {
    /// Preview time T_p, s.
    pub preview_time: f64,
    /// Smallest preview distance, m.
    pub min_preview: f64,
    /// Wheelbase L, m.
    pub wheelbase: f64,
    /// Road-wheel angle per metre of rack input, rad/m (the vehicle's steering gain at design).
    pub steering_gain: f64,
    /// Rack travel limit, m.
    pub rack_limit: f64,
    /// How far the CM is ahead of the rear axle, m (pure pursuit aims the rear axle).
    pub cm_ahead: f64,
    /// Yaw-rate feedback K_r, s: δ = atan(L κ) + K_r (v κ − r), with κ = 2 sin α / L_d the pure-pursuit
    /// curvature: it makes the vehicle's yaw rate follow the curvature asked (its lag and understeer).
    pub yaw_rate_gain: f64,
}

impl PurePursuit {
    /// The rack input for the vehicle in motion `m`.
    pub fn rack(&self, path: &Path, m: &Motion) -> f64 {
        let Motion { x, y, yaw, speed, yaw_rate } = *m;
        let rear = [x - self.cm_ahead * yaw.cos(), y - self.cm_ahead * yaw.sin()];
        let preview = (speed.abs() * self.preview_time).max(self.min_preview);
        let target = path.point_at(path.project(rear).s + preview);
        let (dx, dy) = (target[0] - rear[0], target[1] - rear[1]);
        let alpha = dy.atan2(dx) - yaw;
        let distance = dx.hypot(dy).max(1e-6);
        let curvature = 2.0 * alpha.sin() / distance;
        let delta = (self.wheelbase * curvature).atan() + self.yaw_rate_gain * (speed * curvature - yaw_rate);
        (delta / self.steering_gain).clamp(-self.rack_limit, self.rack_limit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn on_a_straight_path_it_steers_back_towards_it() {
        let path = Path::at_speed(vec![[0.0, 0.0], [100.0, 0.0]], 20.0).unwrap();
        let d = PurePursuit {
            preview_time: 0.7,
            min_preview: 3.0,
            wheelbase: 3.3,
            steering_gain: 7.0,
            rack_limit: 0.07,
            cm_ahead: 1.6,
            yaw_rate_gain: 0.0,
        };
        let at = |x: f64, y: f64| Motion { x, y, yaw: 0.0, speed: 20.0, yaw_rate: 0.0 };
        // On the path, heading along it: no steer.
        assert_eq!(d.rack(&path, &at(10.0, 0.0)), 0.0);
        // 1 m to the right of it (y < 0): steer left (positive).
        assert!(d.rack(&path, &at(10.0, -1.0)) > 0.0);
        // More steer asked than the rack has: clamped at its travel limit.
        let weak = PurePursuit { steering_gain: 0.01, ..d };
        assert_eq!(weak.rack(&path, &at(10.0, -1.0)), 0.07);
    }
}
