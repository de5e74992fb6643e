//! Initial states computed, not settled (docs/physics.md §8.1): the ride-height retune of the spring free
//! lengths, the static equilibrium, and steady rolling at speed. Each is a small Newton solve with a
//! finite-difference Jacobian on residuals taken from the derivative function itself, so the initial
//! state is an equilibrium of exactly the model that is integrated.

use crate::error::{Cause, ModelError};
use crate::math::{quat_from_euler, quat_to_matrix, V3};
use crate::model::options::Options;
use crate::model::road::envelope::ContactModel;
use crate::model::road::RoadModel;
use crate::model::steering::RackMotion;
use crate::model::tire::SlipModel;
use crate::model::vehicle::{idx, AxleKind, Inputs, Layout, Run, SpeedMode, Vehicle, Workspace};
use nalgebra::{DMatrix, DVector};

/// Residual tolerance of the initialisation solves (accelerations in m/s² and rad/s²).
pub const EQUILIBRIUM_TOLERANCE: f64 = 1e-10;

/// Steps of the steady-rolling solve from straight ahead to a steered start (`steady_rolling_steered`).
const STEERING_CONTINUATION_STEPS: usize = 8;

/// Newton with a forward-difference Jacobian (step 1e-7 relative). Allocates: initialisation only.
pub fn newton<F>(
    unknowns: &mut [f64],
    mut residual: F,
    tolerance: f64,
    max_iterations: usize,
) -> Result<usize, ModelError>
where
    F: FnMut(&[f64], &mut [f64]) -> Result<(), ModelError>,
{
    let n = unknowns.len();
    let mut r = vec![0.0; n];
    let mut rp = vec![0.0; n];
    for it in 0..max_iterations {
        residual(unknowns, &mut r)?;
        let norm = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if norm < tolerance {
            return Ok(it);
        }
        let mut jac = DMatrix::<f64>::zeros(n, n);
        for j in 0..n {
            let h = 1e-7 * unknowns[j].abs().max(1e-2);
            let saved = unknowns[j];
            unknowns[j] += h;
            residual(unknowns, &mut rp)?;
            unknowns[j] = saved;
            for i in 0..n {
                jac[(i, j)] = (rp[i] - r[i]) / h;
            }
        }
        let step = jac
            .lu()
            .solve(&DVector::from_column_slice(&r))
            .ok_or_else(|| ModelError::new(Cause::Solve, "equilibrium Jacobian is singular"))?;
        for j in 0..n {
            unknowns[j] -= step[j];
        }
    }
    let mut r = vec![0.0; n];
    residual(unknowns, &mut r)?;
    let norm = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if norm < tolerance {
        Ok(max_iterations)
    } else {
        Err(ModelError::new(Cause::Solve, format!("equilibrium did not converge (residual {norm:.3e})")))
    }
}

/// The residuals of the four suspension unknowns (the corners' θ_L places): each one's acceleration, or on
/// a rigid axle, which has no coordinate there (its acceleration is zero whatever the unknown), the unknown
/// itself, so that it is held at zero and the Jacobian stays regular.
fn travel_residuals(v: &Vehicle, dx: &[f64], u: &[f64], r: &mut [f64]) {
    for i in 0..4 {
        r[i] = match v.axle_kind(i / 2) {
            AxleKind::Rigid => u[i],
            _ => dx[idx::UD + i],
        };
    }
}

/// A state at rest in `layout`: chassis CM at height z with roll and pitch, arm angles u, everything else
/// zero.
pub fn rest_state(layout: &Layout, z: f64, roll: f64, pitch: f64, u: &[f64; 4]) -> Vec<f64> {
    let mut x = vec![0.0; layout.dim];
    x[idx::R0 + 2] = z;
    x[idx::E0..idx::E0 + 4].copy_from_slice(&quat_from_euler(roll, pitch, 0.0));
    x[idx::U..idx::U + 4].copy_from_slice(u);
    x
}

