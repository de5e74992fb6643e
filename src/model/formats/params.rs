#![allow(non_snake_case)] // field names carry their units (N_per_m), as in the data file
//! Vehicle data file (`resources/hmmwv.json`): serde structs and the checks of the data alone.
//! Reading a file (schema, then these checks, then the suspension loops) is `model::formats::vehicle_file`.
//!
//! Every number the model uses comes from this file. Loading validates what would otherwise surface as a
//! NaN deep inside a function evaluation: missing fields (serde names them), non-positive masses, inertia
//! tensors that are not positive definite (and, in `vehicle_file`, suspension loops that cannot close). The triangle inequality
//! of principal moments is only a warning: the source's control-arm inertias (placeholders) break it.

use crate::model::tire::{StiCoefficients, TireParams};
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigidBody {
    pub mass_kg: f64,
    /// Principal or axis moments [Ixx, Iyy, Izz] about the CM, in the body's data frame.
    pub inertia_moments_kg_m2: [f64; 3],
    /// Products [Ixy, Ixz, Iyz] (positive-sum convention: the tensor holds +Ixy off the diagonal).
    pub inertia_products_kg_m2: [f64; 3],
}

impl RigidBody {
    /// No body: what a solid axle has for its lower arm and upright (the serde default of those fields).
    pub const NONE: RigidBody =
        RigidBody { mass_kg: 0.0, inertia_moments_kg_m2: [0.0; 3], inertia_products_kg_m2: [0.0; 3] };

    fn none() -> RigidBody {
        RigidBody::NONE
    }

    fn is_none(&self) -> bool {
        *self == RigidBody::NONE
    }

