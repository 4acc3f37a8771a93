//! The model: a [`Scene`] turned into what the force generator and the
//! steppers work on — constant parameters ([`DriveModel`]), the state in
//! structure-of-arrays form ([`DriveState`]), the free-strand classification
//! ([`Segments`]) — and the rapier bodies that carry it ([`rapier`]).
//!
//! This module lays the chain out; it does not bring it to equilibrium (that
//! is stepping, [`crate::sim`]).

mod excitation;
#[cfg(test)]
mod excitation_tests;
mod governor;
#[cfg(test)]
mod governor_tests;
pub(crate) mod rapier;
mod segments;
#[cfg(test)]
mod strands_tests;

pub(crate) use excitation::{AngleLoad, speed_factor};
pub(crate) use governor::{Governor, target_angle_rad};
pub(crate) use segments::{Segments, StrandRuns};

use crate::geometry::{
    ChainPath, Layout, LayoutError, PathCircle, PathError, ToothProfile, chain_path, hang_excess,
    layout_rollers, layout_with_arms,
};
use crate::scene::{Harmonic, Scene, SpeedLaw, TensionerKind};

/// The further bodies and scalar states of a scene's tensioner arms: arm k is
/// body k (its angle from the scene's pose), and each hydraulic tensioner's
/// chamber pressure a scalar state, in scene order. The arms start at the
/// scene's pose, at rest; the chambers at their supply pressure.
/// Whether a chain of `scene` longer than its path (which needs `needed`
/// pitches) has its excess held by the strands' sag at the pretension
/// (under gravity), within a tenth of a pitch.
fn sag_holds(scene: &Scene, path: &ChainPath, needed: f64) -> bool {
    let chain = &scene.chain;
    let excess_m = (chain.rollers as f64 - needed) * chain.pitch_m;
    let sag_m = path.sag_take_up_m(
        chain.roller_mass_kg / chain.pitch_m,
        scene.gravity_m_s2,
        chain.pretension_n,
    );
    excess_m > 0.0 && excess_m <= sag_m + 0.1 * chain.pitch_m
}

fn tensioner_states(scene: &Scene) -> (Vec<BodyModel>, Vec<ScalarModel>) {
    // Error scales: the arm turning by the static link stretch T/K over its
    // shoe's distance from the pivot; the chamber's fluid volume by what
    // changes its pressure by a kilopascal, V₀ · 1 kPa / β.
    let stretch = scene.chain.pretension_n / scene.chain.stiffness_n_m;
    let bodies = scene
        .tensioners
        .iter()
        .map(|t| {
            let reach = (t.shoe_center_m[0] - t.pivot_m[0])
                .hypot(t.shoe_center_m[1] - t.pivot_m[1])
                .max(t.shoe_radius_m);
            BodyModel {
                name: format!("{} arm", t.name),
                inv_mass: 1.0 / t.inertia_kg_m2,
                error_scale: stretch / reach,
            }
        })
        .collect();
    let scalars = scene
        .tensioners
        .iter()
        .filter_map(|t| match &t.kind {
            TensionerKind::Hydraulic(h) => Some(ScalarModel {
                name: format!("{} chamber fluid volume", t.name),
                error_scale: h.chamber_volume_m3 * 1e3 / h.bulk_modulus_pa,
            }),
            TensionerKind::Spring(_) => None,
        })
        .collect();
    (bodies, scalars)
}