/// The first guess of every static solve, [height, roll, pitch] of the chassis: the design position with the
/// tires deflected by a quarter of the weight each (undeflected tires would start Newton at the lift-off
/// kink), the chassis turned so that the wheel centres' front-rear and left-right mean heights are level
/// (Chrono's generic three-link IRS test vehicle has its front wheel centres 0.21 m below its rear ones: level,
/// its front tires were deflected beyond their validity at the guess), and the height taken at the highest
/// wheel centre, so that every tire touches: a wheel in the air at the guess has no stiffness under it, and
/// Newton's first step from there (measured: a generic car with its rear wheel centres 26 mm above its front
/// ones, before the turn) flies off to a chassis 6 m up.
pub fn design_pose_guess(v: &Vehicle) -> [f64; 3] {
    let w: [V3; 4] = std::array::from_fn(|i| v.corners[i].w0);
    let mean = |a: usize, b: usize| (w[a] + w[b]) * 0.5;
    let (front, rear, left, right) = (mean(0, 1), mean(2, 3), mean(0, 2), mean(1, 3));
    // Ry(θ) puts a point's height at z cos θ − x sin θ, Rx(φ) at z cos φ + y sin φ: level where those agree.
    let pitch = ((front.z - rear.z) / (front.x - rear.x)).atan();
    let roll = ((right.z - left.z) / (left.y - right.y)).atan();
    let a = quat_to_matrix(&quat_from_euler(roll, pitch, 0.0));
    let highest = w.iter().map(|p| (a * p).z).fold(f64::NEG_INFINITY, f64::max);
    let deflection = v.total_mass * v.gravity / 4.0 / v.tire.vertical_stiffness_N_per_m;
    [v.tire.unloaded_radius_m - deflection - highest, roll, pitch]
}

/// The options an initial state is solved with: the run's, on the plane road z = 0 with the point contact
/// (on a plane it is the enveloping one). The road's slope stays: gravity is tilted as in the run, so the
/// state is the equilibrium on the slope (`start_on_plane` puts a file road's start plane in this frame).
fn level(options: &Options) -> Options {
    Options { contact: ContactModel::Point, ..*options }
}

/// The options of the static problems: coasting (no controller at rest) with relaxation slip. At rest
/// every slip velocity is zero: the tire has no shear force with undeflected slip states (ξ = 0). Steady
/// slip is not defined at standstill, so the static problem is posed with them.
fn at_rest(options: &Options) -> Options {
    Options { speed_mode: SpeedMode::Coast, slip: SlipModel::Relaxation, ..level(options) }
}

/// The inputs an initial state is solved with: the steering input (the rack's, m, or the Pitman arm's, rad)
/// held at `steering`, no wheel torques, the speed hold's target `speed`.
fn held(steering: f64, speed: f64) -> Inputs {
    Inputs {
        rack: RackMotion { position: steering, ..RackMotion::default() },
        target_speed: speed,
        ..Inputs::default()
    }
}

fn evaluate(
    v: &Vehicle,
    options: &Options,
    x: &[f64],
    inputs: &Inputs,
    ws: &mut Workspace,
    dx: &mut [f64],
) -> Result<(), ModelError> {
    v.derivative(&Run::flat(v, options), x, inputs, ws, dx)
}

