//! The assembled vehicle and its derivative function f(t, x, inputs) (docs/physics.md §4.9).
//!
//! Stages, in order, once per evaluation (`assemble_into`; one file each, docs/architecture.md "One
//! function evaluation"): chassis and rack → positions (Newton) → velocities and γ̄ → forces → contact and
//! tire → brakes → subsystem terms → synthesis, then the accelerations by the selected formulation → state
//! derivative. Each stage loops over the corners and writes its part of `Workspace`. The spatial origin is
//! put at the chassis CM in every evaluation (§4.0), so all positions below are relative to r0.

pub mod brake;
mod chassis;
mod contact;
pub mod equilibrium;
mod forces;
mod kinematics;
mod synthesis;
mod terms;
mod wheel_columns;

pub use chassis::ChassisFrame;
pub use forces::CornerWrenches;
pub use kinematics::{CornerKinematics, BODY_K, BODY_L, BODY_U};
pub use synthesis::accelerations;
use synthesis::synthesis_stage;

use crate::dynamics::body::{ang, lin, wrench};
use crate::dynamics::{AxleTerms, ChassisTerms, SubsystemTerms};
use crate::error::{Cause, ModelError};
use crate::math::{quat_to_matrix, M3, V3};
use crate::model::formats::params::{DataError, Spring, VehicleData};
use crate::model::road::envelope::ContactModel;
use crate::model::road::{EdgeAveraged, Road, RoadModel};
use crate::model::steering::{assembly::Steering, tie_rod_drive};
use crate::model::suspension::antiroll_bar::AxleBar;
use crate::model::suspension::forces::StopCurve;
use crate::model::suspension::solid_axle::steering::{SteerBodyWork, SteerPositions};
use crate::model::suspension::solid_axle::{AxlePositions, AxleQ, SolidAxle};
use crate::model::suspension::{BodyInertia, Corner, CornerPositions, Side};
use crate::model::tire::{SlipModel, TireModel, TireParams};
use nalgebra::Vector6;
use serde::{Deserialize, Serialize};

/// Corner order everywhere: front left, front right, rear left, rear right.
pub const CORNERS: [&str; 4] = ["fl", "fr", "rl", "rr"];

/// State layout (docs/physics.md §7.1): r0, e0 (w, x, y, z), ṙ0, ω0 (ground frame), θ_L and θ̇_L per corner,
/// absolute spin rates Ω (the 25 states every run has), then, when the options need them, the relaxation
/// states (ξ_x, ξ_y) per corner and the speed-hold integral (see `Layout`). `XI`, `ZV` and `DIM` are their
/// places in the full layout (relaxation slip and speed hold, the defaults).
pub mod idx {
    pub const R0: usize = 0;
    pub const E0: usize = 3;
    pub const V0: usize = 7;
    pub const W0: usize = 10;
    pub const U: usize = 13;
    pub const UD: usize = 17;
    pub const SPIN: usize = 21;
    /// The states of every run.
    pub const CORE: usize = 25;
    pub const XI: usize = 25;
    pub const ZV: usize = 33;
    pub const DIM: usize = 34;
}

/// Where the optional states are, decided by the options: the eight relaxation slip states exist only
/// with relaxation slip (steady slip has no slip dynamics), the speed-hold integral only with the speed
/// hold (coasting has no controller). Leaving them out is exact: they would only carry zero derivatives,
/// never read; it saves integrator work.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Layout {
    /// Index of ξ_x of the front-left corner (then ξ_y, then the next corner), if present.
    pub xi: Option<usize>,
    /// Index of the speed-hold integral z_v, if present.
    pub zv: Option<usize>,
    pub dim: usize,
}

impl Layout {
    /// Refuse a state `x` or a derivative `dxdt` whose length is not this layout's (an evaluation's first
    /// test, the whole one's and a corner's alike).
    #[inline(always)]
    pub fn check_lengths(&self, x: &[f64], dxdt: &[f64]) -> Result<(), ModelError> {
        if x.len() != self.dim || dxdt.len() != self.dim {
            return Err(ModelError::new(
                Cause::Input,
                format!(
                    "state of {} and derivative of {} numbers, the layout of these options has {}",
                    x.len(),
                    dxdt.len(),
                    self.dim
                ),
            ));
        }
        Ok(())
    }

