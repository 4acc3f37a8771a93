//! [`DampingRows`]: the linear form of each roller's contact damping, which
//! the implicit-damping integrator solves for.

/// The linear form of each roller's contact damping, for an implicit solve.
///
/// With the elastic parts E_k = K δ_kⁿ and remembered factors κ_k = χ/δ̇⁻_k of
/// the roller's patches on one sprocket, the damping force on the roller is
/// `Σ E_k κ_k n_k n_kᵀ (v_sp − v)` (v_sp the sprocket's surface velocity under
/// the roller): `C v_sp − C v` with `C = Σ E_k κ_k n_k n_kᵀ`. Patches on a
/// second sprocket (only where reach circles overlap) stay explicit.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub(crate) struct DampingRows {
    /// The sprocket of roller i's implicit contacts; `u32::MAX` for none.
    pub sprocket: Vec<u32>,
    /// C as (c_xx, c_xy, c_yy), N·s/m.
    pub c: Vec<[f64; 3]>,
    /// `C v_sp`, N.
    pub c_v_sprocket: Vec<[f64; 2]>,
    /// The elastic force `Σ E_k n_k`, N.
    pub elastic: Vec<[f64; 2]>,
    /// The damping force included in [`super::Forces::fx`]/`fy` (after the ≥ 0 clamp), N.
    pub explicit: Vec<[f64; 2]>,
    /// Roller centre relative to that sprocket's centre, m.
    pub lever: Vec<[f64; 2]>,
    /// Velocity of that sprocket's point under the roller centre, v_c + ω × r, m/s.
    #[serde(default)]
    pub surface_velocity: Vec<[f64; 2]>,
}

impl DampingRows {
    pub(crate) fn new(rollers: usize) -> Self {
        Self {
            sprocket: vec![u32::MAX; rollers],
            c: vec![[0.0; 3]; rollers],
            c_v_sprocket: vec![[0.0; 2]; rollers],
            elastic: vec![[0.0; 2]; rollers],
            explicit: vec![[0.0; 2]; rollers],
            lever: vec![[0.0; 2]; rollers],
            surface_velocity: vec![[0.0; 2]; rollers],
        }
    }
}
