//! The steering as the vehicle assembles it (`Steering`): its input, the body that moves with it relative to
//! the chassis (the rack) and that body's share of the chassis equation (docs/physics.md §4.7).

use super::RackMotion;
use crate::dynamics::body::{body_force, lin, mass_hat, wrench};
use crate::math::{Axes, M3, V3};
use crate::model::formats::params::{SteeringInput, VehicleData};
use crate::model::suspension::BodyInertia;
use nalgebra::{Matrix6, Vector6};
use serde::{Deserialize, Serialize};

/// The steering of a vehicle: its input, the body that moves with it relative to the chassis (the rack;
/// none for the Pitman arm, whose arm and link ride on the chassis), and the sign that makes a positive
/// input steer left.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Steering {
    pub input: SteeringInput,
    /// Mass properties of the rack; the CM at zero travel, relative to the sprung CM, in chassis axes.
    pub body: BodyInertia,
    /// σ in s = σ u: sign(∂δ̄/∂s) at design, set once the suspension is known, so that u > 0 steers left.
    pub sign: f64,
    /// Largest |u| the steering accepts (m or rad).
    pub travel_limit: f64,
}

impl Steering {
    /// The steering of the data, with σ = +1 until the vehicle has measured the steering gain.
    pub fn from_data(data: &VehicleData) -> Steering {
        let c0 = data.sprung_com();
        match &data.rack {
            Some(r) => {
                let inertia = r.body();
                let com = V3::from(r.com_m) - c0;
                Steering {
                    input: SteeringInput::RackDisplacement,
                    body: BodyInertia { mass: r.mass_kg, com, inertia: inertia.inertia() },
                    sign: 1.0,
                    travel_limit: r.travel_limit_m,
                }
            }
            None => Steering {
                input: SteeringInput::PitmanArmAngle,
                body: BodyInertia::NONE,
                sign: 1.0,
                travel_limit: data.steering_limit(),
            },
        }
    }

    /// The steering coordinate s, ṡ, s̈ (rack translation along +y_C, or Pitman-arm angle) for the input u.
    pub fn translation(&self, u: &RackMotion) -> RackMotion {
        RackMotion {
            position: self.sign * u.position,
            velocity: self.sign * u.velocity,
            acceleration: self.sign * u.acceleration,
        }
    }

    /// Whether a body moves with the steering relative to the chassis (the rack).
    pub fn has_moving_body(&self) -> bool {
        self.body.mass > 0.0
    }

    /// Rack CM position (from the chassis CM), CM velocity and inertia in the `axes`, for chassis velocity
    /// ṙ0 and angular velocity ω0 (in the same axes) and rack translation `s`.
    #[inline(always)]
    pub fn state(&self, axes: &impl Axes, v0: &V3, w0: &V3, s: &RackMotion) -> (V3, V3, M3) {
        let ey = axes.vector(&V3::y());
        let rho = axes.vector(&(self.body.com + V3::y() * s.position));
        let rdot = v0 + ey * s.velocity + w0.cross(&rho);
        (rho, rdot, axes.inertia(&self.body.inertia))
    }

    /// The rack's share of the chassis equation (§4.7): M̂_R and Q̂*_R = Q̂_R − M̂_R (B_R s̈ + D_R), with
    /// B_R = [e_y; 0] and D_R = [ω0 × e_y ṡ; 0].
    #[inline(always)]
    pub fn chassis_terms(
        &self,
        axes: &impl Axes,
        y0: &Vector6<f64>,
        g: &V3,
        s: &RackMotion,
    ) -> (Matrix6<f64>, Vector6<f64>) {
        let (v0, w0) = (lin(y0), V3::new(y0[3], y0[4], y0[5]));
        let (rho, rdot, j) = self.state(axes, &v0, &w0, s);
        let m_hat = mass_hat(self.body.mass, &rho, &j);
        let q_hat = body_force(self.body.mass, &rho, &j, &w0, &rdot, g);
        let ey = axes.vector(&V3::y());
        let prescribed = wrench(&(ey * s.acceleration + w0.cross(&ey) * s.velocity), &V3::zeros());
        (m_hat, q_hat - m_hat * prescribed)
    }
}
