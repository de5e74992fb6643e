//! A path in the ground plane with a speed profile: a polyline of (x, y) points, m, and the speed to hold at
//! each, m/s. Read from a CSV file with the columns `x,y,v` (a header line; `#` starts a comment line).
//!
//! Positions along it are arc lengths s from the first point. Beyond the last point the path goes on along
//! the last segment, at the last speed: a driver at the end of its path drives straight on at that speed.

use serde::{Deserialize, Serialize};

/// At most this many points in a path file (a 1 MiB file holds about 40 000 rows).
pub const MAX_POINTS: usize = 100_000;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Path {
    points: Vec<[f64; 2]>,
    speeds: Vec<f64>,
    /// Arc length at each point, from the first.
    arc: Vec<f64>,
}

/// Where a point lies with respect to the path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    /// Arc length of the nearest point of the path (0 before the start; it grows past the length beyond the
    /// end, along the last segment's extension).
    pub s: f64,
    /// Signed distance from the path, m: positive to the left of its direction of travel.
    pub lateral: f64,
}

impl Path {
    /// A path through `points` with the speed `speeds[k]` at each. Refused with a reason: fewer than two
    /// points, a length mismatch, non-finite values, a negative speed, two consecutive equal points, a
    /// length that is not a finite number (finite points up to ±1.8e308 apart: every distance along the
    /// path would be infinite and the driver's outputs NaN).
    pub fn new(points: Vec<[f64; 2]>, speeds: Vec<f64>) -> Result<Path, String> {
        if points.len() < 2 {
            return Err(format!("a path needs at least two points, it has {}", points.len()));
        }
        if points.len() > MAX_POINTS {
            return Err(format!("a path has at most {MAX_POINTS} points, this one {}", points.len()));
        }
        if speeds.len() != points.len() {
            return Err(format!("{} points but {} speeds", points.len(), speeds.len()));
        }
        for (k, (p, v)) in points.iter().zip(&speeds).enumerate() {
            if !(p[0].is_finite() && p[1].is_finite() && v.is_finite()) {
                return Err(format!("point {}: values must be finite", k + 1));
            }
            if *v < 0.0 {
                return Err(format!("point {}: speed {v} m/s is negative (the driver drives forwards)", k + 1));
            }
        }
        let mut arc = Vec::with_capacity(points.len());
        arc.push(0.0);
        for k in 1..points.len() {
            let len = distance(points[k - 1], points[k]);
            if len <= 0.0 {
                return Err(format!("points {} and {} coincide: a path's segments need a length", k, k + 1));
            }
            let s = arc[k - 1] + len;
            if !s.is_finite() {
                return Err(format!(
                    "the path's length up to point {} overflows ({s} m): coordinates too large",
                    k + 1
                ));
            }
            arc.push(s);
        }
        Ok(Path { points, speeds, arc })
    }

    /// A path at one speed.
    pub fn at_speed(points: Vec<[f64; 2]>, speed: f64) -> Result<Path, String> {
        let speeds = vec![speed; points.len()];
        Path::new(points, speeds)
    }

    /// Parse the CSV text of a path file: a header naming the columns `x`, `y` and `v` (in any order, other
    /// columns ignored), then one row per point. Errors name the line.
    pub fn from_csv(text: &str) -> Result<Path, String> {
        let mut lines =
            text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
        let (_, header) = lines.next().ok_or("the path file is empty (expected a header `x,y,v` and rows)")?;
        let names: Vec<&str> = header.split(',').map(str::trim).collect();
        let column = |name: &str| {
            names.iter().position(|n| *n == name).ok_or_else(|| {
                format!("the header {header:?} has no column {name:?} (expected the columns x, y, v: m, m, m/s)")
            })
        };
        let (cx, cy, cv) = (column("x")?, column("y")?, column("v")?);
        let (mut points, mut speeds) = (Vec::new(), Vec::new());
        for (i, line) in lines {
            if points.len() == MAX_POINTS {
                return Err(format!("line {}: a path has at most {MAX_POINTS} points", i + 1));
            }
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            let value = |c: usize| -> Result<f64, String> {
                let cell = cells
                    .get(c)
                    .ok_or_else(|| format!("line {}: {} columns, expected {}", i + 1, cells.len(), names.len()))?;
                cell.parse::<f64>().map_err(|e| format!("line {}: {cell:?} is not a number: {e}", i + 1))
            };
            points.push([value(cx)?, value(cy)?]);
            speeds.push(value(cv)?);
        }
        Path::new(points, speeds).map_err(|e| format!("the path file: {e}"))
    }

    /// The CSV text `from_csv` reads.
    pub fn to_csv(&self) -> String {
        let mut out = String::from("x,y,v\n");
        for (p, v) in self.points.iter().zip(&self.speeds) {
            out.push_str(&format!("{},{},{}\n", p[0], p[1], v));
        }
        out
    }

    pub fn points(&self) -> &[[f64; 2]] {
        &self.points
    }

    /// The length of the path, m.
    pub fn length(&self) -> f64 {
        *self.arc.last().expect("two points at least")
    }

