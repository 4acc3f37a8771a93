//! Where a running chain's extra length goes: runs a scene and, over the
//! last second, splits the chain's mean stretch above the static one into
//! the length the free strands take up by bending (sag and transverse
//! vibration: each free strand's polyline against its chord), the length
//! the wraps take up (the wrapped rollers' mean radius about their
//! sprocket against the static radius, times the wrap angle), and the rest
//! (the chords' own lengths). docs/model.md, "Running tension", quotes its
//! output.
//!
//! ```text
//! cargo run --release --example running_tension -- tests/data/flat_20_40_1000rpm.toml [rpm]
//! ```

use chaindrive::prelude::*;

/// Means over the window of the loop's decomposition, m.
#[derive(Default)]
struct Split {
    from_s: f64,
    n: f64,
    /// Σ (link length − rest length).
    stretch: f64,
    /// Σ over free strands of (polyline − chord).
    bending: f64,
    /// Σ over free strands of the chord.
    chords: f64,
    /// Per sprocket: Σ (radius of a wrapped roller), and how many.
    wrap_radius: Vec<(f64, f64)>,
    /// The same at t = 0.
    static_split: Option<(f64, f64, f64, Vec<f64>)>,
}

fn measure(s: &Sample<'_>, roller_r: f64) -> (f64, f64, f64, Vec<(f64, f64)>) {
    let (x, y) = (&s.state.x, &s.state.y);
    let rollers = x.len().min(y.len());
    // A roller is wrapped when its centre is within a roller radius of a
    // sprocket's pitch circle.
    let on = |i: usize| {
        s.model.sprockets.iter().position(|sp| {
            let d = (x[i] - sp.center_m[0]).hypot(y[i] - sp.center_m[1]);
            (d - sp.pitch_radius_m).abs() < roller_r
        })
    };
    let owner: Vec<Option<usize>> = (0..rollers).map(on).collect();
    let mut stretch = 0.0;
    for i in 0..rollers {
        let j = (i + 1) % rollers;
        stretch += (x[j] - x[i]).hypot(y[j] - y[i]) - s.model.rest_length_m;
    }
    let mut radius = vec![(0.0, 0.0); s.model.sprockets.len()];
    for (i, o) in owner.iter().enumerate() {
        if let Some(k) = o {
            let sp = &s.model.sprockets[*k];
            radius[*k].0 += (x[i] - sp.center_m[0]).hypot(y[i] - sp.center_m[1]);
            radius[*k].1 += 1.0;
        }
    }
    // Free runs: from a wrapped roller through free ones to the next wrapped one.
    let Some(start) = owner.iter().position(Option::is_some) else {
        return (stretch, 0.0, 0.0, radius);
    };
    let (mut bending, mut chords) = (0.0, 0.0);
    let mut first = start;
    let mut poly = 0.0;
    for step in 1..=rollers {
        let i = (start + step) % rollers;
        let p = (start + step - 1) % rollers;
        poly += (x[i] - x[p]).hypot(y[i] - y[p]);
        if owner[i].is_some() {
            if step - (first + rollers - start) % rollers > 1 {
                let chord = (x[i] - x[first]).hypot(y[i] - y[first]);
                bending += poly - chord;
                chords += chord;
            }
            first = i;
            poly = 0.0;
        }
    }
    (stretch, bending, chords, radius)
}

struct Watch {
    split: Split,
    roller_r: f64,
}

impl Observer for Watch {
    fn sample(&mut self, s: &Sample<'_>) {
        let (stretch, bending, chords, radius) = measure(s, self.roller_r);
        let sp = &mut self.split;
        if sp.static_split.is_none() {
            let r = radius.iter().map(|(sum, n)| sum / n.max(1.0)).collect();
            sp.static_split = Some((stretch, bending, chords, r));
            sp.wrap_radius = vec![(0.0, 0.0); radius.len()];
        }
        if s.state.t_s < sp.from_s {
            return;
        }
        sp.n += 1.0;
        sp.stretch += stretch;
        sp.bending += bending;
        sp.chords += chords;
        for (acc, (sum, n)) in sp.wrap_radius.iter_mut().zip(radius) {
            acc.0 += sum / n.max(1.0);
            acc.1 += n;
        }
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .ok_or("usage: running_tension SCENE.toml [rpm]")?;
    let mut text = std::fs::read_to_string(&path)?;
    if let Some(rpm) = args.next() {
        let rpm: f64 = rpm.parse()?;
        text = text.replace("speed_rpm = 1000.0", &format!("speed_rpm = {rpm:?}"));
    }
    let scene = Scene::from_toml_with(
        &text,
        &Overrides {
            duration_s: Some(1.5),
            dt_s: Some(2e-6),
            ..Overrides::default()
        },
    )?;
    let mut sim = Simulation::new(&scene)?;
    let sampling = SampleRate::new(1000.0, scene.solver().dt_s)?;
    let mut watch = Watch {
        split: Split {
            from_s: 0.5,
            ..Split::default()
        },
        roller_r: scene.chain().roller_radius_m,
    };
    sim.run(1.5, sampling.every, &mut watch, None)?;
    let sp = &watch.split;
    let n = sp.n.max(1.0);
    let (st0, b0, c0, r0) = sp.static_split.clone().ok_or("no sample")?;
    let k_loop = scene.chain().stiffness_n_m / scene.chain().rollers as f64;
    let d_stretch = sp.stretch / n - st0;
    println!(
        "mean tension above static ≈ K/N · Δstretch = {:.1} N (Δstretch {:.1} µm)",
        k_loop * d_stretch,
        d_stretch * 1e6
    );
    println!(
        "free strands' bending (polyline − chord): static {:.1} µm, running {:.1} µm, Δ {:.1} µm",
        b0 * 1e6,
        sp.bending / n * 1e6,
        (sp.bending / n - b0) * 1e6
    );
    println!(
        "free strands' chords: static {:.6} m, running {:.6} m, Δ {:.1} µm",
        c0,
        sp.chords / n,
        (sp.chords / n - c0) * 1e6
    );
    for (k, ((sum, _), r_static)) in sp.wrap_radius.iter().zip(&r0).enumerate() {
        let angle = sim.model().wrap_rad(k).unwrap_or(0.0);
        println!(
            "sprocket {}: wrapped rollers' mean radius static {:.2} µm above pitch radius, running {:.2} µm; Δ × wrap angle = {:.1} µm",
            k + 1,
            (r_static - sim.model().sprockets[k].pitch_radius_m) * 1e6,
            (sum / n - sim.model().sprockets[k].pitch_radius_m) * 1e6,
            (sum / n - r_static) * angle * 1e6
        );
    }
    Ok(())
}
