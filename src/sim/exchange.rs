//! Model Exchange: the importer's solver owns the time and the state; the simulation evaluates ẋ, the
//! outputs and the contact event indicators at whatever (t, x, inputs) it is given.
//!
//! - **State.** Always the full layout (`Layout::FULL`: every relaxation state and the speed-hold integral,
//!   whatever the options would leave out), so that the number of continuous states of an instance is
//!   fixed. The caller builds the simulation with `Options::keep_unused_states`.
//! - **One evaluation** gives ẋ, the outputs and the indicators together; it is made when one of them is
//!   first read after a change of time, state or inputs.
//! - **State-independent Newton warm starts.** Every evaluation starts the cut-joint Newton solves from the
//!   warm starts of the initial state (the evaluation restores them: `evaluate_outputs`), never from the
//!   last evaluation's. ẋ is then a function of (t, x, inputs) alone, to the last bit: a solver that steps
//!   back in time, or repeats an evaluation, gets the same answer.
//! - **Time events at the road's features.** On a flat stretch at steady speed nothing changes, and a
//!   variable-step solver grows its step past a bump it never sees (fmusim's CVODE, which sets no largest
//!   step, stepped over the paper's whole bump course: docs/fmi_checkers.md). The bump course's edges are
//!   known, so the model asks the solver to stop when a wheel reaches the next one at the current speed
//!   (`next_road_event_time`); from there the solver meets the bump with a fresh step. File roads (OpenCRG,
//!   OpenDRIVE, ISO 8608) have no such list: there the importer's largest step must stay below the shortest
//!   feature's length over the speed (docs/fmu.md).
//! - **Inputs** act at the current time: the steering input with the rates the importer gives
//!   (`rack_velocity`, `rack_acceleration`: the kinematically driven steering moves the wheels by them),
//!   the wheel torques as they are.

use super::inputs::RackSource;
use super::{Fresh, Simulation};
use crate::error::{Cause, ModelError};
use crate::model::road::RoadModel;
use crate::model::steering::RackMotion;
use crate::model::vehicle::{idx, Layout};

/// The number of continuous states in Model Exchange.
pub const CONTINUOUS_STATES: usize = idx::DIM;

/// The nominals at an initial speed, for wheels of `unloaded_radius` (before the vehicle is read: 0.5 m,
/// a car's to a truck's within a factor of two, which is all a nominal needs).
pub fn nominals_of_continuous_states(initial_speed: f64, unloaded_radius: Option<f64>) -> [f64; CONTINUOUS_STATES] {
    let mut n = [1.0; CONTINUOUS_STATES];
    let spin = (initial_speed.abs() / unloaded_radius.unwrap_or(0.5)).max(1.0);
    n[idx::R0..idx::R0 + 3].fill(10.0);
    n[idx::V0..idx::V0 + 3].fill(initial_speed.abs().max(1.0));
    n[idx::U..idx::U + 4].fill(0.1);
    n[idx::SPIN..idx::SPIN + 4].fill(spin);
    n[idx::XI..idx::XI + 8].fill(0.01);
    n
}

impl Simulation {
    fn require_full_layout(&self) -> Result<Layout, ModelError> {
        let layout = Layout::of(&self.config.options);
        if layout != Layout::FULL {
            return Err(ModelError::new(
                Cause::Input,
                "Model Exchange needs the full state layout (options.keep_unused_states)",
            ));
        }
        Ok(layout)
    }

    /// The continuous states (`CONTINUOUS_STATES` of them).
    pub fn continuous_states(&self, x: &mut [f64]) -> Result<(), ModelError> {
        self.require_full_layout()?;
        x.copy_from_slice(&self.run.state);
        Ok(())
    }

