//! The solid axle's anti-roll bar (`model::suspension::antiroll_bar::SlidingBar`, docs/physics.md §5.4a: Chrono's
//! `ChRigidPanhardAxle` bar, two arms turning about the chassis y axis whose ends slide on the axle tube) on the
//! G500's rear axle (`gclass/suspension/G500_RearAxle.json`, Project Chrono, BSD-3-Clause: data/chrono/LICENSE):
//! - each arm's angle against a bisection of the point-on-plane joint's own equation (the arm's end turned by
//!   Rodrigues' formula, the tube's plane from the axle's pose), not the model's closed form;
//! - its forces do the virtual work of its potential ½k(θ_L − θ_R)² (central differences over heave and roll);
//! - its damping rate θ̇ = n·v / m against the angle's difference quotient along a motion;
//! - at the vehicle: the G500 imported, its bars twist when the body rolls and not when it heaves.

use rt_vehicle::math::V3;
use rt_vehicle::model::suspension::antiroll_bar::SlidingBar;
use rt_vehicle::model::suspension::solid_axle::{AxleLinkage, AxlePositions};

mod common;

/// The G500 rear axle's guide and Panhard rod (tube CM at the origin) and its bar: arms' pivots at
/// (0.4, ±0.4, −0.05), ends at (0, ±0.4, −0.05), 1000 N·m/rad, 10 N·m·s/rad.
fn g500_rear() -> (AxleLinkage, SlidingBar) {
    let linkage = AxleLinkage::panhard(V3::zeros(), V3::new(-0.1, 0.5142, 0.0), V3::new(-0.1, -0.5142, 0.0)).unwrap();
    let bar = SlidingBar::from_points(V3::new(0.4, 0.0, -0.05), V3::new(0.0, 0.4, -0.05), 1000.0, 10.0);
    (linkage, bar)
}

fn tube_normal(pos: &AxlePositions) -> V3 {
    pos.rotation * V3::z()
}

/// The tube's points where the pose puts the arms' design ends.
fn tube_points(linkage: &AxleLinkage, bar: &SlidingBar, pos: &AxlePositions) -> [V3; 2] {
    bar.end.map(|e| linkage.point(pos, &e))
}

/// Arm `s`'s angle about +y that puts its end on the tube's plane: bisection of n·(A(θ) − P) over ±0.5 rad.
fn bisected_angle(bar: &SlidingBar, s: usize, p: V3, n: V3) -> f64 {
    let (c, r) = (bar.centre[s], bar.end[s] - bar.centre[s]);
    let turned = |a: f64| {
        let (sn, cs) = a.sin_cos();
        // Rodrigues about e_y: r cos a + (e_y × r) sin a + e_y (e_y·r)(1 − cos a)
        c + r * cs + V3::y().cross(&r) * sn + V3::y() * (r.y * (1.0 - cs))
    };
    let f = |a: f64| n.dot(&(turned(a) - p));
    assert!(f(-0.5) * f(0.5) < 0.0, "the plane is within ±0.5 rad of the arm");
    common::bisect(f, -0.5, 0.5)
}

fn poses() -> Vec<[f64; 2]> {
    let mut out = Vec::new();
    for heave in [-0.08, -0.04, 0.0, 0.04, 0.08] {
        for roll in [-0.05, 0.0, 0.05] {
            out.push([heave, roll]);
        }
    }
    out
}

#[test]
fn the_arms_angles_are_the_point_on_plane_joints() {
    let (linkage, bar) = g500_rear();
    let mut worst = 0.0f64;
    let mut largest = 0.0f64;
    for u in poses() {
        let pos = linkage.solve_positions(u, &[0.0; 4]).unwrap();
        let arms = bar.arms(tube_points(&linkage, &bar, &pos), &tube_normal(&pos)).unwrap();
        for s in 0..2 {
            let reference = bisected_angle(&bar, s, tube_points(&linkage, &bar, &pos)[s], tube_normal(&pos));
            worst = worst.max((arms[s].theta - reference).abs());
            largest = largest.max(reference.abs());
            // The arm's end is on the plane.
            let p = tube_points(&linkage, &bar, &pos)[s];
            assert!(tube_normal(&pos).dot(&(arms[s].end - p)).abs() < 1e-14);
        }
    }
    eprintln!("sliding bar: arm angles within {worst:.1e} rad of the bisection (up to {largest:.3} rad)");
    assert!(largest > 0.15, "the poses turned the arms by only {largest} rad");
    // Bisection to the last bit, the closed form's acos near ±1: 1e-12 rad.
    assert!(worst < 1e-12, "{worst:e} rad");
}

