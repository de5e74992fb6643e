//! The largest eigenvalues of the full Jacobian ∂f/∂x (central differences) and the step check's wheel modes
//! along one case of the stability suite, run with RK4 at the suite's reference step: `cargo run --release
//! --example case_modes -- VEHICLE.json "CASE NAME" T1 [T2 ...]`. A diagnostic for WRONG cells that the step
//! check accepts: it shows which modes a step meets (the full Jacobian's, the wheel states' alone and with the
//! chassis velocities, as the check forms them), and the speed and slips the check's refresh rule watches.

use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::vehicle::idx;
use rt_vehicle::sim::{SimConfig, Simulation};
use rt_vehicle::studies::stability;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let vehicle = VehicleData::from_file(std::path::Path::new(&args[1])).unwrap();
    let case = stability::case_named(&vehicle, &args[2]).unwrap();
    let mut data = case.vehicle.clone();
    (case.data)(&mut data);
    let config = SimConfig {
        integrator: rt_vehicle::integrate::IntegratorKind::Rk4,
        internal_step: stability::REFERENCE_STEP,
        ..case.config.clone()
    };
    let mut sim = Simulation::new(data, config).unwrap();
    sim.set_rack_profile(case.rack);
    sim.set_wheel_torques(case.drive, case.brake);
    let mut t = 0.0;
    for at in args[3..].iter().map(|s| s.parse::<f64>().unwrap()) {
        if at > t {
            sim.advance(at - t).unwrap();
            t = at;
        }
        let j = sim.state_jacobian().unwrap();
        let mut ev: Vec<_> = j.complex_eigenvalues().iter().cloned().collect();
        ev.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
        println!("t = {t:.3} s: the full Jacobian's largest eigenvalues (hλ at 8.33 ms):");
        for e in ev.iter().take(10) {
            println!(
                "  {:10.1} {:+10.1}i   |λ| = {:8.1}   hλ = {:+.2}{:+.2}i",
                e.re,
                e.im,
                e.norm(),
                e.re / 120.0,
                e.im / 120.0
            );
        }
        // The wheel states' block, and the same with the chassis velocities (ṙ₀, ω₀) added: the check's states.
        let modes = sim.wheel_modes().unwrap();
        let block = |ks: &[usize]| {
            let m = nalgebra::DMatrix::from_fn(ks.len(), ks.len(), |a, b| j[(ks[a], ks[b])]);
            let mut e: Vec<_> = m.complex_eigenvalues().iter().cloned().collect();
            e.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
            e.iter().take(4).map(|z| format!("{:.1}{:+.1}i", z.re, z.im)).collect::<Vec<_>>().join(", ")
        };
        let wheels = &modes.states[..modes.wheel_len];
        println!("  wheel states' block: {}", block(wheels));
        println!("  with the chassis velocities: {}", block(&modes.states[..modes.len]));
        println!("  with the chassis' first velocity alone: {}", block(&[wheels, &[idx::V0]].concat()));
        // What the refresh rule of the step check watches (`CheckedState`), here the slip and the speed.
        let o = sim.outputs().unwrap();
        let kappa = rt_vehicle::sim::Channel::KAPPA.map(|c| o.values[c.index()]);
        println!(
            "  vx {:.3e} m/s, κ {:?}",
            o.values[rt_vehicle::sim::Channel::Vx.index()],
            kappa.map(|k| format!("{k:.3e}"))
        );
        let mut per: Vec<_> = modes.per_wheel.iter().map(|m| (m.kind.name(), m.corner, m.lambda)).collect();
        per.sort_by(|a, b| b.2.norm().total_cmp(&a.2.norm()));
        println!(
            "  wheel modes: {}",
            per.iter()
                .take(6)
                .map(|(k, c, l)| format!("{k} {c}: {:.0}{:+.0}i", l.re, l.im))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
}
