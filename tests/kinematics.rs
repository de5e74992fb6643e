//! SLA subsystem kinematics against finite differences and against the data set's derived geometry
//! (physics.md §9.1–§9.2).

use nalgebra::Vector4;
use rt_vehicle::model::params::VehicleData;
use rt_vehicle::model::suspension::sla::{SlaGeometry, Side, Vector5f};
use rt_vehicle::model::vehicle::Vehicle;

fn corners() -> Vec<(String, SlaGeometry)> {
    let data = VehicleData::default_hmmwv();
    let mut out = Vec::new();
    for (name, axle) in data.axles() {
        for side in [Side::Left, Side::Right] {
            out.push((format!("{name} {side:?}"), SlaGeometry::from_data(&data, axle, side).unwrap()));
        }
    }
    out
}

fn phi(c: &SlaGeometry, q: &Vector5f, s: f64) -> Vector4<f64> {
    c.constraint_values(&c.evaluate(q, s))
}

#[test]
fn constraint_jacobian_matches_central_differences() {
    // Central differences with ε = 1e-6 have truncation error ~ε²·|Φ'''| ≈ 1e-12 and round-off
    // ~1e-16/ε ≈ 1e-10: agreement to 1e-8 is the physics.md §9.1 bound with margin.
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
    // Along q(τ) = q + q̇τ, s(τ) = s + ṡτ + ½s̈τ²: d²Φ/dτ² = Φ_s s̈ − γ = −γ̄ (physics.md §3.3).
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
    let data = VehicleData::default_hmmwv();
    let limit = data.rack.travel_limit_m;
    let mut worst: f64 = 0.0;
    for (name, c) in corners() {
        // Wheel travel between the stops is about −0.11..+0.2 m: θ_L from −0.25 to +0.35 rad covers it.
        let mut warm = [0.0; 4];
        for k in 0..=60 {
            let u = -0.25 + 0.6 * k as f64 / 60.0;
            for r in -4..=4 {
                let s = if c.steered { limit * r as f64 / 4.0 } else { 0.0 };
                let pos = c.solve_positions(u, s, &warm).unwrap_or_else(|e| panic!("{name}: {}", e.0));
                warm = [pos.q[1], pos.q[2], pos.q[3], pos.q[4]];
                assert!(pos.residual <= 1e-10, "{name}: residual {:e}", pos.residual);
                worst = worst.max(pos.residual);
            }
        }
    }
    println!("max position residual over travel and rack range: {worst:.2e} m");
}

/// Wheel-centre height (chassis frame) and derived quantities at θ_L for the left corner of an axle.
fn left(axle: &str) -> SlaGeometry {
    let data = VehicleData::default_hmmwv();
    let a = if axle == "front" { &data.front } else { &data.rear };
    SlaGeometry::from_data(&data, a, Side::Left).unwrap()
}

fn derivative_wrt_travel(c: &SlaGeometry, f: impl Fn(&SlaGeometry, &rt_vehicle::model::suspension::sla::SlaPositions) -> f64) -> f64 {
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
        let r = &axle.reference_kinematics;
        let k = c.u0 - c.b0;
        check(&format!("{axle_name} kingpin inclination deg"), (-k.y).atan2(k.z).to_degrees(), r.kingpin_inclination_deg);
        check(&format!("{axle_name} caster deg"), (-k.x).atan2(k.z).to_degrees(), r.caster_deg);
        let camber = derivative_wrt_travel(&c, |c, p| c.camber(p).to_degrees());
        check(&format!("{axle_name} camber gain deg/m"), camber, r.camber_gain_deg_per_m);
        let toe = derivative_wrt_travel(&c, |c, p| c.steer_angle(p).to_degrees());
        check(&format!("{axle_name} bump steer deg/m"), toe, r.bump_steer_deg_per_m);
        let ratio = -derivative_wrt_travel(&c, |c, p| (c.on_lower(p, &c.spring_arm) - c.spring_chassis).norm());
        check(&format!("{axle_name} spring motion ratio"), ratio, r.spring_motion_ratio_dLspring_dzwheel);
    }
    let v = Vehicle::new(&data).unwrap();
    let gain = (v.steering_gain_per_rack_metre().unwrap() * v.rack_sign).to_degrees();
    check("steering gain deg/m of rack (left-turn input)", gain, data.rack.reference_gain_deg_per_m);
    assert_eq!(v.rack_sign, -1.0, "steering arms behind the axle: left turn moves the rack to −y");
}
