//! The subsystem stage (§4.2): each corner's effective terms M_qq, M_q0, P_q, M̂_00, P̂_0, Φ_q and the
//! factored Φ_v (`Workspace::assembly.terms`; γ̄ is written by the velocity stage), from its kinematics and
//! the wrenches the force, tire and brake stages put on its bodies.

use super::kinematics::{CornerKinematics, BODY_K, BODY_L, BODY_U};
use super::{point_velocity, AxleKind, AxleWork, Vehicle, Workspace};
use crate::dynamics::body::{ang, body_force, mass_hat, mass_hat_times, MassHatSum};
use crate::dynamics::{AxleTerms, PhiVSolved, SubsystemTerms};
use crate::math::{M3, V3};
use crate::model::suspension::solid_axle::steering::{BELLCRANK, KNUCKLE};
use crate::model::suspension::{BodyInertia, CornerPositions};
use nalgebra::{Matrix6, SMatrix, Vector6};

impl Vehicle {
    /// Writes `assembly.terms` (all but γ̄) from the positions, the kinematics and the wrenches.
    #[inline(always)]
    pub(super) fn subsystem_terms_stage(&self, ws: &mut Workspace) {
        let Workspace { positions, kinematics, wrenches, assembly, axles, chassis, .. } = ws;
        assembly.kinds = [self.axle_kind(0), self.axle_kind(1)];
        for a in 0..2 {
            match assembly.kinds[a] {
                AxleKind::Independent => {
                    for i in [2 * a, 2 * a + 1] {
                        subsystem_terms(&positions[i], &kinematics[i], &wrenches[i].bodies, &mut assembly.terms[i]);
                    }
                }
                AxleKind::Solid => {
                    let on_axle = [&wrenches[2 * a].bodies, &wrenches[2 * a + 1].bodies];
                    let solid = self.solid_axles[a].as_ref().expect("a solid axle has its body");
                    match &solid.steering {
                        None => {
                            axle_terms(&axles[a], solid.body.mass, on_axle, &chassis.g, &mut assembly.axle_terms[a])
                        }
                        Some(steering) => steered_axle_terms(
                            &axles[a],
                            solid.body.mass,
                            &steering.bodies,
                            on_axle,
                            &chassis.g,
                            &mut assembly.axle_terms[a],
                        ),
                    }
                }
                // A subsystem with no coordinate (docs/physics.md §4.6b): its wheels' wrenches are on the
                // chassis, which carries their mass (the synthesis stage adds them to its force).
                AxleKind::Rigid => {}
            }
        }
    }
}

/// A solid axle's terms (§4.2 with one body, docs/physics.md §4.6a): M̂ of the axle body (of `mass`), the wrench on it
/// (its gravity and velocity terms, and what its wheels' corners put on their carrier, which is the axle:
/// springs, dampers, tires, brakes, the wheels' gyroscopic moments), 𝔅 and 𝔇 from the velocity stage, Φ_q
/// and the factored Φ_v from the positions.
#[inline(never)] // not on an independent suspension's path
fn axle_terms(work: &AxleWork, mass: f64, wheels: [&[Vector6<f64>; 3]; 2], g: &V3, terms: &mut AxleTerms) {
    let (w, y) = (ang(&work.velocity), work.velocity);
    let mut q = body_force(mass, &work.com, &work.inertia, &w, &point_velocity(&y, &work.com), g);
    for bodies in wheels {
        q += bodies[0] + bodies[1] + bodies[2];
    }
    let mh = mass_hat(mass, &work.com, &work.inertia);
    let mh_b = mh * work.b;
    terms.m_qq = work.b.tr_mul(&mh_b);
    terms.m_q0 = mh_b.transpose();
    terms.m_00 = mh;
    let p = q - mh * work.rate;
    terms.p_q = work.b.tr_mul(&p);
    terms.p_0 = p;
    let pos = &work.positions;
    terms.phi_q = pos.phi_q;
    terms.phi_v_solved = pos.lu_v.map(|lu| PhiVSolved { lu, phi_v_inv_phi_u: -pos.dv_du });
}

/// A steered solid axle's terms (§4.2 over its four bodies, docs/physics.md §4.6c): the tube (its own
/// wrench, and the springs and dampers its wheels' corners put in their lower slot) and the bellcrank and
/// knuckles, each with its 𝔅 over the axle's q and its 𝔇 from the velocity stage (`solid_axle::steering`); a
/// knuckle takes its wheel corner's carrier wrench (tire, brake, drive, the wheel's gyroscopic moment).
#[inline(never)] // not on an independent suspension's path
fn steered_axle_terms(
    work: &AxleWork,
    tube_mass: f64,
    bodies: &[BodyInertia; 3],
    wheels: [&[Vector6<f64>; 3]; 2],
    g: &V3,
    terms: &mut AxleTerms,
) {
    terms.m_qq = SMatrix::zeros();
    terms.m_q0 = SMatrix::zeros();
    terms.m_00 = Matrix6::zeros();
    terms.p_q = Vector6::zeros();
    terms.p_0 = Vector6::zeros();
    let mut add = |mass: f64,
                   com: &V3,
                   inertia: &M3,
                   b: &SMatrix<f64, 6, 6>,
                   rate: &Vector6<f64>,
                   y: &Vector6<f64>,
                   q: Vector6<f64>| {
        let q = q + body_force(mass, com, inertia, &ang(y), &point_velocity(y, com), g);
        let mh = mass_hat(mass, com, inertia);
        let mh_b = mh * b;
        terms.m_qq += b.tr_mul(&mh_b);
        terms.m_q0 += mh_b.transpose();
        terms.m_00 += mh;
        let p = q - mh * rate;
        terms.p_q += b.tr_mul(&p);
        terms.p_0 += p;
    };
    add(tube_mass, &work.com, &work.inertia, &work.b, &work.rate, &work.velocity, wheels[0][0] + wheels[1][0]);
    for (j, body) in work.steer_bodies.iter().enumerate() {
        let on_it = match j {
            BELLCRANK => Vector6::zeros(),
            _ => {
                let w = wheels[if j == KNUCKLE[0] { 0 } else { 1 }];
                w[1] + w[2]
            }
        };
        add(bodies[j].mass, &body.com, &body.inertia, &body.b, &body.rate, &body.velocity, on_it);
    }
    let pos = &work.positions;
    terms.phi_q = pos.phi_q;
    terms.phi_v_solved = pos.lu_v.map(|lu| PhiVSolved { lu, phi_v_inv_phi_u: -pos.dv_du });
}

/// One corner's effective terms from its positions, kinematics and body wrenches [Q_L, Q_K, Q_U].
#[inline(always)]
pub(super) fn subsystem_terms(
    pos: &CornerPositions,
    k: &CornerKinematics,
    q: &[Vector6<f64>; 3],
    terms: &mut SubsystemTerms,
) {
    let [q_l, q_k, q_u] = q;
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
    // ∂v/∂u = −Φ_v⁻¹Φ_u, solved with the same factors: the negation is exact, so GCP gets its own bits.
    terms.phi_v_solved = pos.lu_v.map(|lu| PhiVSolved { lu, phi_v_inv_phi_u: -pos.dv_du });
}
