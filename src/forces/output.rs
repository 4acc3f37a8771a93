//! [`Forces`]: what one force evaluation leaves for the integrators, the
//! observers, the blow-up detectors, the co-simulation and the rapier sync.

/// The forces at one state, written by the force elements of a
/// `super::ForceGenerator` and read by everything after them.
///
/// Roller forces include gravity. Per-sprocket sums hold the chain's action
/// on each sprocket (its load torque is the model's, not added here).
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Forces {
    /// Force on each roller (links, contacts, gravity, further elements), N.
    pub fx: Vec<f64>,
    /// Force on each roller, y, N.
    pub fy: Vec<f64>,
    /// Link force F_link of link i (roller i to i + 1), N, tension positive.
    pub link_force: Vec<f64>,
    /// Whether roller i touches any sprocket.
    pub touching: Vec<bool>,
    /// Total contact force magnitude on each roller (the magnitude of the
    /// vector sum of its patches' forces), N.
    pub contact_force: Vec<f64>,
    /// Moment of the chain's contact forces on each sprocket about its centre, N·m.
    pub chain_torque: Vec<f64>,
    /// Resultant of the chain's contact forces on each sprocket, N.
    pub chain_force: Vec<[f64; 2]>,
    /// Generalised force on each further body's coordinate
    /// ([`crate::model::BodyModel`]), N or N·m.
    pub body_force: Vec<f64>,
    /// Time derivative of each scalar state ([`crate::model::ScalarModel`]).
    pub scalar_rate: Vec<f64>,
    /// Largest penetration in this evaluation, m.
    pub max_penetration_m: f64,
    /// Largest |l − rest length| of any link in this evaluation, m (NaN propagates).
    pub max_stretch_m: f64,
    /// Largest roller speed in this evaluation, m/s (the links measure it;
    /// the contact's reach caching bounds its skips with it).
    pub max_roller_speed_m_s: f64,
    /// Elastic energy stored in the contacts, Σ K δⁿ⁺¹/(n + 1), J.
    pub contact_energy_j: f64,
    /// Power of the contacts' damping forces (their part beyond the elastic
    /// K δⁿ) on the rollers relative to the sprockets, W (≤ 0).
    pub contact_damping_power_w: f64,
    /// Each joint's friction moment (joint i at roller i: the moment of link
    /// i−1 on link i), N·m; empty without joint friction.
    pub joint_moment_n_m: Vec<f64>,
    /// Power of the joint friction, Σ M_i ω_rel,i, W (≤ 0).
    pub joint_friction_power_w: f64,
    /// Each tensioner arm's reading, in scene order (empty without arms;
    /// an arm sizes it at its first evaluation).
    pub(crate) tensioners: Vec<super::TensionerReading>,
    /// The forces on each shoe ([`super::GuideElement`]), one entry per shoe in the
    /// order the elements are evaluated (the scene's guides in scene order);
    /// empty without shoes.
    pub(crate) shoes: Vec<super::ShoeForces>,
    /// Each link's angular velocity ω = (u × Δv)/ℓ, rad/s: written by the
    /// links when it holds one slot per link (the joint friction sizes it at
    /// its first evaluation), left empty and not computed otherwise.
    pub(crate) link_omega: Vec<f64>,
    /// Each link's unit normal over its length, n/ℓ = (−u_y, u_x)/ℓ, x, 1/m
    /// (written with [`Self::link_omega`]).
    pub(crate) link_normal_x: Vec<f64>,
    /// Its y component, 1/m.
    pub(crate) link_normal_y: Vec<f64>,
}

impl Forces {
    /// Zeroed outputs for a drive of these sizes.
    pub fn new(rollers: usize, sprockets: usize, bodies: usize, scalars: usize) -> Self {
        Self {
            fx: vec![0.0; rollers],
            fy: vec![0.0; rollers],
            link_force: vec![0.0; rollers],
            touching: vec![false; rollers],
            contact_force: vec![0.0; rollers],
            chain_torque: vec![0.0; sprockets],
            chain_force: vec![[0.0; 2]; sprockets],
            body_force: vec![0.0; bodies],
            scalar_rate: vec![0.0; scalars],
            max_penetration_m: 0.0,
            max_stretch_m: 0.0,
            max_roller_speed_m_s: 0.0,
            contact_energy_j: 0.0,
            contact_damping_power_w: 0.0,
            joint_moment_n_m: Vec::new(),
            joint_friction_power_w: 0.0,
            tensioners: Vec::new(),
            shoes: Vec::new(),
            link_omega: Vec::new(),
            link_normal_x: Vec::new(),
            link_normal_y: Vec::new(),
        }
    }

    /// Clears the sums that every element adds to (per sprocket, per body,
    /// per scalar). The roller forces are not cleared: the links set them.
    pub(crate) fn begin(&mut self) {
        self.chain_torque.fill(0.0);
        self.chain_force.fill([0.0; 2]);
        self.body_force.fill(0.0);
        self.scalar_rate.fill(0.0);
        // Cleared, its capacity kept: the shoes push again without allocating.
        self.shoes.clear();
    }
}