    /// A state's name for messages: "roll rate (ω_x)", "wheel spin rl", …
    pub fn state_name(&self, i: usize) -> String {
        let corner = |k: usize| CORNERS[k % 4];
        match i {
            0..=2 => format!("chassis position {}", ["x", "y", "z"][i]),
            3..=6 => format!("chassis attitude (quaternion e{})", i - 3),
            7..=9 => format!("chassis velocity {}", ["v_x", "v_y", "v_z"][i - 7]),
            10..=12 => format!("chassis rate {}", ["ω_x (roll)", "ω_y (pitch)", "ω_z (yaw)"][i - 10]),
            13..=16 => format!("arm angle {}", corner(i - 13)),
            17..=20 => format!("arm rate {}", corner(i - 17)),
            21..=24 => format!("wheel spin {}", corner(i - 21)),
            _ if self.xi.is_some_and(|k| (k..k + 8).contains(&i)) => {
                let j = i - self.xi.unwrap_or(0);
                format!("tread deflection {} {}", ["ξ_x", "ξ_y"][j % 2], corner(j / 2))
            }
            _ if self.zv == Some(i) => "speed-hold integral".to_string(),
            _ => format!("state {i}"),
        }
    }

    /// The full layout (every optional state), whatever the options.
    pub const FULL: Layout = Layout { xi: Some(idx::XI), zv: Some(idx::ZV), dim: idx::DIM };

    pub fn new(slip: SlipModel, speed_mode: SpeedMode) -> Layout {
        let mut dim = idx::CORE;
        let mut take = |n: usize| {
            let at = dim;
            dim += n;
            at
        };
        let xi = (slip == SlipModel::Relaxation).then(|| take(8));
        let zv = (speed_mode == SpeedMode::Hold).then(|| take(1));
        Layout { xi, zv, dim }
    }

    /// The layout a run's options give.
    pub fn of(options: &Options) -> Layout {
        if options.keep_unused_states {
            Layout::FULL
        } else {
            Layout::new(options.slip, options.speed_mode)
        }
    }

    /// The relaxation states of corner i (zero where the layout has none).
    #[inline]
    pub fn xi(&self, x: &[f64], i: usize) -> [f64; 2] {
        self.xi.map_or([0.0; 2], |k| [x[k + 2 * i], x[k + 2 * i + 1]])
    }

    /// `x` (laid out by `from`) in this layout: the common states copied, new ones zero.
    pub fn convert(&self, x: &[f64], from: &Layout) -> Vec<f64> {
        let mut out = vec![0.0; self.dim];
        out[..idx::CORE].copy_from_slice(&x[..idx::CORE]);
        if let (Some(a), Some(b)) = (self.xi, from.xi) {
            out[a..a + 8].copy_from_slice(&x[b..b + 8]);
        }
        if let (Some(a), Some(b)) = (self.zv, from.zv) {
            out[a] = x[b];
        }
        out
    }
}

pub use crate::model::options::{ForceSwitches, Formulation, Options, SpeedMode};

pub use crate::model::steering::RackMotion;

#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Inputs {
    pub rack: RackMotion,
    /// External per-wheel torques (FL, FR, RL, RR), N·m; drive adds to the speed hold, brake ≥ 0.
    pub drive: [f64; 4],
    pub brake: [f64; 4],
    /// The speed hold's target speed, m/s (read with `SpeedMode::Hold` only).
    pub target_speed: f64,
}

/// The last converged dependent coordinates of one corner and their first-order sensitivities, from
/// which the next Newton solve starts: v ≈ v_last + ∂v/∂u Δu + ∂v/∂s Δs (the tangent of the constraint
/// manifold), so Newton starts within O(Δ²) of the solution.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
/// A corner's Newton warm start: the last solution v at (u, s) and its tangent. A solid axle keeps its own in
/// its left wheel's place, with u its heave and s its roll (its v = (x, y, pitch, yaw) has four entries too).
pub struct WarmStart {
    pub v: [f64; 4],
    pub u: f64,
    pub s: f64,
    pub dv_du: [f64; 4],
    pub dv_ds: [f64; 4],
}

impl WarmStart {
    fn predict(&self, u: f64, s: f64) -> [f64; 4] {
        let (du, ds) = (u - self.u, s - self.s);
        std::array::from_fn(|k| self.v[k] + self.dv_du[k] * du + self.dv_ds[k] * ds)
    }
}

/// What the stages of an evaluation write (as MuJoCo's mjData): the Newton warm starts, part of the
/// simulation state (their last bits decide Newton's last bits), then scratch written in place by each
/// evaluation and neither saved nor compared: each stage's part (the file of each stage names it): the corner
/// positions and kinematics, the wrenches, the terms (subsystem
/// stage), the tire loads and the diagnostics (tire and wheel stage).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Workspace {
    pub corners: [WarmStart; 4],
    #[serde(skip)]
    pub positions: [CornerPositions; 4],
    /// The terms of the latest evaluation (scratch, written in place).
    #[serde(skip)]
    pub assembly: Assembly,
    /// The normal load of each tire in the latest evaluation, N (scratch: the error-controlled
    /// integrator's step limit near lift-off reads it, `sim::stepping::step_limit`).
    #[serde(skip)]
    pub tire_loads: [f64; 4],
    /// What the latest evaluation revealed besides ẋ (outputs, events).
    #[serde(skip)]
    pub diagnostics: Diagnostics,
    /// The chassis frame (chassis stage).
    #[serde(skip)]
    pub chassis: ChassisFrame,
    /// The rack's translation s, ṡ, s̈ (chassis stage).
    #[serde(skip)]
    pub rack: RackMotion,
    /// Each corner's bodies' velocity-state kinematics (velocity stage).
    #[serde(skip)]
    pub kinematics: [CornerKinematics; 4],
    /// Each corner's wrenches on its bodies and on the chassis (force, tire and brake stages).
    #[serde(skip)]
    pub wrenches: [CornerWrenches; 4],
    /// Each solid axle's positions and its body's kinematics (positions and velocity stages).
    #[serde(skip)]
    pub axles: [AxleWork; 2],
}