/// Ride-height retune (§8.1 step 1): choose the front and rear spring free-length offsets so that the
/// design position (all arm angles zero) is the static equilibrium. Returns (ΔL_front, ΔL_rear) and
/// leaves them applied to `v`.
pub fn retune_ride_height(v: &mut Vehicle, options: &Options) -> Result<(f64, f64), ModelError> {
    let base: Vec<f64> = v.corner_forces.iter().map(|f| f.spring_free_length).collect();
    let [z, roll, pitch] = design_pose_guess(v);
    let mut p = vec![z, roll, pitch, 0.0, 0.0];
    let mut ws = Workspace::default();
    let mut statics = v.clone();
    // A property of the vehicle: its design position on level ground, whatever road the run is on.
    let rest = at_rest(&Options { slope: [0.0; 2], ..*options });
    let layout = Layout::of(&rest);
    let mut dx = vec![0.0; layout.dim];
    newton(
        &mut p,
        |p, r| {
            for i in 0..4 {
                statics.corner_forces[i].spring_free_length = base[i] + if i < 2 { p[3] } else { p[4] };
            }
            let x = rest_state(&layout, p[0], p[1], p[2], &[0.0; 4]);
            evaluate(&statics, &rest, &x, &Inputs::default(), &mut ws, &mut dx)?;
            r[0] = dx[idx::V0 + 2];
            r[1] = dx[idx::W0];
            r[2] = dx[idx::W0 + 1];
            // A rigid axle has no spring: its offset is held at zero instead.
            for a in 0..2 {
                r[3 + a] = match v.axle_kind(a) {
                    AxleKind::Rigid => p[3 + a],
                    _ => dx[idx::UD + 2 * a] + dx[idx::UD + 2 * a + 1],
                };
            }
            Ok(())
        },
        EQUILIBRIUM_TOLERANCE,
        20,
    )?;
    for i in 0..4 {
        v.corner_forces[i].spring_free_length = base[i] + if i < 2 { p[3] } else { p[4] };
    }
    Ok((p[3], p[4]))
}

/// Static equilibrium (§8.1 step 2): height, roll, pitch and the four arm angles with every
/// acceleration zero; x, y and yaw are free and set to zero. The state is in `v`'s layout.
pub fn static_equilibrium(v: &Vehicle, options: &Options, ws: &mut Workspace) -> Result<Vec<f64>, ModelError> {
    static_equilibrium_steered(v, options, 0.0, ws)
}

/// `static_equilibrium` with the steering input held at `steering` (m of rack or rad of Pitman arm): the
/// wheels stand where it puts them.
pub fn static_equilibrium_steered(
    v: &Vehicle,
    options: &Options,
    steering: f64,
    ws: &mut Workspace,
) -> Result<Vec<f64>, ModelError> {
    let rest = at_rest(options);
    let inputs = held(steering, 0.0);
    let layout = Layout::of(&rest);
    let [z, roll, pitch] = design_pose_guess(v);
    let mut p = vec![z, roll, pitch, 0.0, 0.0, 0.0, 0.0];
    let mut dx = vec![0.0; layout.dim];
    let state = |p: &[f64]| rest_state(&layout, p[0], p[1], p[2], &[p[3], p[4], p[5], p[6]]);
    newton(
        &mut p,
        |p, r| {
            evaluate(v, &rest, &state(p), &inputs, ws, &mut dx)?;
            r[0] = dx[idx::V0 + 2];
            r[1] = dx[idx::W0];
            r[2] = dx[idx::W0 + 1];
            travel_residuals(v, &dx, &p[3..7], &mut r[3..7]);
            Ok(())
        },
        EQUILIBRIUM_TOLERANCE,
        30,
    )?;
    Ok(Layout::of(options).convert(&state(&p), &layout))
}

/// Steady straight rolling at `speed` (§8.1 step 3): starting from the static equilibrium, solve for the
/// attitude, arm angles, spin rates, longitudinal slip states and (hold) the speed-hold integral so that
/// the first step is already an equilibrium: no ringing of the lightly damped spin–slip mode.
/// In coast mode the vehicle decelerates by rolling resistance, so the longitudinal balance is left out.
/// The state is in the layout of `options`, which it is solved with on the level road (`level`); with the
/// speed hold, `speed` is its target.
pub fn steady_rolling(v: &Vehicle, options: &Options, speed: f64, ws: &mut Workspace) -> Result<Vec<f64>, ModelError> {
    steady_rolling_steered(v, options, speed, 0.0, ws)
}

