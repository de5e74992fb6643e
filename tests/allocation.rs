//! The derivative function allocates nothing (a real-time requirement): counted by a global allocator.

use rt_vehicle::alloc_count::{allocations, CountingAllocator};
use rt_vehicle::model::params::VehicleData;
use rt_vehicle::model::vehicle::{idx, Diagnostics, Formulation, Inputs, KinematicsCache, RackMotion};
use rt_vehicle::sim::{SimConfig, Simulation};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn derivative_does_not_allocate() {
    let sim = Simulation::new(VehicleData::default_hmmwv(), SimConfig::default()).unwrap();
    let mut vehicle = sim.vehicle().clone();
    let x = sim.state().to_vec();
    let inputs = Inputs {
        rack: RackMotion { position: 0.002, velocity: 0.01, acceleration: 0.1 },
        drive: [10.0; 4],
        brake: [5.0; 4],
    };
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
        std::hint::black_box(sim.outputs());
    }
    let n = allocations() - before;
    assert_eq!(n, 0, "{n} allocations in 50 steps");
}

#[test]
fn fmi2_do_step_does_not_allocate() {
    use fmi_sys::fmi2::*;
    use rt_vehicle::fmi::exports::*;
    let name = std::ffi::CString::new("alloc").unwrap();
    let guid = std::ffi::CString::new(rt_vehicle::fmi::variables::GUID).unwrap();
    let quiet = fmi2CallbackFunctions {
        logger: None,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    };
    unsafe {
        let c =
            fmi2Instantiate(name.as_ptr(), fmi2Type_fmi2CoSimulation, guid.as_ptr(), std::ptr::null(), &quiet, 0, 0);
        assert!(!c.is_null());
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), fmi2Status_fmi2OK);
        assert_eq!(fmi2EnterInitializationMode(c), fmi2Status_fmi2OK);
        assert_eq!(fmi2ExitInitializationMode(c), fmi2Status_fmi2OK);
        let vr = [rt_vehicle::fmi::variables::vr::RACK_DISPLACEMENT];
        let ay = [rt_vehicle::fmi::variables::vr::AY];
        let mut out = [0.0];
        let mut t = 0.0;
        let mut step = |t: &mut f64| {
            assert_eq!(fmi2SetReal(c, vr.as_ptr(), 1, [0.001 * *t].as_ptr()), fmi2Status_fmi2OK);
            assert_eq!(
                fmi2SetRealInputDerivatives(c, vr.as_ptr(), 1, [1].as_ptr(), [0.001].as_ptr()),
                fmi2Status_fmi2OK
            );
            assert_eq!(fmi2DoStep(c, *t, 0.01, 1), fmi2Status_fmi2OK);
            assert_eq!(fmi2GetReal(c, ay.as_ptr(), 1, out.as_mut_ptr()), fmi2Status_fmi2OK);
            *t += 0.01;
        };
        step(&mut t);
        let before = allocations();
        for _ in 0..50 {
            step(&mut t);
        }
        let n = allocations() - before;
        fmi2FreeInstance(c);
        assert_eq!(n, 0, "{n} allocations in 50 set/doStep/get rounds");
    }
}
