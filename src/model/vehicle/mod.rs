//! The assembled vehicle and its derivative function f(t, x, inputs) (docs/physics.md §4.9).
//!
//! Stages, in order, once per evaluation: chassis and rack → for each corner: dependent coordinates
//! (Newton), velocities and γ̄, global (Bae–Haug velocity-state) kinematics, forces, subsystem terms →
//! accelerations by the selected formulation → state derivative. The spatial origin is put at the
//! chassis CM in every evaluation (§4.0), so all positions below are relative to r0.

pub mod brake;
pub mod equilibrium;

use crate::dynamics::body::{ang, body_force, lin, mass_hat, mass_hat_times, point_force, wrench, MassHatSum};
use crate::dynamics::{self, Accelerations, ChassisTerms, Multipliers, PhiVSolved, SubsystemTerms};
use crate::error::{Cause, Context, ModelError};
use crate::math::{quat_rate, quat_to_matrix, skew, Axes, ChassisAxes, M3, V3};
use crate::model::formats::params::{DataError, Spring, VehicleData};
use crate::model::road::envelope::ContactModel;
use crate::model::road::{EdgeAveraged, Road, RoadModel};
use crate::model::steering::{assembly::Steering, tie_rod_drive};
use crate::model::suspension::antiroll_bar::AxleBar;
use crate::model::suspension::forces::{damper_force, spring_force, StopCurve};
use crate::model::suspension::{BodyInertia, Corner, CornerPositions, LineMount, MountBody, Side, Vector5f};
use crate::model::tire::{self, SlipModel, TireModel, TireParams};
use nalgebra::{SMatrix, Vector4, Vector6};
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
/// evaluation and neither saved nor compared: the corner positions (kinematics stage), the terms (subsystem
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

/// Unit horizontal heading of the chassis: its x axis projected on the ground plane.
pub fn heading(a0: &M3) -> V3 {
    let h = a0 * V3::x();
    V3::new(h.x, h.y, 0.0).normalize()
}

impl Vehicle {
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
        let total_mass = chassis.mass
            + steering.body.mass
            + corners.iter().map(|c| c.lower.mass + c.upper.mass + c.carrier.mass).sum::<f64>();
        let antiroll_bars = [&data.front, &data.rear].map(|a| a.antiroll_bar.as_ref().map(|b| AxleBar::new(data, b)));
        let mut v = Vehicle {
            corners,
            corner_forces,
            antiroll_bars,
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
            let mut sum = 0.0;
            for c in &self.corners[0..2] {
                let p = c.solve_positions(0.0, s, &[0.0; 4])?;
                sum += c.steer_angle(&p);
            }
            Ok(0.5 * sum)
        };
        Ok((mean(h)? - mean(-h)?) / (2.0 * h))
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