    pub fn inertia(&self) -> Matrix3<f64> {
        let [ixx, iyy, izz] = self.inertia_moments_kg_m2;
        let [ixy, ixz, iyz] = self.inertia_products_kg_m2;
        Matrix3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz)
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Chassis {
    pub mass_kg: f64,
    /// Centre of mass in the chassis reference frame.
    pub com_m: [f64; 3],
    pub inertia_moments_kg_m2: [f64; 3],
    pub inertia_products_kg_m2: [f64; 3],
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rack {
    pub mass_kg: f64,
    pub inertia_moments_kg_m2: [f64; 3],
    pub inertia_products_kg_m2: [f64; 3],
    /// Rack centre at zero travel, chassis frame.
    pub com_m: [f64; 3],
    /// Largest rack travel (either way) the steering accepts, m.
    pub travel_limit_m: f64,
    /// Steering gain at centre from the data set, for the kinematics test.
    pub reference_gain_deg_per_m: f64,
}

impl Chassis {
    /// Its mass and inertia as a body.
    pub fn body(&self) -> RigidBody {
        RigidBody {
            mass_kg: self.mass_kg,
            inertia_moments_kg_m2: self.inertia_moments_kg_m2,
            inertia_products_kg_m2: self.inertia_products_kg_m2,
        }
    }
}

impl Rack {
    /// Its mass and inertia as a body.
    pub fn body(&self) -> RigidBody {
        RigidBody {
            mass_kg: self.mass_kg,
            inertia_moments_kg_m2: self.inertia_moments_kg_m2,
            inertia_products_kg_m2: self.inertia_products_kg_m2,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Spring {
    pub free_length_m: f64,
    /// Odd cubic law F = k1 x + k3 x^3, x = L - free length (the data's `derived_cubic_fit`). Both given,
    /// or both absent and `curve` gives the law (`validate` checks which).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k1_N_per_m: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k3_N_per_m3: Option<f64>,
    /// A tabulated law instead of the cubic: F(x) through the points, linear between them as Chrono's
    /// `Spring Curve Data` is (docs/physics.md §5.2, `forces::curve_force`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curve: Option<SpringCurve>,
    /// Bump stop acts below this spring length, rebound stop above `stop_max_length_m` (absent: no stop;
    /// the stop force follows `stop_table`).
    #[serde(default = "no_bump_stop", skip_serializing_if = "is_no_bump_stop")]
    pub stop_min_length_m: f64,
    #[serde(default = "no_rebound_stop", skip_serializing_if = "is_no_rebound_stop")]
    pub stop_max_length_m: f64,
}

/// A spring's force against its deflection x = L − free length, F positive in tension (the element pushes
/// with −F), as Chrono's `Spring Curve Data` gives it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringCurve {
    pub deflection_m: Vec<f64>,
    pub force_N: Vec<f64>,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

impl Spring {
    /// No spring: a rigid suspension's (free length 0 and no law, which `check_spring` refuses elsewhere).
    pub const NONE: Spring = Spring {
        free_length_m: 0.0,
        k1_N_per_m: None,
        k3_N_per_m3: None,
        curve: None,
        stop_min_length_m: f64::NEG_INFINITY,
        stop_max_length_m: f64::INFINITY,
    };

    fn none() -> Spring {
        Spring::NONE
    }

    pub fn is_none(&self) -> bool {
        *self == Spring::NONE
    }
}

impl Damper {
    /// No damper: a rigid suspension's.
    pub const NONE: Damper = Damper {
        midstroke_compression_Ns_per_m: Some(0.0),
        midstroke_rebound_Ns_per_m: Some(0.0),
        bumpstop_compression_Ns_per_m: Some(0.0),
        bumpstop_rebound_Ns_per_m: Some(0.0),
        engagement_min_length_m: Some(0.0),
        engagement_max_length_m: Some(0.0),
        degressivity_compression_s_per_m: 0.0,
        degressivity_rebound_s_per_m: 0.0,
        curve: None,
        map: None,
    };

    fn none() -> Damper {
        Damper::NONE
    }

    pub fn is_none(&self) -> bool {
        *self == Damper::NONE
    }

    /// A damper whose law is `curve` (no rates, no band, no degressivity).
    pub fn of_curve(curve: DamperCurve) -> Damper {
        Damper {
            midstroke_compression_Ns_per_m: None,
            midstroke_rebound_Ns_per_m: None,
            bumpstop_compression_Ns_per_m: None,
            bumpstop_rebound_Ns_per_m: None,
            engagement_min_length_m: None,
            engagement_max_length_m: None,
            degressivity_compression_s_per_m: 0.0,
            degressivity_rebound_s_per_m: 0.0,
            curve: Some(curve),
            map: None,
        }
    }

    /// A damper whose law is the map `map`.
    pub fn of_map(map: DamperMap) -> Damper {
        Damper {
            curve: None,
            map: Some(map),
            ..Damper::of_curve(DamperCurve { velocity_m_per_s: vec![], force_N: vec![] })
        }
    }

    /// The banded law (its absent values 0, which `check_damper` refuses unless a curve replaces them).
    pub fn bands(&self) -> DamperBands {
        let v = |x: Option<f64>| x.unwrap_or(0.0);
        DamperBands {
            midstroke_compression: v(self.midstroke_compression_Ns_per_m),
            midstroke_rebound: v(self.midstroke_rebound_Ns_per_m),
            bumpstop_compression: v(self.bumpstop_compression_Ns_per_m),
            bumpstop_rebound: v(self.bumpstop_rebound_Ns_per_m),
            engagement_min_length: v(self.engagement_min_length_m),
            engagement_max_length: v(self.engagement_max_length_m),
        }
    }

    /// The banded law's six fields, by name.
    fn band_fields(&self) -> [(&'static str, Option<f64>); 6] {
        [
            ("midstroke_compression_Ns_per_m", self.midstroke_compression_Ns_per_m),
            ("midstroke_rebound_Ns_per_m", self.midstroke_rebound_Ns_per_m),
            ("bumpstop_compression_Ns_per_m", self.bumpstop_compression_Ns_per_m),
            ("bumpstop_rebound_Ns_per_m", self.bumpstop_rebound_Ns_per_m),
            ("engagement_min_length_m", self.engagement_min_length_m),
            ("engagement_max_length_m", self.engagement_max_length_m),
        ]
    }
}

fn no_bump_stop() -> f64 {
    f64::NEG_INFINITY
}
fn no_rebound_stop() -> f64 {
    f64::INFINITY
}
fn is_no_bump_stop(v: &f64) -> bool {
    *v == f64::NEG_INFINITY
}
fn is_no_rebound_stop(v: &f64) -> bool {
    *v == f64::INFINITY
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Damper {
    /// The banded law's rates, N s/m, and its mid-stroke band of lengths, m: all six, or none with a `curve`
    /// (`check_damper`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub midstroke_compression_Ns_per_m: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub midstroke_rebound_Ns_per_m: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bumpstop_compression_Ns_per_m: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bumpstop_rebound_Ns_per_m: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub engagement_min_length_m: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub engagement_max_length_m: Option<f64>,
    /// Degressive damping (Chrono's `DegressiveDamperForce`), s/m: each direction's rate c becomes
    /// c/(1 + d·|v|) at the damper's speed v, d the compression's or the rebound's. Absent: 0 (linear).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub degressivity_compression_s_per_m: f64,
    #[serde(default, skip_serializing_if = "is_zero")]
    pub degressivity_rebound_s_per_m: f64,
    /// A tabulated law instead of the bands (Chrono's `Damping Curve Data`, its `NonlinearDamperForce`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curve: Option<DamperCurve>,
    /// A map of the length and the speed instead of the bands (Chrono's `Map Data`, its `MapSpringDamperForce`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub map: Option<DamperMap>,
}

/// The most lengths or speeds a damper map may have (the evaluation gathers its columns on the stack).
pub const MAX_DAMPER_MAP_POINTS: usize = 64;

/// A damper's resisting force (N, with the speed's sign: the element pushes with −F) at each of its lengths
/// and speeds, as Chrono's `MapSpringDamperForce` takes it (`Deformation`, the length less a rest length that
/// is 0 for a shock, and `Map Data`, a row per speed): bilinear between the grid's points and continued
/// linearly past its edges, as Chrono interpolates it (docs/physics.md §5.3; rounded at the grid's lines as a
/// curve is at its knots, `forces::damper_map_force`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DamperMap {
    /// Damper lengths, m, strictly increasing.
    pub length_m: Vec<f64>,
    /// Damper speeds, m/s (positive extending), strictly increasing, with 0 between speeds of both signs.
    pub velocity_m_per_s: Vec<f64>,
    /// For each speed, the force at each length, N.
    pub force_N: Vec<Vec<f64>>,
}

/// A damper's resisting force against its speed v (m/s, positive extending), F with the sign of v (the
/// element pushes with −F), as Chrono's `Damping Curve Data` gives it: linear between the points and held
/// at the end values past them, as Chrono's interpolation holds them (docs/physics.md §5.3).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DamperCurve {
    pub velocity_m_per_s: Vec<f64>,
    pub force_N: Vec<f64>,
}

/// The banded damper law's values, read where `check_damper` has made them present (no curve).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DamperBands {
    pub midstroke_compression: f64,
    pub midstroke_rebound: f64,
    pub bumpstop_compression: f64,
    pub bumpstop_rebound: f64,
    pub engagement_min_length: f64,
    pub engagement_max_length: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceKinematics {
    pub kingpin_inclination_deg: f64,
    pub caster_deg: f64,
    pub camber_gain_deg_per_m: f64,
    pub bump_steer_deg_per_m: f64,
    pub spring_motion_ratio_dLspring_dzwheel: f64,
    pub spring_length_at_design_m: f64,
    pub damper_length_at_design_m: f64,
    pub tierod_length_m: f64,
}

/// The suspension template of an axle (`src/model/suspension/`; docs/vehicle_file.md lists each one's
/// hardpoints and bodies).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SuspensionTemplate {
    /// Short-long arm (SLA): lower and upper control arms on revolute joints, ball joints to the upright,
    /// spring and damper on the lower arm (Chrono's `DoubleWishbone`).
    #[default]
    DoubleWishbone,
    /// Lower control arm on a revolute joint, ball joint to the upright, the strut a cylindrical pair
    /// between the upright and a universal joint at the chassis top mount; spring and damper along the
    /// strut, between chassis and upright (Chrono's `MacPhersonStrut`).
    MacphersonStrut,
    /// One control arm on a revolute joint, the upright on a revolute joint (the kingpin) at its outer end,
    /// about the arm-fixed axis that is the chassis z axis at design; spring and damper on the arm (Chrono's
    /// `SingleWishbone`).
    SingleWishbone,
    /// A solid axle carrying both wheels, located by a triangle (a revolute joint to the chassis about the
    /// chassis y axis, a spherical joint at the axle) and two longitudinal links; spring and damper between
    /// the chassis and the axle (Chrono's `SolidThreeLinkAxle`; not steerable).
    SolidThreeLink,
    /// A solid axle on leaf springs, Chrono's `LeafspringAxle`: the springs' guidance is a joint at the axle's
    /// CM that lets the axle roll about the chassis x axis and slide along its own vertical; spring and damper
    /// between the chassis and the axle (not steerable).
    SolidLeafspring,
    /// A solid axle located by a planar guide at its CM (it rolls about the chassis x axis, its fore-aft
    /// position held) and a Panhard rod, Chrono's `RigidPanhardAxle` (not steerable).
    SolidPanhard,
    /// A steered solid axle located as the three-link axle, its knuckles on kingpins in the axle, turned
    /// through two tie rods by a bellcrank on the axle that a drag link joins to the steering (Chrono's
    /// `SolidBellcrankThreeLinkAxle`; always steered).
    SolidBellcrankThreeLink,
    /// A steered leaf-spring solid axle (Chrono's `ToeBarLeafspringAxle`): the leaf-spring axle's guide, its
    /// knuckles on kingpins in the axle, a toe bar between them and a drag link from the steering to one
    /// knuckle. Always steered.
    SolidToebarLeafspring,
    /// A steered rigid Panhard axle (Chrono's `ToeBarRigidPanhardAxle`: the G500's front): the Panhard axle's
    /// guide and rod, its knuckles, toe bar and drag link as the toe-bar leaf-spring axle's. Always steered.
    SolidToebarPanhard,
    /// No suspension: each spindle turns on a revolute joint fixed to the chassis (Chrono's
    /// `RigidSuspension`: a garden tractor's or a kart's rear axle). No spring, no damper; not steerable.
    Rigid,
    /// One trailing arm per wheel on a revolute joint to the chassis whose axis is swept in plan (between the
    /// pure trailing arm's lateral axis and the swing axle's longitudinal one), the spindle turning on the
    /// arm itself; spring and damper between the chassis and the arm (Chrono's `SemiTrailingArm`: the VW T2's
    /// rear, BMW's). Not steerable.
    SemiTrailingArm,
    /// A trailing arm on a spherical joint to the chassis, held by an upper and a lower link, the spindle
    /// turning on the arm; spring and damper between the chassis and the arm (Chrono's `ThreeLinkIRS`). Not
    /// steerable.
    ThreeLinkIrs,
}

impl SuspensionTemplate {
    pub fn name(self) -> &'static str {
        match self {
            SuspensionTemplate::DoubleWishbone => "double_wishbone",
            SuspensionTemplate::MacphersonStrut => "macpherson_strut",
            SuspensionTemplate::SingleWishbone => "single_wishbone",
            SuspensionTemplate::SolidThreeLink => "solid_three_link",
            SuspensionTemplate::SolidLeafspring => "solid_leafspring",
            SuspensionTemplate::SolidPanhard => "solid_panhard",
            SuspensionTemplate::SolidBellcrankThreeLink => "solid_bellcrank_three_link",
            SuspensionTemplate::SolidToebarLeafspring => "solid_toebar_leafspring",
            SuspensionTemplate::SolidToebarPanhard => "solid_toebar_panhard",
            SuspensionTemplate::Rigid => "rigid",
            SuspensionTemplate::SemiTrailingArm => "semi_trailing_arm",
            SuspensionTemplate::ThreeLinkIrs => "three_link_irs",
        }
    }

    /// The hardpoints an axle of this template must name (left side, chassis reference frame).
    pub fn hardpoints(self) -> &'static [&'static str] {
        match self {
            SuspensionTemplate::DoubleWishbone => &HARDPOINTS,
            SuspensionTemplate::MacphersonStrut => &MACPHERSON_HARDPOINTS,
            SuspensionTemplate::SingleWishbone => &SINGLE_WISHBONE_HARDPOINTS,
            SuspensionTemplate::SolidThreeLink => &SOLID_THREE_LINK_HARDPOINTS,
            SuspensionTemplate::SolidLeafspring => &SOLID_LEAFSPRING_HARDPOINTS,
            SuspensionTemplate::SolidPanhard => &SOLID_PANHARD_HARDPOINTS,
            SuspensionTemplate::SolidBellcrankThreeLink => &SOLID_BELLCRANK_THREE_LINK_HARDPOINTS,
            SuspensionTemplate::SolidToebarLeafspring => &SOLID_TOEBAR_LEAFSPRING_HARDPOINTS,
            SuspensionTemplate::SolidToebarPanhard => &SOLID_TOEBAR_PANHARD_HARDPOINTS,
            SuspensionTemplate::Rigid => &RIGID_HARDPOINTS,
            SuspensionTemplate::SemiTrailingArm => &SEMI_TRAILING_ARM_HARDPOINTS,
            SuspensionTemplate::ThreeLinkIrs => &THREE_LINK_IRS_HARDPOINTS,
        }
    }

    /// Whether one body carries both wheels (a solid axle), rather than one subsystem per wheel.
    pub fn is_solid_axle(self) -> bool {
        matches!(
            self,
            SuspensionTemplate::SolidThreeLink
                | SuspensionTemplate::SolidLeafspring
                | SuspensionTemplate::SolidPanhard
                | SuspensionTemplate::SolidBellcrankThreeLink
                | SuspensionTemplate::SolidToebarLeafspring
                | SuspensionTemplate::SolidToebarPanhard
        )
    }

    /// Whether the template is a solid axle that steers (its knuckles turn on kingpins in the axle).
    pub fn is_steered_solid_axle(self) -> bool {
        matches!(
            self,
            SuspensionTemplate::SolidBellcrankThreeLink
                | SuspensionTemplate::SolidToebarLeafspring
                | SuspensionTemplate::SolidToebarPanhard
        )
    }

    /// Whether the template is a solid axle whose knuckles a toe bar joins (the drag link on one knuckle).
    pub fn has_toe_bar(self) -> bool {
        matches!(self, SuspensionTemplate::SolidToebarLeafspring | SuspensionTemplate::SolidToebarPanhard)
    }

    /// Whether the template is a solid axle located by the Panhard axle's guide and rod.
    pub fn is_panhard(self) -> bool {
        matches!(self, SuspensionTemplate::SolidPanhard | SuspensionTemplate::SolidToebarPanhard)
    }

    /// Whether the wheels are on the chassis itself (no suspension: no coordinate, spring or damper).
    pub fn is_rigid(self) -> bool {
        self == SuspensionTemplate::Rigid
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axle {
    /// The suspension template (default: double wishbone, the HMMWV's).
    #[serde(default)]
    pub template: SuspensionTemplate,
    /// Front tie rods end on the steering (rack or Pitman-arm link); rear toe links end on the chassis.
    pub steered: bool,
    /// Left-side hardpoints in the chassis reference frame (the right side mirrors y).
    pub hardpoints_chassis_frame_m: BTreeMap<String, [f64; 3]>,
    /// Inertia in the arm frame (x = unit(F - B), z normal to the arm plane), rotated at load. Independent
    /// templates only (a solid axle has none: absent).
    #[serde(default = "RigidBody::none", skip_serializing_if = "RigidBody::is_none")]
    pub lower_arm: RigidBody,
    /// Double wishbone only (same frame convention as the lower arm).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub upper_arm: Option<RigidBody>,
    /// MacPherson strut only: the strut (rod) body between the top mount and the upright. Its mass and
    /// inertia (axes parallel to the chassis, CM midway between SPRING_C and SPRING_U) are carried by the
    /// chassis: the rod swings by a few degrees about its top mount.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub strut: Option<RigidBody>,
    /// Inertia in axes parallel to the chassis. Independent templates only (absent for a solid axle).
    #[serde(default = "RigidBody::none", skip_serializing_if = "RigidBody::is_none")]
    pub upright: RigidBody,
    /// Solid axles only: the axle tube (with whatever moves rigidly with it but the spindles, wheels and
    /// tires), its CM at the hardpoint `AXLE_CM`, inertia in axes parallel to the chassis.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axle_tube: Option<RigidBody>,
    /// Inertia [Ixx, Iyy(spin), Izz] parallel to the chassis.
    pub spindle: RigidBody,
    pub axle_shaft_spin_inertia_kg_m2: f64,
    /// Every template's but the rigid suspension's, which has none (absent).
    #[serde(default = "Spring::none", skip_serializing_if = "Spring::is_none")]
    pub spring: Spring,
    #[serde(default = "Damper::none", skip_serializing_if = "Damper::is_none")]
    pub damper: Damper,
    /// Published kinematic figures the model is checked against (the HMMWV's data set; optional).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference_kinematics: Option<ReferenceKinematics>,
    /// Static camber and toe of the wheels at design, deg (Chrono's `Camber Angle (deg)`, `Toe Angle (deg)`):
    /// the spindle's axis turned by Rz(∓toe)·Rx(∓camber) from the chassis y axis (upper sign left, as
    /// `ChDoubleWishbone::InitializeSide`); + camber = top of the wheel outboard, + toe = toe-in. Absent: 0.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub static_camber_deg: f64,
    #[serde(default, skip_serializing_if = "is_zero")]
    pub static_toe_deg: f64,
    /// An anti-roll bar between the axle's two lower arms (optional; `model::suspension::antiroll_bar`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub antiroll_bar: Option<AntirollBar>,
    /// A steered solid axle's bellcrank (Chrono's `SolidBellcrankThreeLinkAxle`): its CM at `BELLCRANK_A`,
    /// inertia in axes parallel to the chassis. Its knuckles are the `upright` (CM at `KNUCKLE_CM`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bellcrank: Option<RigidBody>,
}

/// An anti-roll bar, Chrono's `AntirollBarRSD`: a bar along the chassis y axis, split at the middle by a
/// torsion spring-damper, with an arm on each half; each arm's end is joined by a droplink (a massless
/// distance constraint) to the lower control arm of its side (Chrono's `GetAntirollBody` of both templates).
/// On a solid axle, Chrono's rigid Panhard axle's bar: the same bar and arms, each arm's end sliding on the
/// axle tube (no droplink; `model::suspension::antiroll_bar::SlidingBar`).
/// Points in the chassis reference frame, left side (the right mirrors it).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AntirollBar {
    /// A point of the bar's axis, which is parallel to the chassis y axis, in the plane of symmetry (y = 0).
    pub axis_point_m: [f64; 3],
    /// The left arm's end, where the droplink is jointed to it (Chrono: location + (Width, Length, 0)).
    pub arm_end_m: [f64; 3],
    /// The droplink's other end, a point of the left lower control arm (Chrono: location + (Width, Length,
    /// Height)). The droplink's length is its distance from `arm_end_m`. On a solid axle there is none: the
    /// arm's end slides on the axle tube instead (Chrono's `RigidPanhardAxle` bar: a point-on-plane joint, the
    /// end held in the tube's plane through `arm_end_m` normal to the tube's z axis).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub droplink_end_m: Option<[f64; 3]>,
    /// Torsion spring between the two halves: torque per radian of twist (left arm's angle minus the
    /// right's), N·m/rad.
    pub torsional_stiffness_Nm_per_rad: f64,
    /// Its damping, N·m·s/rad.
    #[serde(default)]
    pub torsional_damping_Nms_per_rad: f64,
    /// Each arm's body (optional): mass and inertia in chassis axes about its CM, which is on the bar's axis
    /// midway between the plane of symmetry and the arm's end (Chrono's). The chassis carries it: its CM
    /// does not move as the arm turns (docs/physics.md §5.4).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub arm: Option<RigidBody>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StopTable {
    /// Stop engagement (m beyond the stop length) against force (N), both increasing from 0.
    pub deflection_m: Vec<f64>,
    pub force_N: Vec<f64>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelBody {
    pub mass_kg: f64,
    /// [Ixx, Iyy(spin), Izz] about the wheel centre.
    pub inertia_kg_m2: [f64; 3],
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedHold {
    pub kp_per_s: f64,
    pub ki_per_s2: f64,
}

/// Pitman-arm steering (Chrono's `PitmanArm`), driven kinematically by the Pitman arm's angle: the arm
/// turns about its pivot axis, the steering (drag) link hangs from it by a universal joint and from the
/// idler arm, which turns about its own chassis axis. The front tie rods end on the link (their TIEROD_C
/// points move with it). Points and axes in the chassis reference frame. The arm and link masses are
/// carried by the chassis (their driven motion is a few centimetres).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PitmanArm {
    pub arm: RigidBody,
    pub arm_com_m: [f64; 3],
    pub link: RigidBody,
    pub link_com_m: [f64; 3],
    /// Revolute joint of the Pitman arm on the chassis: a point on its axis and the axis direction
    /// (+ angle about it turns the vehicle left once the vehicle has measured its sign).
    pub arm_pivot_m: [f64; 3],
    pub arm_axis: [f64; 3],
    /// Universal joint between arm and link.
    pub arm_link_joint_m: [f64; 3],
    /// Idler arm: its pivot point and axis on the chassis, and its joint with the link.
    pub idler_pivot_m: [f64; 3],
    pub idler_axis: [f64; 3],
    pub idler_link_joint_m: [f64; 3],
    /// Largest Pitman-arm angle (either way) the steering accepts, rad.
    pub max_angle_rad: f64,
}

/// Rotary-arm steering (Chrono's `RotaryArm`): one arm turned about a chassis axis by the steering input, a
/// steered solid axle's drag link jointed to its end. Input `pitman_arm_angle` (rad), as Chrono's arm is the
/// Pitman arm; driven kinematically.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotaryArm {
    /// The arm's revolute joint on the chassis: a point of its axis and the axis direction (+ angle about it
    /// turns the vehicle left once the vehicle has measured its sign).
    pub arm_pivot_m: [f64; 3],
    pub arm_axis: [f64; 3],
    /// The drag link's joint on the arm (the steered axle's `DRAGLINK_S`).
    pub arm_draglink_joint_m: [f64; 3],
    /// Largest arm angle (either way) the steering accepts, rad.
    pub max_angle_rad: f64,
    /// The arm's body (optional): the chassis carries it, its CM midway between the pivot and the joint
    /// (Chrono's), inertia in chassis axes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub arm: Option<RigidBody>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleData {
    pub name: String,
    pub provenance: String,
    pub gravity_m_s2: f64,
    pub chassis: Chassis,
    /// Exactly one steering: a rack (input `rack_displacement`, m), a Pitman arm or a rotary arm (input
    /// `pitman_arm_angle`, rad).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rack: Option<Rack>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pitman_arm: Option<PitmanArm>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotary_arm: Option<RotaryArm>,
    /// The driver's eye point in the chassis reference frame (ride tests read accelerations there).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub driver_position_m: Option<[f64; 3]>,
    pub front: Axle,
    pub rear: Axle,
    pub stop_table: StopTable,
    pub wheel: WheelBody,
    pub tire: TireParams,
    pub speed_hold: SpeedHold,
    /// Where the car rides (docs/physics.md §8.1): `retuned` (the default, the paper's choice for the
    /// HMMWV) sets the spring free lengths so that the design position is the static equilibrium; `data`
    /// keeps the springs as written, as the tool the data came from does (an import's default). The CLI's
    /// `--ride-height` overrides it.
    #[serde(default, skip_serializing_if = "RideHeight::is_default")]
    pub ride_height: RideHeight,
}

/// `VehicleData::ride_height`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RideHeight {
    #[default]
    Retuned,
    Data,
}

impl RideHeight {
    pub fn is_default(&self) -> bool {
        *self == RideHeight::default()
    }
}

/// The largest static camber or toe accepted, deg: alignments are a few degrees; beyond this a value is
/// most likely in radians' place or a typo.
pub const MAX_STATIC_ANGLE_DEG: f64 = 10.0;

/// The hardpoints a MacPherson-strut axle must name (Chrono's names: the strut runs from SPRING_U on the
/// upright to its top mount SPRING_C on the chassis; the damper acts from SHOCK_U to SHOCK_C).
pub const MACPHERSON_HARDPOINTS: [&str; 12] = [
    "SPINDLE", "UPRIGHT", "LCA_F", "LCA_B", "LCA_U", "LCA_CM", "SHOCK_C", "SHOCK_U", "SPRING_C", "SPRING_U",
    "TIEROD_C", "TIEROD_U",
];

/// The hardpoints a single-wishbone axle must name: the double wishbone's without the upper arm. LCA_F and
/// LCA_B are two points of the arm's hinge axis (Chrono's single wishbone hinges along the chassis x axis
/// through one point, `Location Chassis`), LCA_U the kingpin's point on the arm.
pub const SINGLE_WISHBONE_HARDPOINTS: [&str; 12] = [
    "SPINDLE", "UPRIGHT", "LCA_F", "LCA_B", "LCA_U", "LCA_CM", "SHOCK_C", "SHOCK_A", "SPRING_C", "SPRING_A",
    "TIEROD_C", "TIEROD_U",
];

/// The hardpoints a semi-trailing-arm axle must name: LCA_F and LCA_B the arm's hinge on the chassis (Chrono's
/// `Location Chassis Outer` and `Inner`: the hinge axis runs from LCA_B to LCA_F), LCA_U the arm's point at
/// the spindle (`Location Spindle`), LCA_CM its CM; the spring and the damper from the chassis to the arm.
/// No upright and no tie rod: the spindle turns on the arm.
pub const SEMI_TRAILING_ARM_HARDPOINTS: [&str; 9] =
    ["SPINDLE", "LCA_F", "LCA_B", "LCA_U", "LCA_CM", "SHOCK_C", "SHOCK_A", "SPRING_C", "SPRING_A"];

/// The hardpoints a three-link IRS axle must name: TA_C the arm's spherical joint on the chassis, TA_S its point
/// at the spindle, TA_CM its CM; the upper and lower links' chassis (UL_C, LL_C) and arm (UL_A, LL_A) ends; the
/// spring and the damper from the chassis to the arm.
pub const THREE_LINK_IRS_HARDPOINTS: [&str; 12] =
    ["SPINDLE", "TA_C", "TA_S", "TA_CM", "UL_C", "UL_A", "LL_C", "LL_A", "SHOCK_C", "SHOCK_A", "SPRING_C", "SPRING_A"];

/// A wheel on its spindle (`VehicleData::wheel_assembly`), kg and kg m².
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelAssembly {
    pub mass: f64,
    pub transverse_inertia: f64,
    pub spin_inertia: f64,
}

/// The hardpoints a three-link solid axle must name (Chrono's `SolidThreeLinkAxle` points, left side):
/// `AXLE_CM` the axle tube's CM (on y = 0), `TRIANGLE_C` one of the triangle's two chassis points (its
/// revolute axis is the chassis y axis through their mid-point), `TRIANGLE_A` its apex on the axle (on
/// y = 0), `LINK_C` and `LINK_A` the longitudinal link's chassis and axle points, the spring's and the
/// damper's ends on the chassis (`_C`) and on the axle (`_A`), and the wheel centre `SPINDLE`.
pub const SOLID_THREE_LINK_HARDPOINTS: [&str; 10] = [
    "SPINDLE",
    "AXLE_CM",
    "TRIANGLE_C",
    "TRIANGLE_A",
    "LINK_C",
    "LINK_A",
    "SHOCK_C",
    "SHOCK_A",
    "SPRING_C",
    "SPRING_A",
];

/// The hardpoints a steered bellcrank three-link axle must name (Chrono's `SolidBellcrankThreeLinkAxle`
/// points, left side): the three-link axle's, the kingpin's lower and upper points `KNUCKLE_L`, `KNUCKLE_U`,
/// the knuckle's tie-rod point `KNUCKLE_T` and CM `KNUCKLE_CM`, the bellcrank's tie-rod point `BELLCRANK_T`;
/// taken as given (one each, not mirrored): the bellcrank's pivot on the axle `BELLCRANK_A` (it turns about
/// the axle's z axis), its drag-link point `BELLCRANK_D`, and the drag link's steering end `DRAGLINK_S`.
pub const SOLID_BELLCRANK_THREE_LINK_HARDPOINTS: [&str; 18] = [
    "SPINDLE",
    "AXLE_CM",
    "TRIANGLE_C",
    "TRIANGLE_A",
    "LINK_C",
    "LINK_A",
    "SHOCK_C",
    "SHOCK_A",
    "SPRING_C",
    "SPRING_A",
    "KNUCKLE_L",
    "KNUCKLE_U",
    "KNUCKLE_T",
    "KNUCKLE_CM",
    "BELLCRANK_A",
    "BELLCRANK_D",
    "BELLCRANK_T",
    "DRAGLINK_S",
];

/// The hardpoints a steered toe-bar leaf-spring axle must name (Chrono's `ToeBarLeafspringAxle` points, left
/// side): the leaf-spring axle's, the kingpin's lower and upper points `KNUCKLE_L`, `KNUCKLE_U`, the knuckle's CM
/// `KNUCKLE_CM`, the toe bar's knuckle point `TIEROD_K`; taken as given (one each, not mirrored): the drag link's
/// knuckle point `KNUCKLE_D` (on the left knuckle where its y is positive, else the right's) and its steering end
/// `DRAGLINK_S`.
pub const SOLID_TOEBAR_LEAFSPRING_HARDPOINTS: [&str; 12] = [
    "SPINDLE",
    "AXLE_CM",
    "SHOCK_C",
    "SHOCK_A",
    "SPRING_C",
    "SPRING_A",
    "KNUCKLE_L",
    "KNUCKLE_U",
    "KNUCKLE_CM",
    "KNUCKLE_D",
    "TIEROD_K",
    "DRAGLINK_S",
];

/// The hardpoints a steered toe-bar Panhard axle must name (Chrono's `ToeBarRigidPanhardAxle` points): the
/// Panhard axle's and the toe-bar axle's steering points (`KNUCKLE_L`, `KNUCKLE_U`, `KNUCKLE_CM`, `KNUCKLE_D`,
/// `TIEROD_K`, `DRAGLINK_S`, as the toe-bar leaf-spring axle's).
pub const SOLID_TOEBAR_PANHARD_HARDPOINTS: [&str; 14] = [
    "SPINDLE",
    "AXLE_CM",
    "PANHARD_C",
    "PANHARD_A",
    "SHOCK_C",
    "SHOCK_A",
    "SPRING_C",
    "SPRING_A",
    "KNUCKLE_L",
    "KNUCKLE_U",
    "KNUCKLE_CM",
    "KNUCKLE_D",
    "TIEROD_K",
    "DRAGLINK_S",
];

/// The hardpoints a leaf-spring solid axle must name (Chrono's `LeafspringAxle` points, left side): the axle
/// tube's CM `AXLE_CM` (on y = 0: the guide's point), the spring's and the damper's ends on the chassis (`_C`)
/// and on the axle (`_A`), the wheel centre `SPINDLE`.
pub const SOLID_LEAFSPRING_HARDPOINTS: [&str; 6] = ["SPINDLE", "AXLE_CM", "SHOCK_C", "SHOCK_A", "SPRING_C", "SPRING_A"];

/// The hardpoints a rigid Panhard axle must name (Chrono's `RigidPanhardAxle` points): as the leaf-spring
/// axle's, and the Panhard rod's chassis and axle ends `PANHARD_C`, `PANHARD_A` (one rod: each point taken as
/// given, not mirrored, as `AXLE_CM`).
pub const SOLID_PANHARD_HARDPOINTS: [&str; 8] =
    ["SPINDLE", "AXLE_CM", "PANHARD_C", "PANHARD_A", "SHOCK_C", "SHOCK_A", "SPRING_C", "SPRING_A"];

/// The hardpoint a rigid suspension must name: the wheel centre `SPINDLE` (Chrono's `RigidSuspension`
/// reads its `Spindle.COM` as that point).
pub const RIGID_HARDPOINTS: [&str; 1] = ["SPINDLE"];

/// The hardpoints a double-wishbone axle must name.
pub const HARDPOINTS: [&str; 16] = [
    "SPINDLE", "UPRIGHT", "UCA_F", "UCA_B", "UCA_U", "UCA_CM", "LCA_F", "LCA_B", "LCA_U", "LCA_CM", "SHOCK_C",
    "SHOCK_A", "SPRING_C", "SPRING_A", "TIEROD_C", "TIEROD_U",
];

/// The steering input a vehicle takes: each steering template has its own (FMU input and CLI unit).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum SteeringInput {
    /// Rack and pinion: rack displacement, m (+ = left turn).
    RackDisplacement,
    /// Pitman arm: the arm's angle, rad (+ = left turn).
    PitmanArmAngle,
}

impl SteeringInput {
    /// The FMU input's name.
    pub fn name(self) -> &'static str {
        match self {
            SteeringInput::RackDisplacement => "rack_displacement",
            SteeringInput::PitmanArmAngle => "pitman_arm_angle",
        }
    }