/// A solid axle's part of the workspace: its solved positions, q̇, and its body's velocity-state kinematics
/// in the evaluation's axes (𝔅, 6×6 over q; 𝔇; Y), CM and inertia.
#[derive(Debug, Clone, Copy, Default)]
pub struct AxleWork {
    pub positions: AxlePositions,
    pub qd: AxleQ,
    pub b: nalgebra::SMatrix<f64, 6, 6>,
    pub rate: Vector6<f64>,
    pub velocity: Vector6<f64>,
    pub com: V3,
    pub inertia: M3,
    /// A steered axle's steering positions and the motion of its bellcrank and knuckles (`solid_axle::steering`).
    pub steer: SteerPositions,
    pub steer_bodies: [SteerBodyWork; 3],
}

impl PartialEq for Workspace {
    fn eq(&self, other: &Self) -> bool {
        self.corners == other.corners
    }
}

/// What one evaluation reveals besides ẋ (for outputs and diagnostics).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Diagnostics {
    /// Chassis CM acceleration r̈0 (ground frame, kinematic).
    pub chassis_acceleration: V3,
    /// Chassis angular acceleration ω̇0 (ground frame).
    pub chassis_angular_acceleration: V3,
    pub tire_force: [[f64; 3]; 4],
    pub kappa: [f64; 4],
    /// tan α (the angle itself, an arctangent, is taken only where it is output).
    pub tan_alpha: [f64; 4],
    pub wheel_centre_z: [f64; 4],
    /// Wheel centres' ground x, y (where the road is asked).
    pub wheel_centre_xy: [[f64; 2]; 4],
    pub wheel_spin_relative: [f64; 4],
    pub drive_torque: [f64; 4],
    pub max_residual: f64,
    pub newton_iterations: u32,
    /// Each wheel's contact event indicator (`tire::contact_indicator`; Model Exchange).
    pub contact_indicator: [f64; 4],
    /// Each wheel's signed penetration δ, m: the tire's deflection in contact, minus the clearance in the
    /// air. Its upward zero crossing is a touchdown, where the normal force jumps to c_z δ̇ (the fixed-step
    /// schemes locate it: `integrate::touchdown`).
    pub penetration: [f64; 4],
    /// Each wheel centre's x less the nearest C⁰ edge of the road under the single-point contact (the
    /// paper's bumps: `RoadModel::edge_offset`), m; −1 where its side has none. Written only where
    /// `Run::has_road_edges`, the one place that decides it. Its upward zero crossing is where the tire's
    /// forces jump with the road's slope (RK4 locates it: `integrate::touchdown`).
    pub road_edge: [f64; 4],
}

/// Per-corner force element data (the spring free length is what the ride-height retune changes).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CornerForces {
    pub spring: Spring,
    pub spring_free_length: f64,
    pub damper: crate::model::formats::params::Damper,
}

/// The vehicle model: geometry, inertia, force laws and modes. Immutable during a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Vehicle {
    pub corners: [Corner; 4],
    pub corner_forces: [CornerForces; 4],
    /// The anti-roll bars of the front and rear axles, where the vehicle file gives one.
    #[serde(default)]
    pub antiroll_bars: [Option<AxleBar>; 2],
    /// The front and rear axles that are solid axles (`model::suspension::solid_axle`): their two corners
    /// are the axle's wheels, and the axle is one subsystem of the synthesis with two coordinates, heave and
    /// roll, in the corners' θ_L places (left: heave, m; right: roll, rad; likewise their rates).
    #[serde(default)]
    pub solid_axles: [Option<SolidAxle>; 2],
    pub stops: StopCurve,
    pub chassis: BodyInertia,
    pub steering: Steering,
    pub tire: TireParams,
    pub tire_model: TireModel,
    pub speed_gains: (f64, f64),
    pub gravity: f64,
    pub total_mass: f64,
    /// The driver's seat (`driver_position_m`) relative to the sprung body's CM, chassis axes, m: where the
    /// ride tests measure (studies::ride).
    #[serde(default)]
    pub driver_position: Option<V3>,
    /// The vehicle file's `ride_height` is `data`: the springs as written, no retune (`sim::Start`).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub springs_as_written: bool,
}