    /// The nearest point of the path to `p` (a search over all segments: a path crossing itself is followed
    /// where it is nearest).
    pub fn project(&self, p: [f64; 2]) -> Projection {
        let last = self.points.len() - 2;
        let mut best = (f64::INFINITY, Projection { s: 0.0, lateral: 0.0 });
        for k in 0..=last {
            let (a, b) = (self.points[k], self.points[k + 1]);
            let len = self.arc[k + 1] - self.arc[k];
            let (ux, uy) = ((b[0] - a[0]) / len, (b[1] - a[1]) / len);
            let (dx, dy) = (p[0] - a[0], p[1] - a[1]);
            let along = dx * ux + dy * uy;
            // Before the first point and beyond the last the path goes on straight.
            let lo = if k == 0 { f64::NEG_INFINITY } else { 0.0 };
            let hi = if k == last { f64::INFINITY } else { len };
            let t = along.clamp(lo, hi);
            let (ex, ey) = (dx - t * ux, dy - t * uy);
            let d = ex.hypot(ey);
            if d < best.0 {
                let lateral = ux * dy - uy * dx;
                best = (d, Projection { s: (self.arc[k] + t).max(0.0), lateral });
            }
        }
        best.1
    }

    /// The point at arc length `s` (along the last segment's extension beyond the end).
    pub fn point_at(&self, s: f64) -> [f64; 2] {
        let k = self.segment(s);
        let (a, b) = (self.points[k], self.points[k + 1]);
        // Along the segment's unit direction (not a fraction of it: beyond the end of a very short last
        // segment the fraction overflows to inf, and inf × 0 is NaN).
        let (len, along) = (self.arc[k + 1] - self.arc[k], s - self.arc[k]);
        [a[0] + along * ((b[0] - a[0]) / len), a[1] + along * ((b[1] - a[1]) / len)]
    }

    /// The speed to hold at arc length `s`: linear between points, the last speed beyond the end.
    pub fn speed_at(&self, s: f64) -> f64 {
        let k = self.segment(s);
        let f = ((s - self.arc[k]) / (self.arc[k + 1] - self.arc[k])).clamp(0.0, 1.0);
        self.speeds[k] + f * (self.speeds[k + 1] - self.speeds[k])
    }

    /// The segment holding arc length `s` (the first before the start, the last beyond the end).
    fn segment(&self, s: f64) -> usize {
        let n = self.arc.partition_point(|&a| a <= s);
        n.clamp(1, self.points.len() - 1) - 1
    }
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (b[0] - a[0]).hypot(b[1] - a[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn l_path() -> Path {
        Path::new(vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0]], vec![5.0, 10.0, 20.0]).unwrap()
    }

    #[test]
    fn projection_arc_length_and_side() {
        let p = l_path();
        assert_eq!(p.length(), 20.0);
        assert_eq!(p.project([4.0, 1.0]), Projection { s: 4.0, lateral: 1.0 });
        assert_eq!(p.project([4.0, -2.0]), Projection { s: 4.0, lateral: -2.0 });
        // On the second leg (heading +y), x > 10 is to the right.
        assert_eq!(p.project([11.0, 5.0]), Projection { s: 15.0, lateral: -1.0 });
        // Beyond the end the path goes straight on.
        assert_eq!(p.project([10.0, 30.0]), Projection { s: 40.0, lateral: 0.0 });
        assert_eq!(p.point_at(40.0), [10.0, 30.0]);
        // Before the start: s stays at 0.
        assert_eq!(p.project([-5.0, 0.0]).s, 0.0);
    }

    #[test]
    fn speed_profile_is_interpolated_and_held_at_the_end() {
        let p = l_path();
        assert_eq!(p.speed_at(5.0), 7.5);
        assert_eq!(p.speed_at(15.0), 15.0);
        assert_eq!(p.speed_at(100.0), 20.0);
        assert_eq!(p.speed_at(-1.0), 5.0);
    }

    #[test]
    fn far_beyond_a_very_short_last_segment_points_stay_finite() {
        // Found by the C-API fuzz of the driver FMU (a path file with a segment of 5e-324 m and a fast
        // vehicle: the preview point was NaN, and so was every output).
        let p = Path::at_speed(vec![[0.0, 0.0], [5e-324, 0.0]], 10.0).unwrap();
        assert_eq!(p.point_at(1e301), [1e301, 0.0]);
        let q = Path::at_speed(vec![[0.0, 0.0], [0.0, 1e-300]], 10.0).unwrap();
        assert_eq!(q.point_at(2.0), [0.0, 2.0]);
    }

    #[test]
    fn csv_round_trip_and_errors_name_the_line() {
        let p = l_path();
        assert_eq!(Path::from_csv(&p.to_csv()).unwrap(), p);
        let reordered = "# a comment\nv, x, y, note\n5, 0, 0, a\n10, 10, 0, b\n";
        assert_eq!(Path::from_csv(reordered).unwrap().speed_at(0.0), 5.0);
        for (text, why) in [
            ("", "empty"),
            ("x,y\n0,0\n1,0\n", "no column \"v\""),
            ("x,y,v\n0,0,1\n1,zero,1\n", "line 3"),
            ("x,y,v\n0,0,1\n", "at least two points"),
            ("x,y,v\n0,0,1\n0,0,1\n", "coincide"),
            ("x,y,v\n0,0,1\n1,0,-1\n", "negative"),
            ("x,y,v\n0,0,1\n1,0,inf\n", "finite"),
            ("x,y,v\n0,0,1\n1,0\n", "2 columns"),
            ("x,y,v\n-1e308,0,1\n1e308,0,1\n", "overflows"),
        ] {
            let e = Path::from_csv(text).unwrap_err();
            assert!(e.contains(why), "{text:?}: {e}");
        }
    }
}
