//! The K&C report (`studies::kc`, `rtv kc`): the HMMWV's figures against its data set, the report's exact
//! rates against central differences of solved positions, the roll centre against an instant centre
//! constructed from the hardpoints alone, and the Ackermann error's definition and properties.

use nalgebra::{Matrix4, Vector3, Vector4};
use rt_vehicle::model::formats::params::{SteeringInput, VehicleData};
use rt_vehicle::model::suspension::{Corner, CornerPositions};
use rt_vehicle::model::vehicle::Vehicle;
use rt_vehicle::studies::kc::{self, KcOptions, KcReport};

type V3 = Vector3<f64>;

mod common;
use common::vehicles;

fn report(data: &VehicleData) -> KcReport {
    KcReport::compute(data, &KcOptions::default()).unwrap()
}

#[test]
fn hmmwv_static_figures_and_slopes_match_the_data_set() {
    // Tolerance 1 %: tight enough to catch a hardpoint mislaid by 1 mm (it turns the 0.334 m kingpin by
    // 0.17°: 1.4 % of the KPI, 5.7 % of the caster) or a sign or axis mixed up; loose enough for what the
    // data set does not say: its figures are rounded to 4-5 digits (≤ 0.02 %) and its slopes may be
    // secants over a few millimetres rather than tangents (the relative secant−tangent gap of these
    // curves over ±10 mm, printed below, is at most 0.62 %: the rear bump steer).
    let data = VehicleData::default_hmmwv();
    let r = report(&data);
    for axle in &r.axles {
        let want = axle.reference.as_ref().expect("the HMMWV data set has reference kinematics");
        let f = &axle.figures;
        let check = |what: &str, got: f64, want: f64| {
            let ok = if want == 0.0 { got.abs() <= 0.03 } else { ((got - want) / want).abs() <= 0.01 };
            println!("{} {what}: report {got:.5}, data set {want}", axle.name);
            assert!(ok, "{} {what}: report {got} vs data set {want}", axle.name);
        };
        check("caster, deg", f.caster.to_degrees(), want.caster_deg);
        check("kingpin inclination, deg", f.kingpin_inclination.to_degrees(), want.kingpin_inclination_deg);
        check("camber gain, deg/m", f.camber_gain.to_degrees(), want.camber_gain_deg_per_m);
        check("bump steer, deg/m", f.bump_steer.to_degrees(), want.bump_steer_deg_per_m);
        check("spring motion ratio", f.spring_ratio, want.spring_motion_ratio_dLspring_dzwheel);
        // The secant over ±10 mm against the tangent, from the report's own curve (2.5 mm steps).
        let at = |z: f64| *axle.travel.iter().find(|row| (row.travel - z).abs() < 1e-9).unwrap();
        let (lo, hi) = (at(-0.01), at(0.01));
        for (what, secant, tangent) in [
            ("camber", (hi.camber[0] - lo.camber[0]) / 0.02, f.camber_gain),
            ("steer", (hi.steer[0] - lo.steer[0]) / 0.02, f.bump_steer),
            ("spring", -(hi.spring_length - lo.spring_length) / 0.02, f.spring_ratio),
        ] {
            let gap = ((secant - tangent) / tangent).abs();
            println!("{} {what}: secant over ±10 mm differs from the tangent by {:.3} %", axle.name, 100.0 * gap);
            assert!(gap < 0.01);
        }
    }
    assert!(r.axles[0].name == "front" && r.axles[0].steered && !r.axles[1].steered);
}

/// The rates of one wheel by central differences of solved positions about θ_L = u: (camber, steer,
/// spring length, damper length, the carrier point at `material`'s y and z) per unit wheel travel.
fn differenced_rates(c: &Corner, u: f64, warm: [f64; 4], material: &V3) -> ([f64; 4], V3) {
    // h = 1e-5 rad: truncation h²|f'''|/6 ≈ 1e-11 relative; round-off 2·1e-12 m (the position tolerance)
    // over Δz = 2h·0.45 m/rad ≈ 9e-6 m.
    let h = 1e-5;
    let at = |u: f64| {
        let p = c.solve_positions(u, 0.0, &warm).unwrap();
        let length = |m: &rt_vehicle::model::suspension::LineMount| (c.mount_point(&p, m) - m.chassis).norm();
        (
            c.on_carrier(&p, &c.w0).z,
            [c.camber(&p), c.steer_angle(&p), length(&c.spring), length(&c.shock)],
            c.on_carrier(&p, material),
        )
    };
    let (zp, fp, mp) = at(u + h);
    let (zm, fm, mm) = at(u - h);
    let dz = zp - zm;
    (std::array::from_fn(|i| (fp[i] - fm[i]) / dz), (mp - mm) / dz)
}

