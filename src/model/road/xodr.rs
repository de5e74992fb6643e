//! Roads from OpenDRIVE maps (`.xodr`), docs/roads.md "OpenDRIVE".
//!
//! The map is read by the `xodr` crate (pure Rust): XML, includes, every element's checks and its warnings
//! (`Provenance`). The crate answers "the surface under a wheel" from a mesh of `f32` vertices, which is
//! for drawing: faceted (the slope jumps at every triangle edge, which the step check would read as stiff
//! wheel modes) and rounded to 1e-5 m at a few hundred metres from the origin. The contact needs heights
//! and slopes in double precision, so this module evaluates the records the crate parsed, read through the
//! crate's serde form (its documented "records the file gives"), in `f64`:
//!
//! - **Reference line**: lines and arcs in closed form; clothoids (spirals) by 8-point Gauss–Legendre
//!   quadrature of the heading from knots at most 2 m (and 0.5 rad of turn) apart, computed at load;
//!   paramPoly3 (and poly3) by the arc length of the cubic curve (Gauss–Legendre per interval, Newton for
//!   the parameter at a given s). Beyond either end the line continues straight along its end heading.
//! - **Position on the road**: a ground point's (s, d) by Newton's method on (P − r(s))·T(s) = 0 to
//!   1e-12 m, from the nearest of the line's passes through the 16 m cells around the point.
//! - **Height**: elevation(s) + d·tan(superelevation(s)): the cross-section rolled about the reference line
//!   by the superelevation angle, d the horizontal offset (OpenDRIVE's t along the surface is d / cos φ).
//!   Its gradient is exact: ∂h/∂s / (1 − κ d) along the tangent and tan φ across. Beyond the ends the
//!   profiles keep their end values.
//! - **Extent**: s in [0, length] and t between the outer edges of the permanent lanes (lane widths and
//!   laneOffset). Outside, the surface continues as above and the simulation logs an event.
//! - **Refused, named**: lateral `<shape>`, `<crossSectionSurface>`, `<crossfall>` and junction elevation
//!   grids (the contact would meet another surface than the file's); OpenCRG surfaces in modes other than
//!   `attached`/`attached0`.
//! - **OpenCRG surfaces** (`<surface><CRG>`, modes `attached` and `attached0`, purpose elevation) on the
//!   driven road: read by `road::crg` (the same bounded reader and checks as a `.crg` road), evaluated at
//!   u = s − sOffset, v = t − tOffset (negated for `orientation="opposite"`). `attached` adds zScale times
//!   the grid's height to the road's; `attached0` replaces the road's height by zScale times the file's
//!   elevation. zOffset is added in both.
//!
//! - **Loops**: where the driven road's successors (`<link><successor>`, entered at their start) lead back
//!   to it, the roads are joined into one road whose s wraps (`looped`).
//!
//! One road is driven: the first in the file, or the one named by `FILE.xodr#ID`. The vehicle starts
//! `START_BEHIND_REAR_AXLE_M` along it, heading along its reference line, on the line or, where the road
//! has lanes on one side of it only, in the middle of its width (`MapRoad::start_offset`); the map is
//! shifted so that the road's height there is the ground frame's zero.
use super::crg::Surface;
use super::surface::{FileRoad, Placement, Road};
use serde::Deserialize;
use std::path::Path;
use std::sync::Arc;

/// The largest map read: 256 MiB (Town-sized maps are a few MB; the crate bounds its includes itself).
pub const MAX_XODR_BYTES: u64 = 256 << 20;

/// Knot spacing of a clothoid's precomputed points, m, and the most it turns between two knots, rad.
const SPIRAL_KNOT_M: f64 = 2.0;
const SPIRAL_KNOT_TURN: f64 = 0.5;
/// Spacing of the reference-line samples that start the projection, m, and of the index's cells.
const SAMPLE_M: f64 = 1.0;
const CELL_M: f64 = 16.0;

/// 8-point Gauss–Legendre nodes on [−1, 1] (positive half) and weights.
const GL_X: [f64; 4] =
    [0.183_434_642_495_649_8, 0.525_532_409_916_329, 0.796_666_477_413_626_7, 0.960_289_856_497_536_3];
const GL_W: [f64; 4] =
    [0.362_683_783_378_362, 0.313_706_645_877_887_3, 0.222_381_034_453_374_5, 0.101_228_536_290_376_3];

/// ∫_a^b f by 8-point Gauss–Legendre.
fn gauss(a: f64, b: f64, f: impl Fn(f64) -> [f64; 2]) -> [f64; 2] {
    let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
    let mut sum = [0.0; 2];
    for (x, w) in GL_X.iter().zip(GL_W) {
        for p in [mid - half * x, mid + half * x] {
            let v = f(p);
            sum[0] += w * v[0];
            sum[1] += w * v[1];
        }
    }
    [sum[0] * half, sum[1] * half]
}

// --- The crate's records (its serde form) -----------------------------------------------------------------

#[derive(Deserialize, Clone, Copy, Debug)]
struct Cubic {
    start: f64,
    a: f64,
    b: f64,
    c: f64,
    d: f64,
}

impl Cubic {
    fn eval(&self, s: f64) -> (f64, f64) {
        let x = s - self.start;
        (self.a + x * (self.b + x * (self.c + x * self.d)), self.b + x * (2.0 * self.c + 3.0 * x * self.d))
    }
}

/// The record of `records` (sorted by start) active at `s`, value and rate; (0, 0) before the first.
fn profile(records: &[Cubic], s: f64) -> (f64, f64) {
    let i = records.partition_point(|r| r.start <= s + 1e-9);
    if i == 0 {
        (0.0, 0.0)
    } else {
        records[i - 1].eval(s)
    }
}

#[derive(Deserialize, Debug)]
enum Shape {
    Line,
    Arc { curvature: f64 },
    Spiral { curv_start: f64, curv_end: f64 },
    ParamPoly3 { u: [f64; 4], v: [f64; 4], p_max: f64 },
}

#[derive(Deserialize, Debug)]
struct GeomRecord {
    s: f64,
    x: f64,
    y: f64,
    hdg: f64,
    length: f64,
    shape: Shape,
}

#[derive(Deserialize, Debug, Default)]
struct LateralRecords {
    #[serde(default)]
    profiles: Vec<serde_json::Value>,
    #[serde(default)]
    surface: Option<serde_json::Value>,
    #[serde(default)]
    ground: Option<serde_json::Value>,
    #[serde(default)]
    crossfall: Vec<serde_json::Value>,
}

#[derive(Deserialize, Debug)]
enum LaneExtent {
    Width(Vec<Cubic>),
    Border(Vec<Cubic>),
}

#[derive(Deserialize, Debug)]
struct LaneRecord {
    extent: LaneExtent,
}

#[derive(Deserialize, Debug)]
struct SectionRecord {
    layer: String,
    start: f64,
    end: f64,
    #[serde(default)]
    left: Vec<LaneRecord>,
    #[serde(default)]
    right: Vec<LaneRecord>,
}

