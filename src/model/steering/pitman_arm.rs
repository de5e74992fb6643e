//! Pitman-arm steering (Chrono's `PitmanArm`), driven kinematically by the arm's angle θ.
//!
//! The Pitman arm turns about its chassis axis; the steering link hangs from it by a universal joint and
//! from the idler arm, which turns about its own chassis axis. Where the idler arm is parallel to the
//! Pitman arm and as long (a parallelogram, as in both of Chrono's generic vehicles), the link translates
//! without turning: every point of it, the tie rods' inner ends among them, moves on the circle the arm's
//! joint describes, p(θ) = p₀ + R(a, θ) r − r with r the arm from its axis to the joint. The universal
//! joint then holds by itself (the link keeps its orientation). Other linkages are refused with the
//! reason: their link turns, which this drive does not model.

use super::tie_rod::TieRodDrive;
use crate::math::V3;
use crate::model::formats::params::{DataError, PitmanArm, RotaryArm};

/// Relative tolerance of the parallelogram check (data are given to about 1e-6 m).
const PARALLELOGRAM_TOLERANCE: f64 = 1e-6;

/// The arm from an axis through `pivot` along `axis` (unit) to `point`: its part normal to the axis.
fn arm(pivot: &V3, axis: &V3, point: &V3) -> V3 {
    let r = point - pivot;
    r - axis * axis.dot(&r)
}

/// The tie-rod drive of a parallelogram Pitman-arm linkage, or why the linkage is not one.
pub fn drive(p: &PitmanArm) -> Result<TieRodDrive, DataError> {
    let err = |field: &str, message: String| DataError { field: format!("pitman_arm.{field}"), message };
    let axis = V3::from(p.arm_axis).normalize();
    let idler_axis = V3::from(p.idler_axis).normalize();
    let r_arm = arm(&V3::from(p.arm_pivot_m), &axis, &V3::from(p.arm_link_joint_m));
    let r_idler = arm(&V3::from(p.idler_pivot_m), &idler_axis, &V3::from(p.idler_link_joint_m));
    let length = r_arm.norm();
    if !(length > 1e-6) {
        return Err(err("arm_link_joint_m", "the arm–link joint lies on the arm's axis: the arm has no length".into()));
    }
    if axis.cross(&idler_axis).norm() > PARALLELOGRAM_TOLERANCE {
        return Err(err(
            "idler_axis",
            format!(
                "the idler axis {idler_axis:?} is not parallel to the Pitman arm's {axis:?}: only a parallelogram \
                 linkage (idler arm parallel to and as long as the Pitman arm) is supported"
            ),
        ));
    }
    if (r_arm - r_idler).norm() > PARALLELOGRAM_TOLERANCE * length.max(1.0) {
        return Err(err(
            "idler_link_joint_m",
            format!(
                "the idler arm {r_idler:?} differs from the Pitman arm {r_arm:?}: only a parallelogram linkage \
                 (idler arm parallel to and as long as the Pitman arm) is supported"
            ),
        ));
    }
    Ok(TieRodDrive::PitmanLink { axis, arm: r_arm })
}

/// The drive of a rotary arm's drag-link joint (Chrono's `RotaryArm`: a Pitman arm with no link): the
/// joint moves on the circle about the arm's axis, as a parallelogram link's points do.
pub fn rotary_arm_drive(a: &RotaryArm) -> TieRodDrive {
    let axis = V3::from(a.arm_axis).normalize();
    TieRodDrive::PitmanLink { axis, arm: arm(&V3::from(a.arm_pivot_m), &axis, &V3::from(a.arm_draglink_joint_m)) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_path_derivatives_match_finite_differences() {
        let drive = TieRodDrive::PitmanLink { axis: V3::new(0.3, 0.0, 1.0).normalize(), arm: V3::new(0.129, 0.0, 0.0) };
        let p0 = V3::new(0.9, 0.5, -0.3);
        let (s, h) = (0.2, 1e-5);
        let at = |s: f64| drive.path(&p0, s);
        let fd1 = (at(s + h).point - at(s - h).point) / (2.0 * h);
        let fd2 = (at(s + h).point - 2.0 * at(s).point + at(s - h).point) / (h * h);
        assert!((fd1 - at(s).d_ds).norm() < 1e-9, "{fd1:?} vs {:?}", at(s).d_ds);
        assert!((fd2 - at(s).d2_ds2).norm() < 1e-4, "{fd2:?} vs {:?}", at(s).d2_ds2);
        assert!((at(0.0).point - p0).norm() < 1e-15);
    }
}