    pub fn unit(self) -> &'static str {
        match self {
            SteeringInput::RackDisplacement => "m",
            SteeringInput::PitmanArmAngle => "rad",
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct DataError {
    /// Dotted path of the offending field, e.g. `front.lower_arm.mass_kg`.
    pub field: String,
    pub message: String,
}

impl std::fmt::Display for DataError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "vehicle data: {}: {}", self.field, self.message)
    }
}

impl std::error::Error for DataError {}

impl From<DataError> for crate::error::ModelError {
    fn from(e: DataError) -> Self {
        crate::error::ModelError::new(crate::error::Cause::Data, e.to_string())
    }
}

pub(crate) fn err(field: impl Into<String>, message: impl Into<String>) -> DataError {
    DataError { field: field.into(), message: message.into() }
}

/// The data shipped in `resources/`, compiled in so the library works without any file at hand.
pub const DEFAULT_VEHICLE_JSON: &str = include_str!("../../../resources/hmmwv.json");

impl VehicleData {
    /// Whether this is the default vehicle (the HMMWV of `resources/hmmwv.json`, its variants included), by
    /// its name: read from the compiled-in file's `name` alone, without loading and validating it.
    pub fn is_default_vehicle(&self) -> bool {
        #[derive(Deserialize)]
        struct Named {
            name: String,
        }
        let default: Named = serde_json::from_str(DEFAULT_VEHICLE_JSON).expect("the shipped vehicle file names itself");
        self.name == default.name
    }