#[derive(Deserialize, Debug)]
struct RoadRecords {
    od_id: String,
    length: f64,
    geoms: Vec<GeomRecord>,
    #[serde(default)]
    elevations: Vec<Cubic>,
    #[serde(default)]
    superelevations: Vec<Cubic>,
    lateral: LateralRecords,
    #[serde(default)]
    lane_offsets: Vec<Cubic>,
    #[serde(default)]
    sections: Vec<SectionRecord>,
}

// --- The reference line in f64 ------------------------------------------------------------------------------

/// A point of the reference line: position, heading (with its cosine and sine) and curvature.
#[derive(Clone, Copy, Debug)]
struct Pose {
    x: f64,
    y: f64,
    heading: f64,
    cos: f64,
    sin: f64,
    curvature: f64,
}

impl Pose {
    fn new(x: f64, y: f64, heading: f64, curvature: f64) -> Pose {
        let (sin, cos) = heading.sin_cos();
        Pose { x, y, heading, cos, sin, curvature }
    }

    /// The pose `by` metres further along the tangent (a straight continuation).
    fn straight_on(self, by: f64) -> Pose {
        Pose { x: self.x + by * self.cos, y: self.y + by * self.sin, curvature: 0.0, ..self }
    }
}

/// One `<geometry>` record, ready to evaluate.
#[derive(Debug)]
struct Geometry {
    s: f64,
    x: f64,
    y: f64,
    hdg: f64,
    /// cos and sin of `hdg`.
    cos: f64,
    sin: f64,
    length: f64,
    kind: Kind,
}

#[derive(Debug)]
enum Kind {
    Line,
    Arc {
        curvature: f64,
    },
    /// Curvature k0 + rate·σ; `knots[i]` is the offset from the start at σ = i·spacing.
    Spiral {
        k0: f64,
        rate: f64,
        spacing: f64,
        knots: Vec<[f64; 2]>,
    },
    /// u(p), v(p) in the record's frame, p in [0, p_max]; `table[i]` = (p_i, arc length to p_i).
    ParamPoly3 {
        u: [f64; 4],
        v: [f64; 4],
        table: Vec<(f64, f64)>,
    },
}

fn cubic(c: &[f64; 4], p: f64) -> [f64; 3] {
    [c[0] + p * (c[1] + p * (c[2] + p * c[3])), c[1] + p * (2.0 * c[2] + 3.0 * p * c[3]), 2.0 * c[2] + 6.0 * p * c[3]]
}

impl Geometry {
    fn new(g: &GeomRecord) -> Result<Geometry, String> {
        let kind = match g.shape {
            Shape::Line => Kind::Line,
            Shape::Arc { curvature } => Kind::Arc { curvature },
            Shape::Spiral { curv_start, curv_end } => {
                let rate = if g.length > 0.0 { (curv_end - curv_start) / g.length } else { 0.0 };
                let turn = curv_start.abs().max(curv_end.abs());
                let spacing = SPIRAL_KNOT_M.min(SPIRAL_KNOT_TURN / turn.max(1e-12));
                let n = (g.length / spacing).ceil().max(1.0);
                if n > 1e7 {
                    return Err(format!("a spiral of {} m turning {turn} 1/m is beyond the evaluator", g.length));
                }
                let heading = |s: f64| curv_start * s + 0.5 * rate * s * s;
                let mut knots = vec![[0.0, 0.0]];
                for i in 0..n as usize {
                    let (a, b) = (i as f64 * spacing, ((i + 1) as f64 * spacing).min(g.length));
                    let [dx, dy] = gauss(a, b, |s| [heading(s).cos(), heading(s).sin()]);
                    let last = knots[knots.len() - 1];
                    knots.push([last[0] + dx, last[1] + dy]);
                }
                Kind::Spiral { k0: curv_start, rate, spacing, knots }
            }
            Shape::ParamPoly3 { u, v, p_max } => {
                if !(p_max > 0.0) {
                    return Err(format!("a paramPoly3 with parameter range {p_max}"));
                }
                let n = (g.length / SAMPLE_M).ceil().clamp(8.0, 1e7) as usize;
                let speed = |p: f64| [cubic(&u, p)[1].hypot(cubic(&v, p)[1]), 0.0];
                let mut table = vec![(0.0, 0.0)];
                for i in 0..n {
                    let (a, b) = (p_max * i as f64 / n as f64, p_max * (i + 1) as f64 / n as f64);
                    let ds = gauss(a, b, speed)[0];
                    table.push((b, table[i].1 + ds));
                }
                Kind::ParamPoly3 { u, v, table }
            }
        };
        let (sin, cos) = g.hdg.sin_cos();
        Ok(Geometry { s: g.s, x: g.x, y: g.y, hdg: g.hdg, cos, sin, length: g.length, kind })
    }

    /// The pose at σ metres from the record's start, 0 ≤ σ ≤ length.
    fn pose(&self, sigma: f64) -> Pose {
        let (x, y, h) = (self.x, self.y, self.hdg);
        let start = Pose { x, y, heading: h, cos: self.cos, sin: self.sin, curvature: 0.0 };
        match &self.kind {
            Kind::Line => start.straight_on(sigma),
            Kind::Arc { curvature: k } if k.abs() < 1e-15 => Pose { curvature: *k, ..start.straight_on(sigma) },
            Kind::Arc { curvature: k } => {
                let end = Pose::new(x, y, h + k * sigma, *k);
                Pose { x: x + (end.sin - self.sin) / k, y: y - (end.cos - self.cos) / k, ..end }
            }
            Kind::Spiral { k0, rate, spacing, knots } => {
                let turn = |s: f64| h + k0 * s + 0.5 * rate * s * s;
                let i = ((sigma / spacing).floor().max(0.0) as usize).min(knots.len() - 1);
                let from = i as f64 * spacing;
                let [dx, dy] = gauss(from, sigma, |s| [turn(s).cos(), turn(s).sin()]);
                // The knots are offsets in the record's own heading-0 frame, turned by h here.
                let [kx, ky] = knots[i];
                let (sin, cos) = (self.sin, self.cos);
                Pose::new(x + cos * kx - sin * ky + dx, y + sin * kx + cos * ky + dy, turn(sigma), k0 + rate * sigma)
            }
            Kind::ParamPoly3 { u, v, table } => {
                let speed = |p: f64| [cubic(u, p)[1].hypot(cubic(v, p)[1]), 0.0];
                let i = table.partition_point(|&(_, len)| len <= sigma).clamp(1, table.len() - 1) - 1;
                let (p0, s0) = table[i];
                let mut p = p0 + (sigma - s0) / speed(p0)[0].max(1e-12);
                for _ in 0..8 {
                    let f = s0 + gauss(p0, p, speed)[0] - sigma;
                    let step = f / speed(p)[0].max(1e-12);
                    p -= step;
                    if step.abs() < 1e-14 * (1.0 + p.abs()) {
                        break;
                    }
                }
                let ([uu, du, ddu], [vv, dv, ddv]) = (cubic(u, p), cubic(v, p));
                let (sin, cos) = (self.sin, self.cos);
                let norm2 = du * du + dv * dv;
                Pose::new(
                    x + cos * uu - sin * vv,
                    y + sin * uu + cos * vv,
                    h + dv.atan2(du),
                    (du * ddv - dv * ddu) / (norm2 * norm2.sqrt()).max(1e-300),
                )
            }
        }
    }
}

