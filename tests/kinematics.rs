//! Suspension kinematics of every template against finite differences, and the HMMWV's against the data
//! set's derived geometry (docs/physics.md §9.1–§9.2). Every shipped vehicle is checked: the HMMWV (double
//! wishbones, rack) and the vehicles in `resources/vehicles/` (double wishbones, MacPherson struts and
//! single wishbones, Pitman arm; a solid axle's kinematics are checked where its own are).

use nalgebra::Vector4;
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::suspension::{Corner, CornerPositions, Vector5f};
use rt_vehicle::model::vehicle::Vehicle;

mod common;
use common::vehicles;

/// Every corner of an independent suspension of every shipped vehicle, with its steering drive and the
/// vehicle's steering limit. (A solid axle's wheels have no loop of their own: the axle's kinematics are
/// checked in `model::suspension::solid_axle`'s tests and in tests/solid_axle.rs.)
fn corners() -> Vec<(String, Corner)> {
    let mut out = Vec::new();
    for (vehicle, data) in vehicles() {
        let v = Vehicle::new(&data).unwrap();
        for (i, c) in v.corners.iter().enumerate() {
            if v.solid_axles[i / 2].is_none() {
                out.push((format!("{vehicle} {}", rt_vehicle::model::vehicle::CORNERS[i]), c.clone()));
            }
        }
    }
    out
}

fn phi(c: &Corner, q: &Vector5f, s: f64) -> Vector4<f64> {
    c.constraint_values(&c.evaluate(q, s))
}

#[test]
fn constraint_jacobian_matches_central_differences() {
    // Central differences with ε = 1e-6 have truncation error ~ε²·|Φ'''| ≈ 1e-12 and round-off
    // ~1e-16/ε ≈ 1e-10: agreement to 1e-8 is the docs/physics.md §9.1 bound with margin.
    let q = Vector5f::new(0.08, 0.03, -0.05, 0.02, 0.11);
    for (name, c) in corners() {
        let s = 0.02;
        let pos = c.evaluate(&q, s);
        let eps = 1e-6;
        for j in 0..5 {
            let mut dq = Vector5f::zeros();
            dq[j] = eps;
            let fd = (phi(&c, &(q + dq), s) - phi(&c, &(q - dq), s)) / (2.0 * eps);
            let err = (fd - pos.phi_q.column(j)).amax();
            assert!(err < 1e-8, "{name}: column {j} error {err:e}");
        }
        let fd = (phi(&c, &q, s + eps) - phi(&c, &q, s - eps)) / (2.0 * eps);
        assert!((fd - pos.phi_s).amax() < 1e-8, "{name}: Φ_s error {:e}", (fd - pos.phi_s).amax());
    }
}

#[test]
fn gamma_bar_matches_second_difference_of_phi() {
    // Along q(τ) = q + q̇τ, s(τ) = s + ṡτ + ½s̈τ²: d²Φ/dτ² = Φ_s s̈ − γ = −γ̄ (docs/physics.md §3.3).
    // Second differences with τ = 1e-4: truncation ~τ²·Φ'''' ≈ 1e-8·O(1), round-off ~1e-16/τ² ≈ 1e-8.
    let q = Vector5f::new(-0.06, 0.02, 0.04, -0.03, -0.09);
    let qd = Vector5f::new(1.3, -0.7, 0.9, 0.4, -1.1);
    let (s, sd, sdd) = (-0.015, 0.3, 2.0);
    for (name, c) in corners() {
        let pos = c.evaluate(&q, s);
        let gb = c.gamma_bar(&pos, &qd, sd, sdd);
        let tau = 1e-4;
        let at = |t: f64| phi(&c, &(q + qd * t), s + sd * t + 0.5 * sdd * t * t);
        let fd = (at(tau) - at(0.0) * 2.0 + at(-tau)) / (tau * tau);
        let err = (fd + gb).amax();
        assert!(err < 1e-6 * (1.0 + gb.amax()), "{name}: γ̄ error {err:e} (γ̄ = {gb:?})");
    }
}

#[test]
fn dependent_velocities_match_the_motion_of_solved_positions() {
    // Checked against a finite difference of solved positions, not with the Φ_q that produced them.
    for (name, c) in corners() {
        let (u, ud, s, sd) = (0.05, 0.8, 0.01, -0.2);
        let h = 1e-6;
        let solve = |t: f64| c.solve_positions(u + ud * t, s + sd * t, &[0.0; 4]).unwrap().q;
        let fd = (solve(h) - solve(-h)) / (2.0 * h);
        let pos = c.solve_positions(u, s, &[0.0; 4]).unwrap();
        let qd = c.velocities(&pos, ud, sd);
        let err = (fd - qd).amax();
        assert!(err < 1e-7, "{name}: q̇ error {err:e}");
        // And the velocity constraint itself, Φ_q q̇ + Φ_s ṡ = 0, to round-off.
        let vc = (pos.phi_q * qd + pos.phi_s * sd).amax();
        assert!(vc < 1e-12, "{name}: velocity constraint {vc:e}");
    }
}

