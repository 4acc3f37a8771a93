//! The search for the tensioner's position on T(s), the static tension of
//! the drive with the tensioner moved by s (see `take_up`): flat while the
//! chain is slack, then about linear. It widens its steps while T stays
//! below the pretension and, once a position above it is known, keeps every
//! step inside the bracket (secant, then regula falsi, then bisection).
//! It only proposes positions; settling the drive at one is the caller's.

/// Largest step before the pretension is bracketed, in steps before.
const MAX_GROWTH: f64 = 4.0;

/// The next position of the tensioner's search on T(s) (module docs).
#[derive(Clone, Debug)]
pub(super) struct TensionSearch {
    target_n: f64,
    /// +1 when moving along the direction tightens the chain, else −1.
    sense: f64,
    /// The position tried last, with its tension.
    previous: (f64, f64),
    /// The last position whose tension was below the target.
    below: Option<(f64, f64)>,
    /// The last position whose tension was at or above it.
    above: Option<(f64, f64)>,
}

impl TensionSearch {
    /// A search from `start_m`, whose static tension is `start_n`; moving
    /// towards `sense` (±1) tightens the chain.
    pub(super) fn new(start_m: f64, start_n: f64, sense: f64, target_n: f64) -> Self {
        let mut search = Self {
            target_n,
            sense: if sense < 0.0 { -1.0 } else { 1.0 },
            previous: (start_m, start_n),
            below: None,
            above: None,
        };
        search.record(start_m, start_n);
        search
    }

    fn record(&mut self, s: f64, tension_n: f64) {
        if tension_n < self.target_n {
            self.below = Some((s, tension_n));
        } else {
            self.above = Some((s, tension_n));
        }
    }

    /// The position to try after `s` gave the static tension `tension_n`
    /// (0 for a slack chain).
    pub(super) fn next(&mut self, s: f64, tension_n: f64) -> f64 {
        let (s0, t0) = std::mem::replace(&mut self.previous, (s, tension_n));
        self.record(s, tension_n);
        let secant = s + (self.target_n - tension_n) * (s - s0) / (tension_n - t0);
        match (self.below, self.above) {
            (Some((sb, tb)), Some((sa, ta))) => {
                let (low, high) = (sa.min(sb), sa.max(sb));
                let margin = 0.1 * (high - low);
                let inside = |x: f64| x.is_finite() && x > low + margin && x < high - margin;
                if inside(secant) {
                    return secant;
                }
                let falsi = sb + (self.target_n - tb) * (sa - sb) / (ta - tb);
                if inside(falsi) {
                    falsi
                } else {
                    0.5 * (sa + sb)
                }
            }
            // Not bracketed: the secant towards the side not yet seen, at
            // most MAX_GROWTH times the last step; a flat T (a slack chain)
            // takes that.
            (below, _) => {
                let toward = if below.is_some() {
                    self.sense
                } else {
                    -self.sense
                };
                let longest = MAX_GROWTH * (s - s0).abs();
                let step = (secant - s) * toward;
                if step.is_finite() && step > 0.0 && step <= longest {
                    secant
                } else {
                    s + toward * longest
                }
            }
        }
    }
}