/// `differenced_rates` for the left wheel of solid axle `a` at `travel`: the rates per unit of parallel travel
/// from positions with both wheel centres Δz = ±5e-6 m off (`kc::axle_at_travel`), and the left contact
/// point's material velocity under equal and opposite travel (the motion the roll centre is taken along).
fn solid_axle_differenced_rates(v: &Vehicle, a: usize, k: usize, travel: f64, ground: f64) -> ([f64; 4], V3, V3) {
    let (c, solid) = (&v.corners[2 * a + k], v.solid_axles[a].as_ref().unwrap());
    let h = 5e-6;
    let (_, state) = kc::axle_at_travel(v, a, [travel, travel], None).unwrap();
    // The contact point at this travel (the pose's; the direction given does not move it) as a point of the
    // wheel's carrier, followed through the differenced positions.
    let contact = kc::axle_wheel_pose(c, k, solid, &state, [1.0, 0.0], 0.0, ground).contact;
    let material = material_point(c, &state.wheels[k], &contact);
    let at = |t: [f64; 2]| {
        let (_, s) = kc::axle_at_travel(v, a, t, None).unwrap();
        let p = &s.wheels[k];
        let length = |m: &rt_vehicle::model::suspension::LineMount| (c.mount_point(p, m) - m.chassis).norm();
        ([c.camber(p), c.steer_angle(p), length(&c.spring), length(&c.shock)], c.on_carrier(p, &material))
    };
    let ((fp, _), (fm, _)) = (at([travel + h, travel + h]), at([travel - h, travel - h]));
    let ((_, mp), (_, mm)) = (at([travel + h, travel - h]), at([travel - h, travel + h]));
    (std::array::from_fn(|i| (fp[i] - fm[i]) / (2.0 * h)), (mp - mm) / (2.0 * h), contact)
}

/// The carrier's point that is at `x` at these positions, in design coordinates.
fn material_point(c: &Corner, pos: &CornerPositions, x: &V3) -> V3 {
    c.b0 + pos.r_k.transpose() * (x - pos.b)
}

