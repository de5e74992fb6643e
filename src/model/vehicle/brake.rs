//! Wheel brake (docs/physics.md §5.5): a friction clamp of a given capacity between the wheel and its carrier;
//! its stage of the evaluation (`brake_stage`) follows the tire's.
//!
//! A brake either holds the wheel to its carrier or slips at its capacity. The old law, capacity ×
//! tanh(Ω_rel / 0.5 rad/s), made "holding" a viscous coupling of slope capacity/0.5 rad/s: a stiff
//! eigenvalue (−1100 1/s at 4 kN·m, −27 000 1/s at 100 kN·m) that RK4 at 2 ms cannot follow, a held wheel
//! that creeps, and a wheel that a large capacity could spin up.
//!
//! Here the brake asks for the torque that stops the relative spin within `STICK_TIME_S`,
//! T* = T_other + I_s Ω_rel / τ (T_other: drive and tire torques on the wheel), and gets it while it is
//! within the capacity C: the wheel then holds exactly (Ω̇_rel = −Ω_rel/τ, no creep), whatever C. Beyond,
//! the torque saturates at C with the sign of T* (sliding pads). The only time scale is τ, so the stiffness
//! no longer grows with C, and the torque never exceeds C. The price of the regularization: while
//! |Ω_rel| < τ |T_other| / I_s the holding brake may pass torque in the direction of the slip (it slows
//! the wheel's way through Ω_rel = 0 to the rate 1/τ), an energy of order T_other Ω_rel τ.

/// Time in which a holding brake takes out the relative spin, s. Its rate 1/τ = 50 1/s stays inside the
/// stability region of every explicit scheme here at the paper's 8.3 ms step (AB3: |λh| ≤ 0.54).
pub const STICK_TIME_S: f64 = 0.02;
/// Below this fraction of the capacity the demanded torque is given exactly; above, it approaches the
/// capacity smoothly (C¹), never exceeding it.
const EXACT_FRACTION: f64 = 0.95;

/// Brake torque on the wheel (opposing Ω_rel when positive) for a clamp `capacity` ≥ 0 and the torque the
/// brake needs to hold the wheel, `demand` = T_other + I_s Ω_rel / τ.
pub fn torque(capacity: f64, demand: f64) -> f64 {
    if !(capacity > 0.0) {
        return 0.0;
    }
    let knee = EXACT_FRACTION * capacity;
    let magnitude = demand.abs();
    if magnitude <= knee {
        return demand;
    }
    let width = capacity - knee;
    (capacity - width * (-(magnitude - knee) / width).exp()).copysign(demand)
}

/// The holding demand T* for a wheel of spin inertia `spin_inertia` at relative spin `spin_rel`.
pub fn demand(other_torque: f64, spin_inertia: f64, spin_rel: f64) -> f64 {
    other_torque + spin_inertia * spin_rel / STICK_TIME_S
}

/// The brake stage: each brake between its wheel and carrier holds the relative spin within its capacity.
impl super::Vehicle {
    /// Adds each brake's torque to its carrier's wrench and takes it out of the wheel's spin torque
    /// (`assembly.spin_torque`, which the tire stage left as the drive and tire torques).
    #[inline(always)]
    pub(super) fn brake_stage(&self, inputs: &super::Inputs, ws: &mut super::Workspace) {
        for i in 0..4 {
            self.corner_brake(i, inputs, ws);
        }
    }

    /// The brake stage for corner i alone.
    #[inline(always)]
    pub(super) fn corner_brake(&self, i: usize, inputs: &super::Inputs, ws: &mut super::Workspace) {
        let super::Workspace { kinematics, wrenches, assembly, diagnostics, .. } = ws;
        let free_torque = assembly.spin_torque[i];
        let spin_rel = diagnostics.wheel_spin_relative[i];
        let brake = torque(inputs.brake[i], demand(free_torque, self.corners[i].spin_inertia, spin_rel));
        let axle = kinematics[i].axle;
        wrenches[i].bodies[super::BODY_K] += crate::dynamics::body::wrench(&crate::math::V3::zeros(), &(axle * brake));
        assembly.spin_torque[i] = free_torque - brake;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holds_exactly_within_capacity_and_saturates_beyond() {
        assert_eq!(torque(4000.0, 1234.5), 1234.5);
        assert_eq!(torque(4000.0, -3800.0), -3800.0);
        // Beyond the knee: below the capacity, approaching it, continuous with slope 1 at the knee.
        let knee = EXACT_FRACTION * 4000.0;
        assert!((torque(4000.0, knee + 1e-6) - (knee + 1e-6)).abs() < 1e-9);
        assert!(torque(4000.0, 5000.0) < 4000.0 && torque(4000.0, 5000.0) > 3999.0);
        assert_eq!(torque(4000.0, 1e9), 4000.0);
        assert_eq!(torque(4000.0, -1e9), -4000.0);
        // No capacity, no torque (and no division by zero).
        assert_eq!(torque(0.0, 500.0), 0.0);
    }

    #[test]
    fn a_held_wheel_loses_its_relative_spin_at_the_stick_rate() {
        // I Ω̇ = T_other − T_b: within the capacity, Ω̇ = −Ω/τ whatever the other torque.
        let (inertia, other, spin) = (7.3, 1500.0, 2.0);
        let tb = torque(1e5, demand(other, inertia, spin));
        assert!(((other - tb) / inertia + spin / STICK_TIME_S).abs() < 1e-9);
    }
}