/// Constant data of one sprocket.
#[derive(Clone, Debug)]
pub struct SprocketModel {
    /// Centre, m (fixed in a standalone run; a mounted sprocket's body may
    /// move it in a co-simulation).
    pub center_m: [f64; 2],
    /// Velocity of the centre, m/s: zero but for a sprocket mounted on a
    /// moving body (the contact damping and the reach caching use it).
    pub center_velocity_m_s: [f64; 2],
    /// 1 / J, 1/(kg·m²).
    pub inv_inertia: f64,
    /// The driver's speed law; `None` for a free sprocket and a
    /// torque-driven driver.
    pub speed_law: Option<SpeedLaw>,
    /// A torque-driven driver's drive torque and speed governor: the
    /// sprocket turns freely under it (read through
    /// [`SprocketModel::torque_at`]) and is held while the drive relaxes to
    /// static equilibrium; `None`: none.
    pub(crate) governor: Option<Governor>,
    /// The driver's speed harmonics in its angle (relative amplitudes):
    /// ω = ω̄(t) (1 + Σ a_k sin(k (θ − θ₀) + φ_k)); empty: ω = ω̄(t).
    pub(crate) speed_harmonics: Vec<Harmonic>,
    /// External load torque at full value, N·m (read through
    /// [`SprocketModel::torque_at`]).
    pub load_torque_n_m: f64,
    /// The part of the load that depends on the angle θ − θ₀, ramped in with
    /// the constant load; `None`: none.
    pub(crate) angle_load: Option<AngleLoad>,
    /// The angle origin θ₀ of the speed harmonics and the angle-dependent
    /// load, rad: the sprocket's angle as laid out (the driver's at t = 0).
    pub angle_origin_rad: f64,
    /// Time over which the load rises linearly from zero to its full value, s
    /// (0: the load acts from rest on).
    pub load_ramp_s: f64,
    /// A torque opposing the sprocket's rotation (read through
    /// [`SprocketModel::torque_at`]); `None`: none.
    pub(crate) resisting: Option<crate::scene::Resisting>,
    /// A torque that does not ramp, N·m: a co-simulation's user torque on the
    /// body a sprocket is mounted on (zero in a standalone run).
    pub user_torque_n_m: f64,
    /// Tooth outline used by the contact generator.
    pub(crate) profile: ToothProfile,
    /// Radius beyond which no roller centre touches the sprocket, m.
    pub reach_m: f64,
    /// Its square, m².
    pub reach_sq_m2: f64,
    /// Pitch radius, m.
    pub pitch_radius_m: f64,
    /// Tooth count.
    pub teeth: u32,
}

impl SprocketModel {
    /// The external torque at time `t_s`, angle `theta_rad` and speed
    /// `omega_rad_s`, N·m: the load M(θ) = M + M_θ(θ − θ₀) times `t/t_r`
    /// while `t < t_r = load_ramp_s`, the full M(θ) after (and always when no
    /// ramp is set, so the load at rest is M(θ) exactly), plus the user's
    /// torque, which does not ramp, plus a resisting load's torque, which
    /// opposes the speed and does not ramp (zero at rest), plus a
    /// torque-driven driver's torque (`Governor::torque_at`).
    #[inline]
    pub fn torque_at(&self, t_s: f64, theta_rad: f64, omega_rad_s: f64) -> f64 {
        let mut external = self.external_torque_at(t_s, theta_rad);
        if let Some(resisting) = &self.resisting {
            external += resisting.torque_at(omega_rad_s);
        }
        match &self.governor {
            Some(g) => external + g.torque_at(t_s, theta_rad - self.angle_origin_rad, omega_rad_s),
            None => external,
        }
    }

    /// Whether the sprocket is held still while the drive relaxes to static
    /// equilibrium: a driver, kinematic or torque-driven.
    #[inline]
    pub fn held_at_rest(&self) -> bool {
        self.speed_law.is_some() || self.governor.is_some()
    }

    /// Whether the static equilibrium keeps the sprocket where it is: held
    /// at rest ([`Self::held_at_rest`]) or without rotational freedom (no
    /// inverse inertia: a sprocket the co-simulation holds for the solve).
    #[inline]
    pub(crate) fn still_in_statics(&self) -> bool {
        self.held_at_rest() || !(self.inv_inertia > 0.0)
    }

    /// The load and the user's torque of [`Self::torque_at`], without a
    /// governor's torque, N·m.
    #[inline]
    fn external_torque_at(&self, t_s: f64, theta_rad: f64) -> f64 {
        let mut load = self.load_torque_n_m;
        if let Some(angle_load) = &self.angle_load {
            load += angle_load.at(theta_rad - self.angle_origin_rad);
        }
        let load = if t_s < self.load_ramp_s {
            load * (t_s / self.load_ramp_s)
        } else {
            load
        };
        load + self.user_torque_n_m
    }

    /// The external torque at time `t_s` with the sprocket at its angle
    /// origin ([`Self::torque_at`]; the same at every angle for a constant
    /// load), N·m.
    #[inline]
    pub fn load_torque_at(&self, t_s: f64) -> f64 {
        self.external_torque_at(t_s, self.angle_origin_rad)
    }

