//! Whether the tensioner arms or the chain's fit to its path set the static
//! tension of a drive whose arms are meant to set it (`pretension_by =
//! "tensioner_preload"`; docs/model.md, “Tensioner arms”).
//!
//! Under that rule the links keep their rest length, the pitch, and the
//! static tension is whatever holds the chain at rest. The arms set it when
//! their shoes bend the strands against their tensioners' pushes. The fit
//! sets it instead when
//!
//! - **no arm holds the chain**: each shoe is clear of every roller, or its
//!   tensioner stands on a stop (the stop, not the tensioner, then balances
//!   the arm); or
//! - **the chain is short of its path**: a shoe only lengthens the path
//!   (`geometry::arm_take_up`), so a chain shorter than the path with
//!   straight strands must stretch to lie on it whatever the arms do. Its
//!   free links, laid at λ > P, carry about K (λ − P) from the shortfall
//!   alone; where that is half the static tension or more, the shortfall,
//!   not the push, sets it (a shortfall that a tensioner's tension would
//!   dwarf is left alone: the arm still bends the strand).
//!
//! Nothing here changes the equilibrium: it reads the rest state the
//! relaxation reached. Under the other rules the pretension iteration sets
//! the tension and nothing is reported.

use crate::forces::ForceGenerator;
use crate::geometry::Layout;
use crate::scene::{PretensionRule, Scene, Tensioner, TensionerKind};

/// Share of the static tension at which the tension of the shortfall's
/// stretch alone, K (λ − P), is said to set it.
const SHORTFALL_SHARE: f64 = 0.5;

/// A static tension the chain's fit to its path sets, not the tensioner
/// arms meant to: its numbers and what each arm does.
#[derive(Clone, Debug, PartialEq)]
pub struct MisfitTension {
    /// The static tension, N.
    pub tension_n: f64,
    /// The chain's length less the path's through the seated rollers as
    /// laid out, m (negative: short).
    pub excess_m: f64,
    /// The free links' stretch as laid out, λ/P − 1.
    pub stretch: f64,
    /// Where the chain is short of its path: the tension its free links
    /// carry stretched by the shortfall alone, K (λ − P), N.
    pub shortfall_tension_n: Option<f64>,
    /// What each arm does at rest (a phrase each, naming the arm).
    pub arms: Vec<String>,
}

impl std::fmt::Display for MisfitTension {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the static tension {:.0} N is set by the chain's fit to its path, not by the tensioner arms",
            self.tension_n
        )?;
        match self.shortfall_tension_n {
            Some(t) => write!(
                f,
                ": the chain is {:.2} mm shorter than the path through the seated rollers with straight strands, which no shoe can shorten; its free links, stretched {:.3} % by that alone, carry about {t:.0} N",
                self.excess_m.abs() * 1e3,
                self.stretch * 100.0,
            )?,
            None if self.excess_m.abs() > 1e-6 => write!(
                f,
                ": the chain is {:.2} mm {} than the path through the seated rollers (its free links laid {:.3} % {} than the pitch)",
                self.excess_m.abs() * 1e3,
                if self.excess_m < 0.0 {
                    "shorter"
                } else {
                    "longer"
                },
                self.stretch.abs() * 100.0,
                if self.stretch > 0.0 {
                    "longer"
                } else {
                    "shorter"
                },
            )?,
            None => {}
        }
        write!(
            f,
            "; {}: fit the chain to its path (`chaindrive check` names the roller counts and the sprocket moves that fit) or bring the arms onto it",
            self.arms.join("; ")
        )
    }
}

/// What one arm does at rest.
enum ArmAtRest {
    /// Its shoe bends a strand against its tensioner's push, N.
    Holds(f64),
    /// It holds no chain (the phrase says why).
    Idle(String),
}

/// Reads arm `t` at rest from its tensioner's reading.
fn arm_at_rest(t: &Tensioner, r: &crate::forces::TensionerReading) -> ArmAtRest {
    let (min_m, max_m) = t.travel_limits_m();
    let stop_k = match &t.kind {
        TensionerKind::Spring(s) => s.stop_stiffness_n_m,
        TensionerKind::Hydraulic(h) => h.stop_stiffness_n_m,
    };
    let x = r.travel_m;
    let stop_n = if x < min_m {
        stop_k * (min_m - x)
    } else if x > max_m {
        -stop_k * (x - max_m)
    } else {
        0.0
    };
    let why = if r.shoe_rollers == 0 {
        "no roller touches its shoe"
    } else if stop_n > 0.0 {
        "the chain pushes it onto its lower stop"
    } else if stop_n < 0.0 {
        "it stands on its upper stop"
    } else if r.plunger_force_n <= 0.0 {
        "its push is spent"
    } else {
        return ArmAtRest::Holds(r.plunger_force_n);
    };
    ArmAtRest::Idle(format!(
        "tensioner \"{}\" holds no chain at rest: {why} (travel {:.2} mm, stops {:.2} to {:.2} mm; its own push {:.1} N, the stop's {:.1} N)",
        t.name,
        x * 1e3,
        min_m * 1e3,
        max_m * 1e3,
        r.plunger_force_n - stop_n,
        stop_n
    ))
}

