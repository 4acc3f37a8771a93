//! A resisting load on a sprocket: a torque that opposes the sprocket's
//! rotation whichever way it turns (a conveyor's friction, a brake), its
//! checks and its default creep speed. The load that acts in one direction
//! whatever the motion is `load_torque_n_m` (`validate`); nothing here
//! steps a drive.

use super::checker::Checker;
use super::file::SprocketFile;
use super::{Role, Sprocket};

/// A torque that opposes a sprocket's rotation (a conveyor's friction, a
/// brake): −T ω / ω_s below the creep speed ω_s, −T sign(ω) above.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Resisting {
    /// Its size T at and above the creep speed, N·m (> 0).
    pub torque_n_m: f64,
    /// The creep speed ω_s, rad/s (> 0).
    pub speed_rad_s: f64,
}

impl Resisting {
    /// The creep speed that the step `dt_s` integrates stably on a
    /// sprocket of inertia `inertia_kg_m2`: 2 T dt / J, so that the
    /// explicit update of ω under the linear part, ω ← ω (1 − dt T / (J ω_s)),
    /// keeps its factor at 1/2; at least [`Self::MIN_SPEED_RAD_S`].
    pub(crate) fn stable_speed_rad_s(torque_n_m: f64, dt_s: f64, inertia_kg_m2: f64) -> f64 {
        (2.0 * torque_n_m * dt_s / inertia_kg_m2).max(Self::MIN_SPEED_RAD_S)
    }

    /// The default creep speed's floor, rad/s (about 0.1 rpm).
    pub(crate) const MIN_SPEED_RAD_S: f64 = 0.01;

    /// The torque at speed `omega_rad_s`, N·m.
    #[inline]
    pub(crate) fn torque_at(&self, omega_rad_s: f64) -> f64 {
        -self.torque_n_m * (omega_rad_s / self.speed_rad_s).clamp(-1.0, 1.0)
    }
}

/// Reads sprocket `i`'s `resisting_torque_n_m` and `resisting_speed_rad_s`
/// (free or tensioner only). A creep speed left out is 0 here and set by
/// [`set_default_speeds`] once the step is known.
pub(super) fn check(c: &mut Checker, f: &SprocketFile, i: usize, role: &Role) -> Option<Resisting> {
    let p = |field: &str| format!("sprockets[{i}].{field}");
    if matches!(role, Role::Driver(_)) {
        for (field, given) in [
            ("resisting_torque_n_m", f.resisting_torque_n_m.is_some()),
            ("resisting_speed_rad_s", f.resisting_speed_rad_s.is_some()),
        ] {
            if given {
                c.fail(p(field), "is not allowed for role = \"driver\" (a driver's speed is prescribed or governed)");
            }
        }
        return None;
    }
    let Some(torque) = f.resisting_torque_n_m else {
        if f.resisting_speed_rad_s.is_some() {
            c.fail(
                p("resisting_speed_rad_s"),
                "is allowed only on a sprocket with a resisting_torque_n_m",
            );
        }
        return None;
    };
    let torque_n_m = c.non_negative(&p("resisting_torque_n_m"), torque);
    let speed_rad_s = match f.resisting_speed_rad_s {
        Some(v) => c.positive(&p("resisting_speed_rad_s"), v),
        None => 0.0,
    };
    (torque_n_m > 0.0).then_some(Resisting {
        torque_n_m,
        speed_rad_s,
    })
}

/// Gives every resisting load without a stated creep speed the stable one
/// for the step `dt_s` ([`Resisting::stable_speed_rad_s`]).
pub(super) fn set_default_speeds(sprockets: &mut [Sprocket], dt_s: f64) {
    for s in sprockets {
        let inertia = s.inertia_kg_m2;
        if let Some(r) = s.resisting.as_mut().filter(|r| r.speed_rad_s == 0.0) {
            r.speed_rad_s = Resisting::stable_speed_rad_s(r.torque_n_m, dt_s, inertia);
        }
    }
}