    /// The load held while the drive relaxes to static equilibrium, N·m: the
    /// load at rest (t = 0) at the angle origin, zero where the load ramps in.
    #[inline]
    pub fn load_at_rest_n_m(&self) -> f64 {
        self.load_torque_at(0.0)
    }

    /// The driver's prescribed speed at time `t_s` and angle `theta_rad`,
    /// rad/s: ω̄(t) (1 + Σ a_k sin(k (θ − θ₀) + φ_k)); 0 without a speed law.
    #[inline]
    pub fn driver_speed_at(&self, t_s: f64, theta_rad: f64) -> f64 {
        let Some(law) = self.speed_law else {
            return 0.0;
        };
        if self.speed_harmonics.is_empty() {
            law.speed_at(t_s)
        } else {
            law.speed_at(t_s)
                * speed_factor(&self.speed_harmonics, theta_rad - self.angle_origin_rad)
        }
    }

    /// The driver's mean speed over a step of `dt_s` from time `t_s` and
    /// angle `theta_rad`, rad/s: the explicit midpoint rule on
    /// dθ/dt = ω(t, θ) (second order); without harmonics ω̄(t + dt/2), which
    /// integrates a ramp exactly.
    #[inline]
    pub fn driver_step_speed(&self, t_s: f64, theta_rad: f64, dt_s: f64) -> f64 {
        let Some(law) = self.speed_law else {
            return 0.0;
        };
        let t_mid = t_s + 0.5 * dt_s;
        if self.speed_harmonics.is_empty() {
            law.speed_at(t_mid)
        } else {
            let theta_mid = theta_rad + 0.5 * dt_s * self.driver_speed_at(t_s, theta_rad);
            self.driver_speed_at(t_mid, theta_mid)
        }
    }
}

/// Constant parameters of a drive, derived from a scene.
#[derive(Clone, Debug)]
pub struct DriveModel {
    /// Roller mass, kg.
    pub roller_mass_kg: f64,
    /// Link stiffness, N/m.
    pub stiffness_n_m: f64,
    /// Link damping, N·s/m.
    pub damping_n_s_m: f64,
    /// Link rest length, m (set by the pretension rule).
    pub rest_length_m: f64,
    /// Gravity, m/s².
    pub gravity_m_s2: [f64; 2],
    /// Sprockets in scene order.
    pub sprockets: Vec<SprocketModel>,
    /// The nominal chain path (tangent lines and wraps on the pitch circles).
    pub(crate) path: ChainPath,
    /// Free-strand classification of links.
    pub(crate) segments: Segments,
    /// Further rigid bodies' coordinates (a tensioner arm's angle, a
    /// plunger's travel), beside the rollers and sprockets.
    pub bodies: Vec<BodyModel>,
    /// Scalar states of first order (a hydraulic chamber's pressure).
    pub scalars: Vec<ScalarModel>,
}

/// One coordinate of a further rigid body (an arm's angle about its pivot,
/// a plunger's travel): a second-order state q with speed u, advanced by
/// every integrator under the generalised force the force elements put in
/// [`crate::forces::Forces::body_force`], ü = Q / m.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyModel {
    /// Name, for outputs and errors.
    pub name: String,
    /// 1 / m, the inverse of the coordinate's mass or moment of inertia,
    /// 1/kg or 1/(kg·m²).
    pub inv_mass: f64,
    /// The coordinate's error scale for the adaptive integrator, m or rad:
    /// a change of this size matters as much as the static link stretch does
    /// for a roller. Its speed's scale is this over the step's time scale.
    pub error_scale: f64,
}

/// A scalar state of first order (a hydraulic chamber's pressure), advanced
/// by every integrator at the rate the force elements put in
/// [`crate::forces::Forces::scalar_rate`].
#[derive(Clone, Debug, PartialEq)]
pub struct ScalarModel {
    /// Name, for outputs and errors.
    pub name: String,
    /// The error scale for the adaptive integrator, in the state's unit.
    pub error_scale: f64,
}

impl DriveModel {
    /// Adds a further body to the model and its coordinate `q` and speed
    /// `u` to `state`: its index in [`DriveState::q`]. The force outputs
    /// are then sized anew by whoever holds them.
    pub(crate) fn push_body(
        &mut self,
        state: &mut DriveState,
        body: BodyModel,
        q: f64,
        u: f64,
    ) -> usize {
        self.bodies.push(body);
        state.q.push(q);
        state.u.push(u);
        state.q.len() - 1
    }

