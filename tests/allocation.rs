//! The derivative function allocates nothing (a real-time requirement): counted by a global allocator.

use rt_vehicle::model::params::VehicleData;
use rt_vehicle::model::vehicle::{idx, Diagnostics, Formulation, Inputs, KinematicsCache, RackMotion};
use rt_vehicle::sim::{SimConfig, Simulation};
use rt_vehicle::alloc_count::{allocations, CountingAllocator};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn derivative_does_not_allocate() {
    let sim = Simulation::new(VehicleData::default_hmmwv(), SimConfig::default()).unwrap();
    let mut vehicle = sim.vehicle().clone();
    let x = sim.state().to_vec();
    let inputs = Inputs { rack: RackMotion { position: 0.002, velocity: 0.01, acceleration: 0.1 }, drive: [10.0; 4], brake: [5.0; 4] };
    let mut cache = KinematicsCache::default();
    let mut dx = vec![0.0; idx::DIM];
    let mut diag = Diagnostics::default();
    for f in [Formulation::Synthesis, Formulation::SynthesisAugmented, Formulation::Conventional] {
        vehicle.formulation = f;
        let before = allocations();
        for _ in 0..100 {
            vehicle.derivative(&x, &inputs, &mut cache, &mut dx, None).unwrap();
            vehicle.derivative(&x, &inputs, &mut cache, &mut dx, Some(&mut diag)).unwrap();
        }
        let n = allocations() - before;
        assert_eq!(n, 0, "{f:?}: {n} allocations in 200 evaluations");
    }
}
