//! The ISO 3888-2:2011 double lane change (obstacle avoidance) and the line a driver takes through it.
//!
//! The course, for a vehicle of width b: lane 1 (12 m long, 1.1 b + 0.25 wide), a 13.5 m gap, lane 3 (11 m,
//! b + 1 wide, its right edge 1 m left of lane 1's left edge), a 12.5 m gap, lane 5 (12 m, 1.3 b + 0.25 wide,
//! at most 3 m, its right edge in line with lane 1's). Positions are in the ground frame: x along the
//! approach, y to the left, the course's entry at `entry` and lane 1 centred on y = 0.

use crate::path::Path;

/// Vehicle width b of the lane widths, m (HMMWV M1025: 2.16 m).
pub const HMMWV_WIDTH_M: f64 = 2.16;
/// Tire width for the footprint, m (37×12.50R16.5: 12.5 in; the vehicle data has no tire width).
pub const HMMWV_TIRE_WIDTH_M: f64 = 0.3175;

/// Half the HMMWV's front track, m (the spindle's lateral position; rt-vehicle's tests check it against the
/// vehicle data).
pub const HMMWV_HALF_TRACK_M: f64 = 0.909701;
/// The HMMWV's wheelbase and how far its CM is ahead of the rear axle, m (checked as the half track is).
pub const HMMWV_WHEELBASE_M: f64 = 3.301984;
pub const HMMWV_CM_AHEAD_M: f64 = 1.709405;
/// Run-up from the start (the vehicle's CM at x = 0, y = 0) to the course's entry, m.
pub const RUN_UP_M: f64 = 30.0;
/// The HMMWV's entry speed of the double lane change as a system of FMUs (`target/ssp/DoubleLaneChange.ssp`):
/// the highest of 30..80 km/h in 5 km/h steps at which `rtv manoeuvre double-lane-change` passes.
pub const SSP_ENTRY_SPEED_KMH: f64 = 40.0;

/// The course and the driver's line of the HMMWV, run up from x = 0 at `speed`, m/s: what `rtv manoeuvre
/// double-lane-change` drives and what the driver FMU follows in the SSP. The line runs 100 m past where the
/// manoeuvre ends (10 m after the course's exit), so that the driver's preview stays on it.
pub fn hmmwv_course_and_line(speed: f64) -> (Course, Path) {
    course_and_line(HMMWV_WIDTH_M, HMMWV_HALF_TRACK_M + 0.5 * HMMWV_TIRE_WIDTH_M, speed)
}

/// The course of a vehicle of width `width` (ISO 3888-2 sizes the lanes by it) and the driver's line for a
/// footprint of half-width `half_width` (half track + half the tire width), run up from x = 0 at `speed`.
pub fn course_and_line(width: f64, half_width: f64, speed: f64) -> (Course, Path) {
    let course = Course::new(width, RUN_UP_M);
    let line = course.driver_line(&HMMWV_LINE, half_width, speed, -10.0, course.exit() + 110.0);
    (course, line)
}

/// The shape of the driver's line through the lanes, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineShape {
    /// How far inside a lane's edge nearest the next lane the footprint's edge runs.
    pub margin: f64,
    /// How long before a lane's end the line starts across.
    pub lead: f64,
    /// How far into the next lane it arrives.
    pub lag: f64,
}

/// The HMMWV's line (docs/manoeuvres.md says how it was chosen).
pub const HMMWV_LINE: LineShape = LineShape { margin: 0.15, lead: 2.0, lag: 0.0 };

/// One lane section: x range (ground frame) and lateral bounds (y_min, y_max), m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lane {
    pub from: f64,
    pub to: f64,
    pub y: (f64, f64),
}

/// The three lanes of the course.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Course {
    pub lanes: [Lane; 3],
}