    /// Adds a scalar state to the model and its value `z` to `state`: its
    /// index in [`DriveState::z`].
    pub(crate) fn push_scalar(
        &mut self,
        state: &mut DriveState,
        scalar: ScalarModel,
        z: f64,
    ) -> usize {
        self.scalars.push(scalar);
        state.z.push(z);
        state.z.len() - 1
    }
}

/// The state that is integrated: rollers as structure of arrays, sprockets.
///
/// `clone_from` reuses the buffers (integrators copy states every step).
#[derive(Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DriveState {
    /// Time, s.
    pub t_s: f64,
    /// Roller x, m.
    pub x: Vec<f64>,
    /// Roller y, m.
    pub y: Vec<f64>,
    /// Roller x velocity, m/s.
    pub vx: Vec<f64>,
    /// Roller y velocity, m/s.
    pub vy: Vec<f64>,
    /// Sprocket angles, rad.
    pub theta: Vec<f64>,
    /// Sprocket angular speeds, rad/s.
    pub omega: Vec<f64>,
    /// Further bodies' coordinates ([`BodyModel`]), m or rad.
    pub q: Vec<f64>,
    /// Their speeds, m/s or rad/s.
    pub u: Vec<f64>,
    /// Scalar states ([`ScalarModel`]).
    pub z: Vec<f64>,
}

impl Clone for DriveState {
    fn clone(&self) -> Self {
        Self {
            t_s: self.t_s,
            x: self.x.clone(),
            y: self.y.clone(),
            vx: self.vx.clone(),
            vy: self.vy.clone(),
            theta: self.theta.clone(),
            omega: self.omega.clone(),
            q: self.q.clone(),
            u: self.u.clone(),
            z: self.z.clone(),
        }
    }

    fn clone_from(&mut self, source: &Self) {
        self.t_s = source.t_s;
        self.x.clone_from(&source.x);
        self.y.clone_from(&source.y);
        self.vx.clone_from(&source.vx);
        self.vy.clone_from(&source.vy);
        self.theta.clone_from(&source.theta);
        self.omega.clone_from(&source.omega);
        self.q.clone_from(&source.q);
        self.u.clone_from(&source.u);
        self.z.clone_from(&source.z);
    }
}

impl DriveState {
    /// Number of rollers.
    pub fn rollers(&self) -> usize {
        self.x.len()
    }
}

/// Why a scene cannot be built into a drive.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// No tangent line with the requested wrap senses joins two sprockets
    /// (e.g. a crossed strand between overlapping circles): no chain path exists.
    #[error(
        "sprockets: no {kind} tangent from sprocket {from} to sprocket {to}: the circles are too close for these wrap senses"
    )]
    NoTangent {
        /// "plain" or "crossed".
        kind: &'static str,
        /// 1-based index.
        from: usize,
        /// 1-based index.
        to: usize,
    },
    /// The chain does not fit the path.
    #[error("chain.rollers: {0}")]
    Layout(#[from] LayoutError),
    /// The real tooth profile cannot be built for these dimensions.
    #[error("sprockets[{sprocket}].profile: {reason}")]
    Profile {
        /// 0-based sprocket index.
        sprocket: usize,
        /// Why the tooth form cannot be drawn.
        reason: String,
    },
}

impl BuildError {
    /// The build's form of a path's error.
    pub(crate) fn no_path(error: PathError) -> Self {
        match error {
            PathError::NoTangent { kind, from, to } => Self::NoTangent { kind, from, to },
        }
    }
}