/// The road as every run sees it unless it names another: the level plane.
pub static FLAT_ROAD: RoadModel = RoadModel::Flat;

/// What a run hands every evaluation besides the vehicle, the state and the inputs: its options and the
/// road its tires meet, seen through the contact model (a context, as rapier's, instead of a chain of
/// arguments through the derivative's dispatch).
#[derive(Clone, Copy)]
pub struct Run<'a> {
    pub options: &'a Options,
    road: RoadView<'a>,
}

/// The road as the tires see it.
#[derive(Clone, Copy)]
enum RoadView<'a> {
    /// At the point below the wheel (the paper's contact).
    Point(&'a RoadModel),
    /// Averaged over the static contact length (`ContactModel::Envelope`, model::road::envelope).
    Enveloped { road: &'a RoadModel, half_length: f64 },
    /// Rounded at its C⁰ edges by a moving average of `width` (`EdgeAveraged`): for finite differences.
    Rounded { road: &'a RoadModel, width: f64 },
}

impl<'a> RoadView<'a> {
    fn ground(&self) -> &'a RoadModel {
        match *self {
            RoadView::Point(road) | RoadView::Enveloped { road, .. } | RoadView::Rounded { road, .. } => road,
        }
    }
}

impl Road for RoadView<'_> {
    #[inline(always)]
    fn height_and_gradient(&self, x: f64, y: f64) -> (f64, [f64; 2]) {
        match *self {
            RoadView::Point(road) => road.height_and_gradient(x, y),
            RoadView::Enveloped { road, half_length } => {
                crate::model::road::envelope::Enveloped { road, half_length }.height_and_gradient(x, y)
            }
            RoadView::Rounded { road, width } => EdgeAveraged { road, width }.height_and_gradient(x, y),
        }
    }

    fn off_road(&self, x: f64, y: f64) -> Option<String> {
        match *self {
            RoadView::Enveloped { road, half_length } => {
                crate::model::road::envelope::Enveloped { road, half_length }.off_road(x, y)
            }
            RoadView::Point(road) | RoadView::Rounded { road, .. } => road.off_road(x, y),
        }
    }

    fn friction(&self, x: f64, y: f64) -> f64 {
        self.ground().friction(x, y)
    }
}

impl<'a> Run<'a> {
    /// `vehicle` run with `options` on `road`.
    pub fn new(vehicle: &Vehicle, options: &'a Options, road: &'a RoadModel) -> Run<'a> {
        let road = match options.contact.resolve(road) {
            ContactModel::Point | ContactModel::Auto => RoadView::Point(road),
            // The static half contact length at a quarter of the weight on the level.
            ContactModel::Envelope => RoadView::Enveloped {
                road,
                half_length: crate::model::road::envelope::enveloping_half_length(
                    road,
                    vehicle.tire.unloaded_radius_m,
                    vehicle.tire.vertical_stiffness_N_per_m,
                    0.25 * vehicle.total_mass * vehicle.gravity,
                ),
            },
        };
        Run { options, road }
    }

    /// `options` on the level road.
    pub fn flat(vehicle: &Vehicle, options: &'a Options) -> Run<'a> {
        Run::new(vehicle, options, &FLAT_ROAD)
    }

    /// This run on its road rounded at the C⁰ edges (`EdgeAveraged`, 2 mm) and seen at a point: for
    /// finite-difference derivatives, which must not straddle an edge. A run with the enveloping contact
    /// keeps it: the envelope is already smooth (C² over the paper's bumps, a weighted sum of eleven
    /// heights on a grid), and the point road under it is not the road the run meets (a half-round
    /// obstacle's foot has slope 4, whose tangent plane would read a 0.37 m deflection).
    pub fn on_rounded_road(&self) -> Run<'a> {
        match self.road {
            RoadView::Enveloped { .. } => *self,
            _ => Run { options: self.options, road: RoadView::Rounded { road: self.road.ground(), width: 0.002 } },
        }
    }

    /// Whether the run's road has C⁰ edges under its contact (the paper's bumps under the single point):
    /// `Diagnostics::road_edge` then locates them.
    pub fn has_road_edges(&self) -> bool {
        self.options.switches.tires && matches!(self.road, RoadView::Point(RoadModel::Bumps(_)))
    }

    /// Whether a tire's lift-off makes the right-hand side jump: with relaxation slip the tread's law
    /// switches there (in contact L ξ̇ = −V_s − |V_x| ξ, in the air ξ decays with its own time constant:
    /// `tire::slip::relaxation_rates`): RK4 and DOPRI5 then locate it. (The normal force itself
    /// reaches 0 continuously, a kink: with steady slip nothing jumps.) A lift-off is the downward crossing
    /// of `Diagnostics::penetration`.
    pub fn has_lift_off_jumps(&self) -> bool {
        self.options.switches.tires && self.options.slip == SlipModel::Relaxation
    }

    /// The road the run is on (before the contact model).
    pub fn road(&self) -> &'a RoadModel {
        self.road.ground()
    }

    /// The state layout of this run's options.
    pub fn layout(&self) -> Layout {
        Layout::of(self.options)
    }
}

