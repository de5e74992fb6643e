//! The run's configuration: `SimConfig` (the options, the integrator and its step, the road, the start), its
//! ranges (generated from the model description) and the one check of them, `SimConfig::validate`.

use super::inputs;
use super::modes;
use crate::error::{Cause, ModelError};
use crate::integrate::{substeps, IntegratorKind};
use crate::model::options::Options;
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
    /// A setting that exists for a test only (feature `test-option`): declared in build.rs's test variable
    /// and bound by the generated table alone (src/fmi/option_tests.rs).
    #[cfg(feature = "test-option")]
    #[serde(default)]
    pub test_setting: f64,
}

// A state or file written before a setting existed takes its default (the model description's start).
fn default_tolerance() -> f64 {
    SimConfig::default().tolerance
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

// The tolerance's range (`limits`): below 1e-9 of peak the Newton solves' 1e-12 and the outputs' round-off
// are no longer far below it; above 0.1 a run is not worth calling accurate.

fn paper_bump() -> [f64; 2] {
    SimConfig::default().bump
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
            "internal_step {step} s is outside [{FIXED_STEP_MIN:e}, {INTERNAL_STEP_MAX}] s (a fixed step; 0 is the \
             automatic step)"
        ),
    ))
}

/// The most derivative evaluations one `advance` may cost (about 1 s here at ~10 µs each): a larger
/// interval is refused before any work, so that no call hangs (an FMU master's doStep, a CLI run's output
/// interval). Split such an interval into several.
pub const MAX_EVALUATIONS_PER_ADVANCE: u64 = 100_000;

/// One Real setting of the run, generated from the model description (`OPTIONS`): its FMU name (also its
/// command-line flag, with dashes), unit, range, default (`start`), its place in `SimConfig` (`get`, `set`),
/// and what the FMU, the CLI, `SimConfig::validate`, `SimConfig::default` and docs/fmu.md make of it.
#[derive(Debug, Clone, Copy)]
pub struct RealOption {
    pub name: &'static str,
    pub unit: &'static str,
    pub min: f64,
    pub max: f64,
    /// The default (the model description's start value).
    pub start: f64,
    /// Older command-line spellings, without `--` (still accepted).
    pub aliases: &'static [&'static str],
    /// A short meaning, for messages and the CLI's help.
    pub summary: &'static str,
    pub description: &'static str,
    /// The check that replaces the range check (a range with a gap: `internal_step`).
    pub check: Option<fn(f64) -> Result<(), ModelError>>,
    pub get: fn(&SimConfig) -> f64,
    pub set: fn(&mut SimConfig, f64),
}

/// One mode of the run (an Integer parameter), generated from the model description (`MODE_OPTIONS`): its
/// FMU name (also its command-line flag, with dashes), default code (`start`), and its place in `SimConfig`
/// through its `sim::modes` table (codes and command-line words).
#[derive(Debug, Clone, Copy)]
pub struct ModeOption {
    pub name: &'static str,
    /// The default code (the model description's start value).
    pub start: i32,
    /// Older command-line spellings, without `--` (still accepted).
    pub aliases: &'static [&'static str],
    /// Whether `rtv scene` takes it (`road` is not: `--road` names a road file there, and the bump course is
    /// the `bump` scene).
    pub cli: bool,
    pub description: &'static str,
    pub get: fn(&SimConfig) -> i32,
    pub set: fn(&mut SimConfig, i32) -> Result<(), String>,
    /// Sets it by its command-line word.
    pub set_word: fn(&mut SimConfig, &str) -> Result<(), String>,
    /// The words, "a|b|c".
    pub words: fn() -> String,
}

impl ModeOption {
    /// The command-line flag, without `--`: the name with dashes.
    pub fn flag(&self) -> String {
        self.name.replace('_', "-")
    }
}

