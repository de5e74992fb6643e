//! The run's configuration: `SimConfig` (the options, the integrator and its step, the road, the start), its
//! ranges (generated from the model description) and the one check of them, `SimConfig::validate`.

use super::inputs;
use crate::error::{Cause, ModelError};
use crate::integrate::{substeps, IntegratorKind};
use crate::model::options::Options;
use crate::model::road::{PAPER_BUMP_HEIGHT_M, PAPER_BUMP_LENGTH_M};
use crate::model::vehicle::idx;
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum RoadChoice {
    Flat,
    /// The paper's unsymmetric bump course.
    PaperBumps,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimConfig {
    /// How the vehicle is evaluated (formulation, slip, speed mode, slope, contact, switches).
    #[serde(flatten)]
    pub options: Options,
    pub integrator: IntegratorKind,
    /// The internal step, s. `AUTOMATIC_STEP` (0, the default): the largest step, at most the scheme's
    /// default (`IntegratorKind::default_step`), that the step check and the road's resolution accept, chosen
    /// at the start and again at every check (`Simulation::choose_step`). A positive value is the step taken:
    /// honoured, or refused with its cause (a HIL rig's frame). For the error-controlled scheme, its largest
    /// step (automatic: the communication interval).
    pub internal_step: f64,
    /// What a fixed step that is stable but does not resolve what the road excites gets (`AccuracyPolicy`).
    #[serde(default)]
    pub accuracy: AccuracyPolicy,
    pub road: RoadChoice,
    /// The speed the run starts at, steady rolling, and the speed hold's target, m/s.
    pub initial_speed: f64,
    /// Retune spring free lengths so that the design position is the static equilibrium (default on),
    /// unless the vehicle file keeps its springs as written (`ride_height: data`, `Vehicle::springs_as_written`).
    pub ride_height_retune: bool,
    /// Height and length of the bumps of the bump course, m.
    #[serde(default = "paper_bump")]
    pub bump: [f64; 2],
    /// The error-controlled integrator's tolerance: the largest over a_y, yaw rate and roll rate of
    /// max |error| / peak that a run should keep (docs/integrators.md, "Error control"). The fixed-step
    /// integrators ignore it.
    #[serde(default = "default_tolerance")]
    pub tolerance: f64,
    /// A road of one's own in place of `road`: an OpenCRG file or `iso8608:CLASS:SEED[:LENGTH_M[:DX_M]]`
    /// (`model::road::crg`), placed with its reference line's start 2 m behind the initial rear axle.
    #[serde(default)]
    pub road_file: Option<String>,
}

fn default_tolerance() -> f64 {
    DEFAULT_TOLERANCE
}

/// `internal_step`'s value for "automatic" (`SimConfig::internal_step`).
pub const AUTOMATIC_STEP: f64 = 0.0;

/// The smallest fixed internal step, s: below it a step buys no accuracy (round-off dominates RK4:
/// docs/integrators.md). The model description's minimum is 0, the automatic step.
pub const FIXED_STEP_MIN: f64 = 1e-6;

/// What a step that is stable but under-resolves the wheel hop or a bump on a road with bumps gets (the
/// hop-resolution and bump-resolution bounds of the step check). Instability always refuses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum AccuracyPolicy {
    /// Refused with its cause (the default): a run is within the suite's tolerance or it stops.
    #[default]
    Refuse,
    /// Run on, and log once the error the hop-resolution measurements expect at that step
    /// (`expected_hop_error`): for a rig that must keep its frame over obstacles.
    Warn,
}

/// The default tolerance of the error-controlled integrator (0.1 % of peak).
pub const DEFAULT_TOLERANCE: f64 = 1e-3;
// The tolerance's range (`limits`): below 1e-9 of peak the Newton solves' 1e-12 and the outputs' round-off
// are no longer far below it; above 0.1 a run is not worth calling accurate.

fn paper_bump() -> [f64; 2] {
    [PAPER_BUMP_HEIGHT_M, PAPER_BUMP_LENGTH_M]
}