/// The driven road: reference line, profiles, lane edges, attached CRG surfaces.
#[derive(Debug)]
pub struct MapRoad {
    pub id: String,
    pub length: f64,
    geoms: Vec<Geometry>,
    elevation: Vec<Cubic>,
    superelevation: Vec<Cubic>,
    lane_offset: Vec<Cubic>,
    /// Permanent lane sections: (start, end, left outer edge records, right outer edge records).
    sections: Vec<Section>,
    crg: Vec<AttachedCrg>,
    /// Reference-line samples (s, x, y) and a grid index over them.
    samples: Vec<(f64, f64, f64)>,
    index: std::collections::HashMap<(i64, i64), Vec<u32>, CellHash>,
    /// A loop (a road whose successor is itself, or a chain of roads whose successors lead back to the
    /// first): s wraps with the period `length`, and these are the roads, in order.
    lap: Option<Vec<String>>,
}

/// The index's hasher: cell coordinates are small integers that no adversary chooses, so a multiply-mix
/// suffices (the default SipHash took 7 % of a run's instructions in the nine lookups per query).
#[derive(Default, Clone, Copy, Debug)]
struct CellHasher(u64);

impl std::hash::Hasher for CellHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.write_u64(u64::from(*b));
        }
    }
    fn write_i64(&mut self, i: i64) {
        self.write_u64(i as u64);
    }
    fn write_u64(&mut self, i: u64) {
        self.0 = (self.0.rotate_left(5) ^ i).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
}

type CellHash = std::hash::BuildHasherDefault<CellHasher>;

#[derive(Debug)]
struct Section {
    start: f64,
    end: f64,
    left: Vec<LaneRecord>,
    right: Vec<LaneRecord>,
}

/// An OpenCRG surface attached to the road (`attached`: added to the road's height; `attached0`: the
/// file's elevation replaces it).
#[derive(Debug)]
struct AttachedCrg {
    surface: Arc<Surface>,
    replaces: bool,
    s_range: [f64; 2],
    s_offset: f64,
    t_offset: f64,
    sign: f64,
    z_offset: f64,
    z_scale: f64,
}

/// A point's place on the road: s along the reference line, d its horizontal offset (left positive), and
/// the line's pose at s.
#[derive(Clone, Copy, Debug)]
struct OnRoad {
    s: f64,
    d: f64,
    pose: Pose,
}

impl MapRoad {
    /// The pose at s; beyond the ends the line continues straight.
    fn pose(&self, s: f64) -> Pose {
        let s = self.wrap(s);
        let first = &self.geoms[0];
        if s < first.s {
            return first.pose(0.0).straight_on(s - first.s);
        }
        let i = self.geoms.partition_point(|g| g.s <= s + 1e-12).max(1) - 1;
        let g = &self.geoms[i];
        let sigma = s - g.s;
        if i + 1 == self.geoms.len() && sigma > g.length {
            return g.pose(g.length).straight_on(sigma - g.length);
        }
        g.pose(sigma.min(g.length))
    }

    /// s on a loop taken into [0, length); s itself on a road with ends.
    fn wrap(&self, s: f64) -> f64 {
        match self.lap {
            Some(_) => s.rem_euclid(self.length),
            None => s,
        }
    }

    fn cell(x: f64, y: f64) -> (i64, i64) {
        ((x / CELL_M).floor() as i64, (y / CELL_M).floor() as i64)
    }

    /// Where Newton's method starts for (x, y): of the reference line's passes through the 3×3 cells around
    /// the point (one sample per pass and cell, the one nearest the cell's centre), the nearest; else the
    /// nearest of all samples (a point far off the road).
    fn start_guess(&self, x: f64, y: f64) -> f64 {
        let distance = |&k: &u32| {
            let (_, sx, sy) = self.samples[k as usize];
            (sx - x).powi(2) + (sy - y).powi(2)
        };
        let (cx, cy) = Self::cell(x, y);
        let near = (-1..=1)
            .flat_map(|i| (-1..=1).map(move |j| (cx + i, cy + j)))
            .filter_map(|c| self.index.get(&c))
            .flatten()
            .min_by(|a, b| distance(a).total_cmp(&distance(b)));
        let k = match near {
            Some(k) => *k,
            None => (0..self.samples.len() as u32).min_by(|a, b| distance(a).total_cmp(&distance(b))).unwrap_or(0),
        };
        self.samples[k as usize].0
    }

    /// A map point's place on the road: Newton's method on the foot point's condition (P − r(s))·T(s) = 0
    /// from the indexed start. The last pose evaluated is the answer's: its tangential residual is below
    /// 1e-12 m.
    fn locate(&self, x: f64, y: f64) -> OnRoad {
        let mut s = self.start_guess(x, y);
        let mut last = None;
        for _ in 0..40 {
            let p = self.pose(s);
            let (wx, wy) = (x - p.x, y - p.y);
            let along = wx * p.cos + wy * p.sin;
            let d = -wx * p.sin + wy * p.cos;
            if along.abs() < 1e-12 {
                return OnRoad { s: self.wrap(s), d, pose: p };
            }
            // d/ds of the tangential offset is −(1 − κ d); keep the step sane where the point lies beyond
            // the centre of curvature (then the projection is not unique anyway).
            s += (along / (1.0 - p.curvature * d).max(0.2)).clamp(-CELL_M, CELL_M);
            last = Some(OnRoad { s, d, pose: p });
        }
        // Not converged in 40 steps (a point far off a tight curve): the last foot point found.
        let on = last.expect("at least one step");
        let p = self.pose(on.s);
        OnRoad { s: self.wrap(on.s), d: -(x - p.x) * p.sin + (y - p.y) * p.cos, pose: p }
    }

    /// The road's own height at (s, d) and its rates along s and d (profiles held beyond the ends).
    /// Also the superelevation angle there.
    fn own_height(&self, s: f64, d: f64) -> (f64, f64, f64, f64) {
        let inside = (0.0..=self.length).contains(&s);
        let sc = s.clamp(0.0, self.length);
        let (z, dz) = profile(&self.elevation, sc);
        let (phi, dphi) = profile(&self.superelevation, sc);
        let (dz, dphi) = if inside { (dz, dphi) } else { (0.0, 0.0) };
        let tan = phi.tan();
        (z + d * tan, dz + d * dphi * (1.0 + tan * tan), tan, phi)
    }