#[test]
fn position_residual_across_travel_and_rack_range() {
    let mut worst: f64 = 0.0;
    for (vehicle, data) in vehicles() {
        let limit = data.steering_limit();
        let v = Vehicle::new(&data).unwrap();
        for (i, c) in v.corners.iter().enumerate().filter(|(i, _)| v.solid_axles[i / 2].is_none()) {
            let name = format!("{vehicle} {i}");
            // Wheel travel between the stops is about −0.11..+0.2 m: θ_L from −0.25 to +0.35 rad covers it.
            let mut warm = [0.0; 4];
            for k in 0..=60 {
                let u = -0.25 + 0.6 * k as f64 / 60.0;
                for r in -4..=4 {
                    let s = if c.steered() { limit * r as f64 / 4.0 } else { 0.0 };
                    let pos = c.solve_positions(u, s, &warm).unwrap_or_else(|e| panic!("{name}: {e}"));
                    warm = [pos.q[1], pos.q[2], pos.q[3], pos.q[4]];
                    assert!(pos.residual <= 1e-10, "{name}: residual {:e}", pos.residual);
                    worst = worst.max(pos.residual);
                }
            }
        }
    }
    println!("max position residual over travel and rack range: {worst:.2e} m");
}

/// Wheel-centre height (chassis frame) and derived quantities at θ_L for the left corner of an axle.
fn left(axle: &str) -> Corner {
    let v = Vehicle::new(&VehicleData::default_hmmwv()).unwrap();
    v.corners[if axle == "front" { 0 } else { 2 }].clone()
}

fn derivative_wrt_travel(c: &Corner, f: impl Fn(&Corner, &CornerPositions) -> f64) -> f64 {
    let h = 1e-5;
    let at = |u: f64| {
        let p = c.solve_positions(u, 0.0, &[0.0; 4]).unwrap();
        (c.on_carrier(&p, &c.w0).z, f(c, &p))
    };
    let (z1, f1) = at(h);
    let (z0, f0) = at(-h);
    (f1 - f0) / (z1 - z0)
}

#[test]
fn suspension_kinematics_match_the_data_set() {
    let data = VehicleData::default_hmmwv();
    let check = |what: &str, got: f64, want: f64| {
        let ok = if want == 0.0 { got.abs() <= 0.03 } else { ((got - want) / want).abs() <= 0.01 };
        println!("{what}: {got:.4} (data {want})");
        assert!(ok, "{what}: {got} vs {want}");
    };
    for (axle_name, axle) in data.axles() {
        let c = left(axle_name);
        let r = axle.reference_kinematics.as_ref().expect("the HMMWV data set has reference kinematics");
        let k = c.solve_positions(0.0, 0.0, &[0.0; 4]).unwrap().upper_joint - c.b0;
        check(
            &format!("{axle_name} kingpin inclination deg"),
            (-k.y).atan2(k.z).to_degrees(),
            r.kingpin_inclination_deg,
        );
        check(&format!("{axle_name} caster deg"), (-k.x).atan2(k.z).to_degrees(), r.caster_deg);
        let camber = derivative_wrt_travel(&c, |c, p| c.camber(p).to_degrees());
        check(&format!("{axle_name} camber gain deg/m"), camber, r.camber_gain_deg_per_m);
        let toe = derivative_wrt_travel(&c, |c, p| c.steer_angle(p).to_degrees());
        check(&format!("{axle_name} bump steer deg/m"), toe, r.bump_steer_deg_per_m);
        let ratio = -derivative_wrt_travel(&c, |c, p| (c.mount_point(p, &c.spring) - c.spring.chassis).norm());
        check(&format!("{axle_name} spring motion ratio"), ratio, r.spring_motion_ratio_dLspring_dzwheel);
    }
    let v = Vehicle::new(&data).unwrap();
    let gain = (v.steering_gain_per_rack_metre().unwrap() * v.steering.sign).to_degrees();
    check("steering gain deg/m of rack (left-turn input)", gain, data.rack.as_ref().unwrap().reference_gain_deg_per_m);
    assert_eq!(v.steering.sign, -1.0, "steering arms behind the axle: left turn moves the rack to −y");
}

/// Body velocity states and their rates against finite differences along a trajectory of the chassis
/// and the joints (docs/physics.md §3.4, §9.1): Y_b = Y0 + 𝔅_b q̇ and Ẏ_b = Ẏ0 + 𝔅_b q̈ + 𝔇_b.
#[test]
fn velocity_state_matrices_match_finite_differences() {
    for (name, data) in vehicles() {
        println!("{name}");
        velocity_states_of(&Vehicle::new(&data).unwrap());
    }
}

