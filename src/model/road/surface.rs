//! What every road is (`Road`), what a road read from a file adds (`FileRoad`), how such a file sits in the
//! ground frame (`Placement`), and the enveloping quadrature over any road: the layer every road format and
//! `RoadModel` build on, importing none of them.

/// Height h(x, y) of the road in the ground frame and its gradient (dh/dx, dh/dy).
pub trait Road {
    fn height_and_gradient(&self, x: f64, y: f64) -> (f64, [f64; 2]);

    /// `None` where the road has a surface at (x, y); beyond a road file's defined area (an OpenCRG grid
    /// where the file declares no border mode that continues it, an OpenDRIVE road beyond its ends or its
    /// lanes) what the wheel left: the position in the file's own coordinates and the file's extent. The run
    /// then ends with this as its error (docs/roads.md, "The road's edge"): no surface is invented there.
    fn off_road(&self, _x: f64, _y: f64) -> Option<String> {
        None
    }

    /// The road's friction at (x, y) as a scale on the tires' peak friction (1: the tire data's road). The
    /// shipped roads are uniform; the run's `Options::road_friction` multiplies it.
    fn friction(&self, _x: f64, _y: f64) -> f64 {
        1.0
    }
}

/// A road read from a file (OpenCRG, ISO 8608, OpenDRIVE): it has a name and an extent, whose leaving the
/// simulation reports as an event.
pub trait FileRoad: Road {
    fn name(&self) -> &str;
    /// Whether the ground point lies within the file's extent (beyond it the surface continues as the file
    /// type's documentation says: border modes for OpenCRG, held profiles for OpenDRIVE).
    fn inside(&self, x: f64, y: f64) -> bool;
    /// What the reader dropped or questioned in the file (an OpenDRIVE map's warnings).
    fn warnings(&self) -> &[String] {
        &[]
    }
}

/// How a road file sits in the simulation's ground frame: ground (x, y) ↦ file (x, y) = origin + R(heading)
/// ((x, y) − anchor), the file's start (`origin`, heading along its reference line) at ground point `anchor`,
/// heading along ground x. Shared by the OpenCRG and OpenDRIVE roads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    pub anchor: [f64; 2],
    pub origin: [f64; 2],
    pub cos: f64,
    pub sin: f64,
}

impl Placement {
    /// The file's (x, y) of a ground point.
    pub fn to_file(&self, x: f64, y: f64) -> [f64; 2] {
        let (dx, dy) = (x - self.anchor[0], y - self.anchor[1]);
        [self.origin[0] + self.cos * dx - self.sin * dy, self.origin[1] + self.sin * dx + self.cos * dy]
    }

    /// A gradient in the file's axes turned into the ground's.
    pub fn gradient_to_ground(&self, [gx, gy]: [f64; 2]) -> [f64; 2] {
        [self.cos * gx + self.sin * gy, -self.sin * gx + self.cos * gy]
    }
}

/// The triangular average of a gridded road (no antiderivatives there) by the trapezoidal rule on the
/// nodes s_k = k a/6, k = −6…6. Height: weights (6 − |k|)/36 (the ends weigh 0). Slope along x: the
/// derivative of the triangle average is the difference of two box averages, (∫_0^a h(x+s) ds −
/// ∫_{−a}^0 h(x+s) ds)/a², taken from the same heights, so it is continuous in x wherever the heights are:
/// the sum of the grid's point slopes would jump whenever a node crosses a grid line (a bilinear grid's
/// slope is only piecewise constant), and a finite difference straddling the jump (the step check's, with
/// a wheel standing on a grid line at the start) would read a stiffness of 10⁵ N/m per mm that is no mode.
/// The lateral slope is the weighted sum of the point slopes (nothing moves the nodes across the road).
/// With a ≈ 0.24 m (half the HMMWV's radius) the nodes are 4 cm apart, four grid increments of the
/// shipped half-round files (1 cm), a fifth of their obstacles' 20 cm base.
pub(crate) fn enveloped_by_quadrature(road: &dyn Road, x: f64, y: f64, half_length: f64) -> (f64, [f64; 2]) {
    let spacing = half_length / 6.0;
    let (mut height, mut ahead, mut behind, mut lateral) = (0.0, 0.0, 0.0, 0.0);
    for k in -6i32..=6 {
        let (h, [_, hy]) = road.height_and_gradient(x + f64::from(k) * spacing, y);
        let w = f64::from(6 - k.abs()) / 36.0;
        height += w * h;
        lateral += w * hy;
        // Trapezoid weights of the two box integrals over [0, a] and [−a, 0].
        let edge = if k.abs() == 6 || k == 0 { 0.5 } else { 1.0 };
        if k >= 0 {
            ahead += edge * h;
        }
        if k <= 0 {
            behind += edge * h;
        }
    }
    let slope = (ahead - behind) * spacing / (half_length * half_length);
    (height, [slope, lateral])
}
