//! Road surface behind a small trait (docs/physics.md §6.1).
//!
//! The shipped roads are a flat plane z = 0 and that plane plus half-sine bumps, each confined to one side of
//! the road (the paper's unsymmetric bump course). Height and gradient are analytic, so the contact normal
//! (§6.2) is exact. The bumps are only C⁰ at their edges: the normal jumps there, which is the paper's profile.
//!
//! Files: `surface` (the `Road` and `FileRoad` traits and `Placement`, which every format implements), the
//! formats `crg` (OpenCRG and the generated ISO 8608 roads of `iso8608`) and `xodr` (OpenDRIVE), `RoadModel`
//! here above them, and `envelope` (the tire's enveloping contact) above `RoadModel`.

pub mod crg;
pub mod envelope;
pub mod iso8608;
pub mod surface;
pub mod xodr;

pub use surface::{FileRoad, Placement, Road};

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// A half-sine bump on one side of the road: h = height sin(pi (x - x_start)/length) on [x_start, x_start + length]
/// for side * y > 0 (side +1 left, -1 right).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HalfSineBump {
    pub x_start: f64,
    pub length: f64,
    pub height: f64,
    pub side: f64,
}

impl HalfSineBump {
    /// Whether (x, y) lies on the bump's footprint. A bump of non-positive length has no footprint (this
    /// also keeps the division by `length` below safe for hand-written road files). The footprint is
    /// (x_start, x_start + length]: at each edge itself the road is the side the edge's indicator
    /// (`RoadModel::edge_offset`, x minus the edge) calls not yet crossed, offset ≤ 0, as every switch
    /// indicator's zero is. Closed at the start, a location trial that landed exactly on it (Illinois' false
    /// position on a linear indicator can) took the bump's slope as the step's lower end: a first-order
    /// error, 5.5e-3 of F_x's peak on the solid-axles vehicle's bump course (tests/scenes.rs).
    fn covers(&self, x: f64, y: f64) -> bool {
        self.on_its_side(y) && x > self.x_start && x <= self.x_start + self.length
    }

    /// Whether a point at lateral position y runs over the bump (its side of the centre line; a bump of
    /// non-positive length is nowhere).
    fn on_its_side(&self, y: f64) -> bool {
        self.length > 0.0 && self.side * y > 0.0
    }
}

impl Road for HalfSineBump {
    fn height_and_gradient(&self, x: f64, y: f64) -> (f64, [f64; 2]) {
        if !self.covers(x, y) {
            return (0.0, [0.0, 0.0]);
        }
        let wave_number = PI / self.length;
        let phase = wave_number * (x - self.x_start);
        // The side boundary y = 0 is a step in h; away from it the bump does not vary with y.
        (self.height * phase.sin(), [self.height * wave_number * phase.cos(), 0.0])
    }
}

impl HalfSineBump {
    /// The profile averaged over a window of `width` along x (a moving average), which is C¹ where the
    /// profile is only C⁰: h̄(x) = (1/w) ∫ h over [x − w/2, x + w/2], h̄'(x) = (h(x + w/2) − h(x − w/2))/w.
    /// It differs from h by at most (π H/W)·w/8 next to an edge.
    fn averaged(&self, x: f64, y: f64, width: f64) -> (f64, [f64; 2]) {
        if !self.on_its_side(y) {
            return (0.0, [0.0, 0.0]);
        }
        let wave_number = PI / self.length;
        let end = self.x_start + self.length;
        let (a, c) = ((x - 0.5 * width).clamp(self.x_start, end), (x + 0.5 * width).clamp(self.x_start, end));
        let height = self.height / (wave_number * width)
            * ((wave_number * (a - self.x_start)).cos() - (wave_number * (c - self.x_start)).cos());
        let slope =
            (self.height_and_gradient(x + 0.5 * width, y).0 - self.height_and_gradient(x - 0.5 * width, y).0) / width;
        (height, [slope, 0.0])
    }
}

/// A road seen through a moving average of `width` along x: C¹ edges for finite-difference derivatives
/// (the simulation's fast-mode check), which would otherwise straddle a C⁰ edge and see an arbitrarily
/// large slope. (The integration itself uses the road as it is.)
pub struct EdgeAveraged<'a> {
    pub road: &'a RoadModel,
    pub width: f64,
}