/// `steady_rolling` with the steering input held at `steering` (m of rack or rad of Pitman arm): the wheels
/// stand where it puts them, rolling straight ahead (the slip states at their steady values for that), from
/// which the car starts to turn. The FMU starts here from its steering input's start value.
pub fn steady_rolling_steered(
    v: &Vehicle,
    options: &Options,
    speed: f64,
    steering: f64,
    ws: &mut Workspace,
) -> Result<Vec<f64>, ModelError> {
    let mut x = static_equilibrium_steered(v, options, steering, ws)?;
    if speed == 0.0 {
        return Ok(x);
    }
    let vel = V3::x() * speed;
    x[idx::V0..idx::V0 + 3].copy_from_slice(vel.as_slice());
    let r = v.tire.unloaded_radius_m;
    for i in 0..4 {
        x[idx::SPIN + i] = speed / r;
    }
    // The slip and hold unknowns exist when the options use them (a full layout may carry unused ones).
    let options = level(options);
    let run = Run::flat(v, &options);
    let layout = run.layout();
    let relaxation = layout.xi.filter(|_| options.slip == SlipModel::Relaxation);
    let hold = layout.zv.filter(|_| options.speed_mode == SpeedMode::Hold);
    // Unknowns: z, roll, pitch, u1..4, Ω1..4, [ξ (x, y) per corner], [z_v].
    let mut p = vec![x[idx::R0 + 2], 0.0, 0.0];
    let (roll, pitch, _) = crate::math::euler_from_matrix(&quat_to_matrix(&x[idx::E0..idx::E0 + 4]));
    p[1] = roll;
    p[2] = pitch;
    p.extend_from_slice(&x[idx::U..idx::U + 4]);
    p.extend_from_slice(&x[idx::SPIN..idx::SPIN + 4]);
    if relaxation.is_some() {
        p.extend_from_slice(&[0.0; 8]);
    }
    if hold.is_some() {
        p.push(0.0);
    }
    let base = x.clone();
    let assemble = |p: &[f64]| -> Vec<f64> {
        let mut x = base.clone();
        x[idx::R0 + 2] = p[0];
        x[idx::E0..idx::E0 + 4].copy_from_slice(&quat_from_euler(p[1], p[2], 0.0));
        // Straight ahead along ground x (yaw 0), horizontal whatever the static pitch.
        x[idx::V0..idx::V0 + 3].copy_from_slice((V3::x() * speed).as_slice());
        x[idx::U..idx::U + 4].copy_from_slice(&p[3..7]);
        x[idx::SPIN..idx::SPIN + 4].copy_from_slice(&p[7..11]);
        put_slip_and_hold(&mut x, &p[11..], relaxation, hold);
        x
    };
    let mut dx = vec![0.0; layout.dim];
    // From straight ahead to `steering` in equal steps, each solve starting from the last one's solution: Newton
    // from the unsteered guess does not reach a strongly steered state (the front tires near their grip).
    let steps = if steering == 0.0 { 1 } else { STEERING_CONTINUATION_STEPS };
    for k in 1..=steps {
        let inputs = held(steering * k as f64 / steps as f64, speed);
        newton(
            &mut p,
            |p, r| {
                let x = assemble(p);
                v.derivative(&run, &x, &inputs, ws, &mut dx)?;
                let acc = V3::new(dx[idx::V0], dx[idx::V0 + 1], dx[idx::V0 + 2]);
                r[0] = dx[idx::V0 + 2];
                r[1] = dx[idx::W0];
                r[2] = dx[idx::W0 + 1];
                travel_residuals(v, &dx, &p[3..7], &mut r[3..7]);
                r[7..11].copy_from_slice(&dx[idx::SPIN..idx::SPIN + 4]);
                let mut k = 11;
                if let Some(xi) = relaxation {
                    r[k..k + 8].copy_from_slice(&dx[xi..xi + 8]);
                    k += 8;
                }
                if hold.is_some() {
                    r[k] = acc.x;
                }
                Ok(())
            },
            EQUILIBRIUM_TOLERANCE,
            30,
        )?;
    }
    Ok(assemble(&p))
}

/// The tread deflections (8, when `relaxation` is their index) and the hold's integral (when `hold` is) of
/// a state, from the solve's unknowns `p` in that order.
fn put_slip_and_hold(x: &mut [f64], p: &[f64], relaxation: Option<usize>, hold: Option<usize>) {
    let mut k = 0;
    if let Some(xi) = relaxation {
        x[xi..xi + 8].copy_from_slice(&p[..8]);
        k = 8;
    }
    if let Some(zv) = hold {
        x[zv] = p[k];
    }
}