    /// Height and gradient (dh/dx, dh/dy) in the map's axes at map point (x, y).
    fn height_and_gradient(&self, x: f64, y: f64) -> (f64, [f64; 2]) {
        let on = self.locate(x, y);
        let (mut h, mut h_s, mut h_d, phi) = self.own_height(on.s, on.d);
        let t = on.d / phi.cos();
        // Beyond the road's ends or its lanes there is no surface (docs/roads.md, "The road's edge").
        if !self.covers(on.s, t) {
            return (f64::NAN, [f64::NAN; 2]);
        }
        for crg in &self.crg {
            if !(crg.s_range[0]..=crg.s_range[1]).contains(&on.s) {
                continue;
            }
            let uv = opencrg::Uv { u: crg.sign * (on.s - crg.s_offset), v: crg.sign * (t - crg.t_offset) };
            let grid = &crg.surface.grid;
            if crg.replaces {
                let (Some(z), Some(n)) = (grid.elevation_at_uv(uv), grid.normal_at_uv(uv)) else { continue };
                if !(n.z > 0.0) {
                    continue;
                }
                // The normal's slopes are in the file's x, y; along its u and v they are taken from the
                // reference line's heading there.
                let head = grid.heading_at_uv(uv).phi;
                let (gx, gy) = (-n.x / n.z, -n.y / n.z);
                let (du, dv) = (gx * head.cos() + gy * head.sin(), -gx * head.sin() + gy * head.cos());
                h = crg.z_scale * z + crg.z_offset;
                h_s = crg.z_scale * crg.sign * du;
                h_d = crg.z_scale * crg.sign * dv / phi.cos();
            } else if let Some(g) = grid.grid_at_uv(uv) {
                h += crg.z_scale * g.z + crg.z_offset;
                h_s += crg.z_scale * crg.sign * g.dz_du;
                h_d += crg.z_scale * crg.sign * g.dz_dv / phi.cos();
            }
            break;
        }
        let (sin, cos) = (on.pose.sin, on.pose.cos);
        let stretch = 1.0 / (1.0 - on.pose.curvature * on.d);
        let along = h_s * stretch;
        (h, [along * cos - h_d * sin, along * sin + h_d * cos])
    }

    /// The permanent lanes' outer edges at s (t, along the surface), left and right.
    fn edges(&self, s: f64) -> Option<(f64, f64)> {
        let section = self.sections.iter().rev().find(|sec| sec.start <= s + 1e-9 && s <= sec.end + 1e-9)?;
        let ds = s - section.start;
        let offset = profile(&self.lane_offset, s).0;
        let side = |lanes: &[LaneRecord]| {
            let mut width = 0.0f64;
            let mut border = 0.0f64;
            for lane in lanes {
                match &lane.extent {
                    LaneExtent::Width(w) => width += profile(w, ds).0.max(0.0),
                    LaneExtent::Border(b) => border = border.max(profile(b, ds).0.abs()),
                }
            }
            width.max(border)
        };
        Some((offset + side(&section.left), offset - side(&section.right)))
    }

    /// The start's horizontal offset d from the reference line at s = 0: 0 (the line) where the road has
    /// lanes on both sides of it; where the line is the road's edge or off it (lanes on one side only, as
    /// esmini's `slope_up_leaning_right.xodr`), the middle of the road's width there, so that a vehicle
    /// does not start with two wheels beside the road.
    fn start_offset(&self) -> f64 {
        match self.edges(0.0) {
            Some((left, right)) if !(left > 0.0 && right < 0.0) => {
                0.5 * (left + right) * profile(&self.superelevation, 0.0).0.cos()
            }
            _ => 0.0,
        }
    }

    /// Whether (s, t) lies on the road: s within its length, t between its permanent lanes' outer edges.
    fn covers(&self, s: f64, t: f64) -> bool {
        (0.0..=self.length).contains(&s)
            && self.edges(s).is_some_and(|(left, right)| t <= left + 1e-9 && t >= right - 1e-9)
    }

    /// The point's (s, t) on the road (t along the surface, d / cos of the superelevation).
    fn s_t(&self, x: f64, y: f64) -> (f64, f64) {
        let on = self.locate(x, y);
        (on.s, on.d / profile(&self.superelevation, on.s).0.cos())
    }

    fn inside(&self, x: f64, y: f64) -> bool {
        let (s, t) = self.s_t(x, y);
        self.covers(s, t)
    }

    /// What a point off the road left (`Road::off_road`): its s and t and the road's extent there.
    fn off_road(&self, x: f64, y: f64) -> Option<String> {
        let (s, t) = self.s_t(x, y);
        if self.covers(s, t) {
            return None;
        }
        let lanes = match self.edges(s.clamp(0.0, self.length)) {
            Some((left, right)) => format!("t {right:.2}..{left:.2} m at s = {:.2} m", s.clamp(0.0, self.length)),
            None => "no lanes".to_string(),
        };
        let along = match &self.lap {
            Some(roads) => format!("s around a loop of roads {} ({:.2} m a lap)", roads.join(", "), self.length),
            None => format!("s 0..{:.2} m", self.length),
        };
        Some(format!("(s = {s:.2} m, t = {t:.2} m) it is beyond the road, whose extent is {along} and {lanes}"))
    }

    fn from_records(r: RoadRecords, crg: Vec<AttachedCrg>) -> Result<MapRoad, String> {
        let what = |e: &str| format!("road {}: {e}", r.od_id);
        let l = &r.lateral;
        for (present, element) in [
            (!l.profiles.is_empty(), "<lateralProfile><shape>"),
            (l.surface.is_some(), "<lateralProfile><crossSectionSurface>"),
            (l.ground.is_some(), "a junction's elevation grid"),
            (!l.crossfall.is_empty(), "<lateralProfile><crossfall>"),
        ] {
            if present {
                return Err(what(&format!(
                    "uses {element}, which rt-vehicle does not evaluate (the contact would meet another surface \
                     than the file's): elevation, superelevation and OpenCRG surfaces are"
                )));
            }
        }
        let geoms = r.geoms.iter().map(Geometry::new).collect::<Result<Vec<_>, _>>().map_err(|e| what(&e))?;
        if geoms.is_empty() || !(r.length > 0.0) {
            return Err(what("no reference line"));
        }
        let sorted = |mut v: Vec<Cubic>| {
            v.sort_by(|a, b| a.start.total_cmp(&b.start));
            v
        };
        let sections = r
            .sections
            .into_iter()
            .filter(|s| s.layer == "Permanent")
            .map(|s| Section { start: s.start, end: s.end, left: s.left, right: s.right })
            .collect();
        let mut road = MapRoad {
            id: r.od_id.clone(),
            length: r.length,
            geoms,
            elevation: sorted(r.elevations),
            superelevation: sorted(r.superelevations),
            lane_offset: sorted(r.lane_offsets),
            sections,
            crg,
            samples: Vec::new(),
            index: Default::default(),
            lap: None,
        };
        let n = (road.length / SAMPLE_M).ceil() as usize;
        for k in 0..=n {
            let s = (k as f64 * SAMPLE_M).min(road.length);
            let p = road.pose(s);
            if ![p.x, p.y, p.heading].iter().all(|v| v.is_finite()) {
                return Err(what(&format!("its reference line is not finite at s = {s} m")));
            }
            road.samples.push((s, p.x, p.y));
        }
        // Consecutive samples in one cell are one pass of the line through it: keep the one nearest the
        // cell's centre.
        let mut pass: Option<((i64, i64), u32)> = None;
        for k in 0..road.samples.len() as u32 {
            let (_, x, y) = road.samples[k as usize];
            let cell = Self::cell(x, y);
            let off_centre = |k: u32| {
                let (_, x, y) = road.samples[k as usize];
                (x - (cell.0 as f64 + 0.5) * CELL_M).powi(2) + (y - (cell.1 as f64 + 0.5) * CELL_M).powi(2)
            };
            match pass {
                Some((c, best)) if c == cell => {
                    if off_centre(k) < off_centre(best) {
                        *road.index.get_mut(&cell).and_then(|v| v.last_mut()).expect("the pass's entry") = k;
                        pass = Some((cell, k));
                    }
                }
                _ => {
                    road.index.entry(cell).or_default().push(k);
                    pass = Some((cell, k));
                }
            }
        }
        Ok(road)
    }
}