impl Road for EdgeAveraged<'_> {
    fn height_and_gradient(&self, x: f64, y: f64) -> (f64, [f64; 2]) {
        match self.road {
            RoadModel::Flat => (0.0, [0.0, 0.0]),
            RoadModel::Bumps(bumps) => sum_averaged(bumps, x, y, self.width),
            // A bilinear grid's slope jumps at every grid line: a finite difference straddling one (a wheel
            // standing on a grid line) would read a stiffness that is no mode. Averaged over the width with
            // the enveloping quadrature, whose slope is continuous (a difference of box averages).
            RoadModel::Surface(_) | RoadModel::Map(_) => {
                let file = self.road.file().expect("a file road");
                surface::enveloped_by_quadrature(file, x, y, self.width)
            }
        }
    }
}

fn sum_averaged(bumps: &[HalfSineBump], x: f64, y: f64, width: f64) -> (f64, [f64; 2]) {
    bumps.iter().fold((0.0, [0.0, 0.0]), |(h, [hx, hy]), bump| {
        let (bh, [bx, by]) = bump.averaged(x, y, width);
        (h + bh, [hx + bx, hy + by])
    })
}

/// The roads the model ships (an enum so a simulation stays plain data).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum RoadModel {
    Flat,
    Bumps(Vec<HalfSineBump>),
    /// An OpenCRG file or an ISO 8608 random road, placed (`road::crg`); rebuilt from the configuration,
    /// never serialized.
    #[serde(skip)]
    Surface(crg::PlacedSurface),
    /// A road of an OpenDRIVE map, placed (`road::xodr`); rebuilt from the configuration, never serialized.
    #[serde(skip)]
    Map(xodr::PlacedMap),
}

/// Bump geometry of the paper's course [P, docs/physics.md §8.3].
pub const PAPER_BUMP_LENGTH_M: f64 = 0.5;
pub const PAPER_BUMP_HEIGHT_M: f64 = 0.05;
/// Leading edges, measured from the initial front wheel centres: left wheels, then right wheels.
const PAPER_BUMPS_LEFT_M: [f64; 2] = [10.0, 14.0];
const PAPER_BUMPS_RIGHT_M: [f64; 2] = [11.0, 15.0];

impl RoadModel {
    /// The road file behind this road, if it came from one.
    pub fn file(&self) -> Option<&dyn FileRoad> {
        match self {
            RoadModel::Surface(surface) => Some(surface),
            RoadModel::Map(map) => Some(map),
            RoadModel::Flat | RoadModel::Bumps(_) => None,
        }
    }

    /// The road a specification names (an OpenCRG file, `iso8608:…`, or an OpenDRIVE map `FILE.xodr[#ROAD]`),
    /// its start (reference line start, v = 0) at ground point `anchor`, heading along ground x.
    pub fn from_file(spec: &str, anchor: [f64; 2]) -> Result<RoadModel, String> {
        Ok(if xodr::is_xodr(spec) {
            RoadModel::Map(xodr::PlacedMap::new(xodr::load(spec)?, anchor))
        } else {
            RoadModel::Surface(crg::PlacedSurface::new(crg::surface_for(spec)?, anchor))
        })
    }

    /// The paper's unsymmetric bump course: 0.5 m long, 5 cm high; left wheels at 10 m and 14 m, right at
    /// 11 m and 15 m, leading edges measured from `front_wheel_x0` (the initial front wheel centres).
    pub fn paper_bump_course(front_wheel_x0: f64) -> RoadModel {
        RoadModel::bump_course(front_wheel_x0, PAPER_BUMP_HEIGHT_M, PAPER_BUMP_LENGTH_M)
    }

    /// The paper's course (bump positions and sides) with bumps of another height and length.
    pub fn bump_course(front_wheel_x0: f64, height: f64, length: f64) -> RoadModel {
        let bump = |offset: f64, side: f64| HalfSineBump { x_start: front_wheel_x0 + offset, length, height, side };
        let left = PAPER_BUMPS_LEFT_M.iter().map(|&x| bump(x, 1.0));
        let right = PAPER_BUMPS_RIGHT_M.iter().map(|&x| bump(x, -1.0));
        RoadModel::Bumps(left.chain(right).collect())
    }
}

impl RoadModel {
    /// Where the road's height has a C⁰ edge across the path of a point at (x, y) moving along x (the
    /// paper's bumps: each half-sine's start and end, on its side): x less the edge nearest to x, so that
    /// it crosses zero upward at each edge in turn (and jumps down halfway between two). `None` on roads
    /// without such edges: flat, and the file roads, whose bilinear grids have a kink at every node (the
    /// enveloping contact rounds them).
    pub fn edge_offset(&self, x: f64, y: f64) -> Option<f64> {
        let RoadModel::Bumps(bumps) = self else { return None };
        bumps
            .iter()
            .filter(|b| b.on_its_side(y))
            .flat_map(|b| [x - b.x_start, x - (b.x_start + b.length)])
            .reduce(|a, b| if b.abs() < a.abs() { b } else { a })
    }
}

