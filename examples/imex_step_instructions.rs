//! Instructions per IMEX-AB3 step against one synthesis evaluation (issue 19: a step may cost at most 1.5×
//! an evaluation), free of machine noise: callgrind counts only `measured` (the N steps), and the count
//! divided by N is one step; `examples/evaluation_instructions.rs` gives the evaluation's own count the same
//! way. `bash scripts/instructions.sh` runs both (docs/results.md, "Instructions"; from a fixed-length path in
//! an empty environment, so that the count repeats: `examples/evaluation_instructions.rs` says why); by hand:
//!
//! ```sh
//! cargo build --release --example imex_step_instructions
//! valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*measured*' --callgrind-out-file=/tmp/cg.imex \
//!     target/release/examples/imex_step_instructions 2000 2>&1 | grep "Collected"
//! ```
//! The state is the J-turn's cornering at t = 4 s (as `evaluation_instructions`), and the steps go on from
//! there at 8.33 ms with the inputs held: steady cornering, the scheme's plain third-order step (one
//! evaluation, one solve with the factors of a0 I − hJ kept between steps, and its SBDF2 estimate on the
//! watched rows by the rows of the inverse kept with them) with the
//! simulation's own implicit block (the wheel states and the chassis velocities, `imex_partial_jacobian`). The two
//! starting steps (five evaluations each) and the J's factorization are outside `measured`; the program
//! prints how many steps were retaken, which would add to the count (0 here).
use rt_vehicle::error::ModelError;
use rt_vehicle::integrate::imex_ab3::ImexAb3;
use rt_vehicle::integrate::{Integrator, OdeSystem};
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::vehicle::{idx, Inputs, Run, Vehicle, Workspace};
use rt_vehicle::sim::{stepping, SimConfig};
use rt_vehicle::studies::scenes::{run, Amplitude, Scene, SceneKind};

/// The vehicle with its inputs held (the J-turn's steer is constant after 1.5 s).
struct Held<'a> {
    vehicle: &'a Vehicle,
    run: Run<'a>,
    inputs: Inputs,
    cache: Workspace,
}

impl OdeSystem for Held<'_> {
    fn dim(&self) -> usize {
        self.run.layout().dim
    }
    fn derivative(&mut self, _t: f64, x: &[f64], dxdt: &mut [f64]) -> Result<(), ModelError> {
        self.vehicle.derivative(&self.run, x, &self.inputs, &mut self.cache, dxdt)
    }
    fn project(&self, x: &mut [f64]) {
        stepping::normalize_attitude(x);
    }
    fn error_scale(&self, scale: &mut [f64]) {
        stepping::error_scale(&self.run.layout(), scale);
    }
}

fn main() {
    let n: usize = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(2000);
    let data = VehicleData::default_hmmwv();
    let scene = Scene::for_vehicle(SceneKind::JTurn, Amplitude::Calibrated, &data).unwrap();
    let mut sim = scene.start(data, &SimConfig::default()).unwrap();
    run(&mut sim, 4.0, 0.01, |_| {}).unwrap();
    let modes = sim.wheel_modes().unwrap();
    let block = sim.imex_partial_jacobian(&modes).unwrap();
    let inputs = sim.inputs();
    let (vehicle, mut x) = (sim.vehicle().clone(), sim.state().to_vec());
    let mut system = Held {
        vehicle: &vehicle,
        run: Run::new(&vehicle, &sim.config().options, sim.road()),
        inputs,
        cache: Workspace::default(),
    };
    let mut scheme = ImexAb3::new();
    scheme.set_partial_jacobian(
        &block.rows[..block.m],
        &block.cols[..block.nc],
        &block.jac[..block.m * block.nc],
        modes.len,
    );
    scheme.set_error_limit(5e-3);
    let h = 1.0 / 120.0;
    // The two starting steps, in both runs.
    for k in 0..2 {
        scheme.step(&mut system, 4.0 + k as f64 * h, h, &mut x).unwrap();
    }
    measured(n, &mut scheme, &mut system, h, &mut x);
    println!("{n} steps after the start, {} retaken; yaw rate {:.6e} rad/s", scheme.substepped, x[idx::W0 + 2]);
}

/// The N steps after the start, the only code callgrind counts (`--toggle-collect='*measured*'`).
#[inline(never)]
fn measured(n: usize, scheme: &mut ImexAb3, system: &mut Held, h: f64, x: &mut [f64]) {
    for k in 0..n {
        scheme.step(system, 4.0 + (k + 2) as f64 * h, h, x).unwrap();
    }
}