/// One file the run reads (a String parameter), generated from the model description (`FILE_OPTIONS`): its
/// FMU name (also its command-line flag, with dashes) and older command-line spellings. The value belongs to
/// the FMU instance or the command, which locate the file (an FMU's resources, a path): not to `SimConfig`.
#[derive(Debug, Clone, Copy)]
pub struct FileOption {
    pub name: &'static str,
    /// Older command-line spellings, without `--` (still accepted).
    pub aliases: &'static [&'static str],
    pub description: &'static str,
}

impl FileOption {
    /// The command-line flag, without `--`: the name with dashes.
    pub fn flag(&self) -> String {
        self.name.replace('_', "-")
    }
}

// The tables: `REAL_OPTIONS`, `MODE_OPTIONS` and `FILE_OPTIONS`, one row per Real parameter, per mode and per
// file of the model description (`fmi_layer::codegen::options_table`).
include!(concat!(env!("OUT_DIR"), "/options_table.rs"));
/// The Real options (`REAL_OPTIONS`, generated).
pub const OPTIONS: &[RealOption] = &REAL_OPTIONS;

impl RealOption {
    /// The option of FMU name `name`.
    pub fn named(name: &str) -> Option<&'static RealOption> {
        OPTIONS.iter().find(|o| o.name == name)
    }

    /// The command-line flag, without `--`: the name with dashes.
    pub fn flag(&self) -> String {
        self.name.replace('_', "-")
    }

    /// The unit as messages write it after a number: "" for 1, else " UNIT".
    fn unit_suffix(&self) -> String {
        if self.unit == "1" {
            String::new()
        } else {
            format!(" {}", self.unit)
        }
    }

    /// The range as messages, help and docs write it: `[0, 60] m/s`.
    pub fn range_text(&self) -> String {
        format!("[{}, {}]{}", Short(self.min), Short(self.max), self.unit_suffix())
    }

    /// The one check of a value, wherever it enters (CLI, FMU parameter, restored state): the option's own
    /// check, else its declared range, the message naming the option, the range, its unit and its meaning.
    pub fn check(&self, value: f64) -> Result<(), ModelError> {
        if let Some(check) = self.check {
            return check(value);
        }
        if (self.min..=self.max).contains(&value) {
            return Ok(());
        }
        Err(ModelError::new(
            Cause::Input,
            format!("{} {value}{} is outside {} ({})", self.name, self.unit_suffix(), self.range_text(), self.summary),
        ))
    }
}

/// A number as a person writes it: 60, 0.05, 1e-9 (messages, help, docs/fmu.md).
pub struct Short(pub f64);

impl std::fmt::Display for Short {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.0 != 0.0 && self.0.abs() < 1e-3 {
            write!(f, "{:e}", self.0)
        } else {
            write!(f, "{}", self.0)
        }
    }
}

impl SimConfig {
    /// The ranges every entry point (CLI, FMU parameters, restored FMU states) enforces: each option's check
    /// (`RealOption::check`), in the table's order.
    pub fn validate(&self) -> Result<(), ModelError> {
        OPTIONS.iter().try_for_each(|o| o.check((o.get)(self)))
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
    /// The model description's start values (`OPTIONS`) for the Real settings; the modes' defaults.
    fn default() -> Self {
        let mut config = SimConfig {
            options: Options::default(),
            integrator: IntegratorKind::Rk4,
            internal_step: AUTOMATIC_STEP,
            accuracy: AccuracyPolicy::Refuse,
            road: RoadChoice::Flat,
            initial_speed: 0.0,
            ride_height_retune: true,
            bump: [0.0; 2],
            tolerance: 0.0,
            road_file: None,
            #[cfg(feature = "test-option")]
            test_setting: 0.0,
        };
        for o in OPTIONS {
            (o.set)(&mut config, o.start);
        }
        for m in &MODE_OPTIONS {
            (m.set)(&mut config, m.start).expect("a mode's start value is one of its codes");
        }
        config
    }
}
