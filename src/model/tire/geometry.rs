//! Single-point disc contact on the local road plane (docs/physics.md §6.2).
use super::Contact;
use crate::model::road::Road;
use nalgebra::Vector3;

/// Below this |n·d| (= |a × n|, the cosine of the inclination) the wheel lies nearly flat on the road and the
/// contact point along the wheel plane is ill-defined: treat as lifted off (docs/physics.md §6.2).
const MIN_NORMAL_ALONG_DOWN: f64 = 0.1;

/// Contact of the wheel with centre `centre` and spin axis `axle`, both in the ground frame. `centre` is the
/// ABSOLUTE ground position: the road is queried at (centre.x, centre.y), and the returned contact point is
/// absolute too. `axle` need not be normalized. `None` when the wheel has lifted off (δ <= 0), when it lies
/// nearly flat on the road (|n·d| < 0.1), or when the axle is zero or not finite.
#[inline(always)]
pub fn contact(road: &dyn Road, centre: &Vector3<f64>, axle: &Vector3<f64>, unloaded_radius: f64) -> Option<Contact> {
    let axle = axle.try_normalize(f64::MIN_POSITIVE)?;
    let (height, [hx, hy]) = road.height_and_gradient(centre.x, centre.y);
    let normal = Vector3::new(-hx, -hy, 1.0).normalize();
    let road_point = Vector3::new(centre.x, centre.y, height);

    // Forward along the road, in the wheel plane. |a × n| = |n·d| because d = a × e_x (a ⟂ e_x, both unit).
    let forward_unnormalized = axle.cross(&normal);
    let normal_along_down_abs = forward_unnormalized.norm();
    if normal_along_down_abs < MIN_NORMAL_ALONG_DOWN {
        return None;
    }
    let ex = forward_unnormalized / normal_along_down_abs;
    let ey = normal.cross(&ex);
    let down = axle.cross(&ex);

    // Distance from the centre along d to the local road plane through road_point.
    let loaded_radius = normal.dot(&(road_point - centre)) / normal.dot(&down);
    let penetration = unloaded_radius - loaded_radius;
    if penetration <= 0.0 {
        return None;
    }
    Some(Contact {
        point: centre + loaded_radius * down,
        normal,
        ex,
        ey,
        penetration,
        loaded_radius,
        inclination: -axle.dot(&normal).clamp(-1.0, 1.0).asin(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::road::{HalfSineBump, RoadModel};

    const R0: f64 = 0.4699;
    const TOL: f64 = 1e-14; // a few ulps of the O(1) quantities involved

    fn close(a: &Vector3<f64>, b: &Vector3<f64>) -> bool {
        (a - b).norm() < TOL
    }

    #[test]
    fn upright_wheel_on_flat_ground() {
        let centre = Vector3::new(3.0, -0.9, 0.45);
        let c = contact(&RoadModel::Flat, &centre, &Vector3::y(), R0).expect("in contact");
        assert!((c.penetration - (R0 - 0.45)).abs() < TOL);
        assert!((c.loaded_radius - 0.45).abs() < TOL);
        assert!(close(&c.point, &Vector3::new(3.0, -0.9, 0.0)), "point under the centre: {}", c.point);
        assert!(close(&c.normal, &Vector3::z()));
        assert!(close(&c.ex, &Vector3::x()));
        assert!(close(&c.ey, &Vector3::y()));
        assert_eq!(c.inclination, 0.0);
    }

    #[test]
    fn scaled_axle_gives_the_same_contact() {
        let centre = Vector3::new(0.0, 0.9, 0.45);
        let unit = contact(&RoadModel::Flat, &centre, &Vector3::y(), R0);
        let scaled = contact(&RoadModel::Flat, &centre, &(3.0 * Vector3::y()), R0);
        assert_eq!(unit, scaled);
        assert!(contact(&RoadModel::Flat, &centre, &Vector3::zeros(), R0).is_none());
    }

    #[test]
    fn steered_wheel_keeps_its_heading() {
        // Steer left by 0.3 rad: the axle turns about +z, so e_x does too.
        let steer: f64 = 0.3;
        let axle = Vector3::new(-steer.sin(), steer.cos(), 0.0);
        let c = contact(&RoadModel::Flat, &Vector3::new(0.0, 0.9, 0.45), &axle, R0).expect("in contact");
        assert!(close(&c.ex, &Vector3::new(steer.cos(), steer.sin(), 0.0)));
        assert_eq!(c.inclination, 0.0);
    }

    #[test]
    fn tilted_axle_gives_the_inclination_sign_of_section_1() {
        // Top of the wheel toward +y: wheel-plane "up" is (0, sin φ, cos φ), so the axle is (0, cos φ, -sin φ).
        let phi: f64 = 0.1;
        let axle = Vector3::new(0.0, phi.cos(), -phi.sin());
        let centre = Vector3::new(0.0, 0.9, 0.45);
        let c = contact(&RoadModel::Flat, &centre, &axle, R0).expect("in contact");
        assert!((c.inclination - phi).abs() < TOL, "γ_w = {}", c.inclination);
        // The contact point lies in the wheel plane, below the centre, on the road.
        let down = Vector3::new(0.0, -phi.sin(), -phi.cos());
        assert!((c.loaded_radius - 0.45 / phi.cos()).abs() < TOL);
        assert!(close(&c.point, &(centre + c.loaded_radius * down)));
        assert!(c.point.z.abs() < TOL);
        // The opposite lean flips the sign.
        let mirrored = Vector3::new(0.0, phi.cos(), phi.sin());
        let c = contact(&RoadModel::Flat, &centre, &mirrored, R0).expect("in contact");
        assert!((c.inclination + phi).abs() < TOL);
    }

    #[test]
    fn lift_off_and_flat_lying_wheel_give_none() {
        let flat = RoadModel::Flat;
        assert!(contact(&flat, &Vector3::new(0.0, 0.9, R0 + 1e-9), &Vector3::y(), R0).is_none());
        assert!(contact(&flat, &Vector3::new(0.0, 0.9, R0), &Vector3::y(), R0).is_none(), "δ = 0 is lift-off");
        assert!(contact(&flat, &Vector3::new(0.0, 0.9, R0 - 1e-6), &Vector3::y(), R0).is_some());
        // Axle almost along the normal: |n·d| = sin(0.05) < 0.1.
        let lying = Vector3::new(0.0, 0.05f64.sin(), 0.05f64.cos());
        assert!(contact(&flat, &Vector3::new(0.0, 0.9, 0.1), &lying, R0).is_none());
    }

    #[test]
    fn bump_tilts_the_normal_as_the_gradient_says() {
        let bump = HalfSineBump { x_start: 10.0, length: 0.5, height: 0.05, side: 1.0 };
        let road = RoadModel::Bumps(vec![bump]);
        let centre = Vector3::new(10.1, 0.9, 0.45);
        let (h, [hx, _]) = road.height_and_gradient(centre.x, centre.y);
        let c = contact(&road, &centre, &Vector3::y(), R0).expect("in contact");
        let expected_normal = Vector3::new(-hx, 0.0, 1.0).normalize();
        assert!(close(&c.normal, &expected_normal));
        assert!(c.normal.x < 0.0, "rising road pushes the wheel backwards");
        assert!(close(&c.ex, &Vector3::new(1.0, 0.0, hx).normalize()), "e_x follows the slope");
        // Distance to the tilted plane along the wheel's down direction d ⟂ e_x, in the wheel plane.
        let down = Vector3::y().cross(&c.ex);
        let expected_radius =
            expected_normal.dot(&(Vector3::new(centre.x, centre.y, h) - centre)) / expected_normal.dot(&down);
        assert!((c.loaded_radius - expected_radius).abs() < TOL);
        assert!(c.penetration > R0 - (0.45 - h), "the tilted plane is closer than the height under the centre");
        // The contact point is on the local plane.
        assert!(c.normal.dot(&(c.point - Vector3::new(centre.x, centre.y, h))).abs() < TOL);
        // The same wheel on the other side of the road does not see the bump.
        let other = contact(&road, &Vector3::new(10.1, -0.9, 0.45), &Vector3::y(), R0).expect("in contact");
        assert!(close(&other.normal, &Vector3::z()));
    }
}
