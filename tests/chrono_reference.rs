//! The imports of Chrono's two reference cars against Chrono's own runs (data/chrono_reference/;
//! docs/vehicle_file.md, "How close an import is to its source"; `studies::chrono_compare`).
use rt_vehicle::studies::chrono_compare::{compare, percent, quantity, Comparison, Measure, CARS, QUANTITIES};
use std::path::Path;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The bound on |difference from Chrono| in % for each (quantity, measure), with the `chrono` convention.
fn check(car: usize, c: &Comparison, bounds: &[(String, Measure, f64)]) {
    for (label, measure, bound) in bounds {
        let (k, m) = (quantity(label), *measure as usize);
        let d = percent(c.with_chrono_convention[k][m], c.chrono[k][m]);
        println!("{} {label} ({measure:?}): {d:+.2} % (bound {bound} %)", CARS[car].name);
        assert!(d.abs() <= *bound, "{} {label} ({measure:?}): {d:+.2} % from Chrono, bound {bound} %", CARS[car].name);
    }
}

/// The switch is what brings the import to its source: with the default convention the steady value of each
/// of the four the issue bounds is further off, except those in `not_closer`.
fn switch_brings_closer(car: usize, c: &Comparison, not_closer: &[&str]) {
    let steady = Measure::Steady as usize;
    for label in ["yaw rate", "a_y [", "roll", "sideslip"].into_iter().filter(|l| !not_closer.contains(l)) {
        let k = quantity(label);
        let (on, off, chrono) = (c.with_chrono_convention[k][steady], c.with_mfeval[k][steady], c.chrono[k][steady]);
        assert!(
            percent(on, chrono).abs() < percent(off, chrono).abs(),
            "{} {}: the chrono convention ({on}) is not closer to Chrono ({chrono}) than mfeval ({off})",
            CARS[car].name,
            QUANTITIES[k].label
        );
    }
}

/// The steady turn's four and its corners. The bounds: 1 % for yaw rate and a_y, 2 % for roll and
/// sideslip. The corners' loads, side forces and slip angles in the steady turn: 2 %, the bound of the
/// issue's least certain pair; a corner's value is one share of the same totals, and Chrono's own limit is
/// an estimate (the HMMWV: its README's +0.5 % for h → 0; the generic car: two first-order steps).
fn steady_bounds() -> Vec<(String, Measure, f64)> {
    let mut bounds = bounded(&[("yaw rate", 1.0), ("a_y [", 1.0), ("roll", 2.0), ("sideslip", 2.0)], Measure::Steady);
    bounds.extend(corners(Measure::Steady, 2.0));
    bounds
}

fn bounded(labels: &[(&str, f64)], measure: Measure) -> Vec<(String, Measure, f64)> {
    labels.iter().map(|(label, bound)| (label.to_string(), measure, *bound)).collect()
}

/// Each corner's load, side force and slip angle, with one bound.
fn corners(measure: Measure, bound: f64) -> Vec<(String, Measure, f64)> {
    let kinds = ["F_z", "F_y", "α"];
    ["FL", "FR", "RL", "RR"]
        .iter()
        .flat_map(|corner| kinds.iter().map(move |kind| (format!("{kind} {corner}"), measure, bound)))
        .collect()
}

#[test]
fn the_hmmwv_import_reproduces_chronos_j_turn() {
    // Reached in the steady turn: yaw rate −0.05 %, a_y −0.11 %, roll +0.19 %, sideslip +0.23 %; corners'
    // loads within 1.63 % (RL, the smallest load: Chrono's four loads at speed sum 0.55 % above its static
    // sum, which the import's loads match within 0.06 %), side forces 0.84 %, slip angles 0.70 %. The
    // changes from straight running (straight running is symmetric on this car): the four within 1 %, each
    // corner's within 1.5 % (loads 0.94 %, F_y 1.09 %, α 0.61 %, road-wheel angles 1.36 %).
    let c = compare(root(), &CARS[1]).unwrap();
    let mut bounds = steady_bounds();
    bounds.extend(bounded(&[("yaw rate", 1.0), ("a_y [", 1.0), ("roll", 1.0), ("sideslip", 1.0)], Measure::Change));
    bounds.extend(corners(Measure::Change, 1.5));
    bounds.extend(bounded(&[("steer FL", 1.5), ("steer FR", 1.5)], Measure::Change));
    check(1, &c, &bounds);
    switch_brings_closer(1, &c, &[]);
}

#[test]
fn the_generic_macpherson_import_reproduces_chronos_steady_turn() {
    // Reached in the steady turn: yaw rate +0.56 %, a_y +0.54 %, roll +1.19 %, sideslip +0.62 %; corners'
    // loads within 0.52 %, side forces 1.42 % (RR), slip angles 1.04 % (RR); road-wheel angles within 0.2 %:
    // 1 %, the steering's kinematics alone.
    //
    // The changes from straight running are not the measure on this car: in Chrono it drifts right
    // with the wheel straight (−0.51 deg/s, its loads 157 N heavier on the left at both axles, against 11 N
    // at rest), which the import does not; the change subtracts that state. Their bounds hold what is
    // reached, half a point above it, so that a change either way is seen: 3–5 % lower here, one corner's F_y
    // 9.5 %.
    let c = compare(root(), &CARS[0]).unwrap();
    let mut bounds = steady_bounds();
    bounds.extend(bounded(&[("steer FL", 1.0), ("steer FR", 1.0)], Measure::Steady));
    bounds.extend(bounded(
        &[
            ("yaw rate", 4.5),
            ("a_y [", 4.5),
            ("roll", 4.0),
            ("sideslip", 5.0),
            ("F_z FL", 5.5),
            ("F_z FR", 3.5),
            ("F_z RL", 3.5),
            ("F_z RR", 5.5),
            ("F_y FL", 6.0),
            ("F_y FR", 3.0),
            ("F_y RL", 10.0),
            ("F_y RR", 3.0),
            ("α FL", 3.5),
            ("α FR", 3.5),
            ("α RL", 5.0),
            ("α RR", 5.0),
            ("steer FL", 1.0),
            ("steer FR", 1.0),
        ],
        Measure::Change,
    ));
    check(0, &c, &bounds);
    // With MFeval's aligning moment (issue 35, part 5) the default convention's steady roll is 0.4256°,
    // −0.59 % from Chrono's, closer than the chrono convention's +1.19 %.
    switch_brings_closer(0, &c, &["roll"]);
}

#[test]
fn chronos_lateral_acceleration_from_its_velocities_matches_its_acceleration_column_where_that_is_smooth() {
    // The a_y compared is Chrono's dv_y/dt + r v_x − p v_z (`chrono_compare::AY_FROM_VELOCITIES`), since its
    // acceleration column is noise on the generic car. On the HMMWV the column is smooth (standard deviation
    // 0.028 m/s² over the 201 samples of the steady turn: its mean's standard error 0.05 %): the two agree
    // within three standard errors, 0.15 %.
    let c = compare(root(), &CARS[1]).unwrap();
    let steady = Measure::Steady as usize;
    let (identity, column) = (c.chrono[quantity("a_y [")][steady], c.chrono[quantity("a_y, Chrono's")][steady]);
    println!("HMMWV steady a_y: from the velocities {identity:.4}, Chrono's column {column:.4}");
    assert!(percent(identity, column).abs() < 0.15, "{identity} against {column}");
}