    pub fn axles(&self) -> [(&'static str, &Axle); 2] {
        [("front", &self.front), ("rear", &self.rear)]
    }

    /// Every check of the data, in this order (the first failing one is the error): gravity, chassis,
    /// steering, driver, each axle, stop table, wheel, tire, speed hold.
    pub fn validate(&self) -> Result<(), DataError> {
        positive("gravity_m_s2", self.gravity_m_s2)?;
        check_chassis(&self.chassis)?;
        check_steering(self)?;
        if let Some(d) = &self.driver_position_m {
            finite3("driver_position_m", d)?;
        }
        for (name, axle) in self.axles() {
            check_axle(name, axle)?;
        }
        check_stop_table(&self.stop_table)?;
        check_wheel(&self.wheel)?;
        check_tire(&self.tire)?;
        nonneg("speed_hold.kp_per_s", self.speed_hold.kp_per_s)?;
        nonneg("speed_hold.ki_per_s2", self.speed_hold.ki_per_s2)?;
        Ok(())
    }

    /// What turns on one spindle of `axle`: spindle, wheel and tire (their mass and their inertia about a
    /// transverse axis, Ixx as the spindle's), and the spin inertia about the axle with the half-shaft.
    pub fn wheel_assembly(&self, axle: &Axle) -> WheelAssembly {
        WheelAssembly {
            mass: axle.spindle.mass_kg + self.wheel.mass_kg + self.tire.mass_kg,
            transverse_inertia: axle.spindle.inertia_moments_kg_m2[0]
                + self.wheel.inertia_kg_m2[0]
                + self.tire.inertia_kg_m2[0],
            spin_inertia: axle.spindle.inertia_moments_kg_m2[1]
                + self.wheel.inertia_kg_m2[1]
                + self.tire.inertia_kg_m2[1]
                + axle.axle_shaft_spin_inertia_kg_m2,
        }
    }

    /// Non-fatal remarks about the data (printed by the CLI, logged by the FMU).
    pub fn warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        for (name, axle) in self.axles() {
            let mut bodies = vec![("lower_arm", &axle.lower_arm), ("upright", &axle.upright)];
            if let Some(b) = &axle.upper_arm {
                bodies.push(("upper_arm", b));
            }
            for (body, b) in bodies {
                let e = b.inertia().symmetric_eigenvalues();
                let (a, bb, c) = (e[0], e[1], e[2]);
                if a > bb + c || bb > a + c || c > a + bb {
                    out.push(format!(
                        "{name}.{body}: principal moments {a:.4}, {bb:.4}, {c:.4} break the triangle inequality \
                         (the source marks these inertias as placeholders); used as given"
                    ));
                }
            }
        }
        // Templates whose stability suite is not clean (issue 34's note): the step check's wheel block does not
        // see every fast motion they have. Said at every load, so that no run on them is silently trusted.
        for (name, axle) in self.axles() {
            let unchecked = match axle.template {
                SuspensionTemplate::Rigid => Some(
                    "the step check does not see the chassis bouncing on this axle's tires (its wheel block has no \
                     coordinate there): the stability suite of a HMMWV with a rigid rear has runs more than 1 % off \
                     without a word at RK4 8.33 ms, AB3 2.08 ms and IMEX-AB3 8.33 and 2.08 ms",
                ),
                SuspensionTemplate::SolidLeafspring
                | SuspensionTemplate::SolidPanhard
                | SuspensionTemplate::SolidToebarPanhard => Some(
                    "the stability suite of a HMMWV with this rear axle has runs more than 1 % off without a word \
                     at IMEX-AB3 on its full-lock lift-off case",
                ),
                SuspensionTemplate::SolidBellcrankThreeLink => Some(
                    "the stability suite of the test vehicle with this front axle (docs/stability_rtv_hmmwv_solid_axles.md) \
                     has runs a few per cent off without a word: RK4 at 8.33 ms on the full-lock cases, whose inner \
                     front wheel leaves the road and lands, RK4 at 2.08 ms on the 8 in half-round obstacle, and \
                     IMEX-AB3 on the full-lock cases and the obstacle before its refusal",
                ),
                _ => None,
            };
            if let Some(what) = unchecked {
                out.push(format!(
                    "{name}: template {}: {what}; check this vehicle with `rtv stability --vehicle-file` before \
                     trusting a scheme and step, or run RK4 at 1 ms or DOPRI5",
                    axle.template.name()
                ));
            }
        }
        // The tire file's remarks: unused sections and keys, mirrored slip ranges.
        if let Some(mf) = &self.tire.magic_formula {
            out.extend(mf.warnings.iter().cloned());
        }
        if let Some(tm) = &self.tire.tmeasy {
            out.extend(tm.warnings.iter().cloned());
            // Measured (`rtv stability` on Chrono's VW microbus as `rtv import-chrono` writes it from its model
            // file, on its TMeasy tire; the Sedan's likewise; the MAN 5t's, shipped, has none): at low speed the
            // tire ties the chassis velocities to the road stiffly, a mode that passes through faster than the
            // step check's schedule as the car stops (docs/integrators.md, "The WRONG runs the suites still find").
            out.push(
                "tire: TMeasy: the stability suites of Chrono's VW microbus, Sedan and G500 on their TMeasy tires \
                 have runs off without a word: RK4 at 8.33 to 2.08 ms on the wheel lock at 100 km/h (3 to 5 % at the \
                 stop), IMEX-AB3 at 4.17 ms on it (2 %), RK4 held on a 20 % grade before its refusal (2 %), RK4 at \
                 8.33 and 4.17 ms braked to a stop from 60 km/h (13 to 16 %); check \
                 this vehicle with `rtv stability --vehicle-file` before trusting a scheme and step, or run RK4 at \
                 1 ms or DOPRI5"
                    .to_string(),
            );
        }
        out
    }