    /// Solve the dependent coordinates of every corner into `cache.positions` (in place) from the warm
    /// starts, and update the warm starts.
    #[inline(always)]
    pub fn solve_corners(&self, x: &[f64], rack_u: f64, cache: &mut Workspace) -> Result<(), ModelError> {
        for i in 0..4 {
            let s = self.rack_translation(i, rack_u);
            let c = &self.corners[i];
            let u = x[idx::U + i];
            let guess = cache.corners[i].predict(u, s);
            let p = &mut cache.positions[i];
            c.solve_positions_into(u, s, &guess, p)
                .map_err(|e| ModelError::new(Cause::MechanismRange, format!("corner {}: {e}", CORNERS[i])))?;
            // The tangent of the constraint manifold at the solution: the next solve's start.
            cache.corners[i] =
                WarmStart { v: [p.q[1], p.q[2], p.q[3], p.q[4]], u, s, dv_du: p.dv_du.into(), dv_ds: p.dv_ds.into() };
        }
        Ok(())
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
        let layout = run.layout();
        if x.len() != layout.dim || dxdt.len() != layout.dim {
            return Err(ModelError::new(
                Cause::Input,
                format!(
                    "state of {} and derivative of {} numbers, the layout of these options has {}",
                    x.len(),
                    dxdt.len(),
                    layout.dim
                ),
            ));
        }
        self.assemble_into(run, x, inputs, ws)?;
        ws.tire_loads = ws.diagnostics.tire_force.map(|f| f[2]);
        let assembly = &ws.assembly;
        // λ feeds neither ẋ nor any output: never computed here (dynamics::Multipliers::Compute gives it).
        let acc = accelerations(run.options.formulation, assembly, Multipliers::Skip)?;

        // State derivative (§4.9 step 7): r̈0 = Ẏ0,lin + ω0 × ṙ0 (ρ0 = 0), ω̇0 = Ẏ0,ang, with Ẏ0 turned from
        // the chassis axes the terms were assembled in to the ground's.
        let (v0, w0) = (vector_at(x, idx::V0), vector_at(x, idx::W0));
        let a0 = quat_to_matrix(&x[idx::E0..idx::E0 + 4]);
        let rdd = a0 * lin(&acc.chassis) + w0.cross(&v0);
        let wd = a0 * ang(&acc.chassis);
        let ed = quat_rate(&x[idx::E0..idx::E0 + 4], &w0);
        for k in 0..3 {
            dxdt[idx::R0 + k] = v0[k];
            dxdt[idx::V0 + k] = rdd[k];
            dxdt[idx::W0 + k] = wd[k];
        }
        dxdt[idx::E0..idx::E0 + 4].copy_from_slice(&ed);
        for i in 0..4 {
            dxdt[idx::U + i] = x[idx::UD + i];
            dxdt[idx::UD + i] = acc.q_ddot[i][0];
            dxdt[idx::SPIN + i] = assembly.spin_torque[i] / self.corners[i].spin_inertia;
            if let Some(k) = layout.xi {
                dxdt[k + 2 * i] = assembly.relaxation_rates[i][0];
                dxdt[k + 2 * i + 1] = assembly.relaxation_rates[i][1];
            }
        }
        if let Some(k) = layout.zv {
            dxdt[k] = match run.options.speed_mode {
                SpeedMode::Hold => inputs.target_speed - assembly.heading_speed,
                SpeedMode::Coast => 0.0, // only in the full layout (`keep_unused_states`)
            };
        }
        if !dxdt.iter().all(|v| v.is_finite()) {
            return Err(ModelError::new(Cause::NonFinite, "non-finite state derivative"));
        }
        ws.diagnostics.chassis_acceleration = rdd;
        ws.diagnostics.chassis_angular_acceleration = wd;
        Ok(())
    }

    /// Everything before the equation solving (§4.9 steps 1–3e): kinematics, forces and the chassis and
    /// subsystem terms, shared by every formulation. The terms are in the chassis axes (`ChassisAxes`): every
    /// vector of the equations turned by A0ᵀ at this instant, which leaves the equations as they are and
    /// spares turning the chassis-fixed suspension data; Ẏ0 comes out in the same axes.
    pub fn assemble(&self, run: &Run, x: &[f64], inputs: &Inputs, ws: &mut Workspace) -> Result<Assembly, ModelError> {
        self.assemble_into(run, x, inputs, ws)?;
        Ok(ws.assembly)
    }