/// The chassis part of the state: attitude A0, CM position r0, velocity ṙ0, angular velocity ω0 (ground).
struct Chassis {
    a0: M3,
    r0: V3,
    v0: V3,
    w0: V3,
}

impl Chassis {
    fn of(x: &[f64]) -> Chassis {
        let a0 = quat_to_matrix(&x[idx::E0..idx::E0 + 4]);
        Chassis { a0, r0: vector_at(x, idx::R0), v0: vector_at(x, idx::V0), w0: vector_at(x, idx::W0) }
    }
}

/// The 3-vector stored at `x[k..k + 3]`.
fn vector_at(x: &[f64], k: usize) -> V3 {
    V3::new(x[k], x[k + 1], x[k + 2])
}

/// The velocity of the point at `rho` of a body of velocity state `y` (same axes).
#[inline(always)]
fn point_velocity(y: &Vector6<f64>, rho: &V3) -> V3 {
    lin(y) + ang(y).cross(rho)
}

/// Unit horizontal heading of the chassis: its x axis projected on the ground plane.
pub fn heading(a0: &M3) -> V3 {
    let h = a0 * V3::x();
    V3::new(h.x, h.y, 0.0).normalize()
}

impl Vehicle {
    /// What axle a (0 front, 1 rear) is in the synthesis.
    #[inline(always)]
    pub fn axle_kind(&self, a: usize) -> AxleKind {
        if self.solid_axles[a].is_some() {
            AxleKind::Solid
        } else if self.corners[2 * a].on_chassis() {
            AxleKind::Rigid
        } else {
            AxleKind::Independent
        }
    }

    pub fn new(data: &VehicleData) -> Result<Vehicle, DataError> {
        data.check()?;
        let axles = [&data.front, &data.front, &data.rear, &data.rear];
        let sides = [Side::Left, Side::Right, Side::Left, Side::Right];
        let drive = tie_rod_drive(data)?;
        let mut corners = Vec::with_capacity(4);
        for i in 0..4 {
            let axle_name = if i < 2 { "front" } else { "rear" };
            corners.push(
                Corner::from_data(data, axles[i], sides[i], drive)
                    .map_err(|e| DataError { field: format!("{axle_name}.{}", e.field), message: e.message })?,
            );
        }
        let corners: [Corner; 4] = corners.try_into().expect("four corners");
        let corner_forces = axles.map(|a| CornerForces {
            spring: a.spring.clone(),
            spring_free_length: a.spring.free_length_m,
            damper: a.damper.clone(),
        });
        // The sprung body: the chassis and what it carries rigidly (strut rods, Pitman arm and link).
        let (sprung_mass, sprung_inertia) = data.sprung_inertia();
        let chassis = BodyInertia { mass: sprung_mass, com: V3::zeros(), inertia: sprung_inertia };
        let steering = Steering::from_data(data);
        let mut solid_axles = [None, None];
        for (k, (name, axle)) in [("front", &data.front), ("rear", &data.rear)].into_iter().enumerate() {
            if axle.template.is_solid_axle() {
                solid_axles[k] = Some(SolidAxle::from_data(data, name, axle)?);
            }
        }
        let total_mass = chassis.mass
            + steering.body.mass
            + corners.iter().map(|c| c.lower.mass + c.upper.mass + c.carrier.mass).sum::<f64>()
            + solid_axles.iter().flatten().map(SolidAxle::mass).sum::<f64>();
        let antiroll_bars =
            [&data.front, &data.rear].map(|a| a.antiroll_bar.as_ref().and_then(|b| AxleBar::new(data, b)));
        let mut v = Vehicle {
            corners,
            corner_forces,
            antiroll_bars,
            solid_axles,
            stops: StopCurve::new(&data.stop_table),
            chassis,
            steering,
            tire: data.tire.clone(),
            tire_model: crate::model::tire::model_for(&data.tire),
            speed_gains: (data.speed_hold.kp_per_s, data.speed_hold.ki_per_s2),
            gravity: data.gravity_m_s2,
            total_mass,
            driver_position: data.driver_position_m.map(|p| V3::from(p) - data.sprung_com()),
            springs_as_written: data.ride_height == crate::model::formats::params::RideHeight::Data,
        };
        if data.tire.tir_file.is_some() && data.tire.magic_formula.is_none() && data.tire.tmeasy.is_none() {
            return Err(DataError {
                field: "tire.tir_file".into(),
                message: "names a tire file that was not read (VehicleData::use_tire_file)".into(),
            });
        }
        // The Magic Formula's relaxation lengths depend on the load; the slip states use them at the static
        // load of an average corner (docs/tire.md, "Magic Formula": what is left out).
        if let Some(mf) = data.tire.magic_formula.as_ref().filter(|mf| mf.has_relaxation()) {
            let [x, y] = mf.relaxation_lengths(0.25 * total_mass * data.gravity_m_s2);
            if !(x > 0.0 && y > 0.0) {
                return Err(DataError {
                    field: "tire.tir_file".into(),
                    message: format!(
                        "{}: relaxation lengths {x} m, {y} m at the static load are not positive",
                        mf.source
                    ),
                });
            }
            v.tire.relaxation_length_x_m = x;
            v.tire.relaxation_length_y_m = y;
        }
        v.steering.sign = if v
            .steering_gain_per_rack_metre()
            .map_err(|e| DataError { field: "front.hardpoints_chassis_frame_m".into(), message: e.to_string() })?
            < 0.0
        {
            -1.0
        } else {
            1.0
        };
        Ok(v)
    }

