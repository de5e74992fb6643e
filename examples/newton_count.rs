//! Newton iterations and cost per evaluation in a running scene (RK4, 2 ms): how good the warm start is.
//! `cargo run --release --example newton_count`
use rt_vehicle::error::ModelError;
use rt_vehicle::integrate::{Integrator, OdeSystem, Rk4};
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::vehicle::{idx, Inputs, Run, Vehicle, Workspace};
use rt_vehicle::sim::{RackProfile, SimConfig};
use rt_vehicle::studies::scenes::{Amplitude, Scene, SceneKind};

struct Counting<'a> {
    vehicle: &'a Vehicle,
    run: Run<'a>,
    target_speed: f64,
    rack: RackProfile,
    cache: Workspace,
    iterations: u64,
    evaluations: u64,
}

impl OdeSystem for Counting<'_> {
    fn dim(&self) -> usize {
        idx::DIM
    }
    fn derivative(&mut self, t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), ModelError> {
        let inputs = Inputs { rack: self.rack.at(t), target_speed: self.target_speed, ..Inputs::default() };
        let r = self.vehicle.derivative(&self.run, x, &inputs, &mut self.cache, dx);
        self.iterations += self.cache.diagnostics.newton_iterations as u64;
        self.evaluations += 1;
        r
    }
}

fn main() {
    for kind in [SceneKind::JTurn, SceneKind::Bump, SceneKind::Sine] {
        let scene = Scene::new(kind, Amplitude::Calibrated);
        let sim = scene.start(VehicleData::default_hmmwv(), &SimConfig::default()).unwrap();
        let vehicle = sim.vehicle().clone();
        let mut x = sim.state().to_vec();
        let mut ode = Counting {
            vehicle: &vehicle,
            run: Run::new(&vehicle, &sim.config().options, sim.road()),
            target_speed: sim.config().initial_speed,
            rack: scene.rack,
            cache: Workspace::default(),
            iterations: 0,
            evaluations: 0,
        };
        let mut rk4 = Rk4::new();
        let clock = std::time::Instant::now();
        for k in 0..4000 {
            rk4.step(&mut ode, k as f64 * 0.002, 0.002, &mut x).unwrap();
        }
        println!(
            "{:<6} {:.2} Newton iterations per evaluation (4 corners), {:.2} us per evaluation (with diagnostics)",
            kind.name(),
            ode.iterations as f64 / ode.evaluations as f64,
            clock.elapsed().as_secs_f64() * 1e6 / ode.evaluations as f64
        );
    }
}