    /// `assemble` writing the workspace only: the kinematics (`positions`), the tire and wheel stage
    /// (`diagnostics`) and the terms (`assembly`).
    #[inline(always)]
    fn assemble_into(&self, run: &Run, x: &[f64], inputs: &Inputs, ws: &mut Workspace) -> Result<(), ModelError> {
        let Chassis { a0, r0, v0, w0 } = Chassis::of(x);
        let g = run.options.gravity_vector(self.gravity);
        // The chassis velocities and gravity in the chassis axes, the terms' axes.
        let (a0t, axes) = (a0.transpose(), ChassisAxes);
        let y0 = wrench(&(a0t * v0), &(a0t * w0));
        let g_chassis = a0t * g;

        // Chassis (ρ0 = 0 after the origin shift) and rack (§4.7).
        let j0 = &self.chassis.inertia;
        let mut chassis_mass = mass_hat(self.chassis.mass, &V3::zeros(), j0);
        let mut chassis_force = body_force(self.chassis.mass, &V3::zeros(), j0, &ang(&y0), &lin(&y0), &g_chassis);
        let rack = &inputs.rack;
        let s = self.steering.translation(rack);
        let (sd, sdd) = (s.velocity, s.acceleration);
        if self.steering.has_moving_body() {
            let (rack_mass, rack_force) = self.steering.chassis_terms(&axes, &y0, &g_chassis, &s);
            chassis_mass += rack_mass;
            chassis_force += rack_force;
        }

        // Speed hold: T_d = m R0 [kp (V* − Vx) + ki z_v], split equally (§8.2). Vx is the speed along the
        // horizontal heading (not the pitched body x axis), so that steady rolling with the static pitch
        // is an exact equilibrium; on a flat road the two differ by V(1 − cos θ) ≈ 1e-5 m/s.
        let vx_body = heading(&a0).dot(&v0);
        let layout = run.layout();
        let hold_torque = match (run.options.speed_mode, layout.zv) {
            (SpeedMode::Hold, Some(zv)) => {
                let (kp, ki) = self.speed_gains;
                let error = inputs.target_speed - vx_body;
                self.total_mass * self.tire.unloaded_radius_m * (kp * error + ki * x[zv]) / 4.0
            }
            _ => 0.0,
        };

        self.solve_corners(x, rack.position, ws)?;
        // The bars' generalized forces (§5.4); out of line, so that a vehicle without one pays one test.
        let mut bar_forces = [0.0; 4];
        if self.antiroll_bars.iter().any(Option::is_some) {
            self.antiroll_bar_forces(run.options, x, &ws.positions, &mut bar_forces)?;
        }
        let chassis = ChassisStage { run, a0, r0, y0, g: g_chassis };
        // Each corner writes its terms in place (no array built and then moved).
        let Workspace { positions, assembly, diagnostics: local, .. } = ws;
        *local = Diagnostics::default();
        for i in 0..4 {
            let c = &self.corners[i];
            let pos = &positions[i];
            let s_i = if c.steered() { sd } else { 0.0 };
            let sdd_i = if c.steered() { sdd } else { 0.0 };
            let qd = c.velocities(pos, x[idx::UD + i], s_i);
            let gamma_bar = c.gamma_bar(pos, &qd, s_i, sdd_i);
            local.max_residual = local.max_residual.max(pos.residual);
            local.newton_iterations += pos.iterations;
            let drive = hold_torque + inputs.drive[i];
            local.drive_torque[i] = drive;
            let state = WheelState {
                spin: x[idx::SPIN + i],
                xi: layout.xi(x, i),
                drive_torque: drive,
                brake_torque: inputs.brake[i],
            };
            let motion = CornerMotion { positions: pos, qd, gamma_bar, bar_force: bar_forces[i] };
            let wheel = self.corner_terms(&chassis, i, &motion, &state, local, &mut assembly.terms[i])?;
            chassis_force += wheel.chassis_wrench;
            assembly.spin_torque[i] = wheel.spin_torque;
            assembly.relaxation_rates[i] = wheel.relaxation_rates;
        }
        assembly.chassis = ChassisTerms { mass: chassis_mass, force: chassis_force };
        assembly.heading_speed = vx_body;
        Ok(())
    }

    /// The anti-roll bars' generalized forces on each corner's θ_L (§5.4), from the solved positions and θ̇_L
    /// of both corners of each axle; zero where an axle has no bar.
    #[inline(never)]
    fn antiroll_bar_forces(
        &self,
        options: &Options,
        x: &[f64],
        positions: &[CornerPositions; 4],
        out: &mut [f64; 4],
    ) -> Result<(), ModelError> {
        for (axle, bar) in self.antiroll_bars.iter().enumerate() {
            let Some(bar) = bar else { continue };
            let (l, r) = (2 * axle, 2 * axle + 1);
            let arms = bar.angles([&self.corners[l], &self.corners[r]], [&positions[l], &positions[r]])?;
            let theta_dot = [x[idx::UD + l], x[idx::UD + r]];
            let [ql, qr] = bar.generalized_forces(&arms, theta_dot, options.switches.springs, options.switches.dampers);
            (out[l], out[r]) = (ql, qr);
        }
        Ok(())
    }