/// A plane road h = h0 + gx x + gy y in the ground frame (the plane through the road's heights below the four
/// wheels at the start): `frame` turns its own axes (x along the ground's x projected on the plane, z its
/// normal) into the ground's.
#[derive(Debug, Clone, Copy)]
pub struct StartPlane {
    pub h0: f64,
    pub gradient: [f64; 2],
}

impl StartPlane {
    /// The least-squares plane through the road's heights at four ground points (exact when they lie on a
    /// plane).
    pub fn through(points: &[[f64; 3]; 4]) -> Option<StartPlane> {
        let mut a = nalgebra::Matrix3::<f64>::zeros();
        let mut b = nalgebra::Vector3::<f64>::zeros();
        for p in points {
            let row = nalgebra::Vector3::new(1.0, p[0], p[1]);
            a += row * row.transpose();
            b += row * p[2];
        }
        let c = a.lu().solve(&b)?;
        c.iter().all(|v| v.is_finite()).then_some(StartPlane { h0: c[0], gradient: [c[1], c[2]] })
    }

    /// Columns: the plane's x (ground x projected on it), y, and normal, in the ground's axes.
    pub fn frame(&self) -> crate::math::M3 {
        let [gx, gy] = self.gradient;
        let ex = V3::new(1.0, 0.0, gx).normalize();
        let ez = V3::new(-gx, -gy, 1.0).normalize();
        let ey = ez.cross(&ex);
        crate::math::M3::from_columns(&[ex, ey, ez])
    }

    pub fn is_level(&self) -> bool {
        self.h0 == 0.0 && self.gradient == [0.0; 2]
    }
}

/// Steady rolling (static equilibrium at speed 0) on a file road's start plane: solved on the plane road
/// z = 0 of the plane's own frame with gravity (the run's, tilted by `options.slope` if set) turned into
/// that frame, as on a slope, then the chassis's pose and velocities turned and moved onto the plane (the
/// arm angles, spins, tread deflections and the hold's integral are relative and stay). The speed hold
/// measures the speed along the horizontal heading: the state rolls at `speed` / cos(grade) along the plane,
/// so that the horizontal speed is the hold's target `speed`.
pub fn start_on_plane(
    v: &Vehicle,
    options: &Options,
    road: &RoadModel,
    plane: &StartPlane,
    speed: f64,
    steering: f64,
    ws: &mut Workspace,
) -> Result<Vec<f64>, ModelError> {
    let frame = plane.frame();
    let g = frame.transpose() * options.gravity_vector(v.gravity);
    let slope = if g.z < 0.0 { [g.x / g.z, g.y / g.z] } else { [0.0; 2] };
    let on_plane = Options { slope, ..*options };
    let along = speed / V3::new(frame[(0, 0)], frame[(1, 0)], 0.0).norm();
    let mut x = steady_rolling_steered(v, &on_plane, along, steering, ws)?;
    let r0 = V3::new(0.0, 0.0, plane.h0) + frame * V3::new(x[idx::R0], x[idx::R0 + 1], x[idx::R0 + 2]);
    let a0 = frame * quat_to_matrix(&x[idx::E0..idx::E0 + 4]);
    let (roll, pitch, yaw) = crate::math::euler_from_matrix(&a0);
    let v0 = frame * V3::new(x[idx::V0], x[idx::V0 + 1], x[idx::V0 + 2]);
    let w0 = frame * V3::new(x[idx::W0], x[idx::W0 + 1], x[idx::W0 + 2]);
    x[idx::R0..idx::R0 + 3].copy_from_slice(r0.as_slice());
    x[idx::E0..idx::E0 + 4].copy_from_slice(&quat_from_euler(roll, pitch, yaw));
    x[idx::V0..idx::V0 + 3].copy_from_slice(v0.as_slice());
    x[idx::W0..idx::W0 + 3].copy_from_slice(w0.as_slice());
    polish_on_road(v, options, road, &frame, x, speed, steering, ws)
}