/// A warning for each resisting load whose stated creep speed is below the
/// stable one at the step `dt_s`, naming its field.
pub(super) fn warnings(sprockets: &[Sprocket], dt_s: f64) -> Vec<String> {
    let mut out = Vec::new();
    for (i, s) in sprockets.iter().enumerate() {
        let Some(r) = s.resisting else { continue };
        // Half the default's 2 T dt / J, without its floor: a stated speed
        // is only too small where the step cannot integrate it.
        let stable = r.torque_n_m * dt_s / s.inertia_kg_m2;
        if r.speed_rad_s < stable {
            out.push(format!(
                "sprockets[{i}].resisting_speed_rad_s = {} rad/s is below {stable:.3e} rad/s, the smallest creep speed a step of {dt_s:e} s integrates stably on this sprocket (T dt / J); raise it or leave it out",
                r.speed_rad_s
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{L60MC_TOML, Scene, SceneError};

    /// The paper's drive with `extra` lines added to its sprocket `k`'s table.
    fn l60mc_with(k: usize, extra: &str) -> Result<Scene, SceneError> {
        let mut text = String::new();
        let mut seen = 0;
        for line in L60MC_TOML.lines() {
            text.push_str(line);
            text.push('\n');
            if line.trim() == "[[sprockets]]" {
                if seen == k {
                    text.push_str(extra);
                    text.push('\n');
                }
                seen += 1;
            }
        }
        Scene::from_toml(&text)
    }

    fn errors(r: Result<Scene, SceneError>) -> String {
        match r {
            Err(e) => e.to_string(),
            Ok(_) => panic!("accepted"),
        }
    }

    #[test]
    fn the_torque_opposes_the_speed_linearly_below_the_creep_speed() {
        let r = Resisting {
            torque_n_m: 4.0,
            speed_rad_s: 0.5,
        };
        assert_eq!(r.torque_at(0.0), 0.0);
        assert_eq!(r.torque_at(0.25), -2.0);
        assert_eq!(r.torque_at(-0.25), 2.0);
        assert_eq!(r.torque_at(10.0), -4.0);
        assert_eq!(r.torque_at(-10.0), 4.0);
    }

    #[test]
    fn the_default_creep_speed_keeps_the_explicit_update_at_one_half() {
        // ω ← ω (1 − dt T / (J ω_s)) with ω_s = 2 T dt / J: factor 1/2.
        let (t, dt, j) = (500.0, 1e-5, 1e-3);
        let w = Resisting::stable_speed_rad_s(t, dt, j);
        assert!((1.0 - dt * t / (j * w) - 0.5).abs() < 1e-12);
        assert_eq!(
            Resisting::stable_speed_rad_s(1.0, 1e-5, 1.0),
            Resisting::MIN_SPEED_RAD_S
        );
    }

    #[test]
    fn a_scene_fills_the_creep_speed_from_its_step_and_warns_below_it() {
        let scene = l60mc_with(1, "resisting_torque_n_m = 50.0").expect("valid");
        let s = &scene.sprockets()[1];
        let r = s.resisting.expect("resisting");
        let expected = Resisting::stable_speed_rad_s(50.0, scene.solver().dt_s, s.inertia_kg_m2);
        assert_eq!(r.speed_rad_s, expected);
        assert_eq!(s.resisting_torque_n_m(), 50.0);
        assert!(scene.warnings().iter().all(|w| !w.contains("resisting")));
        let slow = l60mc_with(
            1,
            "resisting_torque_n_m = 5e4\nresisting_speed_rad_s = 1e-3",
        )
        .expect("valid");
        let w = slow.warnings();
        assert!(
            w.iter()
                .any(|w| w.contains("sprockets[1].resisting_speed_rad_s")),
            "{w:?}"
        );
    }

    #[test]
    fn bad_resisting_fields_are_named() {
        let e = errors(l60mc_with(0, "resisting_torque_n_m = 5.0"));
        assert!(
            e.contains("sprockets[0].resisting_torque_n_m") && e.contains("driver"),
            "{e}"
        );
        let e = errors(l60mc_with(1, "resisting_speed_rad_s = 0.1"));
        assert!(e.contains("sprockets[1].resisting_speed_rad_s"), "{e}");
        let e = errors(l60mc_with(1, "resisting_torque_n_m = -1.0"));
        assert!(e.contains("sprockets[1].resisting_torque_n_m"), "{e}");
        let e = errors(l60mc_with(
            1,
            "resisting_torque_n_m = 1.0\nresisting_speed_rad_s = 0.0",
        ));
        assert!(e.contains("sprockets[1].resisting_speed_rad_s"), "{e}");
    }
}