#[test]
fn report_rates_match_central_differences_of_solved_positions() {
    // Every shipped vehicle, both axles, at five travels. Tolerance: round-off of the differences,
    // 2·1e-12 m / (Δz ≈ 9e-6 m) ≈ 2.2e-7 for lengths, and for angles that over the shortest lever of the
    // linkages (≥ 0.1 m) ≈ 2.2e-6 rad/m; 1e-5 leaves a factor 4.5 (truncation, ~1e-11, is negligible).
    // The roll-centre height is the contact point's offset (≤ 1.2 m) times the ratio of two such rates
    // (|v_z| ≈ 1): 1e-5 m·(1 + 2·1.2) ≈ 3.4e-5 → 5e-5 m.
    let mut worst = [0.0f64; 2];
    for (name, data) in vehicles() {
        let v = Vehicle::new(&data).unwrap();
        let r = report(&data);
        let radius = data.tire.unloaded_radius_m;
        for (a, axle) in r.axles.iter().enumerate() {
            let c = &v.corners[2 * a];
            let y_mid = 0.5 * (v.corners[2 * a].w0.y + v.corners[2 * a + 1].w0.y);
            for travel in [-0.08, -0.04, 0.0, 0.05, 0.1] {
                let row = axle.travel.iter().find(|row| (row.travel - travel).abs() < 1e-9).unwrap();
                let ground = c.w0.z - radius + travel;
                let (fd, v_contact, contact) = if v.solid_axles[a].is_some() {
                    solid_axle_differenced_rates(&v, a, 0, travel, ground)
                } else {
                    let pos = kc::wheel_at_travel(c, travel, 0.0, None).unwrap();
                    let contact = kc::wheel_pose(c, &pos, ground, kc::Along::LowerArm).contact;
                    let warm = [pos.q[1], pos.q[2], pos.q[3], pos.q[4]];
                    let (fd, v_contact) = differenced_rates(c, pos.q[0], warm, &material_point(c, &pos, &contact));
                    (fd, v_contact, contact)
                };
                let rates = [row.camber_gain, row.bump_steer, -row.spring_ratio, -row.damper_ratio];
                for (i, what) in ["camber gain", "bump steer", "spring ratio", "damper ratio"].iter().enumerate() {
                    let err = (fd[i] - rates[i]).abs();
                    worst[0] = worst[0].max(err);
                    assert!(err < 1e-5, "{name} {} {what} at {travel}: report {} vs {}", axle.name, rates[i], fd[i]);
                }
                let mut rc = kc::roll_centre_height(&contact, &v_contact, y_mid);
                if v.solid_axles[a].is_some() {
                    // The report's is the mean of both wheels' (they differ where the axle's steering linkage
                    // is not symmetric: a drag link on one side).
                    let (_, v_right, right) = solid_axle_differenced_rates(&v, a, 1, travel, ground);
                    rc = 0.5 * (rc + kc::roll_centre_height(&right, &v_right, y_mid));
                }
                let err = (rc - row.roll_centre_height).abs();
                worst[1] = worst[1].max(err);
                assert!(err < 5e-5, "{name} {} roll centre at {travel}: {} vs {rc}", axle.name, row.roll_centre_height);
            }
        }
    }
    println!("largest difference: rates {:.2e}, roll-centre height {:.2e} m", worst[0], worst[1]);
}

/// Front-view instant centre of the upright at design, from the hardpoints alone (chassis reference
/// frame): the lower ball joint B turns about the lower arm's axis, the upper one U about the upper arm's,
/// the tie rod keeps its length; that fixes the upright's velocity (ω, v_B) per unit lower-arm rate. The
/// instant centre in the transverse plane through the contact point C is where the velocity has no
/// y or z part. Returns (C, instant centre), both in the chassis reference frame.
fn instant_centre_from_hardpoints(data: &VehicleData, axle_name: &str) -> (V3, V3) {
    let axle = if axle_name == "front" { &data.front } else { &data.rear };
    let p = |n: &str| VehicleData::point(axle, n);
    let (b, u, t, tr, w) = (p("LCA_U"), p("UCA_U"), p("TIEROD_U"), p("TIEROD_C"), p("SPINDLE"));
    let h_l = (p("LCA_F") - p("LCA_B")).normalize();
    let h_u = (p("UCA_F") - p("UCA_B")).normalize();
    let v_b = h_l.cross(&(b - p("LCA_B")));
    // Unknowns x = (ω, λ_U): v_B + ω × (U − B) = λ_U h_U × (U − P_U); (v_B + ω × (T − B))·(T − T_R) = 0.
    let skew = |r: V3| nalgebra::Matrix3::new(0.0, -r.z, r.y, r.z, 0.0, -r.x, -r.y, r.x, 0.0);
    let mut m = Matrix4::zeros();
    let mut rhs = Vector4::zeros();
    let minus_ru = -skew(u - b); // ω × r = −[r]× ω
    let arm_u = h_u.cross(&(u - p("UCA_B")));
    for i in 0..3 {
        for j in 0..3 {
            m[(i, j)] = minus_ru[(i, j)];
        }
        m[(i, 3)] = -arm_u[i];
        rhs[i] = -v_b[i];
    }
    let d = t - tr;
    // (ω × (T − B))·d = ω·((T − B) × d)
    let row = (t - b).cross(&d);
    for j in 0..3 {
        m[(3, j)] = row[j];
    }
    rhs[3] = -v_b.dot(&d);
    let x = m.lu().solve(&rhs).expect("the linkage is not singular at design");
    let omega = V3::new(x[0], x[1], x[2]);
    // The wheel plane is the chassis x-z plane at design (the spindle axis is y): C is R0 below the centre.
    let c = w - V3::z() * data.tire.unloaded_radius_m;
    // v(P) = v_B + ω × (P − B), P = (C_x, y, z): its y and z parts vanish.
    //   v_y = v_By + ω_z (P_x − B_x) − ω_x (P_z − B_z);  v_z = v_Bz + ω_x (P_y − B_y) − ω_y (P_x − B_x).
    let dx = c.x - b.x;
    let z = b.z + (v_b.y + omega.z * dx) / omega.x;
    let y = b.y - (v_b.z - omega.y * dx) / omega.x;
    (c, V3::new(c.x, y, z))
}