/// The ranges of the run's Real settings, generated from the model description's min/max (written once, in
/// modelDescription/modelDescription.xml; the FMU's setters read the same bounds from its variable table).
/// Why they are what they are: internal step, below 1 µs a step buys no accuracy (round-off dominates RK4:
/// docs/integrators.md), above 0.1 s no integrator here is stable; initial speed up to 216 km/h, beyond the
/// vehicle's and the tire data's range; road slopes to 45°; bumps to 0.3 m high (two thirds of the tire
/// radius) and 0.1–10 m long; the tolerance as `TOLERANCE_MIN`/`MAX` say.
pub mod limits {
    include!(concat!(env!("OUT_DIR"), "/parameter_ranges.rs"));
}
pub use limits::{
    BUMP_HEIGHT_MAX, BUMP_HEIGHT_MIN, BUMP_LENGTH_MAX, BUMP_LENGTH_MIN, INITIAL_SPEED_MAX, INITIAL_SPEED_MIN,
    INTERNAL_STEP_MAX, INTERNAL_STEP_MIN, TOLERANCE_MAX, TOLERANCE_MIN,
};

/// The one check of an internal step's value, wherever it enters (CLI, FMU parameter, restored state):
/// `AUTOMATIC_STEP`, or a fixed step in [`FIXED_STEP_MIN`, `INTERNAL_STEP_MAX`].
pub fn check_internal_step(step: f64) -> Result<(), ModelError> {
    if step == AUTOMATIC_STEP || (FIXED_STEP_MIN..=INTERNAL_STEP_MAX).contains(&step) {
        return Ok(());
    }
    Err(ModelError::new(
        Cause::Input,
        format!(
            "internal step {step} s is outside [{FIXED_STEP_MIN:e}, {INTERNAL_STEP_MAX}] s (a fixed step; 0 is the \
             automatic step)"
        ),
    ))
}

/// The most derivative evaluations one `advance` may cost (about 1 s here at ~10 µs each): a larger
/// interval is refused before any work, so that no call hangs (an FMU master's doStep, a CLI run's output
/// interval). Split such an interval into several.
pub const MAX_EVALUATIONS_PER_ADVANCE: u64 = 100_000;

impl SimConfig {
    /// The ranges every entry point (CLI, FMU parameters, restored FMU states) enforces.
    pub fn validate(&self) -> Result<(), ModelError> {
        check_internal_step(self.internal_step)?;
        if !(INITIAL_SPEED_MIN..=INITIAL_SPEED_MAX).contains(&self.initial_speed) {
            return Err(ModelError::new(
                Cause::Input,
                format!(
                    "initial speed {} m/s is outside [{INITIAL_SPEED_MIN}, {INITIAL_SPEED_MAX}] m/s",
                    self.initial_speed
                ),
            ));
        }
        use limits::{ROAD_FRICTION_MAX, ROAD_FRICTION_MIN};
        if !(ROAD_FRICTION_MIN..=ROAD_FRICTION_MAX).contains(&self.options.road_friction) {
            return Err(ModelError::new(
                Cause::Input,
                format!(
                    "road friction {} is outside [{ROAD_FRICTION_MIN}, {ROAD_FRICTION_MAX}] (a scale on the tires' \
                     peak friction: 1 dry, about 0.5 wet, 0.2 snow)",
                    self.options.road_friction
                ),
            ));
        }
        let [grade, cross] = self.options.slope;
        use limits::{ROAD_CROSS_SLOPE_MAX, ROAD_CROSS_SLOPE_MIN, ROAD_GRADE_MAX, ROAD_GRADE_MIN};
        if !((ROAD_GRADE_MIN..=ROAD_GRADE_MAX).contains(&grade)
            && (ROAD_CROSS_SLOPE_MIN..=ROAD_CROSS_SLOPE_MAX).contains(&cross))
        {
            return Err(ModelError::new(
                Cause::Input,
                format!(
                    "road slope {:?} (rise over run) is outside [{ROAD_GRADE_MIN}, {ROAD_GRADE_MAX}] (grade) and \
                     [{ROAD_CROSS_SLOPE_MIN}, {ROAD_CROSS_SLOPE_MAX}] (cross slope)",
                    self.options.slope
                ),
            ));
        }
        if !(TOLERANCE_MIN..=TOLERANCE_MAX).contains(&self.tolerance) {
            return Err(ModelError::new(
                Cause::Input,
                format!("tolerance {} is outside [{TOLERANCE_MIN:e}, {TOLERANCE_MAX}]", self.tolerance),
            ));
        }
        let [height, length] = self.bump;
        if !(BUMP_HEIGHT_MIN..=BUMP_HEIGHT_MAX).contains(&height) {
            return Err(ModelError::new(
                Cause::Input,
                format!("bump height {height} m is outside [{BUMP_HEIGHT_MIN}, {BUMP_HEIGHT_MAX}] m"),
            ));
        }
        if !(BUMP_LENGTH_MIN..=BUMP_LENGTH_MAX).contains(&length) {
            return Err(ModelError::new(
                Cause::Input,
                format!("bump length {length} m is outside [{BUMP_LENGTH_MIN}, {BUMP_LENGTH_MAX}] m"),
            ));
        }
        Ok(())
    }