/// A loaded map: its name, the driven road and the crate's warnings.
#[derive(Debug)]
pub struct OpenDrive {
    pub name: String,
    pub road: MapRoad,
    pub warnings: Vec<String>,
}

impl OpenDrive {
    /// Reads `FILE.xodr` or `FILE.xodr#ROAD_ID` (bounded), CRG files relative to the map's folder.
    pub fn load(spec: &str) -> Result<OpenDrive, String> {
        let (file, road_id) = match spec.rsplit_once('#') {
            Some((file, id)) => (file, Some(id)),
            None => (spec, None),
        };
        let path = Path::new(file);
        let text = bounded_read::read_text(path, MAX_XODR_BYTES, &format!("the road file {file}"))?;
        let folder = path.parent().unwrap_or(Path::new("."));
        OpenDrive::from_text(file, &text, road_id, folder)
    }

    /// A map from its text; `folder` resolves the files it names.
    pub fn from_text(name: &str, text: &str, road_id: Option<&str>, folder: &Path) -> Result<OpenDrive, String> {
        let (net, provenance) = xodr::load_str_with_provenance(text).map_err(|e| match e {
            // The crate's word for a map without any road it could build.
            xodr::ImportError::Malformed(m) if m.contains("no lanes") => {
                format!("road file {name}: no road surface to drive on ({m})")
            }
            e => format!("road file {name}: {e}"),
        })?;
        let warnings: Vec<String> =
            provenance.warnings.iter().filter(|w| !w.is_ignored()).map(|w| format!("road file {name}: {w}")).collect();
        let road = match road_id {
            Some(id) => net.road_by_od_id(id).ok_or_else(|| format!("road file {name}: no road with id {id:?}"))?,
            None => net.roads().first().ok_or_else(|| {
                format!("road file {name}: no road surface (no <road> the reader could build: {warnings:?})")
            })?,
        };
        let mut warnings = warnings;
        let chain = match find_loop(&road_links(text), road.od_id()) {
            Ok(chain) => chain,
            Err(w) => {
                warnings.push(format!("road file {name}: {w}"));
                None
            }
        };
        if let Some(chain) = chain {
            match looped(name, &net, &chain, folder)? {
                Ok(road) => return Ok(OpenDrive { name: name.to_string(), road, warnings }),
                Err(w) => warnings.push(format!("road file {name}: {w}")),
            }
        }
        let crg = attached_crg(name, &net, road, folder)?;
        let road = MapRoad::from_records(records_of(name, road)?, crg).map_err(|e| format!("road file {name}: {e}"))?;
        Ok(OpenDrive { name: name.to_string(), road, warnings })
    }
}

/// A road's records, read through the crate's serde form.
fn records_of(name: &str, road: &xodr::Road) -> Result<RoadRecords, String> {
    let value = serde_json::to_value(road).map_err(|e| format!("road file {name}: {e}"))?;
    serde_json::from_value(value)
        .map_err(|e| format!("road file {name}: the xodr crate's road records changed shape: {e}"))
}

/// Each road's `<link><successor>` (elementType, elementId, contactPoint), by road id. The crate keeps the
/// links only as lane links, so the map's text is read again for them; a text the XML reader refuses (the
/// crate read it) gives no links, and no loop.
fn road_links(text: &str) -> std::collections::HashMap<String, [String; 3]> {
    let options = roxmltree::ParsingOptions { allow_dtd: true, ..Default::default() };
    let Ok(doc) = roxmltree::Document::parse_with_options(text, options) else { return Default::default() };
    let mut links = std::collections::HashMap::new();
    for road in doc.root_element().children().filter(|n| n.has_tag_name("road")) {
        let successor = road
            .children()
            .filter(|n| n.has_tag_name("link"))
            .flat_map(|l| l.children())
            .find(|n| n.has_tag_name("successor"));
        if let (Some(id), Some(succ)) = (road.attribute("id"), successor) {
            let attr = |a: &str| succ.attribute(a).unwrap_or("").to_string();
            links.insert(id.to_string(), [attr("elementType"), attr("elementId"), attr("contactPoint")]);
        }
    }
    links
}

/// The loop through road `first`: its successor, that road's successor, … back to `first`, each entered at
/// its start. `Ok(None)` where the chain ends (no successor, a junction, a missing road) or closes
/// without `first`; `Err` names a link the loop cannot follow (a road entered at its end, i.e. driven
/// against its reference line).
fn find_loop(
    links: &std::collections::HashMap<String, [String; 3]>,
    first: &str,
) -> Result<Option<Vec<String>>, String> {
    let mut chain = vec![first.to_string()];
    loop {
        let here = chain.last().expect("the chain starts with the driven road");
        let Some([kind, next, contact]) = links.get(here) else { return Ok(None) };
        if kind != "road" {
            return Ok(None);
        }
        if contact != "start" {
            return Err(format!(
                "road {here}'s successor is road {next} at its {contact:?} (driven against its reference line): \
                 rt-vehicle follows successors entered at their start, so this chain of roads is not followed \
                 and road {first} ends at its end"
            ));
        }
        if next == first {
            return Ok(Some(chain));
        }
        if chain.contains(next) || chain.len() > links.len() {
            return Ok(None);
        }
        chain.push(next.clone());
    }
}

/// The largest gap where one road of a loop ends and the next starts: position and heights, m; heading and
/// superelevation, rad. Beyond them the surface would step at the seam: the loop is not followed.
const LOOP_GAP_M: f64 = 1e-3;
const LOOP_GAP_RAD: f64 = 1e-3;

