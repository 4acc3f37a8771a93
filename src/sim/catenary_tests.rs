//! A long strand hanging under its own weight against the catenary of the
//! discrete chain.
//!
//! # The discrete elastic catenary
//!
//! Assumptions: the free strand is a string of point masses m (the rollers)
//! joined by hinged, weightless, linearly elastic links (force T = k (ℓ − ℓ₀),
//! no bending stiffness, no friction), under gravity g straight down, at rest,
//! touching nothing between its two end rollers a and b.
//!
//! Number the links of the strand j = 0 … n − 1 from roller a. Link j pulls
//! its first roller towards its second with the force T_j u_j. Roller j + 1
//! balances the links on either side and its weight:
//! T_{j+1} u_{j+1} − T_j u_j + m g = 0, g = (0, −g). So the horizontal
//! component H = T_j u_{j,x} is the same in every link, and the vertical one
//! grows by m g per roller: V_j = V₀ + j m g. Each link's force is then known,
//! T_j = √(H² + V_j²), its length is ℓ_j = ℓ₀ + T_j / k, and its vector is
//! ℓ_j (H, V_j) / T_j. Roller a to roller b:
//!
//! x_b − x_a = Σ_j ℓ_j H / T_j,   y_b − y_a = Σ_j ℓ_j V_j / T_j.
//!
//! Given the two end rollers' positions, these two equations fix (H, V₀)
//! (solved here by a 2 × 2 Newton iteration with a difference Jacobian), and
//! with them every roller's position (partial sums) and the sag below the
//! chord. The drive's solver never sees this form: it balances each roller's
//! links, contacts and weight as a whole loop around the sprockets.
//!
//! As a check of the scale, the continuous inextensible parabola gives
//! H ≈ q L² / (8 s) (q = m g / P, L the span, s the sag), good to O((s/L)²)
//! and O(P/L).

use crate::scene::Scene;
use crate::sim::Simulation;

