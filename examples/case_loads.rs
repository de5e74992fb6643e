//! The tire loads and wheel spins of a stability case run with RK4 at the reference step, every sample
//! between two times: `cargo run --release --example case_loads -- "CASE" FROM TO` ($VEHICLE for an import).
use rt_vehicle::integrate::IntegratorKind;
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::sim::{SimConfig, Simulation};
use rt_vehicle::studies::stability;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let data = match std::env::var("VEHICLE") {
        Ok(p) => VehicleData::from_file(std::path::Path::new(&p)).unwrap(),
        Err(_) => VehicleData::default_hmmwv(),
    };
    let case = stability::case_named(&data, &args[1]).unwrap();
    let (from, to): (f64, f64) = (args[2].parse().unwrap(), args[3].parse().unwrap());
    let mut d = case.vehicle.clone();
    (case.data)(&mut d);
    let config =
        SimConfig { integrator: IntegratorKind::Rk4, internal_step: stability::REFERENCE_STEP, ..case.config.clone() };
    let mut sim = Simulation::new(d, config).unwrap();
    sim.set_rack_profile(case.rack);
    sim.set_wheel_torques(case.drive, case.brake);
    let fz = rt_vehicle::sim::Channel::TIRE_FORCE[2].map(|c| c.index());
    while sim.time() < to {
        sim.advance(stability::SAMPLE / 4.0).unwrap();
        if sim.time() >= from {
            let o = sim.outputs().unwrap();
            let x = sim.state();
            println!(
                "t {:.4} Fz [{:.0} {:.0} {:.0} {:.0}] Ω [{:.2} {:.2} {:.2} {:.2}] v_x {:.3}",
                sim.time(),
                o.values[fz[0]],
                o.values[fz[1]],
                o.values[fz[2]],
                o.values[fz[3]],
                x[21],
                x[22],
                x[23],
                x[24],
                x[7]
            );
        }
    }
}