impl DriveModel {
    /// Lays out `scene`'s chain: path, rollers seated on every wrap, sprockets
    /// turned to receive them, rest length = pitch (the pretension rule
    /// adjusts it later). Returns the model and its initial state (at rest).
    pub(crate) fn build(scene: &Scene) -> Result<(Self, DriveState, Layout), BuildError> {
        let chain = &scene.chain;
        let profiles: Vec<ToothProfile> = scene
            .sprockets
            .iter()
            .enumerate()
            .map(|(i, s)| {
                ToothProfile::new(s.profile, s.teeth, chain.pitch_m, chain.roller_radius_m).map_err(
                    |error| BuildError::Profile {
                        sprocket: i,
                        reason: error.to_string(),
                    },
                )
            })
            .collect::<Result<_, _>>()?;
        let pitch_circles: Vec<PathCircle> = scene
            .sprockets
            .iter()
            .map(|s| PathCircle {
                center_m: s.center_m,
                radius_m: s.pitch_radius_m,
                sense: s.wrap.sign(),
            })
            .collect();
        let path = chain_path(&pitch_circles).map_err(BuildError::no_path)?;
        let seat_circles: Vec<PathCircle> = pitch_circles
            .iter()
            .zip(&profiles)
            .map(|(c, p)| PathCircle {
                radius_m: p.seated_radius_m(),
                ..*c
            })
            .collect();
        let seat_path = chain_path(&seat_circles).map_err(BuildError::no_path)?;
        let teeth: Vec<u32> = scene.sprockets.iter().map(|s| s.teeth).collect();
        let layout = lay_out(scene, &seat_path, &seat_circles, &teeth)?;
        let sprockets: Vec<SprocketModel> = scene
            .sprockets
            .iter()
            .zip(profiles)
            .zip(&layout.sprocket_angles_rad)
            .enumerate()
            .map(|(i, ((s, profile), &angle_origin_rad))| {
                sprocket_model(scene, i, s, profile, angle_origin_rad, &path)
            })
            .collect();
        let n = chain.rollers;
        let state = DriveState {
            t_s: 0.0,
            x: layout.rollers_m.iter().map(|p| p[0]).collect(),
            y: layout.rollers_m.iter().map(|p| p[1]).collect(),
            vx: vec![0.0; n],
            vy: vec![0.0; n],
            theta: layout.sprocket_angles_rad.clone(),
            omega: vec![0.0; scene.sprockets.len()],
            q: Vec::new(),
            u: Vec::new(),
            z: Vec::new(),
        };
        let segments = Segments::new(&path);
        let (bodies, scalars) = tensioner_states(scene);
        let mut state = state;
        state.q = if layout.arms.len() == bodies.len() {
            layout.arms.iter().map(|a| a.angle_rad).collect()
        } else {
            vec![0.0; bodies.len()]
        };
        state.u = vec![0.0; bodies.len()];
        state.z = scene
            .tensioners
            .iter()
            .filter_map(|t| match &t.kind {
                // The fluid's volume is measured from the chamber's at the
                // scene's pose; the arm calibrates it to the supply pressure
                // where the static equilibrium leaves it.
                TensionerKind::Hydraulic(_) => Some(0.0),
                TensionerKind::Spring(_) => None,
            })
            .collect();
        let model = DriveModel {
            roller_mass_kg: chain.roller_mass_kg,
            stiffness_n_m: chain.stiffness_n_m,
            damping_n_s_m: chain.damping_n_s_m,
            rest_length_m: chain.pitch_m,
            gravity_m_s2: scene.gravity_m_s2,
            sprockets,
            path,
            segments,
            bodies,
            scalars,
        };
        Ok((model, state, layout))
    }

    /// The angle the nominal chain path wraps sprocket `k` by, rad (`None`:
    /// no sprocket `k`).
    pub fn wrap_rad(&self, k: usize) -> Option<f64> {
        self.path.wraps.get(k).map(|w| w.wrap_rad)
    }

    /// Moves sprocket `k`'s centre to `scene`'s (a tensioner moved after
    /// the layout: a worn chain taken up) and traces the nominal path and
    /// its strands anew from `scene`'s sprockets. The state is not touched.
    pub(crate) fn retrace(&mut self, scene: &Scene, k: usize) -> Result<(), BuildError> {
        let circles: Vec<PathCircle> = scene
            .sprockets
            .iter()
            .map(|s| PathCircle {
                center_m: s.center_m,
                radius_m: s.pitch_radius_m,
                sense: s.wrap.sign(),
            })
            .collect();
        let path = chain_path(&circles).map_err(BuildError::no_path)?;
        if let (Some(sp), Some(s)) = (self.sprockets.get_mut(k), scene.sprockets.get(k)) {
            sp.center_m = s.center_m;
        }
        self.segments = Segments::new(&path);
        self.path = path;
        Ok(())
    }

    /// Number of sprockets.
    pub fn sprocket_count(&self) -> usize {
        self.sprockets.len()
    }

    /// Number of free-strand segments (segment k runs from sprocket k to
    /// the next, numbered from 1 in outputs).
    pub fn segment_count(&self) -> usize {
        self.segments.len()
    }