#[test]
fn roll_centre_matches_the_instant_centre_constructed_from_the_hardpoints() {
    // The report's roll centre comes from the model's velocity analysis (Bryant angles, Φ_q, Φ_v) in
    // sprung-CM coordinates; the construction here from the hardpoints and three hinge/length conditions.
    // Both are exact, so they agree to round-off: 1e-9 m (a 4×4 solve of O(1) numbers, ~1e-15 relative,
    // scaled by lever arms ≤ 3 m; 1e-9 leaves a wide margin).
    let data = VehicleData::default_hmmwv();
    let r = report(&data);
    for axle in &r.axles {
        let (c, ic) = instant_centre_from_hardpoints(&data, axle.name);
        // The line from C through the instant centre, at the centre plane y = 0 of the reference frame.
        let z_rc = c.z + (ic.z - c.z) * (0.0 - c.y) / (ic.y - c.y);
        let height = z_rc - c.z;
        println!(
            "{}: instant centre y = {:.4} m, {:.4} m above ground; roll centre {:.6} m (report {:.6} m)",
            axle.name,
            ic.y,
            ic.z - c.z,
            height,
            axle.figures.roll_centre_height
        );
        assert!((height - axle.figures.roll_centre_height).abs() < 1e-9, "{}", axle.name);
        // And the classical planar construction (the lines of the two arms in the front view, each from
        // its pivot axis' trace on the plane x = C_x to its ball joint) for comparison: it neglects the
        // upright's rotation about y and z, so it is only close.
        let axle_data = if axle.name == "front" { &data.front } else { &data.rear };
        let p = |n: &str| VehicleData::point(axle_data, n);
        let trace = |f: V3, b: V3| b + (f - b) * ((c.x - b.x) / (f.x - b.x));
        let (l0, l1) = (trace(p("LCA_F"), p("LCA_B")), p("LCA_U"));
        let (u0, u1) = (trace(p("UCA_F"), p("UCA_B")), p("UCA_U"));
        // Intersect l0 + s (l1 − l0) and u0 + t (u1 − u0) in (y, z).
        let (a1, a2) = (l1 - l0, u1 - u0);
        let det = a1.y * (-a2.z) - a1.z * (-a2.y);
        let s = ((u0.y - l0.y) * (-a2.z) - (u0.z - l0.z) * (-a2.y)) / det;
        let planar = l0 + a1 * s;
        let z_planar = c.z + (planar.z - c.z) * (0.0 - c.y) / (planar.y - c.y);
        println!(
            "{}: planar construction: instant centre y = {:.4} m, {:.4} m above ground; roll centre {:.4} m",
            axle.name,
            planar.y,
            planar.z - c.z,
            z_planar - c.z
        );
    }
}

#[test]
fn ackermann_error_is_zero_for_ackermann_angles_and_negative_for_parallel_steer() {
    // cot δ_o − cot δ_i = t/L defines the ideal: pairs built from it have zero error to round-off
    // (a few ulps of the angles: 1e-14 rad). Parallel steer (δ_i = δ_o) is short of it by
    // (t/L) δ² + O(δ³), so its error is negative at every angle.
    let (l, t) = (3.302, 1.82);
    for k in 1..=40 {
        let outside = (k as f64).to_radians();
        let inside = 1.0 / (1.0 / outside.tan() - t / l);
        let inside = inside.atan();
        let e = kc::ackermann_error(outside, inside, l, t);
        assert!(e.abs() < 1e-14, "{k} deg: {e:e}");
        let parallel = kc::ackermann_error(outside, outside, l, t);
        assert!(parallel < 0.0, "{k} deg: parallel steer error {parallel}");
        if k <= 2 {
            let leading = -(t / l) * outside * outside;
            assert!(((parallel - leading) / leading).abs() < 0.05, "{k} deg: {parallel} vs {leading}");
        }
    }
    // Beyond the inside wheel's right angle the ideal is still continuous (atan2).
    assert!(kc::ackermann_inside(1.2, l, t) > std::f64::consts::FRAC_PI_2);
}

