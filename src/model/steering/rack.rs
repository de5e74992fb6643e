//! The steering rack, driven kinematically (physics.md §2, §4.7).
//!
//! The rack translates along the chassis y axis by the prescribed s(t) = σ_r·u(t) (u: the input, + left
//! turn). Prescribed relative to the chassis, it belongs kinematically to the chassis: it closes no loop
//! (each front SLA subsystem stays independent), adds its inertia M̂_R to the chassis equation and its
//! motion, through Q̂*_R = Q̂_R − M̂_R (B_R s̈ + D_R), to the chassis force. Its translation enters the
//! front tie-rod constraints (`SlaGeometry::tie_rod_inner`).

use crate::dynamics::body::{body_force, lin, mass_hat, wrench};
use crate::math::{Axes, M3, V3};
use crate::model::params::{RigidBody, VehicleData};
use crate::model::suspension::sla::BodyInertia;
use nalgebra::{Matrix6, Vector6};
use serde::{Deserialize, Serialize};

/// Rack input and its time derivatives (+ = left turn input u, m, m/s, m/s²).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct RackMotion {
    pub position: f64,
    pub velocity: f64,
    pub acceleration: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Rack {
    /// Mass properties; the CM at zero travel, relative to the chassis CM, in chassis axes.
    pub body: BodyInertia,
    /// σ_r in s = σ_r u: sign(∂δ̄/∂s) at design, set once the suspension is known, so that u > 0 steers left.
    pub sign: f64,
    /// Largest |u| the steering accepts, m.
    pub travel_limit: f64,
}

impl Rack {
    /// The rack of the data, with σ_r = +1 until the vehicle has measured the steering gain.
    pub fn from_data(data: &VehicleData) -> Rack {
        let r = &data.rack;
        let inertia = RigidBody {
            mass_kg: r.mass_kg,
            inertia_moments_kg_m2: r.inertia_moments_kg_m2,
            inertia_products_kg_m2: r.inertia_products_kg_m2,
        };
        let com = V3::from(r.com_m) - V3::from(data.chassis.com_m);
        Rack {
            body: BodyInertia { mass: r.mass_kg, com, inertia: inertia.inertia() },
            sign: 1.0,
            travel_limit: r.travel_limit_m,
        }
    }

    /// Rack translation s, ṡ, s̈ along +y of the chassis for the input u.
    pub fn translation(&self, u: &RackMotion) -> RackMotion {
        RackMotion {
            position: self.sign * u.position,
            velocity: self.sign * u.velocity,
            acceleration: self.sign * u.acceleration,
        }
    }

    /// CM position (from the chassis CM), CM velocity and inertia in the `axes`, for chassis velocity ṙ0 and
    /// angular velocity ω0 (in the same axes) and rack translation `s`.
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