    /// Set the continuous states: finite, `CONTINUOUS_STATES` of them, an attitude quaternion that is not
    /// zero (the evaluation normalizes it; the solver's drift off unit length is its own).
    pub fn set_continuous_states(&mut self, x: &[f64]) -> Result<(), ModelError> {
        self.require_full_layout()?;
        if x.len() != CONTINUOUS_STATES {
            return Err(ModelError::new(
                Cause::Input,
                format!("{} continuous states expected, got {}", CONTINUOUS_STATES, x.len()),
            ));
        }
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(ModelError::new(
                Cause::Input,
                format!("continuous state {} ({}) is {}", i, Layout::FULL.state_name(i), x[i]),
            ));
        }
        let norm = x[idx::E0..idx::E0 + 4].iter().map(|v| v * v).sum::<f64>().sqrt();
        if !(norm > 0.5 && norm < 2.0) {
            return Err(ModelError::new(
                Cause::Input,
                format!("the attitude quaternion's length is {norm}: not a rotation (a unit quaternion is expected)"),
            ));
        }
        self.run.state.copy_from_slice(x);
        self.changed();
        Ok(())
    }

    /// Set the time (seconds since the start), with the steering input held at its value.
    pub fn set_time(&mut self, t: f64) -> Result<(), ModelError> {
        if !t.is_finite() {
            return Err(ModelError::new(Cause::Input, format!("time {t} is not finite")));
        }
        let rack = self.run.rack.at(self.run.time);
        self.run.time = t;
        self.set_inputs_now(rack, self.run.drive, self.run.brake);
        Ok(())
    }

    /// The inputs from now on: the steering input with its rates, the wheel torques.
    pub fn set_inputs_now(&mut self, rack: RackMotion, drive: [f64; 4], brake: [f64; 4]) {
        self.run.rack = RackSource::External {
            t_k: self.run.time,
            start: rack.position,
            slope: rack.velocity,
            curvature: rack.acceleration,
        };
        self.set_wheel_torques(drive, brake);
        self.changed();
    }

    /// ẋ at the current time, state and inputs.
    pub fn derivatives(&mut self, dx: &mut [f64]) -> Result<(), ModelError> {
        self.require_full_layout()?;
        let (full, _) = self.evaluated()?;
        dx.copy_from_slice(&full[..CONTINUOUS_STATES]);
        Ok(())
    }

    /// The contact event indicators (`tire::contact_indicator`) at the current time, state and inputs.
    pub fn contact_indicators(&mut self) -> Result<[f64; 4], ModelError> {
        Ok(self.evaluated()?.1)
    }

    /// When a wheel centre reaches the next mark of a bump at the current forward speed (simulation time), or
    /// `None` (no bump ahead, a road without a list of features, standing still). The marks are a bump's
    /// start, quarter points and end, and one unloaded radius before and after it, where the enveloping
    /// contact begins and ends to feel it. The inner marks matter: an implicit solver stepping from a bump's
    /// start to its end evaluates only where the road is level again, finds nothing to correct and accepts
    /// the step (fmusim's CVODE did, with events at the edges alone).
    pub fn next_road_event_time(&mut self) -> Result<Option<f64>, ModelError> {
        /// An edge closer than this is where the wheel is now (the last event's): the next one is sought.
        const AT_EDGE_M: f64 = 1e-6;
        /// Below this forward speed a bump is reached by no time worth predicting.
        const CREEPING_M_S: f64 = 1e-3;
        let RoadModel::Bumps(bumps) = &self.road else { return Ok(None) };
        let vx = self.run.state[idx::V0];
        if vx.abs() < CREEPING_M_S {
            return Ok(None);
        }
        let bumps = bumps.clone();
        self.evaluate_now()?;
        let r0 = self.vehicle().tire.unloaded_radius_m;
        let mut next = f64::INFINITY;
        for [x, y] in self.cache.diagnostics.wheel_centre_xy {
            for b in bumps.iter().filter(|b| b.side * y > 0.0) {
                let end = b.x_start + b.length;
                let quarter = 0.25 * b.length;
                let marks = [
                    b.x_start - r0,
                    b.x_start,
                    b.x_start + quarter,
                    b.x_start + 2.0 * quarter,
                    end - quarter,
                    end,
                    end + r0,
                ];
                for edge in marks {
                    if (edge - x) * vx.signum() > AT_EDGE_M {
                        next = next.min((edge - x) / vx);
                    }
                }
            }
        }
        Ok(next.is_finite().then_some(self.run.time + next))
    }

    /// Nominal magnitudes of the continuous states, for the solver's error weights: the sizes a state moves
    /// by in a manoeuvre (metres, a rotation, m/s, rad/s, the arms' travel, the spin rate at speed, the
    /// tread's deflection).
    pub fn nominals_of_continuous_states(&self) -> [f64; CONTINUOUS_STATES] {
        nominals_of_continuous_states(self.config.initial_speed, Some(self.vehicle().tire.unloaded_radius_m))
    }

    /// State `i` of the full layout (zero for a state the run's options leave out): what a Co-Simulation
    /// instance serves for the state variables.
    pub fn full_state_value(&self, i: usize) -> f64 {
        Layout::FULL.convert(&self.run.state, &Layout::of(&self.config.options))[i]
    }

    /// Evaluate ẋ, the outputs and the indicators at the current time, state and inputs, unless done.
    pub fn evaluate_now(&mut self) -> Result<(), ModelError> {
        self.evaluated().map(|_| ())
    }

    /// ẋ in the full layout and the contact indicators, if evaluated at the current time, state and inputs.
    pub fn current_evaluation(&self) -> Option<([f64; idx::DIM], [f64; 4])> {
        let (dx, z) = self.output_derivative.filter(|_| self.fresh >= Fresh::All)?;
        let layout = Layout::of(&self.config.options);
        let mut full = [0.0; idx::DIM];
        full.copy_from_slice(&Layout::FULL.convert(&dx[..layout.dim], &layout));
        Some((full, z))
    }

    fn evaluated(&mut self) -> Result<([f64; idx::DIM], [f64; 4]), ModelError> {
        if self.fresh < Fresh::All || self.output_derivative.is_none() {
            self.evaluate_outputs()?;
        }
        self.output_derivative.ok_or_else(|| ModelError::new(Cause::NonFinite, "no evaluation"))
    }

    /// Time, state or inputs changed: the outputs, ẋ and the indicators are computed again when read.
    fn changed(&mut self) {
        self.fresh = Fresh::None;
        self.output_derivative = None;
        self.first_stage = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::formats::params::VehicleData;
    use crate::sim::SimConfig;

    fn exchange_simulation() -> Simulation {
        let config = SimConfig::default().with_options(|o| o.keep_unused_states = true);
        Simulation::new(VehicleData::default_hmmwv(), config).expect("the simulation starts")
    }

    /// ẋ is a function of (t, x, inputs) alone: the same state evaluated before and after others gives the
    /// same bits (the Newton solves start from the initial warm starts every time).
    #[test]
    fn derivatives_do_not_depend_on_the_evaluations_before() {
        let mut sim = exchange_simulation();
        let mut x0 = [0.0; CONTINUOUS_STATES];
        sim.continuous_states(&mut x0).unwrap();
        let mut moved = x0;
        moved[idx::R0 + 2] -= 0.03; // the body 3 cm lower
        moved[idx::U] += 0.05; // an arm turned
        moved[idx::W0] = 0.2; // rolling
        let rack = RackMotion { position: 0.01, velocity: 0.1, acceleration: 0.0 };
        let at = |sim: &mut Simulation, x: &[f64]| {
            sim.set_time(0.5).unwrap();
            sim.set_inputs_now(rack, [0.0; 4], [0.0; 4]);
            sim.set_continuous_states(x).unwrap();
            let mut dx = [0.0; CONTINUOUS_STATES];
            sim.derivatives(&mut dx).unwrap();
            dx
        };
        let first = at(&mut sim, &moved);
        at(&mut sim, &x0);
        let mut far = moved;
        far[idx::U + 1] -= 0.1;
        at(&mut sim, &far);
        assert_eq!(at(&mut sim, &moved), first, "the same (t, x, inputs) gives the same bits");
        // A fresh simulation agrees to the bit as well.
        assert_eq!(at(&mut exchange_simulation(), &moved), first);
        // The rack's rate is an input: it changes ẋ.
        sim.set_inputs_now(RackMotion { velocity: 0.0, ..rack }, [0.0; 4], [0.0; 4]);
        let mut dx = [0.0; CONTINUOUS_STATES];
        sim.derivatives(&mut dx).unwrap();
        assert_ne!(dx, first);
    }

    /// At the initial state, ẋ is the one the simulation's own integrator starts from (steady rolling: the
    /// body and arms at rest), and every wheel is in contact.
    #[test]
    fn the_initial_state_is_steady_rolling_with_every_wheel_on_the_road() {
        let mut sim = exchange_simulation();
        let mut dx = [0.0; CONTINUOUS_STATES];
        sim.derivatives(&mut dx).unwrap();
        for i in [idx::V0 + 2, idx::W0, idx::W0 + 1, idx::W0 + 2] {
            assert!(dx[i].abs() < 1e-6, "state {} derivative {}", Layout::FULL.state_name(i), dx[i]);
        }
        assert!(sim.contact_indicators().unwrap().iter().all(|z| *z > 0.0));
        // Lift the car 1 m: every indicator is negative, by the clearance.
        let mut x = [0.0; CONTINUOUS_STATES];
        sim.continuous_states(&mut x).unwrap();
        x[idx::R0 + 2] += 1.0;
        sim.set_continuous_states(&x).unwrap();
        let z = sim.contact_indicators().unwrap();
        assert!(z.iter().all(|z| *z < -0.5 && *z > -1.0), "{z:?}");
    }

    /// On the paper's bump course the next event is a wheel reaching a bump edge: the front left wheel's
    /// first bump starts 10 m ahead (PAPER_BUMPS_LEFT_M), one unloaded radius earlier the envelope meets it.
    #[test]
    fn the_next_time_event_is_a_wheel_at_a_bump_edge() {
        let config = SimConfig { road: crate::sim::RoadChoice::PaperBumps, initial_speed: 5.0, ..SimConfig::default() }
            .with_options(|o| o.keep_unused_states = true);
        let mut sim = Simulation::new(VehicleData::default_hmmwv(), config).unwrap();
        let r0 = sim.vehicle().tire.unloaded_radius_m;
        let t = sim.next_road_event_time().unwrap().expect("bumps ahead");
        assert!((t - (10.0 - r0) / 5.0).abs() < 1e-9, "{t}");
        // At that time (the car moved on at its speed) the next one is the bump's start itself.
        let mut x = [0.0; CONTINUOUS_STATES];
        sim.continuous_states(&mut x).unwrap();
        x[idx::R0] += 5.0 * t;
        sim.set_time(t).unwrap();
        sim.set_continuous_states(&x).unwrap();
        let next = sim.next_road_event_time().unwrap().unwrap();
        assert!((next - 10.0 / 5.0).abs() < 1e-9, "{next}");
        // A flat road has none.
        assert_eq!(exchange_simulation().next_road_event_time().unwrap(), None);
    }

    #[test]
    fn bad_states_are_refused_and_the_old_ones_kept() {
        let mut sim = exchange_simulation();
        let mut x = [0.0; CONTINUOUS_STATES];
        sim.continuous_states(&mut x).unwrap();
        let mut bad = x;
        bad[idx::U + 2] = f64::NAN;
        let e = sim.set_continuous_states(&bad).unwrap_err().to_string();
        assert!(e.contains("arm angle rl"), "{e}");
        bad = x;
        bad[idx::E0..idx::E0 + 4].fill(0.0);
        assert!(sim.set_continuous_states(&bad).unwrap_err().to_string().contains("quaternion"));
        assert!(sim.set_continuous_states(&x[..10]).is_err());
        let mut now = [0.0; CONTINUOUS_STATES];
        sim.continuous_states(&mut now).unwrap();
        assert_eq!(now, x);
        // A simulation without the full layout refuses Model Exchange.
        let mut cs = Simulation::new(VehicleData::default_hmmwv(), SimConfig::default()).unwrap();
        if Layout::of(&cs.config().options) != Layout::FULL {
            assert!(cs.derivatives(&mut now).is_err());
        }
    }
}
