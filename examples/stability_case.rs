//! One case of the stability suite, channel by channel: `cargo run --release --example stability_case --
//! VEHICLE.json "CASE NAME" STEP_S [INTEGRATOR]` prints each channel's largest difference from the reference
//! (RK4 at the suite's reference step) relative to its excursion, and where it occurs, for the run with
//! INTEGRATOR (the CLI's name; rk4 by default). A diagnostic for WRONG cells.

use rt_vehicle::integrate::IntegratorKind;
use rt_vehicle::model::params::VehicleData;
use rt_vehicle::sim::calibration;
use rt_vehicle::studies::stability;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let data = VehicleData::from_file(std::path::Path::new(&args[1])).unwrap();
    let (a, _) = calibration::amplitude_for(&data).unwrap();
    let case = stability::cases_for(&data, a).into_iter().find(|c| c.name.contains(args[2].as_str())).unwrap();
    let h: f64 = args[3].parse().unwrap();
    let reference = stability::run_case(&case, IntegratorKind::Rk4, stability::REFERENCE_STEP);
    let kind = match args.get(4) {
        Some(name) => rt_vehicle::sim::modes::INTEGRATORS.by_name(name).unwrap(),
        None => IntegratorKind::Rk4,
    };
    let run = stability::run_case(&case, kind, h);
    println!("{}: run {:?}", case.name, run.result.as_ref().err().map(|e| e.to_string()));
    if std::env::var("TRACE").is_ok() {
        let c = case.channels.iter().position(|c| c.name == "yaw_rate").unwrap_or(0);
        for k in (0..run.samples.len().min(reference.samples.len())).step_by(6) {
            println!(
                "  t {:.3}  run {:+.4e}  reference {:+.4e}",
                k as f64 * stability::SAMPLE,
                run.samples[k][c],
                reference.samples[k][c]
            );
        }
    }
    for (c, ch) in case.channels.iter().enumerate() {
        let start = reference.samples[0][c];
        let excursion = reference.samples.iter().map(|r| (r[c] - start).abs()).fold(0.0, f64::max).max(ch.floor);
        let (k, diff) = run
            .samples
            .iter()
            .zip(&reference.samples)
            .map(|(x, y)| (x[c] - y[c]).abs())
            .enumerate()
            .fold((0, 0.0), |m, (k, d)| if d > m.1 { (k, d) } else { m });
        println!(
            "  {:10} excursion {:9.3e}  worst {:9.3e} ({:.2e} relative) at t = {:.3} s: run {:.6e} reference {:.6e}",
            ch.name,
            excursion,
            diff,
            diff / excursion,
            k as f64 * stability::SAMPLE,
            run.samples[k][c],
            reference.samples[k][c]
        );
    }
}