#[test]
fn ackermann_error_of_the_hmmwv_rack_is_mirror_symmetric_and_follows_its_toe_curvature() {
    let data = VehicleData::default_hmmwv();
    assert_eq!(data.steering_input(), SteeringInput::RackDisplacement);
    let r = report(&data);
    let rows = &r.steering.rows;
    let n = rows.len();
    // The rack and the two sides are mirror images: a right turn by u is a left turn by −u with the wheels
    // swapped, so the error is the same (to the position tolerance, 1e-12 m over 0.1 m levers: 1e-11 rad).
    for k in 0..n {
        let (a, b) = (rows[k], rows[n - 1 - k]);
        assert!((a.input + b.input).abs() < 1e-15);
        assert!(
            (a.ackermann_error - b.ackermann_error).abs() < 1e-10,
            "{} vs {}",
            a.ackermann_error,
            b.ackermann_error
        );
    }
    assert!(rows[n / 2].ackermann_error.abs() < 1e-10, "zero at centre (no static toe)");
    // Second order: δ_L(u) = a u + b u² + O(u³) and, mirrored, δ_R(u) = a u − b u² + O(u³); for u > 0
    // the left wheel is inside: error = δ_L − δ_R − (t/L) δ_R² + O(u³) = (2b − (t/L) a²) u² + O(u³).
    // a and 2b by central differences of solved positions (h = 1e-4 m of rack: truncation ~h²|δ''''| and
    // round-off 1e-11 rad/h² ≈ 1e-3 rad/m², 3e-5 of 2b − (t/L)a² ≈ −35 rad/m²). From the report: the error
    // at the first two inputs u1 and 2u1 (u1 = 1/40 of full lock, 1.75 mm) gives the u² coefficient by
    // Richardson extrapolation, c2 = (8 e(u1) − e(2u1)) / (4 u1²), with O(u1²) left, (u1 / full lock)² ≈
    // 6e-4 of the curve's relative change over full lock. 1 % covers both with a wide margin; the plain
    // e(u1)/u1², printed beside, is off by O(u1), 0.7 %.
    let v = Vehicle::new(&data).unwrap();
    let c = &v.corners[0];
    let delta = |u: f64| c.steer_angle(&c.solve_positions(0.0, v.steering.sign * u, &[0.0; 4]).unwrap());
    let h = 1e-4;
    let a = (delta(h) - delta(-h)) / (2.0 * h);
    let two_b = (delta(h) - 2.0 * delta(0.0) + delta(-h)) / (h * h);
    let k = r.steering.track / r.steering.wheelbase;
    let predicted = two_b - k * a * a;
    let (u1, e1, e2) = (rows[n / 2 + 1].input, rows[n / 2 + 1].ackermann_error, rows[n / 2 + 2].ackermann_error);
    // e(u) = c2 u² + c3 u³ + O(u⁴): c2 = (8 e(u1) − e(2u1)) / (4 u1²) − O(u1²).
    let c2 = (8.0 * e1 - e2) / (4.0 * u1 * u1);
    let plain = e1 / (u1 * u1);
    println!(
        "Ackermann error / u², rad/m²: from toe curvature {predicted:.4}, report {c2:.4} (plain e(u1)/u1² {plain:.4})"
    );
    assert!(((c2 - predicted) / predicted).abs() < 0.01);
}

