//! The three-link independent rear suspension (Chrono's `ThreeLinkIRS`, `ChThreeLinkIRS::InitializeSide`): a
//! trailing arm on a spherical joint to the chassis at TA_C, held by an upper and a lower link (each a
//! universal joint on the chassis and a spherical one on the arm: a rod of fixed length between UL_C and UL_A,
//! LL_C and LL_A); the spindle turns on the arm, and the spring and the damper act between the chassis and the
//! arm. One degree of freedom per wheel. Not steerable.
//!
//! Tree: chassis →(revolute θ_L about h through TA_C)→ L →(Bryant φ1..3 at TA_C)→ arm. L is a massless frame:
//! the spherical joint's three rotations are θ_L and the Bryant angles, one of which is held at 0 so that the
//! four make three; h is the arm's instantaneous axis at design (the direction no link's length resists, ⊥ to
//! both (A − TA_C) × (A − C)), so θ_L is the arm's swing and the held angle the one along h (the other two are
//! what the links fix). Rows: the upper link's length, the held angle, q[4] = 0 (`Closure::Links`), and the
//! lower link as the corner's tie rod, fixed to the chassis. The carrier body is the arm with the spindle, wheel
//! and tire (the links are massless: two-force members).

use super::{carrier_inertia, static_axle, BodyInertia, Closure, Corner, Hardpoints, LineMount, Links, MountBody};
use super::{Side, TieRodDrive};
use crate::model::formats::params::{Axle, DataError, SuspensionTemplate, VehicleData};

/// The corner of a three-link IRS axle: left side as given, right side mirrored.
pub fn from_data(data: &VehicleData, axle: &Axle, side: Side) -> Result<Corner, DataError> {
    let points = Hardpoints::new(data, axle, side);
    let pt = |name: &str| points.point(name);
    let (ta_c, w0) = (pt("TA_C"), pt("SPINDLE"));
    let (ul_c, ul_a, ll_c, ll_a) = (pt("UL_C"), pt("UL_A"), pt("LL_C"), pt("LL_A"));
    let field = "hardpoints_chassis_frame_m".to_string();
    // The arm's instantaneous axis: ω with each link's end velocity ω × (A − TA_C) across its rod.
    let n_u = (ul_a - ta_c).cross(&(ul_a - ul_c));
    let n_l = (ll_a - ta_c).cross(&(ll_a - ll_c));
    let axis = n_u.cross(&n_l);
    if !(axis.norm() > 1e-6 * n_u.norm() * n_l.norm()) {
        return Err(DataError {
            field,
            message: "the upper and lower links do not locate the trailing arm (with the spherical joint at TA_C \
                      they leave it more than one motion, or none)"
                .into(),
        });
    }
    let mut h = axis.normalize();
    if h.cross(&(w0 - ta_c)).z < 0.0 {
        h = -h; // a positive θ_L lifts the wheel, as every template's
    }
    let held = (0..3).max_by(|&a, &b| h[a].abs().total_cmp(&h[b].abs())).expect("three axes");
    let arm = BodyInertia {
        mass: axle.lower_arm.mass_kg,
        com: pt("TA_CM"),
        inertia: side.mirror_inertia(axle.lower_arm.inertia()),
    };
    let (wheel, spin_inertia) = carrier_inertia(data, axle, side, w0, w0);
    let mount =
        |chassis: &str, moving: &str| LineMount { chassis: pt(chassis), moving: pt(moving), body: MountBody::Carrier };
    Ok(Corner {
        template: SuspensionTemplate::ThreeLinkIrs,
        side,
        drive: TieRodDrive::Chassis,
        p_l: ta_c,
        h_l: h,
        b0: ta_c,
        t_k: ll_a,
        t_r0: ll_c,
        w0,
        tie_length: (ll_a - ll_c).norm(),
        closure: Closure::Links(Links { chassis: ul_c, arm0: ul_a, length: (ul_a - ul_c).norm(), held }),
        spring: mount("SPRING_C", "SPRING_A"),
        shock: mount("SHOCK_C", "SHOCK_A"),
        lower: BodyInertia::NONE,
        upper: BodyInertia::NONE,
        carrier: BodyInertia::combined(&[wheel, arm]),
        spin_inertia,
        axle: static_axle(axle, side),
        design_det: 1.0,
    }
    .measured_at_design())
}
