//! TEMPORARY stand-in with the agreed interface (the dynamics branch replaces this file).
use nalgebra::{DMatrix, DVector, Matrix6, SMatrix, Vector4, Vector5, Vector6};
pub const NQ: usize = 5;
pub const NC: usize = 4;
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SubsystemTerms {
    pub m_qq: SMatrix<f64, 5, 5>,
    pub m_q0: SMatrix<f64, 5, 6>,
    pub m_00: Matrix6<f64>,
    pub p_q: Vector5<f64>,
    pub p_0: Vector6<f64>,
    pub phi_q: SMatrix<f64, 4, 5>,
    pub gamma_bar: Vector4<f64>,
}
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChassisTerms { pub mass: Matrix6<f64>, pub force: Vector6<f64> }
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Accelerations<const K: usize> {
    pub chassis: Vector6<f64>,
    pub q_ddot: [Vector5<f64>; K],
    pub lambda: [Vector4<f64>; K],
}
#[derive(Debug, Clone, PartialEq)]
pub struct SolveError(pub String);
pub fn solve_conventional(ch: &ChassisTerms, subs: &[SubsystemTerms; 4]) -> Result<Accelerations<4>, SolveError> {
    let n = 42;
    let mut a = DMatrix::<f64>::zeros(n, n);
    let mut b = DVector::<f64>::zeros(n);
    let mut m00 = ch.mass;
    let mut f0 = ch.force;
    for (i, s) in subs.iter().enumerate() {
        let o = 6 + 9 * i;
        m00 += s.m_00;
        f0 += s.p_0;
        a.view_mut((o, 0), (5, 6)).copy_from(&s.m_q0);
        a.view_mut((0, o), (6, 5)).copy_from(&s.m_q0.transpose());
        a.view_mut((o, o), (5, 5)).copy_from(&s.m_qq);
        a.view_mut((o + 5, o), (4, 5)).copy_from(&s.phi_q);
        a.view_mut((o, o + 5), (5, 4)).copy_from(&s.phi_q.transpose());
        b.rows_mut(o, 5).copy_from(&s.p_q);
        b.rows_mut(o + 5, 4).copy_from(&s.gamma_bar);
    }
    a.view_mut((0, 0), (6, 6)).copy_from(&m00);
    b.rows_mut(0, 6).copy_from(&f0);
    let z = a.lu().solve(&b).ok_or_else(|| SolveError("singular".into()))?;
    let mut out = Accelerations { chassis: Vector6::from_iterator(z.rows(0, 6).iter().copied()), q_ddot: [Vector5::zeros(); 4], lambda: [Vector4::zeros(); 4] };
    for i in 0..4 {
        let o = 6 + 9 * i;
        out.q_ddot[i] = Vector5::from_iterator(z.rows(o, 5).iter().copied());
        out.lambda[i] = Vector4::from_iterator(z.rows(o + 5, 4).iter().copied());
    }
    Ok(out)
}
pub fn solve_synthesis_gcp<const K: usize>(ch: &ChassisTerms, subs: &[SubsystemTerms; K]) -> Result<Accelerations<K>, SolveError> {
    let s4: &[SubsystemTerms; 4] = (subs as &dyn std::any::Any).downcast_ref().unwrap();
    let a = solve_conventional(ch, s4)?;
    Ok(*(&a as &dyn std::any::Any).downcast_ref::<Accelerations<K>>().unwrap())
}
pub fn solve_synthesis_augmented<const K: usize>(ch: &ChassisTerms, subs: &[SubsystemTerms; K]) -> Result<Accelerations<K>, SolveError> {
    solve_synthesis_gcp(ch, subs)
}