#[test]
fn steering_ratio_on_centre_is_the_data_sets_gain() {
    // The HMMWV data set gives the steering gain at centre, 408.735 deg per m of rack; the overall ratio
    // on centre is its inverse in m/rad. 1 %, as the other derived figures of the data set (see above).
    let data = VehicleData::default_hmmwv();
    let r = report(&data);
    let gain = data.rack.as_ref().unwrap().reference_gain_deg_per_m;
    let want = 1.0 / gain.to_radians();
    println!("ratio on centre {:.6} m/rad, from the data set's gain {want:.6}", r.steering.ratio_on_centre);
    assert!(((r.steering.ratio_on_centre - want) / want).abs() < 0.01);
}

#[test]
fn every_shipped_vehicle_has_a_report_over_the_default_sweeps() {
    for (name, data) in vehicles() {
        let r = report(&data);
        for axle in &r.axles {
            // ±100 mm of wheel travel is within every shipped vehicle's linkage (about the HMMWV's stop to stop:
            // its rear rebound stop engages at −97.5 mm); a file whose linkage locks sooner is worth a look.
            assert!(axle.travel_notes.is_empty(), "{name} {}: {:?}", axle.name, axle.travel_notes);
            assert_eq!(axle.travel.len(), 81, "{name} {}", axle.name);
            let f = &axle.figures;
            let kingpin = [f.caster, f.kingpin_inclination, f.scrub_radius, f.trail];
            if axle.template.is_steered_solid_axle() {
                // A steered solid axle's knuckles turn on kingpins in the axle.
                assert!(kingpin.iter().all(|x| x.is_finite()), "{name} {}: {kingpin:?}", axle.name);
            } else if axle.template.is_solid_axle()
                || axle.template == rt_vehicle::model::formats::params::SuspensionTemplate::SemiTrailingArm
            {
                // A solid axle, and a spindle on its semi-trailing arm, have no kingpin: their figures are not
                // defined (the report prints –).
                assert!(kingpin.iter().all(|x| x.is_nan()), "{name} {}: {kingpin:?}", axle.name);
            } else {
                assert!(kingpin.iter().all(|x| x.is_finite()), "{name} {}: {kingpin:?}", axle.name);
            }
            assert!(f.roll_centre_height.is_finite(), "{name}");
        }
        assert_eq!(r.steering.rows.len(), 81);
        println!(
            "{name}: front caster {:.3} deg, KPI {:.3} deg, scrub {:.1} mm, trail {:.1} mm, roll centres {:.1} / \
             {:.1} mm",
            r.axles[0].figures.caster.to_degrees(),
            r.axles[0].figures.kingpin_inclination.to_degrees(),
            1e3 * r.axles[0].figures.scrub_radius,
            1e3 * r.axles[0].figures.trail,
            1e3 * r.axles[0].figures.roll_centre_height,
            1e3 * r.axles[1].figures.roll_centre_height
        );
    }
}

#[test]
fn rtv_kc_writes_the_report_and_its_csvs() {
    let dir = std::env::temp_dir().join(format!("rtv-kc-test-{}", std::process::id()));
    let out = dir.join("car.md");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_rtv"))
        .args(["kc", "--out", out.to_str().unwrap(), "--plots", "none"])
        .output()
        .unwrap();
    assert!(status.status.success(), "{}", String::from_utf8_lossy(&status.stderr));
    let md = std::fs::read_to_string(&out).unwrap();
    assert!(md.contains("| caster, deg | 2.999 |"), "{md}");
    assert!(md.contains("The figures were not made"));
    for f in ["car_front_travel.csv", "car_rear_travel.csv", "car_steering.csv"] {
        let text = std::fs::read_to_string(dir.join(f)).unwrap();
        assert!(text.lines().count() > 50, "{f}");
    }
    let steering = std::fs::read_to_string(dir.join("car_steering.csv")).unwrap();
    assert!(steering.starts_with("rack_displacement_m,steer_l_deg,steer_r_deg,ackermann_error_deg,ratio_m_per_rad\n"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn rtv_kc_refuses_bad_sweeps_with_exit_2() {
    for (args, needle) in [
        (vec!["kc", "--steering-points", "10"], "--steering-points"),
        (vec!["kc", "--from", "0.05"], "--from ≤ 0 ≤ --to"),
        (vec!["kc", "--increment", "1e-300"], "points"),
        (vec!["kc", "--plots", "maybe"], "--plots"),
    ] {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_rtv")).args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}
