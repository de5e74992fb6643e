//! IMEX-AB3's advance allocates nothing once sized (the step check's Jacobian refreshes included):
//! `cargo run --release --example imex_alloc`.
use rt_vehicle::alloc_count::{allocations, CountingAllocator};
use rt_vehicle::integrate::IntegratorKind;
use rt_vehicle::model::params::VehicleData;
use rt_vehicle::sim::{SimConfig, Simulation};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

fn main() {
    let config = SimConfig { integrator: IntegratorKind::ImexAb3, internal_step: 1.0 / 120.0, ..SimConfig::default() };
    let mut sim = Simulation::new(VehicleData::default_hmmwv(), config).unwrap();
    sim.set_rack_profile(rt_vehicle::sim::RackProfile::Sine { amplitude: 0.002, period: 2.0 });
    sim.advance(1.0 / 120.0).unwrap();
    let before = allocations();
    for _ in 0..240 {
        sim.advance(1.0 / 120.0).unwrap();
        std::hint::black_box(sim.outputs().unwrap());
    }
    let n = allocations() - before;
    println!("{n} allocations in 240 IMEX-AB3 steps (24 step checks)");
    assert_eq!(n, 0);
}
