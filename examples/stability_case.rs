//! One case of the stability suite, channel by channel: `cargo run --release --example stability_case --
//! VEHICLE.json "CASE NAME" STEP_S [INTEGRATOR]` prints each channel's largest difference from the reference
//! (RK4 at the suite's reference step) relative to its excursion, and where it occurs, for the run with
//! INTEGRATOR (the CLI's name; rk4 by default), on the vehicle's own tire or on the Magic Formula tire of
//! TIRE.tir (`... STEP_S INTEGRATOR TIRE.tir`, as `rtv stability --tire-file`). A diagnostic for WRONG cells.

use rt_vehicle::integrate::IntegratorKind;
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::studies::stability;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mut data = VehicleData::from_file(std::path::Path::new(&args[1])).unwrap();
    if let Some(tir) = args.get(5) {
        data.use_tire_file(std::path::Path::new(tir)).unwrap();
    }
    let case = stability::case_named(&data, &args[2]).unwrap();
    let h: f64 = args[3].parse().unwrap();
    let reference = stability::run_case(&case, IntegratorKind::Rk4, stability::REFERENCE_STEP);
    let kind = match args.get(4) {
        Some(name) => rt_vehicle::sim::modes::INTEGRATORS.by_name(name).unwrap(),
        None => IntegratorKind::Rk4,
    };
    let run = stability::run_case(&case, kind, h);
    println!("{}: run {:?}", case.name, run.result.as_ref().err().map(|e| e.to_string()));
    // TRACE=1 prints the yaw rate every 0.05 s; TRACE=CHANNEL (a case's channel name) that channel, and
    // TRACE_EVERY=N every N samples.
    if let Ok(trace) = std::env::var("TRACE") {
        let c = case
            .channels
            .iter()
            .position(|c| c.output.name() == trace)
            .or_else(|| case.channels.iter().position(|c| c.output == rt_vehicle::sim::Channel::YawRate))
            .unwrap_or(0);
        let every = std::env::var("TRACE_EVERY").ok().and_then(|s| s.parse().ok()).unwrap_or(6);
        for k in (0..run.samples.len().min(reference.samples.len())).step_by(every) {
            println!(
                "  t {:.3}  run {:+.4e}  reference {:+.4e}",
                k as f64 * stability::SAMPLE,
                run.samples[k][c],
                reference.samples[k][c]
            );
        }
    }
    for (c, e) in stability::channel_errors(&case, &run.samples, &reference.samples).iter().enumerate() {
        println!("  {}", e.describe(run.samples[e.at][c], reference.samples[e.at][c]));
    }
}