    /// ∂δ̄/∂s at design (mean of the two front wheels), rad per metre of rack translation along +y_C.
    pub fn steering_gain_per_rack_metre(&self) -> Result<f64, ModelError> {
        let h = 1e-5;
        let mean = |s: f64| -> Result<f64, ModelError> {
            if let Some(angles) = self.steered_axle_angles(0, s)? {
                return Ok(0.5 * (angles[0] + angles[1]));
            }
            let mut sum = 0.0;
            for c in &self.corners[0..2] {
                let p = c.solve_positions(0.0, s, &[0.0; 4])?;
                sum += c.steer_angle(&p);
            }
            Ok(0.5 * sum)
        };
        Ok((mean(h)? - mean(-h)?) / (2.0 * h))
    }

    /// A steered solid axle's wheels' steer angles (left, right) at design heave and roll and steering
    /// coordinate s; `None` when axle a is not one.
    pub fn steered_axle_angles(&self, a: usize, s: f64) -> Result<Option<[f64; 2]>, ModelError> {
        let Some(solid) = &self.solid_axles[a] else { return Ok(None) };
        let Some(steering) = &solid.steering else { return Ok(None) };
        let pos = solid.linkage.solve_positions([0.0, 0.0], &[0.0; 4])?;
        let st = steering.solve(&solid.linkage, &pos, s, &nalgebra::Vector3::zeros())?;
        let angles = [0, 1].map(|k| {
            let mut w = CornerPositions::default();
            solid.place_steered_wheel(steering, &pos, &st, k, &mut w);
            self.corners[2 * a + k].steer_angle(&w)
        });
        Ok(Some(angles))
    }

    /// Steering coordinate for corner i (rear toe links ignore it).
    fn rack_translation(&self, i: usize, u: f64) -> f64 {
        if self.corners[i].steered() {
            self.steering.sign * u
        } else {
            0.0
        }
    }

    /// Solve the dependent coordinates of every corner (updates the warm starts); a copy of the positions.
    pub fn corner_positions(
        &self,
        x: &[f64],
        rack_u: f64,
        cache: &mut Workspace,
    ) -> Result<[CornerPositions; 4], ModelError> {
        self.solve_corners(x, rack_u, cache)?;
        Ok(cache.positions.clone())
    }

    /// The derivative function: writes ẋ, updates the warm starts and fills the workspace (terms,
    /// diagnostics). No heap allocation.
    pub fn derivative(
        &self,
        run: &Run,
        x: &[f64],
        inputs: &Inputs,
        ws: &mut Workspace,
        dxdt: &mut [f64],
    ) -> Result<(), ModelError> {
        #[cfg(target_arch = "x86_64")]
        if crate::simd::avx2_fma() {
            // SAFETY: the CPU has AVX2 and FMA, checked at run time.
            return unsafe { self.derivative_avx2_fma(run, x, inputs, ws, dxdt) };
        }
        self.derivative_any_cpu(run, x, inputs, ws, dxdt)
    }

    /// `derivative` on the baseline x86-64 code whatever the CPU (tests compare it with the dispatched one).
    #[cfg(any(test, feature = "test-support"))]
    pub fn derivative_portable(
        &self,
        run: &Run,
        x: &[f64],
        inputs: &Inputs,
        ws: &mut Workspace,
        dxdt: &mut [f64],
    ) -> Result<(), ModelError> {
        self.derivative_any_cpu(run, x, inputs, ws, dxdt)
    }

