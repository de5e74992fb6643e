//! What moves the inner ends of the tie rods (`TieRodDrive`) and the path it gives them (`TieRodPath`): the
//! steering's side of the front suspension loops, which `suspension::Corner` follows (moved from suspension/
//! so that the steering no longer imports the suspension for it, issue 33).

use crate::math::{rotation_about_sc, V3};
use serde::{Deserialize, Serialize};

/// What moves the inner end of the tie rod, as a function of the steering coordinate s (after the
/// steering's sign): nothing (a rear toe link), a rack (s along +y_C, m) or the link of a parallelogram
/// Pitman-arm steering (s the arm's angle, rad: the link translates on the circle its arm joint describes).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum TieRodDrive {
    Chassis,
    Rack,
    PitmanLink {
        /// The Pitman arm's pivot axis (unit) and the arm from its axis to the arm–link joint.
        axis: V3,
        arm: V3,
    },
}

/// The inner tie-rod point's path at s: the point and its first and second derivatives with respect to s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TieRodPath {
    pub point: V3,
    pub d_ds: V3,
    pub d2_ds2: V3,
}

impl TieRodDrive {
    #[inline(always)]
    pub fn path(&self, design: &V3, s: f64) -> TieRodPath {
        match *self {
            TieRodDrive::Chassis => TieRodPath { point: *design, d_ds: V3::zeros(), d2_ds2: V3::zeros() },
            TieRodDrive::Rack => {
                TieRodPath { point: design + V3::new(0.0, s, 0.0), d_ds: V3::y(), d2_ds2: V3::zeros() }
            }
            TieRodDrive::PitmanLink { axis, arm } => {
                let (sn, cs) = crate::math::elementary::sin_cos(s);
                let turned = rotation_about_sc(&axis, sn, cs) * arm;
                let d_ds = axis.cross(&turned);
                TieRodPath { point: design + turned - arm, d_ds, d2_ds2: axis.cross(&d_ds) }
            }
        }
    }
}