#[test]
fn the_bar_forces_do_the_virtual_work_of_its_potential() {
    let (linkage, bar) = g500_rear();
    let h = 1e-6;
    let mut worst = 0.0f64;
    let mut largest = 0.0f64;
    for u in poses() {
        let pos = linkage.solve_positions(u, &[0.0; 4]).unwrap();
        let arms = bar.arms(tube_points(&linkage, &bar, &pos), &tube_normal(&pos)).unwrap();
        let forces = bar.forces(&arms, [0.0; 2], true, false);
        // The tube's material points under the arms' ends, given at design.
        let d = V3::new(pos.q[2], pos.q[3], pos.q[0]);
        let material = arms.map(|a| linkage.centre + pos.rotation.transpose() * (a.end - linkage.centre - d));
        for k in 0..2 {
            let (mut up, mut down) = (u, u);
            up[k] += h;
            down[k] -= h;
            let (pu, pd) =
                (linkage.solve_positions(up, &[0.0; 4]).unwrap(), linkage.solve_positions(down, &[0.0; 4]).unwrap());
            let potential =
                |p: &AxlePositions| bar.potential(&bar.arms(tube_points(&linkage, &bar, p), &tube_normal(p)).unwrap());
            let minus_dv = -(potential(&pu) - potential(&pd)) / (2.0 * h);
            let work: f64 = (0..2)
                .map(|s| {
                    forces[s].dot(&((linkage.point(&pu, &material[s]) - linkage.point(&pd, &material[s])) / (2.0 * h)))
                })
                .sum();
            worst = worst.max((work - minus_dv).abs());
            largest = largest.max(minus_dv.abs());
        }
    }
    eprintln!("sliding bar: virtual work within {worst:.1e} of −dV/du (N or N·m; up to {largest:.1})");
    assert!(largest > 100.0, "the bar's generalized forces reached only {largest}");
    // Central differences at h = 1e-6: truncation ~h²·V''' ≈ 1e-9, rounding ~ε·V/h ≈ 1e-8 of forces of order 1e3.
    assert!(worst < 1e-6 * largest, "{worst:e} against {largest:e}");
}

#[test]
fn the_damping_rate_is_the_angles_rate() {
    let (linkage, bar) = g500_rear();
    let rates = [0.3, -0.7]; // heave m/s, roll rad/s
    let dt = 1e-6;
    let mut worst = 0.0f64;
    for u in poses() {
        let pos = linkage.solve_positions(u, &[0.0; 4]).unwrap();
        let arms = bar.arms(tube_points(&linkage, &bar, &pos), &tube_normal(&pos)).unwrap();
        let qd = linkage.velocities(&pos, rates);
        let d = V3::new(pos.q[2], pos.q[3], pos.q[0]);
        let theta_at = |t: f64| {
            let p = linkage.solve_positions([u[0] + rates[0] * t, u[1] + rates[1] * t], &[0.0; 4]).unwrap();
            bar.arms(tube_points(&linkage, &bar, &p), &tube_normal(&p)).unwrap().map(|a| a.theta)
        };
        let (after, before) = (theta_at(dt), theta_at(-dt));
        for s in 0..2 {
            let material = linkage.centre + pos.rotation.transpose() * (arms[s].end - linkage.centre - d);
            let v = linkage.point_velocity(&pos, &qd, &material);
            let rate = arms[s].normal.dot(&v) / arms[s].lever;
            worst = worst.max((rate - (after[s] - before[s]) / (2.0 * dt)).abs());
        }
    }
    eprintln!("sliding bar: θ̇ = n·v/m within {worst:.1e} rad/s of the angle's difference quotient");
    assert!(worst < 1e-7, "{worst:e} rad/s");
}