    /// The evaluation compiled for AVX2 and FMA: everything it calls in the hot path is `#[inline(always)]`
    /// so that it is compiled here again with these features (a `target_feature` does not reach callees).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn derivative_avx2_fma(
        &self,
        run: &Run,
        x: &[f64],
        inputs: &Inputs,
        ws: &mut Workspace,
        dxdt: &mut [f64],
    ) -> Result<(), ModelError> {
        self.derivative_any_cpu(run, x, inputs, ws, dxdt)
    }

    #[inline(always)]
    fn derivative_any_cpu(
        &self,
        run: &Run,
        x: &[f64],
        inputs: &Inputs,
        ws: &mut Workspace,
        dxdt: &mut [f64],
    ) -> Result<(), ModelError> {
        run.layout().check_lengths(x, dxdt)?;
        self.assemble_into(run, x, inputs, ws)?;
        self.acceleration_stage(run, x, inputs, ws, dxdt) // synthesis.rs
    }

    /// Everything before the equation solving (§4.9 steps 1–3e): kinematics, forces and the chassis and
    /// subsystem terms, shared by every formulation. The terms are in the chassis axes (`ChassisAxes`): every
    /// vector of the equations turned by A0ᵀ at this instant, which leaves the equations as they are and
    /// spares turning the chassis-fixed suspension data; Ẏ0 comes out in the same axes.
    pub fn assemble(&self, run: &Run, x: &[f64], inputs: &Inputs, ws: &mut Workspace) -> Result<Assembly, ModelError> {
        self.assemble_into(run, x, inputs, ws)?;
        Ok(ws.assembly)
    }

    /// `assemble` writing the workspace only, as the list of its stages (docs/architecture.md, "One function
    /// evaluation"; as MuJoCo's mj_fwdPosition → mj_fwdVelocity → …). Each reads the vehicle, the run, the
    /// state and inputs and what the stages before it wrote, and writes its part of the workspace; the file
    /// beside each names it.
    #[inline(always)]
    fn assemble_into(&self, run: &Run, x: &[f64], inputs: &Inputs, ws: &mut Workspace) -> Result<(), ModelError> {
        self.chassis_stage(run, x, inputs, ws); // chassis.rs: frame, chassis and rack terms, drive torques
        self.solve_corners(x, inputs.rack.position, ws)?; // kinematics.rs: positions (Newton)
        self.velocity_stage(x, ws); // kinematics.rs: q̇, γ̄, the bodies' B, D and velocities
        self.force_stage(run, x, ws)?; // forces.rs: bodies, springs, dampers, anti-roll bars, drive
        self.tire_stage(run, x, ws)?; // contact.rs: contact, slip, tire forces, relaxation rates
        self.brake_stage(inputs, ws); // brake.rs: the brakes, the wheels' spin torques
        self.subsystem_terms_stage(ws); // terms.rs: each subsystem's effective terms
        synthesis_stage(ws); // synthesis.rs: the corners' reactions summed on the chassis
        Ok(())
    }
}
/// What an axle is in the synthesis: two corner subsystems, one solid-axle subsystem, or none (a rigid
/// suspension: the wheels on the chassis).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum AxleKind {
    #[default]
    Independent,
    Solid,
    Rigid,
}

/// The terms of one evaluation, before the equation solving.
#[derive(Debug, Clone, Copy, Default)]
pub struct Assembly {
    pub chassis: ChassisTerms,
    /// Each corner's terms (a solid axle's wheels' are not used).
    pub terms: [SubsystemTerms; 4],
    /// Each solid axle's terms, and what each axle is (the formulations take a solid axle as one subsystem
    /// in place of two corners, and a rigid one as none: its wheels' wrenches are on the chassis's terms).
    pub axle_terms: [AxleTerms; 2],
    pub kinds: [AxleKind; 2],
    /// a·M_W + T_d − T_b per wheel: I_s Ω̇ (§4.8).
    pub spin_torque: [f64; 4],
    pub relaxation_rates: [[f64; 2]; 4],
    /// Chassis speed along its horizontal heading (the speed hold's V_x).
    pub heading_speed: f64,
}

/// Momenta and energies of the whole system (for conservation tests and diagnostics).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MechanicalSummary {
    /// Σ m ṙ, ground frame.
    pub linear_momentum: V3,
    /// About the ground origin, including the wheel spin I_s Ω a.
    pub angular_momentum: V3,
    pub kinetic_energy: f64,
    /// Gravity and spring potential (stops excluded: switch them off to test energy).
    pub potential_energy: f64,
}

