//! The derivative function allocates nothing (a real-time requirement): counted by a global allocator.

use rt_vehicle::alloc_count::{allocations, CountingAllocator};
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::vehicle::{idx, Formulation, Inputs, Options, RackMotion, Run, Workspace};
use rt_vehicle::sim::{SimConfig, Simulation};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn derivative_does_not_allocate() {
    let sim = Simulation::new(VehicleData::default_hmmwv(), SimConfig::default()).unwrap();
    let vehicle = sim.vehicle().clone();
    let x = sim.state().to_vec();
    let inputs = Inputs {
        rack: RackMotion { position: 0.002, velocity: 0.01, acceleration: 0.1 },
        drive: [10.0; 4],
        brake: [5.0; 4],
        target_speed: 20.0,
    };
    let mut cache = Workspace::default();
    let mut dx = vec![0.0; idx::DIM];
    for f in [Formulation::Synthesis, Formulation::SynthesisAugmented, Formulation::Conventional] {
        let options = Options { formulation: f, ..Options::default() };
        let run = Run::flat(&vehicle, &options);
        let before = allocations();
        for _ in 0..200 {
            vehicle.derivative(&run, &x, &inputs, &mut cache, &mut dx).unwrap();
        }
        let n = allocations() - before;
        assert_eq!(n, 0, "{f:?}: {n} allocations in 200 evaluations");
    }
}

#[test]
fn advancing_a_simulation_does_not_allocate() {
    // After the first step has sized the integrator's scratch, a step (5 RK4 sub-steps, outputs, slip
    // monitor, rollback copy) allocates nothing: the FMU's doStep stays deterministic in time for HIL.
    let mut sim = Simulation::new(VehicleData::default_hmmwv(), SimConfig::default()).unwrap();
    sim.set_rack_profile(rt_vehicle::sim::RackProfile::Sine { amplitude: 0.002, period: 2.0 });
    sim.advance(0.01).unwrap();
    let before = allocations();
    for _ in 0..50 {
        sim.advance(0.01).unwrap();
        std::hint::black_box(sim.outputs().unwrap());
    }
    let n = allocations() - before;
    assert_eq!(n, 0, "{n} allocations in 50 steps");
}

#[test]
fn imex_ab3_does_not_allocate() {
    // IMEX-AB3 at the paper's frame, its step checks included (24 in 2 s: the partial Jacobian and the
    // factors of a0 I − hJ are refreshed on the stack and in sized buffers).
    let config = SimConfig {
        integrator: rt_vehicle::integrate::IntegratorKind::ImexAb3,
        internal_step: 1.0 / 120.0,
        ..SimConfig::default()
    };
    let mut sim = Simulation::new(VehicleData::default_hmmwv(), config).unwrap();
    sim.set_rack_profile(rt_vehicle::sim::RackProfile::Sine { amplitude: 0.002, period: 2.0 });
    sim.advance(1.0 / 120.0).unwrap();
    let before = allocations();
    for _ in 0..240 {
        sim.advance(1.0 / 120.0).unwrap();
        std::hint::black_box(sim.outputs().unwrap());
    }
    let n = allocations() - before;
    assert_eq!(n, 0, "{n} allocations in 240 IMEX-AB3 steps");
}

#[test]
fn fmi2_do_step_does_not_allocate() {
    use fmi_sys::fmi2::fmi2Status_fmi2OK as OK;
    use rt_vehicle::fmi::exports::{fmi2GetReal, fmi2SetReal, fmi2SetRealInputDerivatives};
    use rt_vehicle::fmi::variables::vr;
    let mut fmu = rt_vehicle::fmi::native::NativeInstance::initialized("alloc").unwrap();
    let c = fmu.component();
    let round = |fmu: &mut rt_vehicle::fmi::native::NativeInstance| unsafe {
        // The calls of a master's loop: the input and its derivative, a step, an output.
        let u = [0.001 * fmu.time()];
        assert_eq!(fmi2SetReal(c, [vr::RACK_DISPLACEMENT].as_ptr(), 1, u.as_ptr()), OK);
        assert_eq!(
            fmi2SetRealInputDerivatives(c, [vr::RACK_DISPLACEMENT].as_ptr(), 1, [1].as_ptr(), [0.001].as_ptr()),
            OK
        );
        assert_eq!(fmu.do_step(0.01), OK);
        let mut ay = [0.0];
        assert_eq!(fmi2GetReal(c, [vr::AY].as_ptr(), 1, ay.as_mut_ptr()), OK);
    };
    round(&mut fmu);
    let before = allocations();
    for _ in 0..50 {
        round(&mut fmu);
    }
    let n = allocations() - before;
    assert_eq!(n, 0, "{n} allocations in 50 set/doStep/get rounds");
}