impl Course {
    /// The course for a vehicle of width `b`, its entry at x = `entry`.
    pub fn new(b: f64, entry: f64) -> Course {
        let w1 = 1.1 * b + 0.25;
        let w3 = b + 1.0;
        let w5 = (1.3 * b + 0.25).min(3.0);
        let lane = |from: f64, to: f64, y| Lane { from: entry + from, to: entry + to, y };
        Course {
            lanes: [
                lane(0.0, 12.0, (-0.5 * w1, 0.5 * w1)),
                lane(25.5, 36.5, (0.5 * w1 + 1.0, 0.5 * w1 + 1.0 + w3)),
                lane(49.0, 61.0, (-0.5 * w1, -0.5 * w1 + w5)),
            ],
        }
    }

    /// Where the course ends (lane 5's exit), m.
    pub fn exit(&self) -> f64 {
        self.lanes[2].to
    }

    /// The driver's line at speed `speed`, from `start` to `end` (x, m): in each lane a line `shape.margin`
    /// inside the edge nearest the next lane (the shortest lateral travel) for a vehicle whose outer tire
    /// edges are `half_width` from its centre line, joined by smootherstep curves that start `shape.lead`
    /// before a lane ends and finish `shape.lag` after the next begins, as a driver cuts across a gap.
    pub fn driver_line(&self, shape: &LineShape, half_width: f64, speed: f64, start: f64, end: f64) -> Path {
        let lanes = &self.lanes;
        let inside = half_width + shape.margin;
        let target = [0.5 * (lanes[0].y.0 + lanes[0].y.1), lanes[1].y.0 + inside, lanes[2].y.1 - inside];
        let y_at = |x: f64| {
            let blend = |k: usize| {
                let (from, to) = (lanes[k].to - shape.lead, lanes[k + 1].from + shape.lag);
                let tau = ((x - from) / (to - from)).clamp(0.0, 1.0);
                let s = tau * tau * tau * (10.0 - 15.0 * tau + 6.0 * tau * tau);
                target[k] + s * (target[k + 1] - target[k])
            };
            if x < 0.5 * (lanes[1].from + lanes[1].to) {
                blend(0)
            } else {
                blend(1)
            }
        };
        let n = ((end - start) / 0.5).ceil().max(1.0) as usize;
        let points = (0..=n).map(|k| start + (end - start) * k as f64 / n as f64).map(|x| [x, y_at(x)]).collect();
        Path::at_speed(points, speed).expect("a course line has increasing x")
    }

    /// Lower each lane's clearance in `clearance` (m; negative: a cone is hit) by the points `footprint`
    /// (ground frame) that lie within the lane's length.
    pub fn update_clearance(&self, footprint: &[[f64; 2]], clearance: &mut [f64; 3]) {
        for p in footprint {
            for (k, lane) in self.lanes.iter().enumerate() {
                if (lane.from..=lane.to).contains(&p[0]) {
                    clearance[k] = clearance[k].min(p[1] - lane.y.0).min(lane.y.1 - p[1]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn course_dimensions_for_the_hmmwv() {
        let c = Course::new(HMMWV_WIDTH_M, 30.0);
        let w = |l: &Lane| l.y.1 - l.y.0;
        assert!((w(&c.lanes[0]) - 2.626).abs() < 1e-12);
        assert!((w(&c.lanes[1]) - 3.16).abs() < 1e-12);
        assert!((w(&c.lanes[2]) - 3.0).abs() < 1e-12, "lane 5 is capped at 3 m");
        assert_eq!((c.lanes[1].from, c.exit()), (55.5, 91.0));
        // The line of a point vehicle runs inside every lane (it starts across before a lane ends and cuts
        // into the next lane's start, so there it comes nearer an edge than the margin).
        let line = c.driver_line(&HMMWV_LINE, 0.0, 10.0, 0.0, 100.0);
        let mut clearance = [f64::INFINITY; 3];
        c.update_clearance(line.points(), &mut clearance);
        assert!(clearance.iter().all(|&m| m > 0.1), "{clearance:?}");
    }
}