impl Vehicle {
    pub fn mechanical_summary(
        &self,
        options: &Options,
        x: &[f64],
        rack: &RackMotion,
        cache: &mut Workspace,
    ) -> Result<MechanicalSummary, ModelError> {
        let Chassis { a0, r0, v0, w0 } = Chassis::of(x);
        let y0 = wrench(&v0, &w0);
        let g = options.gravity_vector(self.gravity);
        let mut p = V3::zeros();
        let mut h = V3::zeros();
        let mut t = 0.0;
        let mut v = 0.0;
        let mut add_body = |m: f64, rho: &V3, j: &M3, rdot: &V3, w: &V3| {
            let r = r0 + rho;
            p += rdot * m;
            h += r.cross(&(rdot * m)) + j * w;
            t += 0.5 * m * rdot.norm_squared() + 0.5 * w.dot(&(j * w));
            v -= m * g.dot(&r);
        };
        let j0 = a0 * self.chassis.inertia * a0.transpose();
        add_body(self.chassis.mass, &V3::zeros(), &j0, &v0, &w0);
        let s = self.steering.translation(rack);
        let sd = s.velocity;
        let (rho_r, rdot_r, j_r) = self.steering.state(&a0, &v0, &w0, &s);
        add_body(self.steering.body.mass, &rho_r, &j_r, &rdot_r, &w0);
        let positions = self.corner_positions(x, rack.position, cache)?;
        // A solid axle's body (its wheels' corners have no mass of their own).
        for (a, solid) in self.solid_axles.iter().enumerate() {
            let Some(solid) = solid else { continue };
            let pos = &cache.axles[a].positions;
            let qd = solid.linkage.velocities(pos, [x[idx::UD + 2 * a], x[idx::UD + 2 * a + 1]]);
            let (c, rot) = (solid.linkage.point(pos, &solid.body.com), a0 * pos.rotation);
            let w = w0 + a0 * solid.linkage.angular_velocity(pos, &qd);
            let rdot = v0 + w0.cross(&(a0 * c)) + a0 * solid.linkage.point_velocity(pos, &qd, &solid.body.com);
            add_body(solid.body.mass, &(a0 * c), &(rot * solid.body.inertia * rot.transpose()), &rdot, &w);
            if let Some(steering) = &solid.steering {
                let st = &cache.axles[a].steer;
                let zd = steering.rates(st, &qd, sd);
                for (j, body) in steering.bodies.iter().enumerate() {
                    let c = steering.body_point(&solid.linkage, pos, st, j, &body.com);
                    let (v_rel, w_rel) = steering.relative_motion(&solid.linkage, pos, st, &qd, &zd, j);
                    let rot = a0 * steering.body_rotation(pos, st, j);
                    let rdot = v0 + w0.cross(&(a0 * c)) + a0 * v_rel;
                    add_body(body.mass, &(a0 * c), &(rot * body.inertia * rot.transpose()), &rdot, &(w0 + a0 * w_rel));
                }
            }
        }
        let mut spin_terms = Vec::new();
        let mut spring_potential = 0.0;
        for i in 0..4 {
            let c = &self.corners[i];
            let pos = &positions[i];
            let qd = c.velocities(pos, x[idx::UD + i], if c.steered() { sd } else { 0.0 });
            let k = self.corner_kinematics(i, pos, &qd, &a0, &y0);
            for b in 0..3 {
                let w = ang(&k.velocity[b]);
                let rdot = lin(&k.velocity[b]) + w.cross(&k.com[b]);
                add_body(k.mass[b], &k.com[b], &k.inertia[b], &rdot, &w);
            }
            spin_terms.push((k.axle, x[idx::SPIN + i], c.spin_inertia));
            if options.switches.springs && c.has_line_elements() {
                let f = &self.corner_forces[i];
                let length = (c.mount_point(pos, &c.spring) - c.spring.chassis).norm();
                let xs = length - f.spring_free_length;
                spring_potential += match &f.spring.curve {
                    None => {
                        let (k1, k3) = (f.spring.k1_N_per_m.unwrap_or(0.0), f.spring.k3_N_per_m3.unwrap_or(0.0));
                        0.5 * k1 * xs * xs + 0.25 * k3 * xs.powi(4)
                    }
                    Some(curve) => crate::model::suspension::forces::curve_energy(curve, xs),
                };
            }
        }
        if options.switches.springs {
            for (axle, bar) in self.antiroll_bars.iter().enumerate() {
                if let Some(bar) = bar {
                    let (l, r) = (2 * axle, 2 * axle + 1);
                    let arms = bar.angles([&self.corners[l], &self.corners[r]], [&positions[l], &positions[r]])?;
                    spring_potential += bar.potential(&arms);
                }
            }
            for (a, solid) in self.solid_axles.iter().enumerate() {
                let Some((solid, bar)) = solid.as_ref().and_then(|s| Some((s, s.bar.as_ref()?))) else { continue };
                if let Some(arms) = solid.bar_arms(&cache.axles[a].positions)? {
                    spring_potential += bar.potential(&arms);
                }
            }
        }
        v += spring_potential;
        for (axle, spin, is) in spin_terms {
            h += axle * (is * spin);
            t += 0.5 * is * spin * spin;
        }
        Ok(MechanicalSummary { linear_momentum: p, angular_momentum: h, kinetic_energy: t, potential_energy: v })
    }
}