    /// Kinematics, forces and the subsystem terms of corner i (§3.4, §4.2, §5, §6) in the chassis axes, from
    /// the chassis stage's `ChassisStage` and the corner's solved `CornerMotion`.
    #[inline(always)]
    fn corner_terms(
        &self,
        chassis: &ChassisStage,
        i: usize,
        motion: &CornerMotion,
        wheel: &WheelState,
        diag: &mut Diagnostics,
        terms: &mut SubsystemTerms,
    ) -> Result<CornerOutput, ModelError> {
        let ChassisStage { run, a0, r0, y0, g } = chassis;
        let (road, options) = (&run.road, run.options);
        let CornerMotion { positions: pos, qd, gamma_bar, bar_force } = motion;
        let bar_force = *bar_force;
        let WheelState { spin, xi, drive_torque, brake_torque } = *wheel;
        let c = &self.corners[i];
        let (v0, w0) = (lin(y0), ang(y0));
        let k = self.corner_kinematics(i, pos, qd, &ChassisAxes, y0);
        let [y_l, y_k, _] = k.velocity;
        let point_velocity = |y: &Vector6<f64>, rho: &V3| lin(y) + ang(y).cross(rho);
        let w_k = ang(&y_k);
        let body_wrench = |b: usize| {
            let (m, rho, j, y) = (k.mass[b], k.com[b], k.inertia[b], k.velocity[b]);
            body_force(m, &rho, &j, &ang(&y), &point_velocity(&y, &rho), g)
        };
        let mut q_l = body_wrench(BODY_L);
        let mut q_k = body_wrench(BODY_K);
        let q_u = body_wrench(BODY_U);
        let mut chassis_wrench = Vector6::zeros();

        // Spring, stops and damper between the chassis and the lower arm or the upright (§5.2–5.3).
        let f = &self.corner_forces[i];
        let mut line_element = |mount: &LineMount, kind: LineElement| {
            let rho_c = mount.chassis;
            let rho_a = c.mount_point(pos, mount);
            let y_a = match mount.body {
                MountBody::LowerArm => &y_l,
                MountBody::Carrier => &y_k,
            };
            let dvec = rho_a - rho_c;
            let length = dvec.norm();
            let e = dvec / length;
            let magnitude = match kind {
                LineElement::Spring => {
                    let stops = options.switches.stops.then_some(&self.stops);
                    spring_force(&f.spring, f.spring_free_length, stops, length)
                }
                LineElement::Damper => {
                    let rate = e.dot(&(point_velocity(y_a, &rho_a) - (v0 + w0.cross(&rho_c))));
                    damper_force(&f.damper, length, rate)
                }
            };
            match mount.body {
                MountBody::LowerArm => q_l += point_force(&(e * magnitude), &rho_a),
                MountBody::Carrier => q_k += point_force(&(e * magnitude), &rho_a),
            }
            chassis_wrench += point_force(&(-e * magnitude), &rho_c);
        };
        if options.switches.springs {
            line_element(&c.spring, LineElement::Spring);
        }
        if options.switches.dampers {
            line_element(&c.shock, LineElement::Damper);
        }
        // The anti-roll bar's generalized force on θ_L: a torque about the lower arm's hinge, its reaction on
        // the chassis (§5.4). Skipped when zero, so that a vehicle without a bar computes what it did.
        if bar_force != 0.0 {
            let torque = ang(&k.b_l) * bar_force;
            q_l += wrench(&V3::zeros(), &torque);
            chassis_wrench -= wrench(&V3::zeros(), &torque);
        }

        // Wheel: tire on the road, spin decoupled exactly (§4.8, §6).
        let axle = k.axle;
        let spin_rel = spin - axle.dot(&w_k);
        let rho_w = k.wheel_centre;
        chassis_wrench += wrench(&V3::zeros(), &(-axle * drive_torque));
        q_k += wrench(&V3::zeros(), &(-w_k.cross(&axle) * (c.spin_inertia * spin)));
        // Torque about the spin axis from everything but the brake: the drive, then the tire.
        let mut free_torque = drive_torque;
        let mut relaxation_rates = [0.0; 2];
        // The road is in the ground axes: the tire works there, on the wheel turned by A0, and its loads are
        // turned back.
        let centre_abs = a0 * rho_w + r0;
        if run.has_road_edges() {
            diag.road_edge[i] = road.ground().edge_offset(centre_abs.x, centre_abs.y).unwrap_or(-1.0);
        }
        let axle_ground = a0 * axle;
        diag.wheel_centre_z[i] = centre_abs.z;
        diag.wheel_spin_relative[i] = spin_rel;
        diag.wheel_centre_xy[i] = [centre_abs.x, centre_abs.y];
        let contact = if options.switches.tires {
            tire::contact(road, &centre_abs, &axle_ground, self.tire.unloaded_radius_m)
        } else {
            None
        };
        // Beyond a road file's defined area the road's height is NaN (no surface is invented there): the
        // check costs nothing until then, and the road names what the wheel left.
        if contact.as_ref().is_some_and(|ct| ct.penetration.is_nan()) {
            let off = road.off_road(centre_abs.x, centre_abs.y).unwrap_or_else(|| {
                format!("the road has no surface at x = {:.2} m, y = {:.2} m", centre_abs.x, centre_abs.y)
            });
            return Err(ModelError::new(Cause::PhysicalEvent, format!("wheel {} left the road: {off}", CORNERS[i])));
        }
        match contact {
            Some(ct) if ct.penetration > tire::BOTTOMING_FRACTION * self.tire.unloaded_radius_m => {
                // The single point's tangent plane on an obstacle's steep face reads a deflection the road
                // below the wheel centre does not give (a 10 cm half-round's foot has slope 4): that is the
                // contact's geometry, not the obstacle's height, and the enveloping contact follows it.
                let (h, [hx, hy]) = road.height_and_gradient(centre_abs.x, centre_abs.y);
                let below = self.tire.unloaded_radius_m - (centre_abs.z - h);
                if matches!(road, RoadView::Point(_)) && below <= tire::BOTTOMING_FRACTION * self.tire.unloaded_radius_m
                {
                    return Err(ModelError::new(
                        Cause::ModelValidity,
                        format!(
                            "wheel {} at x = {:.3} m: the single-point contact reads a tire deflection of {:.3} m \
                             from the road's tangent plane below the wheel centre, whose slope is {:.2} (a steep \
                             face, such as an obstacle's), where the road's height below the centre deflects it by \
                             {:.3} m: the point contact cannot follow an obstacle shorter than the tire; \
                             use the enveloping contact (`--contact envelope`, FMU parameter `contact` = 2)",
                            CORNERS[i],
                            centre_abs.x,
                            ct.penetration,
                            hx.hypot(hy),
                            below
                        ),
                    ));
                }
                return Err(ModelError::new(
                    Cause::ModelValidity,
                    format!(
                        "wheel {} at x = {:.3} m: tire deflection {:.3} m is more than {} of its radius {:.3} m: the \
                         rim would strike the road, which the single-contact tire does not model (an obstacle \
                         taller than the tire envelops, or a hard landing)",
                        CORNERS[i],
                        centre_abs.x,
                        ct.penetration,
                        tire::BOTTOMING_FRACTION,
                        self.tire.unloaded_radius_m
                    ),
                ));
            }
            Some(ct) => {
                let v_c = a0 * point_velocity(&y_k, &(a0.tr_mul(&(ct.point - r0))));
                let penetration_rate = tire::penetration_rate(&ct, &v_c);
                let fz = tire::normal_force(&self.tire, ct.penetration, penetration_rate);
                diag.contact_indicator[i] = tire::contact_indicator(&self.tire, ct.penetration, penetration_rate);
                diag.penetration[i] = ct.penetration;
                let friction = options.road_friction * road.friction(ct.point.x, ct.point.y);
                let slip = tire::slip_velocities(&self.tire, &ct, &v_c, spin_rel);
                // 1 when rolling above the low-speed range (the model of §6.7 exactly), 0 at standstill.
                let blend = tire::low_speed_blend(&self.tire, slip.vx);
                let (kappa, tan_alpha) = match options.slip {
                    SlipModel::Relaxation => {
                        let context = tire::SlipStateContext {
                            in_contact: true,
                            blend,
                            sliding_limit: tire::sliding_limits(&self.tire, fz, friction),
                        };
                        relaxation_rates =
                            tire::relaxation_rates(&self.tire, slip.vx, slip.vsx, slip.vsy, xi, &context);
                        tire::damped_slip(&self.tire, fz, xi, &slip, blend)
                    }
                    SlipModel::Steady if blend < 1.0 => {
                        return Err(ModelError::new(
                            Cause::ModelValidity,
                            format!(
                                "wheel {}: forward speed {:.3} m/s is below {} m/s, where steady slip does not \
                             hold (it divides by \
                             the speed); use relaxation slip (slip_model = 1), which covers standstill",
                                CORNERS[i],
                                slip.vx.abs(),
                                self.tire.low_speed_blend_m_s[1]
                            ),
                        ))
                    }
                    SlipModel::Steady => tire::steady_slip(&self.tire, slip.vx, slip.vsx, slip.vsy),
                };
                // Camber thrust and aligning moment build up by rolling: faded out at standstill (b = 0),
                // where they would push and twist a parked car.
                let side = if i.is_multiple_of(2) { tire::TireSide::Left } else { tire::TireSide::Right };
                let [kappa_f, tan_alpha_f] = tire::evaluated_slips(&self.tire, kappa, tan_alpha, slip.vx);
                let input = tire::SlipInput {
                    fz,
                    kappa: kappa_f,
                    tan_alpha: tan_alpha_f,
                    inclination: ct.inclination * blend,
                    side,
                    blend,
                    friction,
                };
                let shear = tire::shear_forces(self.tire_model, &self.tire, &input);
                let moments = [shear.mx * blend, shear.mz * blend];
                let m_rr = tire::rolling_resistance_moment(
                    &self.tire,
                    fz,
                    ct.loaded_radius,
                    spin_rel,
                    shear.fx,
                    slip.vx,
                    ct.inclination,
                );
                let force_ground = ct.force(fz, &shear);
                let moment_ground = ct.moment_about_centre(&axle_ground, &force_ground, moments, m_rr);
                let (force, moment_w) = (a0.tr_mul(&force_ground), a0.tr_mul(&moment_ground));
                // The axial moment drives the spin (§4.8); the rest acts on the carrier at the wheel centre.
                let axial = axle.dot(&moment_w);
                q_k += wrench(&force, &(rho_w.cross(&force) + moment_w - axle * axial));
                free_torque += axial;
                diag.tire_force[i] = [shear.fx, shear.fy, fz];
                diag.kappa[i] = kappa;
                diag.tan_alpha[i] = tan_alpha;
            }
            None => {
                // The signed clearance (negative), exact for an upright wheel: continuous with the
                // deflection at touchdown.
                let clearance =
                    centre_abs.z - road.height_and_gradient(centre_abs.x, centre_abs.y).0 - self.tire.unloaded_radius_m;
                diag.penetration[i] = -clearance.abs();
                diag.contact_indicator[i] = diag.penetration[i];
                if options.slip == SlipModel::Relaxation {
                    let lifted = tire::SlipStateContext { in_contact: false, blend: 1.0, sliding_limit: [1.0; 2] };
                    relaxation_rates = tire::relaxation_rates(&self.tire, 0.0, 0.0, 0.0, xi, &lifted);
                }
            }
        }
        // Brake between wheel and carrier (model::vehicle::brake): holds the relative spin within its capacity.
        let brake = crate::model::vehicle::brake::torque(
            brake_torque,
            crate::model::vehicle::brake::demand(free_torque, c.spin_inertia, spin_rel),
        );
        q_k += wrench(&V3::zeros(), &(axle * brake));
        let spin_torque = free_torque - brake;

        // Subsystem terms (§4.2) from the joint-Jacobian structure: 𝔅_L = [b_L 0 0 0 0], 𝔅_K = [b_L B_K 0],
        // 𝔅_U = [0 0 0 0 b_U], so that M_qq = Σ 𝔅ᵀM̂𝔅 has the blocks below (zero between θ_U and the rest)
        // and only M̂ times these columns is needed: 6-vector products instead of dense 6×5 ones.
        let mh = |b: usize, y: &Vector6<f64>| mass_hat_times(k.mass[b], &k.com[b], &k.inertia[b], y);
        let ml_bl = mh(BODY_L, &k.b_l);
        let mk_bl = mh(BODY_K, &k.b_l);
        let mk_bk_j = |j: usize| mh(BODY_K, &k.b_k.column(j).into_owned());
        let mk_bk = [mk_bk_j(0), mk_bk_j(1), mk_bk_j(2)];
        let mu_bu = mh(BODY_U, &k.b_u);
        let m_bl = ml_bl + mk_bl;
        let p_l = q_l - mh(BODY_L, &k.rate[BODY_L]);
        let p_k = q_k - mh(BODY_K, &k.rate[BODY_K]);
        let p_u = q_u - mh(BODY_U, &k.rate[BODY_U]);
        let SubsystemTerms { m_qq, m_q0, p_q, .. } = terms;
        // M_qq's zero block (θ_U with the rest): set here, every other entry is written below.
        for j in 0..4 {
            m_qq[(j, 4)] = 0.0;
            m_qq[(4, j)] = 0.0;
        }
        m_qq[(0, 0)] = k.b_l.dot(&m_bl);
        m_qq[(4, 4)] = k.b_u.dot(&mu_bu);
        for j in 0..3 {
            let bkj = k.b_k.column(j);
            m_qq[(0, 1 + j)] = k.b_l.dot(&mk_bk[j]);
            m_qq[(1 + j, 0)] = m_qq[(0, 1 + j)];
            for l in j..3 {
                m_qq[(1 + j, 1 + l)] = bkj.dot(&mk_bk[l]);
                m_qq[(1 + l, 1 + j)] = m_qq[(1 + j, 1 + l)];
            }
            m_q0.set_row(1 + j, &mk_bk[j].transpose());
            p_q[1 + j] = bkj.dot(&p_k);
        }
        m_q0.set_row(0, &m_bl.transpose());
        m_q0.set_row(4, &mu_bu.transpose());
        p_q[0] = k.b_l.dot(&(p_l + p_k));
        p_q[4] = k.b_u.dot(&p_u);
        let mut m_00 = MassHatSum::new();
        for b in [BODY_L, BODY_K, BODY_U] {
            m_00.add(k.mass[b], &k.com[b], &k.inertia[b]);
        }
        m_00.write_into(&mut terms.m_00);
        terms.p_0 = p_l + p_k + p_u;
        terms.phi_q = pos.phi_q;
        terms.gamma_bar = *gamma_bar;
        // ∂v/∂u = −Φ_v⁻¹Φ_u, solved with the same factors: the negation is exact, so GCP gets its own bits.
        terms.phi_v_solved = pos.lu_v.map(|lu| PhiVSolved { lu, phi_v_inv_phi_u: -pos.dv_du });
        Ok(CornerOutput { chassis_wrench, spin_torque, relaxation_rates })
    }
}