    /// Whether the internal step is chosen by the step check (`AUTOMATIC_STEP`).
    pub fn automatic_step(&self) -> bool {
        self.internal_step == AUTOMATIC_STEP
    }

    /// The largest internal step for an interval `h`: the fixed step, or the automatic step's bound (the
    /// scheme's default; the interval itself, within the range, for the error-controlled scheme).
    pub fn step_bound(&self, h: f64) -> f64 {
        if !self.automatic_step() {
            self.internal_step
        } else if self.integrator.is_error_controlled() {
            h.clamp(FIXED_STEP_MIN, INTERNAL_STEP_MAX)
        } else {
            self.integrator.default_step()
        }
    }

    /// This configuration with its options changed by `change`.
    pub fn with_options(mut self, change: impl FnOnce(&mut Options)) -> SimConfig {
        change(&mut self.options);
        self
    }

    /// The sub-steps that cover an interval `h`, or an error if they would cost more than
    /// `MAX_EVALUATIONS_PER_ADVANCE` derivative evaluations (nothing is done then).
    pub fn plan(&self, h: f64) -> Result<(usize, f64), ModelError> {
        self.plan_with(h, self.step_bound(h))
    }

    /// `plan` with internal steps no larger than `step`.
    pub fn plan_with(&self, h: f64, step: f64) -> Result<(usize, f64), ModelError> {
        if !(h > 0.0 && h.is_finite()) {
            return Err(ModelError::new(Cause::Input, format!("step must be positive and finite, got {h}")));
        }
        // The largest layout: a bound that holds whatever states the options keep.
        let per_step = self.integrator.max_evaluations_per_step(idx::DIM);
        // One evaluation is left for the outputs; every input breakpoint inside the interval may add a step.
        let max_steps = (MAX_EVALUATIONS_PER_ADVANCE - 1) / per_step - inputs::MAX_BREAKPOINTS as u64;
        // Compare before converting: ceil(h / step) may not fit a usize.
        if h / step > max_steps as f64 {
            return Err(ModelError::new(
                Cause::Input,
                format!(
                    "an interval of {h} s needs {:.3e} internal steps of {} s, more than the {max_steps} one call may \
                 take (at most {MAX_EVALUATIONS_PER_ADVANCE} evaluations, about 1 s): split it into intervals of \
                 at most {} s",
                    (h / step).ceil(),
                    step,
                    max_steps as f64 * step
                ),
            ));
        }
        Ok(substeps(h, step))
    }
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig {
            options: Options::default(),
            integrator: IntegratorKind::Rk4,
            internal_step: AUTOMATIC_STEP,
            accuracy: AccuracyPolicy::Refuse,
            road: RoadChoice::Flat,
            initial_speed: 100.0 / 3.6,
            ride_height_retune: true,
            bump: paper_bump(),
            tolerance: DEFAULT_TOLERANCE,
            road_file: None,
        }
    }
}