/// The roads of a loop joined into one road whose s wraps: each road's records shifted by the lengths of
/// the roads before it. `Ok(Err(warning))` where a road does not start where the one before it ends.
fn looped(
    name: &str,
    net: &xodr::RoadNetwork,
    chain: &[String],
    folder: &Path,
) -> Result<Result<MapRoad, String>, String> {
    let mut parts = Vec::new();
    for id in chain {
        let road = net.road_by_od_id(id).ok_or_else(|| format!("road file {name}: no road with id {id:?}"))?;
        // Each road alone: its own checks (refused elements), and its ends for the joints below.
        let alone =
            MapRoad::from_records(records_of(name, road)?, Vec::new()).map_err(|e| format!("road file {name}: {e}"))?;
        parts.push((road, alone));
    }
    for (k, (_, a)) in parts.iter().enumerate() {
        let b = &parts[(k + 1) % parts.len()].1;
        let (end, start) = (a.pose(a.length), b.pose(0.0));
        let turn = (end.heading - start.heading).sin().atan2((end.heading - start.heading).cos());
        let dz = a.own_height(a.length, 0.0).0 - b.own_height(0.0, 0.0).0;
        let dphi = a.own_height(a.length, 0.0).3 - b.own_height(0.0, 0.0).3;
        let gap = (end.x - start.x).hypot(end.y - start.y);
        if gap > LOOP_GAP_M || dz.abs() > LOOP_GAP_M || turn.abs() > LOOP_GAP_RAD || dphi.abs() > LOOP_GAP_RAD {
            return Ok(Err(format!(
                "roads {} close a loop, but road {} starts {gap:.2e} m away from where road {} ends, its heading \
                 turned by {turn:.2e} rad, its height {dz:.2e} m, its superelevation {dphi:.2e} rad (at most \
                 {LOOP_GAP_M} m and {LOOP_GAP_RAD} rad): the loop is not followed",
                chain.join(", "),
                b.id,
                a.id
            )));
        }
    }
    let mut joined = RoadRecords {
        od_id: chain[0].clone(),
        length: 0.0,
        geoms: Vec::new(),
        elevations: Vec::new(),
        superelevations: Vec::new(),
        lateral: LateralRecords::default(),
        lane_offsets: Vec::new(),
        sections: Vec::new(),
    };
    let mut crg = Vec::new();
    for (road, _) in &parts {
        let r = records_of(name, road)?;
        let o = joined.length;
        joined.geoms.extend(r.geoms.into_iter().map(|g| GeomRecord { s: g.s + o, ..g }));
        for (out, records) in [
            (&mut joined.elevations, r.elevations),
            (&mut joined.superelevations, r.superelevations),
            (&mut joined.lane_offsets, r.lane_offsets),
        ] {
            // Before its first record a road's profile is 0, not the previous road's last record.
            if records.iter().all(|c| c.start > 1e-9) {
                out.push(Cubic { start: o, a: 0.0, b: 0.0, c: 0.0, d: 0.0 });
            }
            out.extend(records.into_iter().map(|c| Cubic { start: c.start + o, ..c }));
        }
        joined.sections.extend(r.sections.into_iter().map(|s| SectionRecord {
            start: s.start + o,
            end: s.end + o,
            ..s
        }));
        for mut c in attached_crg(name, net, road, folder)? {
            c.s_range = [c.s_range[0] + o, c.s_range[1] + o];
            c.s_offset += o;
            crg.push(c);
        }
        joined.length += r.length;
    }
    let mut road = MapRoad::from_records(joined, crg).map_err(|e| format!("road file {name}: {e}"))?;
    road.lap = Some(chain.to_vec());
    Ok(Ok(road))
}

/// The OpenCRG surfaces on the driven road: those whose stretch starts on its reference line.
fn attached_crg(
    name: &str,
    net: &xodr::RoadNetwork,
    road: &xodr::Road,
    folder: &Path,
) -> Result<Vec<AttachedCrg>, String> {
    #[derive(Deserialize)]
    struct Station {
        s: f64,
    }
    #[derive(Deserialize)]
    struct Stretch {
        stations: Vec<Station>,
    }
    #[derive(Deserialize)]
    struct Record {
        road: Option<Stretch>,
    }
    let lanes: std::collections::HashSet<_> = net
        .lanes()
        .iter()
        .filter(|l| net.road_lane(l.id).is_some_and(|rl| rl.road == road.id()))
        .map(|l| l.id)
        .collect();
    let mut out = Vec::new();
    for record in net.crg_surfaces() {
        if !record.lanes.iter().any(|l| lanes.contains(l)) {
            continue;
        }
        let (along, replaces) = match record.mode {
            xodr::CrgMode::Attached(a) => (a, false),
            xodr::CrgMode::Attached0(a) => (a, true),
            other => {
                return Err(format!(
                    "road file {name}: the OpenCRG surface {} is in mode {other:?}; rt-vehicle reads attached and \
                     attached0",
                    record.file
                ))
            }
        };
        if record.purpose != xodr::CrgPurpose::Elevation {
            return Err(format!(
                "road file {name}: the OpenCRG surface {} gives friction; rt-vehicle reads elevation surfaces (use \
                 road_friction for a uniform scale)",
                record.file
            ));
        }
        let stretch: Record = serde_json::from_value(serde_json::to_value(record).map_err(|e| e.to_string())?)
            .map_err(|e| format!("road file {name}: the xodr crate's CRG records changed shape: {e}"))?;
        let stations = stretch.road.map(|s| s.stations).unwrap_or_default();
        let (Some(first), Some(last)) = (stations.first(), stations.last()) else {
            return Err(format!("road file {name}: the OpenCRG surface {} covers no stretch of road", record.file));
        };
        let path = folder.join(&record.file);
        let surface = super::crg::load(&path)
            .map_err(|e| format!("road file {name}: its OpenCRG surface {}: {e}", record.file))?;
        out.push(AttachedCrg {
            surface,
            replaces,
            s_range: [first.s, last.s],
            s_offset: along.s_offset,
            t_offset: along.t_offset,
            sign: if along.opposite { -1.0 } else { 1.0 },
            z_offset: record.z_offset,
            z_scale: record.z_scale,
        });
    }
    Ok(out)
}

/// The map placed in the simulation's ground frame: ground (X, Y) ↦ map (x, y) = start + R(heading)·((X, Y) −
/// anchor), heights less the road's height at its start.
#[derive(Debug, Clone)]
pub struct PlacedMap {
    pub map: Arc<OpenDrive>,
    /// The driven road's start at the anchor, heading along ground x.
    pub placement: Placement,
    /// The road's height at its start, the ground's zero.
    z0: f64,
}

impl PartialEq for PlacedMap {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.map, &other.map) && self.placement.anchor == other.placement.anchor
    }
}

impl PlacedMap {
    pub fn new(map: Arc<OpenDrive>, anchor: [f64; 2]) -> PlacedMap {
        let p = map.road.pose(0.0);
        let d = map.road.start_offset();
        let (x, y) = (p.x - d * p.sin, p.y + d * p.cos);
        let z0 = map.road.height_and_gradient(x, y).0;
        PlacedMap { placement: Placement { anchor, origin: [x, y], cos: p.cos, sin: p.sin }, z0, map }
    }
}

impl Road for PlacedMap {
    fn height_and_gradient(&self, x: f64, y: f64) -> (f64, [f64; 2]) {
        let [mx, my] = self.placement.to_file(x, y);
        let (h, gradient) = self.map.road.height_and_gradient(mx, my);
        (h - self.z0, self.placement.gradient_to_ground(gradient))
    }

    fn off_road(&self, x: f64, y: f64) -> Option<String> {
        let [mx, my] = self.placement.to_file(x, y);
        let off = self.map.road.off_road(mx, my)?;
        Some(format!("at x = {x:.2} m, y = {y:.2} m {off} (road {} of {})", self.map.road.id, self.map.name))
    }
}

impl FileRoad for PlacedMap {
    fn name(&self) -> &str {
        &self.map.name
    }

    fn inside(&self, x: f64, y: f64) -> bool {
        let [mx, my] = self.placement.to_file(x, y);
        self.map.road.inside(mx, my)
    }

    fn warnings(&self) -> &[String] {
        &self.map.warnings
    }
}

/// Whether a road specification names an OpenDRIVE map.
pub fn is_xodr(spec: &str) -> bool {
    let file = spec.rsplit_once('#').map_or(spec, |(f, _)| f);
    file.to_ascii_lowercase().ends_with(".xodr")
}