    /// Bodies the chassis carries rigidly besides its own: the anti-roll bars' arms (their CMs are on the
    /// bar's axis), the MacPherson strut rods (CM midway between
    /// SPRING_C and SPRING_U, both sides) and the Pitman arm and steering link. Each as (mass, CM in the
    /// chassis reference frame, inertia about its CM in chassis axes).
    pub fn carried_bodies(&self) -> Vec<(f64, Vector3<f64>, Matrix3<f64>)> {
        let mut out = Vec::new();
        for (_, axle) in self.axles() {
            if let (Some(strut), SuspensionTemplate::MacphersonStrut) = (&axle.strut, axle.template) {
                let c = 0.5 * (Self::point(axle, "SPRING_C") + Self::point(axle, "SPRING_U"));
                let mirror = Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, 1.0));
                out.push((strut.mass_kg, c, strut.inertia()));
                out.push((strut.mass_kg, Vector3::new(c.x, -c.y, c.z), mirror * strut.inertia() * mirror));
            }
        }
        for (_, axle) in self.axles() {
            if let Some(AntirollBar { arm: Some(arm), axis_point_m: c, arm_end_m: e, .. }) = &axle.antiroll_bar {
                // Chrono's arm CM: on the bar's axis, halfway out to the arm's end; mirrored on the right.
                for y in [0.5 * e[1], -0.5 * e[1]] {
                    let mirror = Matrix3::from_diagonal(&Vector3::new(1.0, y.signum(), 1.0));
                    out.push((arm.mass_kg, Vector3::new(c[0], y, c[2]), mirror * arm.inertia() * mirror));
                }
            }
        }
        for (_, axle) in self.axles() {
            if axle.template.is_rigid() {
                // The spindle, wheel and tire of a rigid suspension turn on the chassis: their mass and their
                // inertia about the transverse axes are carried (the spin axis's is the wheel's spin state's).
                let WheelAssembly { mass: m, transverse_inertia: i_t, .. } = self.wheel_assembly(axle);
                let j = Matrix3::from_diagonal(&Vector3::new(i_t, 0.0, i_t));
                let w = Self::point(axle, "SPINDLE");
                out.push((m, w, j));
                out.push((m, Vector3::new(w.x, -w.y, w.z), j));
            }
        }
        if let Some(RotaryArm { arm: Some(arm), arm_pivot_m: p, arm_draglink_joint_m: j, .. }) = &self.rotary_arm {
            out.push((arm.mass_kg, (Vector3::from(*p) + Vector3::from(*j)) / 2.0, arm.inertia()));
        }
        if let Some(p) = &self.pitman_arm {
            out.push((p.arm.mass_kg, Vector3::from(p.arm_com_m), p.arm.inertia()));
            out.push((p.link.mass_kg, Vector3::from(p.link_com_m), p.link.inertia()));
        }
        out
    }

    /// The sprung body's CM (chassis and the bodies it carries), chassis reference frame: the origin of
    /// every position in the model.
    pub fn sprung_com(&self) -> Vector3<f64> {
        let c = Vector3::from(self.chassis.com_m);
        let carried = self.carried_bodies();
        if carried.is_empty() {
            return c;
        }
        let mass = self.chassis.mass_kg + carried.iter().map(|b| b.0).sum::<f64>();
        (c * self.chassis.mass_kg + carried.iter().map(|b| b.1 * b.0).sum::<Vector3<f64>>()) / mass
    }

    /// The sprung body's mass and inertia about `sprung_com` (chassis axes).
    pub fn sprung_inertia(&self) -> (f64, Matrix3<f64>) {
        let chassis = self.chassis.body();
        let carried = self.carried_bodies();
        if carried.is_empty() {
            return (chassis.mass_kg, chassis.inertia());
        }
        let c0 = self.sprung_com();
        let steiner = |m: f64, r: Vector3<f64>| (Matrix3::identity() * r.norm_squared() - r * r.transpose()) * m;
        let mut mass = chassis.mass_kg;
        let mut j = chassis.inertia() + steiner(chassis.mass_kg, Vector3::from(self.chassis.com_m) - c0);
        for (m, c, jb) in carried {
            mass += m;
            j += jb + steiner(m, c - c0);
        }
        (mass, j)
    }

    /// The steering input's limit (either way): rack travel, m, or Pitman-arm angle, rad.
    pub fn steering_limit(&self) -> f64 {
        match (&self.rack, &self.pitman_arm, &self.rotary_arm) {
            (Some(r), _, _) => r.travel_limit_m,
            (None, Some(p), _) => p.max_angle_rad,
            (None, None, Some(a)) => a.max_angle_rad,
            (None, None, None) => 0.0,
        }
    }

    /// What steers the vehicle, in words: rack and pinion, Pitman arm or rotary arm.
    pub fn steering_name(&self) -> &'static str {
        match (&self.pitman_arm, &self.rotary_arm) {
            (Some(_), _) => "Pitman arm",
            (None, Some(_)) => "rotary arm",
            (None, None) => "rack and pinion",
        }
    }

    /// The steering input's name and unit: `rack_displacement` (m) or `pitman_arm_angle` (rad).
    pub fn steering_input(&self) -> SteeringInput {
        if self.pitman_arm.is_some() || self.rotary_arm.is_some() {
            SteeringInput::PitmanArmAngle
        } else {
            SteeringInput::RackDisplacement
        }
    }

    pub fn point(axle: &Axle, name: &str) -> Vector3<f64> {
        Vector3::from(axle.hardpoints_chassis_frame_m[name])
    }
}

