//! The run-time choices, each tabled once: the value, the FMU parameter's integer code, the CLI's word and
//! a description. The FMU adapter, the CLI and the docs all read these tables (a test checks that
//! docs/fmu.md and the model description's min/max agree with them).

use super::{AccuracyPolicy, ContactModel, RoadChoice};
use crate::integrate::IntegratorKind;
use crate::model::tire::{SlipModel, TireConvention};
use crate::model::vehicle::{Formulation, SpeedMode};

/// One choice of a mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Choice<T: 'static> {
    pub value: T,
    /// The FMU parameter's value.
    pub code: i32,
    /// The CLI's word.
    pub name: &'static str,
    pub description: &'static str,
}

/// A mode: its FMU parameter and CLI option names and its choices.
#[derive(Debug, Clone, Copy)]
pub struct Table<T: 'static> {
    /// The FMU parameter (modelDescription.xml).
    pub parameter: &'static str,
    /// The CLI option (without `--`), if the CLI offers the choice.
    pub option: Option<&'static str>,
    pub choices: &'static [Choice<T>],
}

impl<T: Copy + PartialEq> Table<T> {
    pub fn by_code(&self, code: i32) -> Result<T, String> {
        self.choices.iter().find(|c| c.code == code).map(|c| c.value).ok_or_else(|| {
            let list: Vec<String> = self.choices.iter().map(|c| format!("{} ({})", c.code, c.name)).collect();
            format!("{} {code} is not one of {}", self.parameter, list.join(", "))
        })
    }

    pub fn by_name(&self, name: &str) -> Result<T, String> {
        self.choices.iter().find(|c| c.name == name).map(|c| c.value).ok_or_else(|| {
            let list: Vec<&str> = self.choices.iter().map(|c| c.name).collect();
            format!("--{}: '{name}' is not one of {}", self.option.unwrap_or(self.parameter), list.join(", "))
        })
    }

    pub fn code(&self, value: T) -> i32 {
        self.choices.iter().find(|c| c.value == value).map(|c| c.code).expect("every value is tabled")
    }

    /// "1 coast, 2 hold …": the docs' description of the codes.
    pub fn describe(&self) -> String {
        let parts: Vec<String> = self.choices.iter().map(|c| format!("{} {}", c.code, c.description)).collect();
        parts.join(", ")
    }

    /// "a|b|c": the CLI's usage.
    pub fn names(&self) -> String {
        self.choices.iter().map(|c| c.name).collect::<Vec<_>>().join("|")
    }
}

pub const FORMULATIONS: Table<Formulation> = Table {
    parameter: "formulation",
    option: Some("formulation"),
    choices: &[
        Choice { value: Formulation::Synthesis, code: 1, name: "synthesis", description: "synthesis (GCP)" },
        Choice {
            value: Formulation::Conventional, code: 2, name: "conventional", description: "conventional (42×42)"
        },
        Choice {
            value: Formulation::SynthesisAugmented,
            code: 3,
            name: "augmented",
            description: "synthesis with the augmented 9×9 subsystem solve",
        },
    ],
};

pub const INTEGRATORS: Table<IntegratorKind> = Table {
    parameter: "integrator",
    option: Some("integrator"),
    choices: &[
        Choice { value: IntegratorKind::Ab3, code: 1, name: "ab3", description: "AB3 (RK4 start)" },
        Choice { value: IntegratorKind::Rk4, code: 2, name: "rk4", description: "RK4" },
        Choice {
            value: IntegratorKind::Dopri5,
            code: 4,
            name: "dopri5",
            description: "Dormand–Prince 5(4) with error control (takes the tolerance)",
        },
        Choice {
            value: IntegratorKind::ImexAb3,
            code: 5,
            name: "imex-ab3",
            description:
                "IMEX-AB3: the wheels' fast states and the chassis velocities implicit (BDF3), the rest explicit, one evaluation per step",
        },
    ],
};

pub const SPEED_MODES: Table<SpeedMode> = Table {
    parameter: "speed_mode",
    option: Some("speed-mode"),
    choices: &[
        Choice { value: SpeedMode::Coast, code: 1, name: "coast", description: "coast" },
        Choice { value: SpeedMode::Hold, code: 2, name: "hold", description: "hold" },
    ],
};

pub const SLIP_MODELS: Table<SlipModel> = Table {
    parameter: "slip_model",
    option: Some("slip-model"),
    choices: &[
        Choice { value: SlipModel::Relaxation, code: 1, name: "relaxation", description: "relaxation lengths" },
        Choice { value: SlipModel::Steady, code: 2, name: "steady", description: "steady slip" },
    ],
};

pub const ROADS: Table<RoadChoice> = Table {
    parameter: "road",
    option: None, // a scene decides its road
    choices: &[
        Choice { value: RoadChoice::Flat, code: 1, name: "flat", description: "flat" },
        Choice { value: RoadChoice::PaperBumps, code: 2, name: "bumps", description: "the paper's bump course" },
    ],
};

pub const CONTACTS: Table<ContactModel> = Table {
    parameter: "contact",
    option: Some("contact"),
    choices: &[
        Choice {
            value: ContactModel::Auto,
            code: 0,
            name: "auto",
            description: "enveloping on a road file (OpenCRG, OpenDRIVE), single point on the others (default)",
        },
        Choice { value: ContactModel::Point, code: 1, name: "point", description: "single point (the paper's)" },
        Choice {
            value: ContactModel::Envelope,
            code: 2,
            name: "envelope",
            description: "enveloping: the road averaged over the contact length",
        },
    ],
};

/// The FMU's `tire_convention`: `None` keeps the vehicle file's `tire.convention`.
pub const TIRE_CONVENTIONS: Table<Option<TireConvention>> = Table {
    parameter: "tire_convention",
    option: Some("tire-convention"),
    choices: &[
        Choice { value: None, code: 0, name: "vehicle", description: "as the vehicle file says (`tire.convention`)" },
        Choice {
            value: Some(TireConvention::Mfeval),
            code: 1,
            name: "mfeval",
            description: "the Magic Formula as MFeval computes it",
        },
        Choice {
            value: Some(TireConvention::Chrono),
            code: 2,
            name: "chrono",
            description: "as Project Chrono's Pac02 does (sides swapped, camber ignored, no rolling-resistance \
                          moment on the wheel, slips over the forward speed + 0.1 m/s, combined slip by the friction ellipse)",
        },
    ],
};

pub const ACCURACY_POLICIES: Table<AccuracyPolicy> = Table {
    parameter: "accuracy_policy",
    option: Some("accuracy-policy"),
    choices: &[
        Choice { value: AccuracyPolicy::Refuse, code: 1, name: "refuse", description: "refused with its cause" },
        Choice {
            value: AccuracyPolicy::Warn,
            code: 2,
            name: "warn",
            description: "run on, logging once the error the hop-resolution measurements expect",
        },
    ],
};