    /// The fastest sprocket centre's speed, m/s, or `None` when no centre
    /// moves (only a sprocket mounted on a moving body in a co-simulation
    /// does).
    pub fn moving_centres_speed_m_s(&self) -> Option<f64> {
        self.sprockets
            .iter()
            .filter(|sp| sp.center_velocity_m_s != [0.0; 2])
            .map(|sp| {
                let [vx, vy] = sp.center_velocity_m_s;
                vx * vx + vy * vy
            })
            .reduce(f64::max)
            .map(f64::sqrt)
    }

    /// Index of the driver, the sprocket with a speed law; `None` in a drive
    /// without one (every sprocket free, as in a co-simulation whose motor
    /// drives a mounted sprocket).
    pub fn driver(&self) -> Option<usize> {
        self.sprockets.iter().position(|s| s.speed_law.is_some())
    }

    /// Index of the sprocket that drives the chain: the kinematic driver or
    /// a torque-driven one (`SprocketModel::governor`).
    pub fn driving(&self) -> Option<usize> {
        self.sprockets.iter().position(SprocketModel::held_at_rest)
    }
}

/// The rollers laid on the seated path: as long as the path needs, or with
/// tensioner arms swung into the strands, or a long chain hung in its
/// strands' sag (docs/model.md, “Pretension and static equilibrium”).
fn lay_out(
    scene: &Scene,
    seat_path: &ChainPath,
    seat_circles: &[PathCircle],
    teeth: &[u32],
) -> Result<Layout, BuildError> {
    let chain = &scene.chain;
    // A chain longer than its path by more than half a pitch hangs in
    // its strands' sag where that sag, at the pretension, holds the
    // excess (within a tenth of a pitch); otherwise the layout's error
    // stands (and `check` offers the counts and moves that fit).
    // Tensioner arms take up a long chain first: their shoes swing into
    // the strands until the path needs the chain's length.
    let arms: Vec<_> = scene
        .tensioners
        .iter()
        .map(|t| t.arm_shoe(chain.roller_radius_m))
        .collect();
    let laid = match layout_rollers(seat_path, seat_circles, teeth, chain.rollers, chain.pitch_m) {
        Err(LayoutError::ChainLength { .. }) if !arms.is_empty() => layout_with_arms(
            seat_path,
            seat_circles,
            teeth,
            chain.rollers,
            chain.pitch_m,
            &arms,
        ),
        laid => laid,
    };
    Ok(match laid {
        Err(LayoutError::ChainLength { needed, .. }) if sag_holds(scene, seat_path, needed) => {
            hang_excess(
                seat_path,
                seat_circles,
                teeth,
                chain.rollers,
                chain.pitch_m,
                scene.gravity_m_s2,
                needed,
            )?
        }
        laid => laid?,
    })
}

/// Sprocket `i` of `scene` as the model steps it, its teeth drawn by
/// `profile`, turned by `angle_origin_rad` to receive the laid rollers.
fn sprocket_model(
    scene: &Scene,
    i: usize,
    s: &crate::scene::Sprocket,
    profile: ToothProfile,
    angle_origin_rad: f64,
    path: &ChainPath,
) -> SprocketModel {
    let reach = profile.reach_m();
    let excitation = &s.excitation;
    let governor = excitation.governor.as_ref().and_then(|spec| {
        s.speed_law()
            .map(|target| Governor::new(scene, i, spec, target, path))
    });
    SprocketModel {
        center_m: s.center_m,
        center_velocity_m_s: [0.0; 2],
        inv_inertia: 1.0 / s.inertia_kg_m2,
        speed_law: if governor.is_some() {
            None
        } else {
            s.speed_law()
        },
        governor,
        speed_harmonics: excitation.speed_harmonics.clone(),
        load_torque_n_m: s.load_torque_n_m(),
        angle_load: AngleLoad::new(&excitation.load_harmonics, excitation.load_table.as_ref()),
        angle_origin_rad,
        load_ramp_s: s.load_ramp_s(),
        resisting: s.resisting,
        user_torque_n_m: 0.0,
        reach_m: reach,
        reach_sq_m2: reach * reach,
        pitch_radius_m: s.pitch_radius_m,
        teeth: s.teeth,
        profile,
    }
}