/// Accelerations from the assembled terms by the selected formulation (§4.9 steps 3f–5, or the 42x42 of
/// §4.3): what the paper's Table 1 calls the acceleration evaluation.
#[inline(always)]
pub fn accelerations(
    formulation: Formulation,
    a: &Assembly,
    multipliers: Multipliers,
) -> Result<Accelerations<4>, ModelError> {
    match formulation {
        Formulation::Synthesis => dynamics::solve_synthesis_gcp_with(&a.chassis, &a.terms, multipliers),
        Formulation::SynthesisAugmented => dynamics::solve_synthesis_augmented(&a.chassis, &a.terms),
        Formulation::Conventional => dynamics::solve_conventional(&a.chassis, &a.terms),
    }
    .context("acceleration solve failed")
}

pub const BODY_L: usize = 0;
pub const BODY_K: usize = 1;
pub const BODY_U: usize = 2;

/// Kinematics of the three bodies of one corner (origin at the chassis CM, in the axes `corner_kinematics`
/// is given), in the order lower arm, carrier, upper arm: Y_b = Y0 + 𝔅_b q̇, Ẏ_b = Ẏ0 + 𝔅_b q̈ + 𝔇_b (§3.4).
#[derive(Debug, Clone, Copy)]
pub struct CornerKinematics {
    /// The non-zero columns of the joint Jacobians 𝔅_b (6×5): 𝔅_L = [b_L 0 0 0 0], 𝔅_K = [b_L B_K 0],
    /// 𝔅_U = [0 0 0 0 b_U] (`jacobian(b)` builds them whole).
    pub b_l: Vector6<f64>,
    pub b_k: SMatrix<f64, 6, 3>,
    pub b_u: Vector6<f64>,
    pub rate: [Vector6<f64>; 3],
    pub velocity: [Vector6<f64>; 3],
    pub mass: [f64; 3],
    pub com: [V3; 3],
    pub inertia: [M3; 3],
    pub axle: V3,
    pub wheel_centre: V3,
}