/// The plane's solution solved again on the road itself (Newton from it): where the road is not a plane
/// under the car (a grade or a bank changing along it, a twist) the wheels' deflections differ from the
/// plane's by the road's departure from it. Unknowns: the height, two rotations about the plane's x and y,
/// the arm angles and (at speed) the spins, tread deflections and the hold's integral; residuals: the
/// chassis's acceleration along the plane's normal, its angular accelerations about the plane's x and y,
/// and the rest as `steady_rolling_steered` takes them. On a plane the first evaluation is already within
/// tolerance and the state is the plane's.
#[allow(clippy::too_many_arguments)]
fn polish_on_road(
    v: &Vehicle,
    options: &Options,
    road: &RoadModel,
    frame: &crate::math::M3,
    x: Vec<f64>,
    speed: f64,
    steering: f64,
    ws: &mut Workspace,
) -> Result<Vec<f64>, ModelError> {
    let at_speed = speed != 0.0;
    let solve = if at_speed { level(options) } else { at_rest(options) };
    let run = Run::new(v, &solve, road);
    let layout = run.layout();
    let base = layout.convert(&x, &Layout::of(options));
    let inputs = held(steering, speed);
    let relaxation = layout.xi.filter(|_| at_speed && solve.slip == SlipModel::Relaxation);
    let hold = layout.zv.filter(|_| at_speed && solve.speed_mode == SpeedMode::Hold);
    let (ex, ey, n) = (frame.column(0).into_owned(), frame.column(1).into_owned(), frame.column(2).into_owned());
    let a_base = quat_to_matrix(&base[idx::E0..idx::E0 + 4]);
    let mut p = vec![base[idx::R0 + 2], 0.0, 0.0];
    p.extend_from_slice(&base[idx::U..idx::U + 4]);
    if at_speed {
        p.extend_from_slice(&base[idx::SPIN..idx::SPIN + 4]);
    }
    if let Some(k) = relaxation {
        p.extend_from_slice(&base[k..k + 8]);
    }
    if let Some(k) = hold {
        p.push(base[k]);
    }
    let assemble = |p: &[f64]| -> Vec<f64> {
        let mut x = base.clone();
        x[idx::R0 + 2] = p[0];
        let a = crate::math::rotation_about(&ex, p[1]) * crate::math::rotation_about(&ey, p[2]) * a_base;
        let (roll, pitch, yaw) = crate::math::euler_from_matrix(&a);
        x[idx::E0..idx::E0 + 4].copy_from_slice(&quat_from_euler(roll, pitch, yaw));
        x[idx::U..idx::U + 4].copy_from_slice(&p[3..7]);
        if at_speed {
            x[idx::SPIN..idx::SPIN + 4].copy_from_slice(&p[7..11]);
            put_slip_and_hold(&mut x, &p[11..], relaxation, hold);
        }
        x
    };
    let mut dx = vec![0.0; layout.dim];
    newton(
        &mut p,
        |p, r| {
            v.derivative(&run, &assemble(p), &inputs, ws, &mut dx)?;
            let a = V3::new(dx[idx::V0], dx[idx::V0 + 1], dx[idx::V0 + 2]);
            let w = V3::new(dx[idx::W0], dx[idx::W0 + 1], dx[idx::W0 + 2]);
            r[0] = n.dot(&a);
            r[1] = ex.dot(&w);
            r[2] = ey.dot(&w);
            travel_residuals(v, &dx, &p[3..7], &mut r[3..7]);
            let mut k = 7;
            if at_speed {
                r[7..11].copy_from_slice(&dx[idx::SPIN..idx::SPIN + 4]);
                k = 11;
            }
            if let Some(xi) = relaxation {
                r[k..k + 8].copy_from_slice(&dx[xi..xi + 8]);
                k += 8;
            }
            if hold.is_some() {
                r[k] = ex.dot(&a);
            }
            Ok(())
        },
        EQUILIBRIUM_TOLERANCE,
        30,
    )?;
    Ok(Layout::of(options).convert(&assemble(&p), &layout))
}