/// A map, loaded once per process (shared like CRG files: same path, road, length and time).
pub fn load(spec: &str) -> Result<Arc<OpenDrive>, String> {
    static LOADED: super::crg::SharedFiles<OpenDrive> = super::crg::SharedFiles::new();
    let (file, road) = spec.rsplit_once('#').unwrap_or((spec, ""));
    LOADED.get(Path::new(file), road, || OpenDrive::load(spec))
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRACK: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/resources/roads/test_track.xodr");

    fn track() -> OpenDrive {
        OpenDrive::load(TRACK).unwrap()
    }

    /// The map point at (s, d) of the road.
    fn at(road: &MapRoad, s: f64, d: f64) -> (f64, f64) {
        let p = road.pose(s);
        (p.x - d * p.sin, p.y + d * p.cos)
    }

    #[test]
    fn each_record_ends_where_the_file_starts_the_next() {
        // scripts/make_test_track.py integrated the clothoids and the paramPoly3 by Simpson's rule on 20 000
        // intervals (an independent method, relative error < 1e-12) to write each record's start.
        let map = track();
        let g = &map.road.geoms;
        for w in g.windows(2) {
            let end = w[0].pose(w[0].length);
            let gap = (end.x - w[1].x).hypot(end.y - w[1].y);
            assert!(gap < 1e-9, "record at s = {}: ends {gap} m from the next start", w[0].s);
            assert!((end.heading - w[1].hdg).abs() < 1e-9, "heading at s = {}", w[1].s);
        }
    }

    #[test]
    fn a_point_off_the_line_is_found_at_its_s_and_d() {
        let road = track().road;
        for k in 0..400 {
            let s = 0.5 + k as f64 * 1.0437;
            let d = -6.0 + (k as f64 * 0.73) % 12.0;
            let (x, y) = at(&road, s, d);
            let on = road.locate(x, y);
            assert!((on.s - s).abs() < 1e-9 && (on.d - d).abs() < 1e-9, "s {s} d {d}: {} {}", on.s, on.d);
        }
    }

    #[test]
    fn heights_and_their_gradient() {
        let road = track().road;
        // The crest's top at s = 90; the banked arc (tan φ = 0.04) at d = 2 m left of the line.
        let (x, y) = at(&road, 90.0, 0.0);
        assert!((road.height_and_gradient(x, y).0 - 1.5).abs() < 1e-12);
        let (x, y) = at(&road, 180.0, 2.0);
        assert!((road.height_and_gradient(x, y).0 - 2.0 * 0.04).abs() < 1e-12);
        // The gradient against central differences over 1e-5 m (truncation ~1e-10 · h''', round-off 1e-11).
        for k in 0..200 {
            let (x, y) = at(&road, 3.0 + k as f64 * 2.07, -5.0 + (k as f64 * 0.37) % 10.0);
            let (_, [gx, gy]) = road.height_and_gradient(x, y);
            let e = 1e-5;
            let fx = (road.height_and_gradient(x + e, y).0 - road.height_and_gradient(x - e, y).0) / (2.0 * e);
            let fy = (road.height_and_gradient(x, y + e).0 - road.height_and_gradient(x, y - e).0) / (2.0 * e);
            assert!((gx - fx).abs() < 1e-8 && (gy - fy).abs() < 1e-8, "at {x} {y}: {gx} {gy} vs {fx} {fy}");
        }
    }

    #[test]
    fn agrees_with_the_crates_own_surface_points() {
        // The crate's road_point (its own evaluator: spirals and paramPoly3 baked into samples, f32 output)
        // checks the conventions independently: t's sign, the heading, the bank's roll. Its f32 rounding at a
        // few hundred metres (3e-5 m at 300 m) and its 0.25 m bake bound the agreement: 2.2e-5 m measured, 1e-4 asked.
        let text = std::fs::read_to_string(TRACK).unwrap();
        let net = xodr::load_str(&text).unwrap();
        let id = net.roads()[0].id();
        let road = track().road;
        for k in 0..80 {
            let (s, t) = (2.0 + k as f64 * 5.2, -4.0 + (k as f64 * 0.61) % 8.0);
            let p = net.road_point(xodr::RoadPosition { road: id, s, t }).unwrap();
            let (x, y) = (f64::from(p.x), f64::from(p.y));
            let on = road.locate(x, y);
            let h = road.height_and_gradient(x, y).0;
            let phi = profile(&road.superelevation, s).0;
            assert!((on.s - s).abs() < 1e-4 && (on.d - t * phi.cos()).abs() < 1e-4, "s {s} t {t}: {on:?}");
            assert!((h - f64::from(p.z)).abs() < 1e-4, "s {s} t {t}: {h} vs {}", p.z);
        }
    }

    #[test]
    fn extent_is_the_lanes() {
        let road = track().road;
        // A 3.75 m lane and a 2.5 m shoulder each side: 6.25 m (on the straight, no bank).
        let inside = |s: f64, d: f64| {
            let (x, y) = at(&road, s, d);
            road.inside(x, y)
        };
        assert!(inside(50.0, 6.2) && inside(50.0, -6.2));
        assert!(!inside(50.0, -6.3) && !inside(50.0, 6.3));
        assert!(!inside(-1.0, 0.0) && !inside(road.length + 1.0, 0.0));
    }

    #[test]
    fn bad_maps_are_named_errors() {
        let text = std::fs::read_to_string(TRACK).unwrap();
        let folder = Path::new(".");
        let no_road = "<OpenDRIVE><header revMajor=\"1\" revMinor=\"6\"/></OpenDRIVE>";
        let shaped = text.replace(
            "<lateralProfile>",
            "<lateralProfile>\n<shape s=\"0\" t=\"-5\" a=\"0\" b=\"0.01\" c=\"0\" d=\"0\"/>",
        );
        let with_crg = text.replace(
            "</lanes>",
            "</lanes><surface><CRG file=\"missing.crg\" sStart=\"0\" sEnd=\"50\" orientation=\"same\" \
             mode=\"attached\" purpose=\"elevation\"/></surface>",
        );
        for (name, body, id, needle) in [
            ("none.xodr", no_road, None, "no road surface"),
            ("garbage.xodr", "<OpenDRIVE><road", None, "garbage.xodr"),
            ("shaped.xodr", shaped.as_str(), None, "<shape>"),
            ("crg.xodr", with_crg.as_str(), None, "missing.crg"),
            ("id.xodr", text.as_str(), Some("7"), "no road with id"),
        ] {
            let e = OpenDrive::from_text(name, body, id, folder).unwrap_err();
            assert!(e.contains(name) && e.contains(needle), "{name}: {e}");
        }
    }
}

#[cfg(test)]
mod loop_tests {
    use super::*;

    const LOOP: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data/roads/circle_50m_loop.xodr");

    fn text() -> String {
        std::fs::read_to_string(LOOP).unwrap()
    }

    fn road(text: &str, id: Option<&str>) -> OpenDrive {
        OpenDrive::from_text("loop.xodr", text, id, Path::new(".")).unwrap()
    }