impl CornerKinematics {
    /// 𝔅_b as a dense 6×5 matrix (for tests and diagnostics; the terms use the columns).
    pub fn jacobian(&self, b: usize) -> SMatrix<f64, 6, 5> {
        let mut m = SMatrix::<f64, 6, 5>::zeros();
        match b {
            BODY_L => m.set_column(0, &self.b_l),
            BODY_K => {
                m.set_column(0, &self.b_l);
                m.fixed_view_mut::<6, 3>(0, 1).copy_from(&self.b_k);
            }
            _ => m.set_column(4, &self.b_u),
        }
        m
    }
}

impl Vehicle {
    /// The corner's kinematics in the `axes` (the evaluation's: `ChassisAxes`; ground: A0), with the chassis
    /// velocity state `y0` in the same axes.
    #[inline(always)]
    pub fn corner_kinematics(
        &self,
        i: usize,
        pos: &CornerPositions,
        qd: &Vector5f,
        axes: &impl Axes,
        y0: &Vector6<f64>,
    ) -> CornerKinematics {
        let c = &self.corners[i];
        let (v0, w0) = (lin(y0), ang(y0));
        let phid = V3::new(qd[1], qd[2], qd[3]);
        // Joint velocity matrices: revolute B = [ρ_p × h; h], spherical B_K = [ρ̃_b; I] A_L G.
        // The body of q[4]: the upper arm's revolute, or (the strut slide) no body: B_U = 0, D_U = 0.
        let (p_u, h_u) = c.upper_revolute().unwrap_or((V3::zeros(), V3::zeros()));
        let h_l = axes.vector(&c.h_l);
        let h_u = axes.vector(&h_u);
        let rho_pl = axes.vector(&c.p_l);
        let rho_pu = axes.vector(&p_u);
        let rho_b = axes.vector(&pos.b);
        let a_l_g = axes.matrix(&pos.rl_g);
        let b_l = wrench(&rho_pl.cross(&h_l), &h_l);
        let b_u = wrench(&rho_pu.cross(&h_u), &h_u);
        let mut b_k = SMatrix::<f64, 6, 3>::zeros();
        b_k.fixed_view_mut::<3, 3>(0, 0).copy_from(&(skew(&rho_b) * a_l_g));
        b_k.fixed_view_mut::<3, 3>(3, 0).copy_from(&a_l_g);
        let y_l = y0 + b_l * qd[0];
        let y_k = y_l + b_k * phid;
        let y_u = y0 + b_u * qd[4];
        // Rates: D = d(B)/dt q̇ with the chassis turning the axes (ḣ = ω0 × h).
        let revolute_rate = |rho_p: &V3, h: &V3, rate: f64| -> Vector6<f64> {
            let hd = w0.cross(h);
            let pd = v0 + w0.cross(rho_p);
            wrench(&((pd.cross(h) + rho_p.cross(&hd)) * rate), &(hd * rate))
        };
        let d_l = revolute_rate(&rho_pl, &h_l, qd[0]);
        let d_u = revolute_rate(&rho_pu, &h_u, qd[4]);
        let omega_r = a_l_g * phid;
        let w_l = ang(&y_l);
        let wv = w_l.cross(&omega_r) + axes.vector(&(pos.r_l * pos.bryant.rate_quadratic(&phid)));
        let b_dot = lin(&y_l) + w_l.cross(&rho_b);
        let d_k = wrench(&(b_dot.cross(&omega_r) + rho_b.cross(&wv)), &wv);

        let rot_l = axes.matrix(&pos.r_l);
        let rot_u = axes.matrix(&pos.r_u);
        let rot_k = axes.matrix(&pos.r_k);
        CornerKinematics {
            b_l,
            b_k,
            b_u,
            rate: [d_l, d_l + d_k, d_u],
            velocity: [y_l, y_k, y_u],
            mass: [c.lower.mass, c.carrier.mass, c.upper.mass],
            com: [
                axes.vector(&c.on_lower(pos, &c.lower.com)),
                axes.vector(&c.on_carrier(pos, &c.carrier.com)),
                axes.vector(&c.on_upper(pos, &c.upper.com)),
            ],
            inertia: [
                rot_l * c.lower.inertia * rot_l.transpose(),
                rot_k * c.carrier.inertia * rot_k.transpose(),
                rot_u * c.upper.inertia * rot_u.transpose(),
            ],
            axle: rot_k * c.axle,
            wheel_centre: axes.vector(&c.on_carrier(pos, &c.w0)),
        }
    }
}

