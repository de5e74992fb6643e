//! The wheel-hop resolution bound of a scheme (`Integrator::hop_resolution`), measured: the stability suite's road
//! cases (obstacles that strike the wheel hop) run with the step check's refusals off
//! (`studies::stability::run_case_refusing`) at the suite's steps halved down to 0.26 ms, each judged against
//! the suite's reference and tolerance, beside |hλ| of the vehicle's fastest wheel-hop mode at the start.
//! The bound is set below the smallest |hλ| at which a run that finishes is off.
//!
//! ```sh
//! cargo run --release --example hop_resolution -- imex-ab3|rk4 [VEHICLE.json ...] > docs/hop_resolution_<scheme>.md
//! cargo run --release --example hop_resolution -- imex-ab3|rk4 --stiff > docs/hop_resolution_stiff_<scheme>.md
//! ```
//! (docs/hop_resolution_imex.md and docs/hop_resolution_rk4.md are this command's output on the HMMWV and
//! both imports; with `--stiff`, the suite's stiff variants on the paper's bump course instead, on the HMMWV:
//! where a fixed step resolves their wheel hop, apart from the check that refuses them.)
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::sim::{ModeKind, Simulation};
use rt_vehicle::studies::calibration;
use rt_vehicle::studies::stability;

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let stiff = args.iter().any(|a| a == "--stiff");
    args.retain(|a| a != "--stiff");
    let kind = rt_vehicle::sim::modes::INTEGRATORS.by_name(args.first().map_or("imex-ab3", |s| s.as_str())).unwrap();
    let vehicles: Vec<VehicleData> = if args.len() > 1 {
        args[1..].iter().map(|p| VehicleData::from_file(std::path::Path::new(p)).unwrap()).collect()
    } else {
        vec![VehicleData::default_hmmwv()]
    };
    let steps = [1.0 / 120.0, 1.0 / 240.0, 1.0 / 480.0, 1.0 / 960.0, 1.0 / 1920.0, 1.0 / 3840.0];
    let title = if stiff { "the stiff variants on the paper's bump course" } else { "obstacles" };
    println!("# {kind:?} on {title} with the step check's refusals off: the wheel-hop resolution bound\n");
    println!(
        "Written by `cargo run --release --example hop_resolution -- {} > docs/hop_resolution_{}{}.md`. Each {} \
         case of the stability suite runs at the suite's steps halved down to 0.26 ms with the step check refusing \
         nothing (`Simulation::set_step_refusals(false)`; IMEX-AB3's own accuracy monitor still refuses: \
         \"stopped\"), judged against the suite's reference and tolerance (the last column: error over tolerance, \
         above 1 is off; \"no reference\" where the suite's rule finds no converged one, docs/stability.md). |hλ| is the fastest wheel-hop mode's at the start. IMEX-AB3's bound (`Integrator::hop_resolution`) \
         is set 20 % below the smallest |hλ| of a run that finishes off on a road where it is not refused whatever \
         the step (`Simulation::check_imex_on_bumps` refuses it from the start on the paper's bumps under the \
         single-point contact, and once a wheel leaves the road); RK4's (0.25) acts together with the \
         bump-resolution rule (at least 20 steps per bump), which refuses some of its runs that finish off below \
         it (the HMMWV's 20 cm bump at 2.08 ms); the others are the stability suites' WRONG runs \
         (docs/integrators.md).\n",
        args.iter().chain(stiff.then(|| "--stiff".to_string()).as_ref()).cloned().collect::<Vec<_>>().join(" "),
        if stiff { "stiff_" } else { "" },
        if kind == rt_vehicle::integrate::IntegratorKind::ImexAb3 {
            "imex".to_string()
        } else {
            format!("{kind:?}").to_lowercase()
        },
        if stiff { "stiff bump" } else { "road" },
    );
    println!("| vehicle | case | h (ms) | \\|hλ\\| hop | outcome | error / tolerance |\n|---|---|---|---|---|---|");
    for data in vehicles {
        let (a, _) = calibration::amplitude_for(&data).unwrap();
        for case in stability::cases_for(&data, a).into_iter().filter(|c| {
            if stiff {
                c.group == "stiff" && c.name.contains("bump")
            } else {
                c.group == "road" || c.name.contains("20 cm")
            }
        }) {
            // The suite's reference (`stability::case_reference`, the rule docs/stability.md states) and its
            // tolerance; a case without a known reference is not judged.
            let rk4 = rt_vehicle::integrate::IntegratorKind::Rk4;
            let reference = stability::case_reference(
                &case,
                stability::run_case(&case, rk4, stability::REFERENCE_STEP),
                stability::run_case(&case, rk4, 0.5 * stability::REFERENCE_STEP),
            );
            let known = matches!(reference.status, stability::Reference::Known { .. });
            let mut vehicle = case.vehicle.clone();
            (case.data)(&mut vehicle);
            let hop = Simulation::new(vehicle, case.config.clone())
                .and_then(|mut s| s.fast_modes())
                .map(|modes| {
                    modes.iter().filter(|m| m.kind == ModeKind::WheelHop).map(|m| m.lambda.norm()).fold(0.0, f64::max)
                })
                .unwrap_or(f64::NAN);
            for h in steps {
                let run = stability::run_case_refusing(&case, kind, h, false);
                let error = stability::relative_error(&case, &run.samples, &reference.run.samples);
                let judged = if known { format!("{:.3}", error / stability::TOLERANCE) } else { "no reference".into() };
                let outcome = match &run.result {
                    Ok(()) => "finished".to_string(),
                    Err(e) => format!("stopped: {}", e.to_string().chars().take(60).collect::<String>()),
                };
                println!(
                    "| {} | {} | {:.2} | {:.3} | {} | {} |",
                    data.name.chars().take(20).collect::<String>(),
                    case.name,
                    h * 1e3,
                    hop * h,
                    outcome,
                    judged
                );
            }
        }
    }
}