fn scene(file: &str) -> Scene {
    let path = format!("{}/tests/data/{file}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("the scene file exists");
    Scene::from_toml(&text).expect("a valid scene")
}

/// The discrete catenary's link vectors for (H, V₀): each link's (dx, dy).
fn links(h: f64, v0: f64, n: usize, weight_n: f64, rest_m: f64, k: f64) -> Vec<(f64, f64)> {
    (0..n)
        .map(|j| {
            let v = v0 + j as f64 * weight_n;
            let t = h.hypot(v);
            let l = rest_m + t / k;
            (l * h / t, l * v / t)
        })
        .collect()
}

/// (H, V₀) such that the n links span `span` = (x_b − x_a, y_b − y_a).
fn solve_catenary(
    span: (f64, f64),
    n: usize,
    weight_n: f64,
    rest_m: f64,
    k: f64,
    guess: (f64, f64),
) -> (f64, f64) {
    let end = |h: f64, v0: f64| {
        links(h, v0, n, weight_n, rest_m, k)
            .iter()
            .fold((0.0, 0.0), |a, d| (a.0 + d.0, a.1 + d.1))
    };
    let (mut h, mut v0) = guess;
    for _ in 0..100 {
        let (ex, ey) = end(h, v0);
        let (rx, ry) = (ex - span.0, ey - span.1);
        if rx.hypot(ry) < 1e-14 * span.0.hypot(span.1) {
            break;
        }
        let dh = 1e-6 * h.abs();
        let dv = 1e-6 * h.abs();
        let (hx, hy) = end(h + dh, v0);
        let (vx, vy) = end(h, v0 + dv);
        let (a, c) = ((hx - ex) / dh, (hy - ey) / dh);
        let (b, d) = ((vx - ex) / dv, (vy - ey) / dv);
        let det = a * d - b * c;
        h -= (d * rx - b * ry) / det;
        v0 -= (a * ry - c * rx) / det;
    }
    (h, v0)
}

/// The upper strand of a 4 m, 20T/20T drive at 560 N (tests/data/catenary_4m.toml):
/// between two rollers 60 links either side of its lowest roller, the
/// settled chain's horizontal tension, its sag below the chord and every
/// roller's position against the discrete catenary through those two rollers.
///
/// Tolerance 10⁻⁴ of the tension and of the sag: the solver leaves each
/// roller out of balance by at most 10⁻⁶ T₀ (asserted), and those imbalances
/// add up along the 120 links to at most 1.2 · 10⁻⁴ T₀ in a link's force.
/// The parabola's H is looser by its own error, (s/L)² and P/L: 1 %.
#[test]
fn hanging_strand_is_the_discrete_catenary() {
    let scene = scene("catenary_4m.toml");
    let sim = Simulation::new(&scene).expect("a static equilibrium");
    let t0 = scene.chain().pretension_n;
    assert!(
        sim.equilibrium.force_residual <= 1e-6,
        "not settled: {:?}",
        sim.equilibrium
    );
    let (x, y) = (&sim.state.x, &sim.state.y);
    let n = x.len();
    let span_m = 4.058285;
    // The upper strand's lowest roller: the highest of the rollers near mid-span
    // is on the upper strand; walk down to the lowest one beside it.
    let mut mid = (0..n)
        .filter(|&i| (x[i] + 0.5 * span_m).abs() < 0.05)
        .max_by(|&a, &b| y[a].total_cmp(&y[b]))
        .expect("rollers at mid-span");
    loop {
        let (before, after) = ((mid + n - 1) % n, (mid + 1) % n);
        let next = [before, after]
            .into_iter()
            .min_by(|&a, &b| y[a].total_cmp(&y[b]))
            .expect("two neighbours");
        if y[next] < y[mid] {
            mid = next;
        } else {
            break;
        }
    }
    let p = 60;
    let a = (mid + n - p) % n;
    let idx = |j: usize| (a + j) % n;
    let touching = &sim.forces.output().touching;
    assert!(
        (0..=2 * p).all(|j| !touching[idx(j)]),
        "the strand touches a sprocket"
    );
    let m = scene.chain().roller_mass_kg;
    let weight = m * 9.81;
    let k = sim.model.stiffness_n_m;
    let rest = sim.model.rest_length_m;
    let b = idx(2 * p);
    let span = (x[b] - x[a], y[b] - y[a]);
    let guess = (span.0.signum() * t0, -(p as f64) * weight);
    let (h, v0) = solve_catenary(span, 2 * p, weight, rest, k, guess);

    // Horizontal tension: every link of the strand in the solver's state.
    let link_force = &sim.forces.output().link_force;
    for j in 0..2 * p {
        let (i, i1) = (idx(j), idx(j + 1));
        let l = (x[i1] - x[i]).hypot(y[i1] - y[i]);
        let h_j = link_force[i] * (x[i1] - x[i]) / l;
        assert!(
            (h_j - h).abs() <= 1e-4 * t0,
            "link {j}: H {h_j} N against the catenary's {h} N"
        );
    }
    // Every roller's position and the sag below the chord.
    let vectors = links(h, v0, 2 * p, weight, rest, k);
    let (mut cx, mut cy) = (x[a], y[a]);
    let mut sag_catenary: f64 = 0.0;
    let mut sag_solver: f64 = 0.0;
    let chord = |px: f64, py: f64| {
        // Depth below the chord a–b, measured vertically.
        let s = (px - x[a]) / span.0;
        y[a] + s * span.1 - py
    };
    for (j, d) in vectors.iter().enumerate() {
        cx += d.0;
        cy += d.1;
        let i = idx(j + 1);
        sag_catenary = sag_catenary.max(chord(cx, cy));
        sag_solver = sag_solver.max(chord(x[i], y[i]));
        assert!(
            (cx - x[i]).hypot(cy - y[i]) <= 1e-4 * 0.1,
            "roller {j}: ({}, {}) against the catenary's ({cx}, {cy})",
            x[i],
            y[i]
        );
    }
    assert!(
        (sag_solver - sag_catenary).abs() <= 1e-4 * sag_catenary,
        "sag {sag_solver} m against the catenary's {sag_catenary} m"
    );
    // The scale: the parabola's H = q L² / (8 s) over the same chord.
    let q = weight / scene.chain().pitch_m;
    let parabola = q * span.0 * span.0 / (8.0 * sag_catenary);
    assert!(
        (h.abs() - parabola).abs() <= 0.01 * parabola,
        "H {h} N against the parabola's {parabola} N"
    );
    // The strand really hangs: a sag of centimetres, far above the tolerance.
    assert!(sag_catenary > 0.02, "sag {sag_catenary} m");
}

/// A chain one pitch longer than its path hangs: the layout lays the excess
/// in the strands' sag (links of one pitch on parabolas), and the static
/// equilibrium settles there, each strand hanging as a cable does.
///
/// The 3 m conveyor of `tests/data/conveyor_hanging_3m.toml` (two 12-tooth
/// sprockets, ANSI 80, 251 rollers where the path through the seated
/// rollers needs 249.998 pitches; before, it was refused: "no roller count
/// fits as the sprockets stand"). At rest each strand is a shallow cable of
/// weight q = m_r g / P per length: over a chord c between two of its
/// rollers it sags s = q c² / (8 H) below the chord's middle, H the
/// horizontal component of its tension (the mean link force T over the
/// chord's links, T = H √(1 + y′²), within (8/3) (s/c)² = 0.3 % of H here).
/// Checked on each strand's middle two metres (clear of the wraps' ends,
/// where the sprockets hold it) within 2 %: the parabola's own error is
/// O((s/c)²), 0.1 %, and the discrete chain's O(P/c).
#[test]
fn a_chain_a_pitch_longer_than_its_path_hangs_as_a_cable() {
    let text = std::fs::read_to_string(format!(
        "{}/tests/data/conveyor_hanging_3m.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .expect("the scene file exists");
    for profile in ["real", "circular"] {
        let text = text.replace("profile = \"real\"", &format!("profile = \"{profile}\""));
        let scene = Scene::from_toml(&text).expect("a valid scene");
        let chain = scene.chain();
        let sim = Simulation::new(&scene).expect("settles");
        let eq = &sim.equilibrium;
        assert!(eq.force_residual <= 1e-6, "{profile}: {eq:?}");
        assert!(
            ((eq.tension_n - chain.pretension_n) / chain.pretension_n).abs() <= 1e-3,
            "{profile}: {eq:?}"
        );
        let q = chain.roller_mass_kg * 9.81 / chain.pitch_m;
        let (x, y) = (&sim.state.x, &sim.state.y);
        let link_force = &sim.forces.output().link_force;
        let n = x.len();
        // The strands: rollers between x = 0.5 m and 2.5 m from the head
        // (the tail at x = −3.02 m), below (lower strand) or above y = −0.1 m.
        let mut checked = 0;
        for lower in [true, false] {
            let on = |i: usize| {
                let along = -x[i];
                (0.5..=2.5).contains(&along) && (y[i] < -0.1) == lower
            };
            let ids: Vec<usize> = (0..n).filter(|&i| on(i)).collect();
            let (&a, &b) = (ids.first().expect("rollers"), ids.last().expect("rollers"));
            // The run is contiguous in chain order (one strand).
            assert_eq!(b - a + 1, ids.len(), "{profile}: one strand");
            let (dx, dy) = (x[b] - x[a], y[b] - y[a]);
            let c = dx.hypot(dy);
            let sag = ids
                .iter()
                .map(|&i| ((x[i] - x[a]) * dy - (y[i] - y[a]) * dx).abs() / c)
                .fold(0.0, f64::max);
            let mean_t = ids[..ids.len() - 1]
                .iter()
                .map(|&i| link_force[i])
                .sum::<f64>()
                / (ids.len() - 1) as f64;
            let expected = q * c * c / (8.0 * mean_t);
            assert!(
                (sag / expected - 1.0).abs() < 0.02,
                "{profile}, lower {lower}: sag {sag} m over {c} m at {mean_t} N, cable {expected} m"
            );
            checked += 1;
        }
        assert_eq!(checked, 2);
    }
}