// The steps of `VehicleData::validate`, one part of the vehicle each.

fn check_chassis(c: &Chassis) -> Result<(), DataError> {
    positive("chassis.mass_kg", c.mass_kg)?;
    finite3("chassis.com_m", &c.com_m)?;
    pos_def("chassis.inertia", &c.body())
}

/// Exactly one steering, a rack or a Pitman arm, and its data.
fn check_steering(data: &VehicleData) -> Result<(), DataError> {
    match (&data.rack, &data.pitman_arm, &data.rotary_arm) {
        (Some(rack), None, None) => check_rack(rack)?,
        (None, Some(p), None) => check_pitman_arm(p)?,
        (None, None, Some(a)) => check_rotary_arm(a)?,
        (None, None, None) => {
            return Err(err("rack", "missing steering: give `rack` (rack and pinion), `pitman_arm` or `rotary_arm`"))
        }
        _ => {
            return Err(err(
                "rack",
                "a vehicle has one steering: give one of `rack`, `pitman_arm` and `rotary_arm`, not more",
            ))
        }
    }
    // A rotary arm drives a drag link; the tie rods of an independent axle need a rack or a Pitman arm's link.
    for (name, axle) in data.axles() {
        let steered_axle = axle.template.is_steered_solid_axle();
        if data.rotary_arm.is_some() && axle.steered && !steered_axle {
            return Err(err(
                "rotary_arm",
                format!(
                    "a rotary arm steers a solid axle's drag link; the {name} axle ({}) has tie rods, which need a rack \
                     or a Pitman arm",
                    axle.template.name()
                ),
            ));
        }
        if let (Some(a), true) = (&data.rotary_arm, steered_axle) {
            let (s, j) = (VehicleData::point(axle, "DRAGLINK_S"), Vector3::from(a.arm_draglink_joint_m));
            if (s - j).norm() > 1e-6 * j.norm().max(1.0) {
                return Err(err(
                    format!("{name}.hardpoints_chassis_frame_m.DRAGLINK_S"),
                    format!(
                        "the drag link's steering end {s:?} is not the rotary arm's joint {j:?} \
                         (rotary_arm.arm_draglink_joint_m): the drag link would not meet the arm"
                    ),
                ));
            }
        }
    }
    Ok(())
}

fn check_rotary_arm(a: &RotaryArm) -> Result<(), DataError> {
    for (k, v) in [("arm_pivot_m", &a.arm_pivot_m), ("arm_draglink_joint_m", &a.arm_draglink_joint_m)] {
        finite3(&format!("rotary_arm.{k}"), v)?;
    }
    finite3("rotary_arm.arm_axis", &a.arm_axis)?;
    let axis = Vector3::from(a.arm_axis);
    if axis.norm() < 1e-9 {
        return Err(err("rotary_arm.arm_axis", "axis direction of zero length"));
    }
    let r = Vector3::from(a.arm_draglink_joint_m) - Vector3::from(a.arm_pivot_m);
    if (r - axis.normalize() * axis.normalize().dot(&r)).norm() < 1e-6 {
        return Err(err("rotary_arm.arm_draglink_joint_m", "the joint lies on the arm's axis: the arm has no length"));
    }
    positive("rotary_arm.max_angle_rad", a.max_angle_rad)?;
    if a.max_angle_rad >= std::f64::consts::FRAC_PI_2 {
        return Err(err("rotary_arm.max_angle_rad", "must be below π/2 (90°)"));
    }
    if let Some(b) = &a.arm {
        positive("rotary_arm.arm.mass_kg", b.mass_kg)?;
        pos_def("rotary_arm.arm.inertia", b)?;
    }
    Ok(())
}

fn check_rack(rack: &Rack) -> Result<(), DataError> {
    positive("rack.mass_kg", rack.mass_kg)?;
    positive("rack.travel_limit_m", rack.travel_limit_m)?;
    finite3("rack.com_m", &rack.com_m)?;
    pos_def("rack.inertia", &rack.body())
}

fn check_pitman_arm(p: &PitmanArm) -> Result<(), DataError> {
    for (body, b) in [("pitman_arm.arm", &p.arm), ("pitman_arm.link", &p.link)] {
        positive(&format!("{body}.mass_kg"), b.mass_kg)?;
        pos_def(&format!("{body}.inertia"), b)?;
    }
    for (k, v) in [
        ("arm_com_m", &p.arm_com_m),
        ("link_com_m", &p.link_com_m),
        ("arm_pivot_m", &p.arm_pivot_m),
        ("arm_link_joint_m", &p.arm_link_joint_m),
        ("idler_pivot_m", &p.idler_pivot_m),
        ("idler_link_joint_m", &p.idler_link_joint_m),
    ] {
        finite3(&format!("pitman_arm.{k}"), v)?;
    }
    for (k, v) in [("arm_axis", &p.arm_axis), ("idler_axis", &p.idler_axis)] {
        finite3(&format!("pitman_arm.{k}"), v)?;
        if Vector3::from(*v).norm() < 1e-9 {
            return Err(err(format!("pitman_arm.{k}"), "axis direction of zero length"));
        }
    }
    positive("pitman_arm.max_angle_rad", p.max_angle_rad)?;
    if p.max_angle_rad >= std::f64::consts::FRAC_PI_2 {
        return Err(err("pitman_arm.max_angle_rad", "must be below π/2 (90°)"));
    }
    Ok(())
}

/// One axle (`name`: front or rear): its hardpoints, bodies, shaft, spring, damper, bar and alignment.
fn check_axle(name: &str, axle: &Axle) -> Result<(), DataError> {
    check_hardpoints(name, axle)?;
    check_suspension_bodies(name, axle)?;
    nonneg(&format!("{name}.axle_shaft_spin_inertia_kg_m2"), axle.axle_shaft_spin_inertia_kg_m2)?;
    let template = axle.template.name();
    for (element, none) in [("spring", axle.spring.is_none()), ("damper", axle.damper.is_none())] {
        match (axle.template.is_rigid(), none) {
            (true, false) => return Err(err(format!("{name}.{element}"), format!("a {template} has none"))),
            (false, true) => return Err(err(format!("{name}.{element}"), format!("missing: a {template} has one"))),
            _ => {}
        }
    }
    if axle.template.is_rigid() {
        return check_alignment(name, axle);
    }
    check_spring(&format!("{name}.spring"), &axle.spring)?;
    check_damper(&format!("{name}.damper"), &axle.damper)?;
    if let Some(bar) = &axle.antiroll_bar {
        check_antiroll_bar(&format!("{name}.antiroll_bar"), bar)?;
        if bar.droplink_end_m.is_none() && !axle.template.is_solid_axle() {
            return Err(err(
                format!("{name}.antiroll_bar.droplink_end_m"),
                "missing: the bar's droplink meets the lower arm (only a solid axle's bar slides on its axle instead)",
            ));
        }
    }
    check_alignment(name, axle)
}

/// Every hardpoint of the axle's template given and finite, and no other.
fn check_hardpoints(name: &str, axle: &Axle) -> Result<(), DataError> {
    let field = |p: &str| format!("{name}.hardpoints_chassis_frame_m.{p}");
    let template = axle.template.hardpoints();
    for p in template {
        let v = axle.hardpoints_chassis_frame_m.get(*p).ok_or_else(|| err(field(p), "missing hardpoint"))?;
        finite3(&field(p), v)?;
    }
    for (k, v) in &axle.hardpoints_chassis_frame_m {
        if !template.contains(&k.as_str()) {
            return Err(err(
                field(k),
                format!("not a hardpoint of the {} template (it has: {})", axle.template.name(), template.join(", ")),
            ));
        }
        finite3(&field(k), v)?;
    }
    Ok(())
}

/// The bodies the template has (an upper arm for a double wishbone, none for a MacPherson strut; a strut
/// body only for the latter), each with a positive mass and a positive definite inertia.
fn check_suspension_bodies(name: &str, axle: &Axle) -> Result<(), DataError> {
    if axle.template.is_solid_axle() || axle.template.is_rigid() {
        return check_solid_axle_bodies(name, axle);
    }
    // A semi-trailing arm's spindle turns on the arm: it has no upright.
    let has_upright = !matches!(axle.template, SuspensionTemplate::SemiTrailingArm | SuspensionTemplate::ThreeLinkIrs);
    for (body, b, has) in [("lower_arm", &axle.lower_arm, true), ("upright", &axle.upright, has_upright)] {
        match (has, b.is_none()) {
            (true, true) => {
                return Err(err(format!("{name}.{body}"), format!("missing: a {} has one", axle.template.name())))
            }
            (false, false) => {
                return Err(err(format!("{name}.{body}"), format!("a {} has none", axle.template.name())))
            }
            _ => {}
        }
    }
    if axle.axle_tube.is_some() {
        return Err(err(format!("{name}.axle_tube"), "only a solid axle has an axle tube"));
    }
    match axle.template {
        SuspensionTemplate::DoubleWishbone => {
            if axle.upper_arm.is_none() {
                return Err(err(format!("{name}.upper_arm"), "missing: a double wishbone has an upper arm"));
            }
            if axle.strut.is_some() {
                return Err(err(format!("{name}.strut"), "a double wishbone has no strut body"));
            }
        }
        SuspensionTemplate::MacphersonStrut => {
            if axle.upper_arm.is_some() {
                return Err(err(format!("{name}.upper_arm"), "a MacPherson strut has no upper arm"));
            }
        }
        SuspensionTemplate::SingleWishbone | SuspensionTemplate::SemiTrailingArm | SuspensionTemplate::ThreeLinkIrs => {
            let template = axle.template.name();
            if axle.upper_arm.is_some() {
                return Err(err(format!("{name}.upper_arm"), format!("a {template} has no upper arm")));
            }
            if axle.strut.is_some() {
                return Err(err(format!("{name}.strut"), format!("a {template} has no strut body")));
            }
            let arm_only =
                matches!(axle.template, SuspensionTemplate::SemiTrailingArm | SuspensionTemplate::ThreeLinkIrs);
            if arm_only && axle.steered {
                return Err(err(format!("{name}.steered"), format!("a {template} is not steerable")));
            }
            if axle.template == SuspensionTemplate::ThreeLinkIrs && axle.antiroll_bar.is_some() {
                return Err(err(format!("{name}.antiroll_bar"), "a three_link_irs takes none (its arm has no hinge)"));
            }
        }
        SuspensionTemplate::SolidThreeLink
        | SuspensionTemplate::SolidLeafspring
        | SuspensionTemplate::SolidPanhard
        | SuspensionTemplate::SolidBellcrankThreeLink
        | SuspensionTemplate::SolidToebarLeafspring
        | SuspensionTemplate::SolidToebarPanhard
        | SuspensionTemplate::Rigid => unreachable!("checked above"),
    }
    let mut bodies = vec![("lower_arm", &axle.lower_arm), ("spindle", &axle.spindle)];
    if has_upright {
        bodies.push(("upright", &axle.upright));
    }
    if let Some(b) = &axle.upper_arm {
        bodies.push(("upper_arm", b));
    }
    if let Some(b) = &axle.strut {
        bodies.push(("strut", b));
    }
    for (body, b) in bodies {
        positive(&format!("{name}.{body}.mass_kg"), b.mass_kg)?;
        pos_def(&format!("{name}.{body}.inertia"), b)?;
    }
    Ok(())
}