fn velocity_states_of(v: &Vehicle) {
    use nalgebra::{Matrix3, Vector3, Vector6};
    use rt_vehicle::math::rotation_about;
    let axis = Vector3::new(0.3, -0.5, 0.8).normalize();
    let (r0, vel, acc) = (Vector3::new(10.0, -4.0, 0.7), Vector3::new(12.0, 3.0, -0.5), Vector3::new(1.0, -2.0, 0.5));
    let (th, thd, thdd) = (0.4, 0.7, -1.5);
    let q = Vector5f::new(0.05, 0.02, -0.03, 0.04, 0.06);
    let qd = Vector5f::new(0.9, -0.4, 0.6, 0.3, -0.8);
    let qdd = Vector5f::new(-3.0, 2.0, 1.0, -2.5, 4.0);
    let pose = |t: f64| {
        let a0 = rotation_about(&axis, th + thd * t + 0.5 * thdd * t * t);
        (
            r0 + vel * t + acc * 0.5 * t * t,
            a0,
            vel + acc * t,
            axis * (thd + thdd * t),
            q + qd * t + qdd * 0.5 * t * t,
            qd + qdd * t,
        )
    };
    let bodies = |i: usize, t: f64| {
        // Absolute CM positions, rotations, and (from the velocity states) CM velocities and ω.
        let (r, a0, rd, w, qt, qdt) = pose(t);
        let c = &v.corners[i];
        let pos = c.evaluate(&qt, 0.0);
        let y0 = Vector6::new(rd.x, rd.y, rd.z, w.x, w.y, w.z);
        let k = v.corner_kinematics(i, &pos, &qdt, &a0, &y0);
        let rots = [a0 * pos.r_l, a0 * pos.r_k, a0 * pos.r_u];
        (0..3)
            .map(|b| {
                let wb = Vector3::new(k.velocity[b][3], k.velocity[b][4], k.velocity[b][5]);
                let vhat = Vector3::new(k.velocity[b][0], k.velocity[b][1], k.velocity[b][2]);
                let rdot = vhat + wb.cross(&k.com[b]);
                (r + k.com[b], rots[b], rdot, wb, k)
            })
            .collect::<Vec<(Vector3<f64>, Matrix3<f64>, Vector3<f64>, Vector3<f64>, _)>>()
    };
    let h = 1e-5;
    for i in 0..4 {
        let (now, plus, minus) = (bodies(i, 0.0), bodies(i, h), bodies(i, -h));
        let origin = pose(0.0).0;
        for b in 0..3 {
            // Velocities: CM velocity and angular velocity from the states vs differences of positions.
            let fd_v = (plus[b].0 - minus[b].0) / (2.0 * h);
            let wt = (plus[b].1 - minus[b].1) / (2.0 * h) * now[b].1.transpose();
            let fd_w = Vector3::new(wt[(2, 1)] - wt[(1, 2)], wt[(0, 2)] - wt[(2, 0)], wt[(1, 0)] - wt[(0, 1)]) * 0.5;
            assert!(
                (fd_v - now[b].2).amax() < 1e-7 * (1.0 + fd_v.amax()),
                "corner {i} body {b}: ṙ {fd_v} vs {}",
                now[b].2
            );
            assert!((fd_w - now[b].3).amax() < 1e-7, "corner {i} body {b}: ω {fd_w} vs {}", now[b].3);
            // Rates: Y_b about a fixed origin, differenced, against Ẏ0 + 𝔅 q̈ + 𝔇.
            let y_fixed = |s: &(Vector3<f64>, Matrix3<f64>, Vector3<f64>, Vector3<f64>, _)| {
                let vhat = s.2 - s.3.cross(&(s.0 - origin));
                Vector6::new(vhat.x, vhat.y, vhat.z, s.3.x, s.3.y, s.3.z)
            };
            let fd_ydot = (y_fixed(&plus[b]) - y_fixed(&minus[b])) / (2.0 * h);
            let (_, _, rd, w, _, _) = pose(0.0);
            let wdot = axis * thdd;
            let lin0 = acc - w.cross(&rd);
            let y0dot = Vector6::new(lin0.x, lin0.y, lin0.z, wdot.x, wdot.y, wdot.z);
            let k = &now[b].4;
            let model = y0dot + k.jacobian(b) * qdd + k.rate[b];
            let err = (fd_ydot - model).amax();
            assert!(err < 1e-5 * (1.0 + model.amax()), "corner {i} body {b}: Ẏ error {err:e}");
        }
    }
}