    /// The file's surface at map point (x, y), from the file's own numbers (a circle of radius 50 m about
    /// (0, 50); the first half, s = R θ up to π R, rises by the smoothstep 1 m (3x² − 2x³), the second falls
    /// back; superelevation −0.05 rad, t along the surface outward negative), independent of the reader.
    fn expected(x: f64, y: f64) -> (f64, f64) {
        let (r, pi) = (50.0, std::f64::consts::PI);
        let theta = (x).atan2(r - y).rem_euclid(2.0 * pi);
        let d = r - x.hypot(y - r);
        let u = (theta % pi) / pi;
        let smooth = 3.0 * u * u - 2.0 * u * u * u;
        let z = if theta < pi { smooth } else { 1.0 - smooth };
        (r * theta, z + d * (-0.05f64).tan())
    }

    /// Two half circles whose successors lead to each other are one loop: every point of the 12 m track,
    /// all around it and across both joints, is on the road at its s (wrapping at 2πR) with the file's
    /// height; the road's start can be either half.
    #[test]
    fn a_loop_of_two_roads_wraps() {
        for id in [None, Some("2")] {
            let map = road(&text(), id);
            let r = &map.road;
            let order: &[&str] = if id.is_some() { &["2", "1"] } else { &["1", "2"] };
            assert_eq!(r.lap.as_ref().unwrap(), order);
            assert!((r.length - 100.0 * std::f64::consts::PI).abs() < 1e-9, "{}", r.length);
            let shift = if id.is_some() { 50.0 * std::f64::consts::PI } else { 0.0 };
            for k in 0..2000 {
                let theta = k as f64 * 2.0 * std::f64::consts::PI / 2000.0 + 1e-7 * (k % 3) as f64;
                let d = -5.5 + (k as f64 * 0.37) % 11.0;
                let (x, y) = ((50.0 - d) * theta.sin(), 50.0 - (50.0 - d) * theta.cos());
                assert!(r.off_road(x, y).is_none(), "{k}: {:?}", r.off_road(x, y));
                let (s, z) = expected(x, y);
                let on = r.locate(x, y);
                let s_expected = (s - shift).rem_euclid(r.length);
                let ds = (on.s - s_expected).abs();
                // 1e-9 m: Newton's tolerance is 1e-12 m, the arc's pose is closed-form.
                assert!(ds.min(r.length - ds) < 1e-9, "{k}: s {} against {s_expected}", on.s);
                let h = r.height_and_gradient(x, y).0;
                assert!((h - z).abs() < 1e-9, "{k}: height {h} against {z}");
            }
        }
    }
}

#[cfg(test)]
mod loop_link_tests {
    use super::loop_tests_text as text;
    use super::*;

    fn load(text: &str) -> OpenDrive {
        OpenDrive::from_text("loop.xodr", text, None, Path::new(".")).unwrap()
    }

    /// One road whose successor is itself, a whole circle in one arc (the file's first half made a whole
    /// circle, linked to itself, level: its smoothstep rise would not meet its start): a loop of one road.
    #[test]
    fn a_road_linked_to_itself_is_a_loop() {
        let pi = std::f64::consts::PI;
        let level = r#"    <elevationProfile><elevation s="0.0" a="0.0" b="0.0" c="0.0" d="0.0"/></elevationProfile>"#;
        let text = text()
            .replace(&format!("length=\"{:?}\"", 50.0 * pi), &format!("length=\"{:?}\"", 100.0 * pi))
            .replace("elementId=\"2\"", "elementId=\"1\"")
            .lines()
            .map(|l| if l.contains("<elevation ") { level } else { l })
            .collect::<Vec<_>>()
            .join("\n");
        let map = load(&text);
        let r = &map.road;
        assert_eq!(r.lap.as_ref().unwrap(), &["1"]);
        assert!((r.length - 100.0 * pi).abs() < 1e-9);
        // Just behind the start (θ = −0.01 rad, 0.5 m) is the lap's end.
        let (x, y) = (50.0 * (-0.01f64).sin(), 50.0 - 50.0 * (-0.01f64).cos());
        assert!(r.off_road(x, y).is_none());
        assert!((r.locate(x, y).s - (r.length - 0.5)).abs() < 1e-9, "{}", r.locate(x, y).s);
    }

    /// Links the loop cannot follow leave a road with ends and a warning naming why: a successor entered
    /// at its end; roads that do not meet (the second half moved 1 cm); a chain that does not come back.
    #[test]
    fn links_the_loop_cannot_follow_are_named() {
        let against = text().replacen("contactPoint=\"start\"", "contactPoint=\"end\"", 1);
        let moved = text().replace("x=\"0.0\" y=\"100.0\"", "x=\"0.01\" y=\"100.0\"");
        let open = text().replacen(r#"<successor elementType="road" elementId="1" contactPoint="start"/>"#, "", 1);
        assert!(moved.contains("0.01") && open.len() < text().len());
        for (name, t, needle) in [
            ("against", against, Some("at its \"end\"")),
            ("moved", moved, Some("starts 1.00e-2 m away from where road 1 ends")),
            ("open", open, None),
        ] {
            let map = load(&t);
            assert!(map.road.lap.is_none(), "{name}");
            assert!((map.road.length - 50.0 * std::f64::consts::PI).abs() < 1e-9, "{name}");
            let warned = map.warnings.iter().find(|w| w.contains("loop") || w.contains("chain"));
            match needle {
                Some(n) => assert!(warned.is_some_and(|w| w.contains(n)), "{name}: {:?}", map.warnings),
                None => assert!(warned.is_none(), "{name}: {:?}", map.warnings),
            }
        }
    }
}

#[cfg(test)]
fn loop_tests_text() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/data/roads/circle_50m_loop.xodr")).unwrap()
}

#[cfg(test)]
mod attached_crg_tests {
    use super::*;
    use crate::model::road::crg::{load as load_crg, PlacedSurface};

    #[test]
    fn an_attached_crg_adds_its_grid_to_the_road() {
        // The shipped RMS course on a straight road on a 1 % grade, against the same CRG file placed on its
        // own (road::crg, checked against PyOpenCRG): the map's heights rise by the grade over the CRG's.
        let roads = concat!(env!("CARGO_MANIFEST_DIR"), "/resources/roads/");
        let map = PlacedMap::new(load(&format!("{roads}rms_course_1in.xodr")).unwrap(), [-2.0, 0.0]);
        let crg = PlacedSurface::new(
            load_crg(Path::new(&format!("{roads}detrended_rms_course_1in.crg"))).unwrap(),
            [-2.0, 0.0],
        );
        let (h0, c0) = (map.height_and_gradient(-2.0, 0.0).0, crg.height_and_gradient(-2.0, 0.0).0);
        assert_eq!(h0, 0.0);
        for k in 0..300 {
            let (x, y) = (-1.5 + k as f64 * 1.6789, -2.9 + (k as f64 * 0.37) % 5.8);
            let (h, [hx, hy]) = map.height_and_gradient(x, y);
            let (c, [cx, cy]) = crg.height_and_gradient(x, y);
            let s = x + 2.0;
            assert!((h - (c - c0 + 0.01 * s)).abs() < 1e-12, "at {x} {y}: {h} vs {}", c - c0 + 0.01 * s);
            assert!((hx - (cx + 0.01)).abs() < 1e-9 && (hy - cy).abs() < 1e-9, "slopes at {x} {y}");
        }
        assert!(map.inside(100.0, 2.9) && !map.inside(100.0, 3.1));
    }
}