/// A solid axle's bodies: the axle tube and the spindle, each with a positive mass and a positive definite
/// inertia, and none of an independent suspension's; an anti-roll bar only as Chrono's rigid Panhard axle has
/// one (its arms' ends slide on the tube: no droplink, which would need a lower arm), no static camber or toe
/// (the spindles are on the tube).
/// A rigid suspension's likewise, with no axle tube: its spindles turn on the chassis, parallel to its y
/// axis (Chrono's `RigidSuspension` sets them so).
fn check_solid_axle_bodies(name: &str, axle: &Axle) -> Result<(), DataError> {
    let template = axle.template.name();
    let steered_axle = axle.template.is_steered_solid_axle();
    let present = [
        ("lower_arm", !axle.lower_arm.is_none()),
        ("upright", !steered_axle && !axle.upright.is_none()),
        ("upper_arm", axle.upper_arm.is_some()),
        ("strut", axle.strut.is_some()),
        ("antiroll_bar", axle.template.is_rigid() && axle.antiroll_bar.is_some()),
        ("bellcrank", axle.template != SuspensionTemplate::SolidBellcrankThreeLink && axle.bellcrank.is_some()),
    ];
    if let Some((body, _)) = present.iter().find(|(_, p)| *p) {
        return Err(err(format!("{name}.{body}"), format!("a {template} has none")));
    }
    if axle.antiroll_bar.as_ref().is_some_and(|b| b.droplink_end_m.is_some()) {
        return Err(err(
            format!("{name}.antiroll_bar.droplink_end_m"),
            format!(
                "a {template}'s bar has no droplink: its arms' ends slide on the axle tube (Chrono's rigid Panhard \
                 axle's bar); leave droplink_end_m out"
            ),
        ));
    }
    if axle.steered != steered_axle {
        return Err(err(
            format!("{name}.steered"),
            if steered_axle {
                format!("a {template} is steered: its drag link ends on the steering (give `steered: true`)")
            } else {
                format!("a {template} is not steerable (Chrono's is not)")
            },
        ));
    }
    if axle.static_camber_deg != 0.0 || axle.static_toe_deg != 0.0 {
        return Err(err(format!("{name}.static_camber_deg"), format!("a {template} takes no static camber or toe")));
    }
    let mut bodies = vec![("spindle", &axle.spindle)];
    if steered_axle {
        bodies.push(("upright", &axle.upright));
    }
    if axle.template == SuspensionTemplate::SolidBellcrankThreeLink {
        match &axle.bellcrank {
            Some(b) => bodies.push(("bellcrank", b)),
            None => return Err(err(format!("{name}.bellcrank"), format!("missing: a {template} has one"))),
        }
    }
    match (&axle.axle_tube, axle.template.is_rigid()) {
        (Some(_), true) => return Err(err(format!("{name}.axle_tube"), format!("a {template} has none"))),
        (Some(tube), false) => bodies.push(("axle_tube", tube)),
        (None, false) => return Err(err(format!("{name}.axle_tube"), "missing: a solid axle has one")),
        (None, true) => {}
    }
    for (body, b) in bodies {
        positive(&format!("{name}.{body}.mass_kg"), b.mass_kg)?;
        pos_def(&format!("{name}.{body}.inertia"), b)?;
    }
    Ok(())
}

/// The spring (`field`, e.g. `front.spring`): its free length, its law (the cubic or a curve, exactly one)
/// and its stops.
fn check_spring(field: &str, s: &Spring) -> Result<(), DataError> {
    positive(&format!("{field}.free_length_m"), s.free_length_m)?;
    match (&s.curve, s.k1_N_per_m, s.k3_N_per_m3) {
        (None, Some(k1), Some(k3)) => {
            nonneg(&format!("{field}.k1_N_per_m"), k1)?;
            nonneg(&format!("{field}.k3_N_per_m3"), k3)?;
        }
        (None, k1, _) => {
            let missing = if k1.is_none() { "k1_N_per_m" } else { "k3_N_per_m3" };
            return Err(err(format!("{field}.{missing}"), "missing: give k1_N_per_m and k3_N_per_m3, or a curve"));
        }
        (Some(c), None, None) => check_spring_curve(&format!("{field}.curve"), c)?,
        (Some(_), _, _) => {
            return Err(err(
                format!("{field}.curve"),
                "give either the cubic (k1_N_per_m, k3_N_per_m3) or a curve, not both",
            ));
        }
    }
    // Absent stops are ∓∞ (serde defaults); a given one must be a positive length.
    let stop_ok = |v: f64| v.is_infinite() || (v.is_finite() && v > 0.0);
    if !(stop_ok(s.stop_min_length_m)
        && stop_ok(s.stop_max_length_m)
        && s.stop_min_length_m < s.stop_max_length_m
        && s.stop_min_length_m != f64::INFINITY
        && s.stop_max_length_m != f64::NEG_INFINITY)
    {
        return Err(err(
            format!("{field}.stop_min_length_m"),
            "stop lengths must satisfy 0 < stop_min_length_m < stop_max_length_m",
        ));
    }
    Ok(())
}

/// The damper (`field`, e.g. `front.damper`): the banded law's six values, each given and the rates not
/// negative, with the band's ends in order; or a curve (`check_curve`, through v = 0 with no force) and
/// none of them, and no degressivity (Chrono reads a degressivity only with a coefficient).
fn check_damper(field: &str, d: &Damper) -> Result<(), DataError> {
    for (k, v) in [
        ("degressivity_compression_s_per_m", d.degressivity_compression_s_per_m),
        ("degressivity_rebound_s_per_m", d.degressivity_rebound_s_per_m),
    ] {
        nonneg(&format!("{field}.{k}"), v)?;
    }
    // A table (a curve or a map) replaces the bands and their degressivity.
    let table = match (&d.curve, &d.map) {
        (Some(_), Some(_)) => return Err(err(format!("{field}.curve"), "give either a curve or a map, not both")),
        (Some(curve), None) => Some(("curve", check_damper_curve(&format!("{field}.curve"), curve))),
        (None, Some(map)) => Some(("map", check_damper_map(&format!("{field}.map"), map))),
        (None, None) => None,
    };
    if let Some((name, checked)) = table {
        if let Some((k, _)) = d.band_fields().into_iter().find(|(_, v)| v.is_some()) {
            return Err(err(
                format!("{field}.{k}"),
                format!("give either the rates and their band or a {name}, not both"),
            ));
        }
        if d.degressivity_compression_s_per_m != 0.0 || d.degressivity_rebound_s_per_m != 0.0 {
            return Err(err(
                format!("{field}.degressivity_compression_s_per_m"),
                format!("a {name} has no degressivity"),
            ));
        }
        return checked;
    }
    for (k, v) in d.band_fields() {
        match v {
            Some(v) if k.starts_with("engagement") => finite(&format!("{field}.{k}"), v)?,
            Some(v) => nonneg(&format!("{field}.{k}"), v)?,
            None => return Err(err(format!("{field}.{k}"), "missing (or give a curve instead of the rates)")),
        }
    }
    let b = d.bands();
    if !(b.engagement_min_length < b.engagement_max_length) {
        return Err(err(format!("{field}.engagement_min_length_m"), "must be below engagement_max_length_m"));
    }
    Ok(())
}

/// The static camber and toe, within ±`MAX_STATIC_ANGLE_DEG`.
fn check_alignment(name: &str, axle: &Axle) -> Result<(), DataError> {
    for (k, v) in [("static_camber_deg", axle.static_camber_deg), ("static_toe_deg", axle.static_toe_deg)] {
        if !(v.abs() <= MAX_STATIC_ANGLE_DEG) {
            return Err(err(
                format!("{name}.{k}"),
                format!("{v}° is beyond ±{MAX_STATIC_ANGLE_DEG}° (an alignment angle, in degrees)"),
            ));
        }
    }
    Ok(())
}

fn check_stop_table(t: &StopTable) -> Result<(), DataError> {
    if t.deflection_m.len() != t.force_N.len() || t.deflection_m.len() < 2 {
        return Err(err("stop_table", "deflection_m and force_N must have the same length, at least 2"));
    }
    if t.deflection_m.windows(2).any(|w| !(w[1] > w[0])) || t.deflection_m[0] != 0.0 {
        return Err(err("stop_table.deflection_m", "must start at 0 and increase strictly"));
    }
    if t.force_N.windows(2).any(|w| w[1] < w[0]) || t.force_N[0] != 0.0 {
        return Err(err("stop_table.force_N", "must start at 0 and never decrease"));
    }
    Ok(())
}