impl Road for RoadModel {
    fn height_and_gradient(&self, x: f64, y: f64) -> (f64, [f64; 2]) {
        match self {
            RoadModel::Flat => (0.0, [0.0, 0.0]),
            // Sum over the bumps (§6.1); overlapping bumps add up.
            RoadModel::Bumps(bumps) => bumps.iter().fold((0.0, [0.0, 0.0]), |(h, [hx, hy]), bump| {
                let (bh, [bx, by]) = bump.height_and_gradient(x, y);
                (h + bh, [hx + bx, hy + by])
            }),
            RoadModel::Surface(surface) => surface.height_and_gradient(x, y),
            RoadModel::Map(map) => map.height_and_gradient(x, y),
        }
    }

    fn off_road(&self, x: f64, y: f64) -> Option<String> {
        match self {
            RoadModel::Surface(surface) => surface.off_road(x, y),
            RoadModel::Map(map) => map.off_road(x, y),
            RoadModel::Flat | RoadModel::Bumps(_) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRACK_HALF: f64 = 0.9; // |y| of a wheel, roughly the HMMWV half-track

    fn height(road: &RoadModel, x: f64, y: f64) -> f64 {
        road.height_and_gradient(x, y).0
    }

    /// At each edge of a bump itself the road is the side its indicator calls not yet crossed (offset 0 ≤ 0):
    /// at the start the level road's slope, at the end the bump's; just past either, the other side's.
    #[test]
    fn an_edge_itself_is_on_the_side_its_indicator_has_not_crossed() {
        let road = RoadModel::paper_bump_course(0.0);
        let RoadModel::Bumps(bumps) = &road else { panic!("bumps") };
        let b = bumps.iter().find(|b| b.on_its_side(TRACK_HALF)).expect("a bump on this side");
        let (start, end) = (b.x_start, b.x_start + b.length);
        let slope = |x: f64| road.height_and_gradient(x, TRACK_HALF).1[0];
        assert_eq!(road.edge_offset(start, TRACK_HALF), Some(0.0));
        assert_eq!(slope(start), 0.0);
        assert!(slope(start.next_up()) > 0.0);
        assert_eq!(road.edge_offset(end, TRACK_HALF), Some(0.0));
        assert!(slope(end) < 0.0);
        assert_eq!(slope(end.next_up()), 0.0);
    }

    #[test]
    fn edge_averaged_road_is_c1_and_close_to_the_profile() {
        let road = RoadModel::paper_bump_course(0.0);
        let width = 0.002;
        let avg = EdgeAveraged { road: &road, width };
        let bound = PI * 0.05 / 0.5 * width / 8.0 * 1.0001;
        let step = 1e-6;
        for i in 0..4000 {
            let x = 9.99 + 0.52 * f64::from(i) / 4000.0;
            let (h, [hx, _]) = avg.height_and_gradient(x, TRACK_HALF);
            assert!((h - height(&road, x, TRACK_HALF)).abs() <= bound, "x = {x}: averaged {h}");
            // The gradient is the derivative of the averaged height (central difference, 1e-6 m)...
            let fd = (avg.height_and_gradient(x + step, TRACK_HALF).0
                - avg.height_and_gradient(x - step, TRACK_HALF).0)
                / (2.0 * step);
            assert!((hx - fd).abs() < 1e-4, "x = {x}: {hx} vs {fd}");
        }
        // ... and continuous across the edge (the exact profile's slope jumps by πH/W = 0.314 there).
        let slope = |x: f64| avg.height_and_gradient(x, TRACK_HALF).1[0];
        assert!((slope(10.0 + 1e-9) - slope(10.0 - 1e-9)).abs() < 1e-5);
        assert!((slope(10.5 + 1e-9) - slope(10.5 - 1e-9)).abs() < 1e-5);
    }

    #[test]
    fn the_edge_offset_crosses_zero_upward_at_each_edge_of_the_wheels_side() {
        let road = RoadModel::paper_bump_course(1.0);
        // Left wheels: edges at 11, 11.5, 15, 15.5; the offset is x less the nearest.
        for (x, offset) in
            [(10.0, -1.0), (11.0, 0.0), (11.2, 0.2), (11.3, -0.2), (13.0, 1.5), (13.5, -1.5), (16.0, 0.5)]
        {
            assert!((road.edge_offset(x, TRACK_HALF).unwrap() - offset).abs() < 1e-12, "x = {x}");
        }
        // Right wheels: edges at 12, 12.5, 16, 16.5.
        assert!((road.edge_offset(11.9, -TRACK_HALF).unwrap() + 0.1).abs() < 1e-12);
        assert_eq!(RoadModel::Flat.edge_offset(11.0, TRACK_HALF), None);
    }

    #[test]
    fn flat_road_is_zero_everywhere() {
        for &(x, y) in &[(0.0, 0.0), (12.3, -4.0), (-1e3, 7.0)] {
            assert_eq!(RoadModel::Flat.height_and_gradient(x, y), (0.0, [0.0, 0.0]));
        }
    }

    #[test]
    fn paper_course_heights_and_sides() {
        let x0 = 1.7;
        let road = RoadModel::paper_bump_course(x0);
        // Peaks (mid-bump) on the side each bump belongs to; nothing on the other side.
        for &(offset, side) in &[(10.0, 1.0), (14.0, 1.0), (11.0, -1.0), (15.0, -1.0)] {
            let mid = x0 + offset + 0.25;
            assert!((height(&road, mid, side * TRACK_HALF) - 0.05).abs() < 1e-15, "peak at {offset}");
            assert_eq!(height(&road, mid, -side * TRACK_HALF), 0.0, "other side at {offset}");
            // Quarter point: 0.05 sin(pi/4).
            let quarter = x0 + offset + 0.125;
            let expected = 0.05 * (PI / 4.0).sin();
            assert!((height(&road, quarter, side * TRACK_HALF) - expected).abs() < 1e-15);
        }
        // Before, between and after the bumps, and exactly on the centre line: flat.
        for &x in &[x0, x0 + 9.99, x0 + 10.51, x0 + 12.0, x0 + 15.51, x0 + 30.0] {
            assert_eq!(height(&road, x, TRACK_HALF), 0.0, "left at {x}");
            assert_eq!(height(&road, x, -TRACK_HALF), 0.0, "right at {x}");
        }
        assert_eq!(height(&road, x0 + 10.25, 0.0), 0.0);
        // The edges are the leading/trailing zeros of the sine (C⁰ profile).
        assert!(height(&road, x0 + 10.0, TRACK_HALF).abs() < 1e-15);
        assert!(height(&road, x0 + 10.5, TRACK_HALF).abs() < 1e-15);
    }

    #[test]
    fn gradient_matches_finite_difference() {
        let road = RoadModel::paper_bump_course(0.0);
        // Central difference error is h_step² H (pi/W)³ / 6 ≈ 1e-12 for h_step = 1e-5; allow 1e-8
        // (round-off 1e-17/1e-5 is far below that too).
        let step = 1e-5;
        for i in 1..50 {
            let x = 10.0 + 0.5 * f64::from(i) / 50.0;
            let (_, [hx, hy]) = road.height_and_gradient(x, TRACK_HALF);
            let fd = (height(&road, x + step, TRACK_HALF) - height(&road, x - step, TRACK_HALF)) / (2.0 * step);
            assert!((hx - fd).abs() < 1e-8, "x = {x}: analytic {hx}, fd {fd}");
            assert_eq!(hy, 0.0);
        }
        // Steepest just past the leading edge: H pi / W = 0.1 pi (at the edge itself the road is still level:
        // `an_edge_itself_is_on_the_side_its_indicator_has_not_crossed`).
        let (_, [hx, _]) = road.height_and_gradient(10.0f64.next_up(), TRACK_HALF);
        assert!((hx - 0.1 * PI).abs() < 1e-12);
    }

    #[test]
    fn overlapping_bumps_add_up() {
        let bump = HalfSineBump { x_start: 0.0, length: 1.0, height: 0.1, side: 1.0 };
        let road = RoadModel::Bumps(vec![bump.clone(), HalfSineBump { height: 0.2, ..bump }]);
        let (h, [hx, _]) = road.height_and_gradient(0.25, 1.0);
        assert!((h - 0.3 * (PI / 4.0).sin()).abs() < 1e-15);
        assert!((hx - 0.3 * PI * (PI / 4.0).cos()).abs() < 1e-14);
    }

    #[test]
    fn degenerate_bump_is_ignored() {
        let road = RoadModel::Bumps(vec![HalfSineBump { x_start: 0.0, length: 0.0, height: 0.1, side: 1.0 }]);
        assert_eq!(road.height_and_gradient(0.0, 1.0), (0.0, [0.0, 0.0]));
    }
}
