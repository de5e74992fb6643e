//! Road surface behind a small trait (physics.md §6.1). (Placeholder: the tire/road helper implements it.)
use serde::{Deserialize, Serialize};

/// Height h(x, y) of the road in the ground frame and its gradient (dh/dx, dh/dy).
pub trait Road {
    fn height_and_gradient(&self, x: f64, y: f64) -> (f64, [f64; 2]);
}

/// A half-sine bump on one side of the road: h = height sin(pi (x - x_start)/length) on [x_start, x_start + length]
/// for side * y > 0 (side +1 left, -1 right).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HalfSineBump {
    pub x_start: f64,
    pub length: f64,
    pub height: f64,
    pub side: f64,
}

/// The roads the model ships (an enum so a simulation stays plain data).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum RoadModel {
    Flat,
    Bumps(Vec<HalfSineBump>),
}

impl RoadModel {
    /// The paper's unsymmetric bump course: 0.5 m long, 5 cm high; left wheels at 10 m and 14 m, right at
    /// 11 m and 15 m, leading edges measured from `front_wheel_x0` (the initial front wheel centres).
    pub fn paper_bump_course(front_wheel_x0: f64) -> RoadModel {
        let _ = front_wheel_x0;
        RoadModel::Flat
    }
}

impl Road for RoadModel {
    fn height_and_gradient(&self, _x: f64, _y: f64) -> (f64, [f64; 2]) {
        (0.0, [0.0, 0.0])
    }
}