fn check_wheel(wheel: &WheelBody) -> Result<(), DataError> {
    positive("wheel.mass_kg", wheel.mass_kg)?;
    for (i, v) in wheel.inertia_kg_m2.iter().enumerate() {
        positive(&format!("wheel.inertia_kg_m2[{i}]"), *v)?;
    }
    Ok(())
}

/// The tire's body, vertical law, relaxation, low-speed blend and its STI coefficients.
fn check_tire(tire: &TireParams) -> Result<(), DataError> {
    positive("tire.mass_kg", tire.mass_kg)?;
    for (i, v) in tire.inertia_kg_m2.iter().enumerate() {
        positive(&format!("tire.inertia_kg_m2[{i}]"), *v)?;
    }
    positive("tire.unloaded_radius_m", tire.unloaded_radius_m)?;
    positive("tire.vertical_stiffness_N_per_m", tire.vertical_stiffness_N_per_m)?;
    nonneg("tire.vertical_stiffness2_N_per_m2", tire.vertical_stiffness2_N_per_m2)?;
    nonneg("tire.vertical_damping_Ns_per_m", tire.vertical_damping_Ns_per_m)?;
    nonneg("tire.rolling_resistance", tire.rolling_resistance)?;
    positive("tire.relaxation_length_x_m", tire.relaxation_length_x_m)?;
    positive("tire.relaxation_length_y_m", tire.relaxation_length_y_m)?;
    positive("tire.v_min_m_s", tire.v_min_m_s)?;
    let [v_lo, v_hi] = tire.low_speed_blend_m_s;
    positive("tire.low_speed_blend_m_s[0]", v_lo)?;
    if !(v_hi > v_lo && v_hi.is_finite()) {
        return Err(err("tire.low_speed_blend_m_s", "must be two increasing finite speeds, the first positive"));
    }
    nonneg("tire.low_speed_damping_Ns_per_m", tire.low_speed_damping_Ns_per_m)?;
    check_sti(&tire.sti)
}

fn check_sti(sti: &StiCoefficients) -> Result<(), DataError> {
    positive("tire.sti.a1", sti.a1)?;
    positive("tire.sti.a2_N", sti.a2_N)?;
    positive("tire.sti.cs", sti.cs)?;
    positive("tire.sti.mu0", sti.mu0)?;
    for (k, v) in [
        ("a0", sti.a0),
        ("k_mu", sti.k_mu),
        ("k_a", sti.k_a),
        ("c1", sti.c1),
        ("c2", sti.c2),
        ("c3", sti.c3),
        ("c4", sti.c4),
        ("c_gamma_per_rad", sti.c_gamma_per_rad),
        ("trail_m", sti.trail_m),
    ] {
        finite(&format!("tire.sti.{k}"), v)?;
    }
    Ok(())
}

fn finite(field: &str, v: f64) -> Result<(), DataError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(err(field, format!("must be a finite number, got {v}")))
    }
}

fn finite3(field: &str, v: &[f64; 3]) -> Result<(), DataError> {
    v.iter().try_for_each(|x| finite(field, *x))
}

fn positive(field: &str, v: f64) -> Result<(), DataError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(err(field, format!("must be positive, got {v}")))
    }
}

fn nonneg(field: &str, v: f64) -> Result<(), DataError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(err(field, format!("must be zero or positive, got {v}")))
    }
}

/// The anti-roll bar's data alone (that the droplink closes over the travel is checked with the suspension,
/// `model::suspension::antiroll_bar::check_closes`).
fn check_antiroll_bar(field: &str, bar: &AntirollBar) -> Result<(), DataError> {
    for (k, p) in [("axis_point_m", &bar.axis_point_m), ("arm_end_m", &bar.arm_end_m)] {
        finite3(&format!("{field}.{k}"), p)?;
    }
    if let Some(p) = &bar.droplink_end_m {
        finite3(&format!("{field}.droplink_end_m"), p)?;
    }
    if bar.axis_point_m[1] != 0.0 {
        return Err(err(
            format!("{field}.axis_point_m"),
            format!("y = {} m: the bar's axis lies in the plane of symmetry (y = 0)", bar.axis_point_m[1]),
        ));
    }
    if !(bar.arm_end_m[1] > 0.0) {
        return Err(err(
            format!("{field}.arm_end_m"),
            format!(
                "y = {} m: the left arm's end is on the left (y > 0), as every point of the file",
                bar.arm_end_m[1]
            ),
        ));
    }
    let arm = (bar.arm_end_m[0] - bar.axis_point_m[0]).hypot(bar.arm_end_m[2] - bar.axis_point_m[2]);
    if arm < 1e-6 {
        return Err(err(
            format!("{field}.arm_end_m"),
            "lies on the bar's axis: the arm has no length, so the droplink cannot turn the bar",
        ));
    }
    if let Some(low) = bar.droplink_end_m {
        if (Vector3::from(low) - Vector3::from(bar.arm_end_m)).norm() < 1e-6 {
            return Err(err(format!("{field}.droplink_end_m"), "coincides with arm_end_m: the droplink has no length"));
        }
    }
    nonneg(&format!("{field}.torsional_stiffness_Nm_per_rad"), bar.torsional_stiffness_Nm_per_rad)?;
    nonneg(&format!("{field}.torsional_damping_Nms_per_rad"), bar.torsional_damping_Nms_per_rad)?;
    if let Some(b) = &bar.arm {
        positive(&format!("{field}.arm.mass_kg"), b.mass_kg)?;
        pos_def(&format!("{field}.arm.inertia"), b)?;
    }
    Ok(())
}

/// A damper curve (`field`): a force table against the speed (`check_curve`) with the point (0, 0) between
/// speeds of both signs: a damper at rest pushes nothing, and the law's blend of its compression and
/// rebound halves there (`forces::damper_curve_force`) keeps that exactly.
pub(crate) fn check_damper_curve(field: &str, curve: &DamperCurve) -> Result<(), DataError> {
    check_curve(field, ("velocity_m_per_s", "speed"), &curve.velocity_m_per_s, &curve.force_N)?;
    let (v, f) = (&curve.velocity_m_per_s, &curve.force_N);
    match v.iter().position(|x| *x == 0.0) {
        Some(k) if k > 0 && k + 1 < v.len() && f[k] == 0.0 => Ok(()),
        Some(k) if k > 0 && k + 1 < v.len() => Err(err(
            format!("{field}.force_N"),
            format!("must be 0 at v = 0 (a damper at rest pushes nothing); it is {} N there", f[k]),
        )),
        _ => Err(err(
            format!("{field}.velocity_m_per_s"),
            "must have the point v = 0 (force 0) between speeds of both signs: compression and rebound",
        )),
    }
}

/// A damper map (`field`): at least two lengths, positive and strictly increasing, at most
/// `MAX_DAMPER_MAP_POINTS` of them and of the speeds; a row of forces per speed, one per length; and at each
/// length, its column a damper curve against the speed (`check_damper_curve`: rising, 0 at rest).
pub(crate) fn check_damper_map(field: &str, m: &DamperMap) -> Result<(), DataError> {
    let (l, v) = (&m.length_m, &m.velocity_m_per_s);
    if l.len() < 2 || l.len() > MAX_DAMPER_MAP_POINTS || v.len() > MAX_DAMPER_MAP_POINTS {
        return Err(err(field, format!("2 to {MAX_DAMPER_MAP_POINTS} lengths and at most as many speeds")));
    }
    if !l.iter().all(|x| x.is_finite() && *x > 0.0) || l.windows(2).any(|w| !(w[1] > w[0])) {
        return Err(err(format!("{field}.length_m"), "must be positive, finite and strictly increasing"));
    }
    if m.force_N.len() != v.len() || m.force_N.iter().any(|row| row.len() != l.len()) {
        return Err(err(
            format!("{field}.force_N"),
            format!("must have a row per speed ({}) of a force per length ({})", v.len(), l.len()),
        ));
    }
    for (j, length) in l.iter().enumerate() {
        let column = DamperCurve { velocity_m_per_s: v.clone(), force_N: m.force_N.iter().map(|row| row[j]).collect() };
        check_damper_curve(field, &column).map_err(|e| err(e.field, format!("at length {length} m: {}", e.message)))?;
    }
    Ok(())
}

/// A spring curve: at least two points, deflections strictly increasing, forces finite and never falling
/// with extension, the last above the first (a curve that does not rise is no spring).
fn check_spring_curve(field: &str, c: &SpringCurve) -> Result<(), DataError> {
    check_curve(field, ("deflection_m", "extension"), &c.deflection_m, &c.force_N)
}

/// A force table against `x_name` (a spring's deflection, a damper's speed): at least two points, x strictly
/// increasing, every value finite, the forces never falling as x grows and the last above the first (a
/// falling stretch would be a negative stiffness or damping).
fn check_curve(field: &str, (x_name, rising_with): (&str, &str), x: &[f64], f: &[f64]) -> Result<(), DataError> {
    if x.len() != f.len() || x.len() < 2 {
        return Err(err(field, format!("{x_name} and force_N must have the same length, at least 2")));
    }
    if x.iter().chain(f).any(|v| !v.is_finite()) {
        return Err(err(field, "every point must be a finite number"));
    }
    if x.windows(2).any(|w| !(w[1] > w[0])) {
        return Err(err(format!("{field}.{x_name}"), "must increase strictly"));
    }
    if f.windows(2).any(|w| w[1] < w[0]) || !(f[f.len() - 1] > f[0]) {
        return Err(err(
            format!("{field}.force_N"),
            format!("must rise with {rising_with} (never fall, last above first)"),
        ));
    }
    Ok(())
}

fn pos_def(field: &str, b: &RigidBody) -> Result<(), DataError> {
    finite3(field, &b.inertia_moments_kg_m2)?;
    finite3(field, &b.inertia_products_kg_m2)?;
    let e = b.inertia().symmetric_eigenvalues();
    if e.iter().all(|x| *x > 0.0) {
        Ok(())
    } else {
        Err(err(
            field,
            format!("inertia tensor is not positive definite (eigenvalues {:.4}, {:.4}, {:.4})", e[0], e[1], e[2]),
        ))
    }
}