/// Under the tensioner-preload rule, the static tension the chain's fit
/// sets (module docs); `None` under the other rules, or where the arms set
/// it. `forces` evaluated at the rest state, whose static tension is
/// `tension_n`; `layout` the chain as laid before the relaxation.
pub(crate) fn misfit_tension(
    scene: &Scene,
    layout: &Layout,
    forces: &ForceGenerator,
    tension_n: f64,
) -> Option<MisfitTension> {
    if scene.chain.pretension_by != PretensionRule::TensionerPreload {
        return None;
    }
    let pitch_m = scene.chain.pitch_m;
    let stretch = layout.strand_stretch(pitch_m);
    let readings = &forces.output().tensioners;
    let at_rest: Vec<ArmAtRest> = scene
        .tensioners
        .iter()
        .zip(readings)
        .map(|(t, r)| arm_at_rest(t, r))
        .collect();
    let idle = at_rest.iter().all(|a| matches!(a, ArmAtRest::Idle(_)));
    // The chain short of its straight path: free links laid longer than P.
    let shortfall_tension_n = (layout.misfit_pitches > 0.0 && !layout.hanging && stretch > 0.0)
        .then_some(scene.chain.stiffness_n_m * pitch_m * stretch)
        .filter(|&t| t >= SHORTFALL_SHARE * tension_n);
    if !idle && shortfall_tension_n.is_none() {
        return None;
    }
    let arms = scene
        .tensioners
        .iter()
        .zip(readings)
        .zip(at_rest)
        .map(|((t, r), a)| match a {
            ArmAtRest::Idle(why) => why,
            ArmAtRest::Holds(push_n) => format!(
                "tensioner \"{}\" pushes {push_n:.1} N at travel {:.2} mm, its shoe carrying {:.1} N",
                t.name,
                r.travel_m * 1e3,
                r.shoe_force_n
            ),
        })
        .collect();
    Some(MisfitTension {
        tension_n,
        excess_m: -layout.misfit_pitches * pitch_m,
        stretch,
        shortfall_tension_n,
        arms,
    })
}

/// A worn chain longer than the tensioner arms take up (tensioner-preload
/// rule, `chain.elongation_pct`): every arm stands on a stop or holds no
/// chain at the worn rest state, and the chain hangs slack. Nothing here
/// changes the rest state; a run warns.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct WornSlack {
    /// The links' elongation, a fraction of the pitch.
    pub elongation: f64,
    /// Rollers (links) in the loop.
    pub rollers: usize,
    /// The pitch, m.
    pub pitch_m: f64,
    /// The length the chain gained, N P e, m.
    pub gain_m: f64,
    /// The most chain the arms' shoes take up over their travel on the
    /// path through the seated rollers, m (`None` where it is not known).
    pub take_up_m: Option<f64>,
    /// The worn chain's static tension, N.
    pub tension_n: f64,
    /// What each arm does at rest (a phrase each, naming the arm).
    pub arms: Vec<String>,
}

impl std::fmt::Display for WornSlack {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the worn chain is longer than the tensioner arms take up and hangs slack at {:.1} N: worn by {:.3} % (chain.elongation_pct), its {} links of {:.2} mm gained {:.2} mm",
            self.tension_n,
            100.0 * self.elongation,
            self.rollers,
            1e3 * self.pitch_m,
            1e3 * self.gain_m,
        )?;
        if let Some(t) = self.take_up_m {
            write!(
                f,
                ", while the arms' shoes take up at most {:.2} mm of chain over their travel",
                1e3 * t
            )?;
        }
        write!(
            f,
            "; {}: take the slack up otherwise (fewer rollers, a sprocket moved apart, a tensioner with more travel)",
            self.arms.join("; ")
        )
    }
}

/// Under the tensioner-preload rule with a worn chain, where every arm
/// holds no chain at the worn rest state (each on a stop, clear of the
/// chain, or its push spent): the worn chain's slack ([`WornSlack`]);
/// `None` otherwise. `scene` the worn scene, `forces` evaluated at its rest
/// state, whose static tension is `tension_n`; `take_up_m` the most chain
/// the arms take up over their travel.
pub(crate) fn worn_slack(
    scene: &Scene,
    forces: &ForceGenerator,
    tension_n: f64,
    take_up_m: Option<f64>,
) -> Option<WornSlack> {
    let chain = &scene.chain;
    if chain.pretension_by != PretensionRule::TensionerPreload
        || !(chain.elongation > 0.0)
        || scene.tensioners.is_empty()
    {
        return None;
    }
    let readings = &forces.output().tensioners;
    let mut arms = Vec::with_capacity(scene.tensioners.len());
    for (t, r) in scene.tensioners.iter().zip(readings) {
        match arm_at_rest(t, r) {
            ArmAtRest::Idle(why) => arms.push(why),
            ArmAtRest::Holds(_) => return None,
        }
    }
    Some(WornSlack {
        elongation: chain.elongation,
        rollers: chain.rollers,
        pitch_m: chain.pitch_m,
        gain_m: chain.wear_gain_m(),
        take_up_m,
        tension_n,
        arms,
    })
}