/// The terms of one evaluation, before the equation solving.
#[derive(Debug, Clone, Copy, Default)]
pub struct Assembly {
    pub chassis: ChassisTerms,
    pub terms: [SubsystemTerms; 4],
    /// a·M_W + T_d − T_b per wheel: I_s Ω̇ (§4.8).
    pub spin_torque: [f64; 4],
    pub relaxation_rates: [[f64; 2]; 4],
    /// Chassis speed along its horizontal heading (the speed hold's V_x).
    pub heading_speed: f64,
}

enum LineElement {
    Spring,
    Damper,
}

/// What the chassis stage of an evaluation hands every corner: the run (its options and road), the chassis
/// attitude A0 and CM r0
/// (which place the wheel on the road, in the ground's axes), and the chassis velocity state Y0 and
/// gravity in the chassis axes the terms are assembled in.
struct ChassisStage<'a> {
    run: &'a Run<'a>,
    a0: M3,
    r0: V3,
    y0: Vector6<f64>,
    g: V3,
}

/// One corner's solved motion: its positions (Newton), q̇ and γ̄, and the anti-roll bar's generalized force
/// on its θ_L (computed from both corners of the axle before the corner terms).
#[derive(Clone, Copy)]
struct CornerMotion<'a> {
    positions: &'a CornerPositions,
    qd: Vector5f,
    gamma_bar: Vector4<f64>,
    bar_force: f64,
}

/// A wheel's own state and torques, as one corner's evaluation reads them.
#[derive(Debug, Clone, Copy)]
struct WheelState {
    /// Absolute spin rate Ω, rad/s.
    spin: f64,
    /// Relaxation slip states (ξ_x, ξ_y); zero where the layout has none.
    xi: [f64; 2],
    drive_torque: f64,
    brake_torque: f64,
}

/// What a corner adds besides its subsystem terms.
struct CornerOutput {
    chassis_wrench: Vector6<f64>,
    spin_torque: f64,
    relaxation_rates: [f64; 2],
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
            if options.switches.springs {
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
        }
        v += spring_potential;
        for (axle, spin, is) in spin_terms {
            h += axle * (is * spin);
            t += 0.5 * is * spin * spin;
        }
        Ok(MechanicalSummary { linear_momentum: p, angular_momentum: h, kinetic_energy: t, potential_energy: v })
    }
}
