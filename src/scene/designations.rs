//! Chains by designation: `[chain] designation = "ISO 606 16B-1"` or
//! `"ANSI 80"` fills the chain's pitch, roller radius, mass per link, pin
//! radius and an axial link stiffness estimate; a field written in the
//! scene overrides the table's (docs/model.md, “Chains by designation”).
//!
//! **Sources.** Pitch P, roller diameter d₁, pin diameter d₂ and inner plate
//! depth h₂ are the standards' dimension tables: ISO 606:2004, Table 1
//! (B series, European), and ASME B29.1 (American standard, ANSI numbers;
//! ISO 606's A series has the same dimensions). ANSI 25 and 35 are bush
//! chains without rollers: d₁ is then the bush's diameter, which is what
//! seats in the sprocket. Neither standard gives a mass or a plate
//! thickness: mass per metre and link plate thickness are from a
//! manufacturer's catalogue, named in [`Designation::mass_source`].
//!
//! **Stiffness estimate.** A link's two side plates in tension, through their
//! net section at the pin hole: K = η E A / P with A = 2 t (h₂ − d₂),
//! E = 206 GPa (steel) and a reduction η = 1/3 for what the plates' section
//! leaves out — the pin–bush and bush–plate contacts and the plates' waist.
//! η is calibrated on the paper's chain (pitch 88.9 mm, rollers 54 mm, the
//! size of a 56B: E A / P = 2.42 GN/m against the paper's 815 MN/m); it is
//! an estimate within a factor of about two, not a measurement. A measured
//! stiffness belongs in `chain.stiffness_n_m`, which overrides it.

/// Young's modulus of chain steel, Pa.
pub const STEEL_E_PA: f64 = 206e9;
/// Reduction η of the plates' E A / P for the joints' compliance (module docs).
pub const STIFFNESS_REDUCTION: f64 = 1.0 / 3.0;

/// Source of the ISO 606 B-series dimensions.
const ISO_DIMENSIONS: &str = "ISO 606:2004 Table 1 (B series)";
/// Source of the ANSI dimensions.
const ANSI_DIMENSIONS: &str = "ASME B29.1 (= ISO 606 A series)";
/// Source of the B-series mass per metre and plate thickness.
const ISO_CATALOGUE: &str = "Renold transmission chain catalogue, European (BS/ISO) simplex";
/// Source of the ANSI mass per metre and plate thickness.
const ANSI_CATALOGUE: &str = "Tsubaki RS roller chain catalogue, single strand";

/// One chain of the table, single strand.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Designation {
    /// The designation as written in a scene (`"ISO 606 16B-1"`, `"ANSI 80"`).
    pub name: &'static str,
    /// Pitch P, m.
    pub pitch_m: f64,
    /// Roller diameter d₁ (bush diameter for a rollerless chain), m.
    pub roller_diameter_m: f64,
    /// Pin diameter d₂, m.
    pub pin_diameter_m: f64,
    /// Inner plate depth h₂, m.
    pub plate_depth_m: f64,
    /// Inner link plate thickness t, m (catalogue).
    pub plate_thickness_m: f64,
    /// Mass per metre, kg/m (catalogue).
    pub mass_per_m_kg: f64,
    /// Where P, d₁, d₂ and h₂ come from.
    pub dimension_source: &'static str,
    /// Where the mass per metre and the plate thickness come from.
    pub mass_source: &'static str,
}

impl Designation {
    /// Roller radius, m.
    pub fn roller_radius_m(&self) -> f64 {
        0.5 * self.roller_diameter_m
    }

    /// Pin radius, m (the joint friction's r_pin).
    pub fn pin_radius_m(&self) -> f64 {
        0.5 * self.pin_diameter_m
    }

    /// Mass lumped at each roller: mass per metre times the pitch, kg.
    pub fn roller_mass_kg(&self) -> f64 {
        self.mass_per_m_kg * self.pitch_m
    }

    /// Axial link stiffness estimate η E A / P, A = 2 t (h₂ − d₂), N/m
    /// (module docs).
    pub fn stiffness_n_m(&self) -> f64 {
        let area_m2 = 2.0 * self.plate_thickness_m * (self.plate_depth_m - self.pin_diameter_m);
        STIFFNESS_REDUCTION * STEEL_E_PA * area_m2 / self.pitch_m
    }

    /// How the stiffness estimate is derived, for listings.
    pub fn stiffness_source() -> &'static str {
        "estimate: (1/3) E A / P, A = 2 t (h2 - d2) net plate section, E = 206 GPa; 1/3 calibrated on the paper's 88.9 mm chain"
    }
}

/// Builds a row; lengths in millimetres.
#[allow(clippy::too_many_arguments)]
const fn row(
    name: &'static str,
    p_mm: f64,
    d1_mm: f64,
    d2_mm: f64,
    h2_mm: f64,
    t_mm: f64,
    q_kg_m: f64,
    iso: bool,
) -> Designation {
    Designation {
        name,
        pitch_m: p_mm * 1e-3,
        roller_diameter_m: d1_mm * 1e-3,
        pin_diameter_m: d2_mm * 1e-3,
        plate_depth_m: h2_mm * 1e-3,
        plate_thickness_m: t_mm * 1e-3,
        mass_per_m_kg: q_kg_m,
        dimension_source: if iso { ISO_DIMENSIONS } else { ANSI_DIMENSIONS },
        mass_source: if iso { ISO_CATALOGUE } else { ANSI_CATALOGUE },
    }
}

/// Every designation known, ISO 606 B series then ANSI, by pitch.
/// Columns: name, P, d₁, d₂, h₂, t (mm), mass per metre (kg/m).
pub const DESIGNATIONS: &[Designation] = &[
    row("ISO 606 05B-1", 8.00, 5.00, 2.31, 7.11, 0.75, 0.18, true),
    row("ISO 606 06B-1", 9.525, 6.35, 3.28, 8.26, 1.00, 0.41, true),
    row("ISO 606 08B-1", 12.70, 8.51, 4.45, 11.81, 1.60, 0.69, true),
    row(
        "ISO 606 10B-1",
        15.875,
        10.16,
        5.08,
        14.73,
        1.50,
        0.93,
        true,
    ),
    row("ISO 606 12B-1", 19.05, 12.07, 5.72, 16.13, 1.80, 1.15, true),
    row("ISO 606 16B-1", 25.40, 15.88, 8.28, 21.08, 3.10, 2.71, true),
    row(
        "ISO 606 20B-1",
        31.75,
        19.05,
        10.19,
        26.42,
        3.50,
        3.70,
        true,
    ),
    row(
        "ISO 606 24B-1",
        38.10,
        25.40,
        14.63,
        33.40,
        4.80,
        7.10,
        true,
    ),
    row(
        "ISO 606 28B-1",
        44.45,
        27.94,
        15.90,
        37.08,
        6.00,
        8.50,
        true,
    ),
    row(
        "ISO 606 32B-1",
        50.80,
        29.21,
        17.81,
        42.29,
        6.00,
        10.25,
        true,
    ),
    row(
        "ISO 606 40B-1",
        63.50,
        39.37,
        22.89,
        52.96,
        8.00,
        16.35,
        true,
    ),
    row(
        "ISO 606 48B-1",
        76.20,
        48.26,
        29.24,
        63.88,
        10.00,
        25.00,
        true,
    ),
    row(
        "ISO 606 56B-1",
        88.90,
        53.98,
        34.32,
        77.85,
        12.00,
        35.00,
        true,
    ),
    row(
        "ISO 606 64B-1",
        101.60,
        63.50,
        39.40,
        90.17,
        13.00,
        46.00,
        true,
    ),
    row(
        "ISO 606 72B-1",
        114.30,
        72.39,
        44.48,
        103.63,
        15.00,
        60.00,
        true,
    ),
    row("ANSI 25", 6.35, 3.30, 2.31, 6.02, 0.76, 0.14, false),
    row("ANSI 35", 9.525, 5.08, 3.58, 9.05, 1.27, 0.33, false),
    row("ANSI 40", 12.70, 7.92, 3.96, 12.07, 1.52, 0.64, false),
    row("ANSI 41", 12.70, 7.77, 3.58, 9.91, 1.27, 0.41, false),
    row("ANSI 50", 15.875, 10.16, 5.08, 15.09, 2.03, 1.04, false),
    row("ANSI 60", 19.05, 11.91, 5.94, 18.08, 2.39, 1.53, false),
    row("ANSI 80", 25.40, 15.88, 7.92, 24.13, 3.18, 2.66, false),
    row("ANSI 100", 31.75, 19.05, 9.53, 30.18, 3.96, 3.99, false),
    row("ANSI 120", 38.10, 22.23, 11.10, 36.20, 4.75, 5.93, false),
    row("ANSI 140", 44.45, 25.40, 12.70, 42.24, 5.56, 7.49, false),
    row("ANSI 160", 50.80, 28.58, 14.27, 48.26, 6.35, 10.10, false),
    row("ANSI 180", 57.15, 35.71, 17.46, 54.30, 7.14, 13.45, false),
    row("ANSI 200", 63.50, 39.68, 19.85, 60.33, 7.92, 16.49, false),
    row("ANSI 240", 76.20, 47.63, 23.81, 72.39, 9.53, 24.00, false),
];

/// A designation's canonical spelling for comparison: upper case, no
/// blanks, an optional "ISO606"/"ANSI" prefix and a single-strand "-1"
/// suffix dropped.
fn canonical(name: &str) -> String {
    let s: String = name
        .chars()
        .filter(|c| !c.is_whitespace())
        .flat_map(char::to_uppercase)
        .collect();
    let s = s
        .strip_prefix("ISO606")
        .or_else(|| s.strip_prefix("ANSI"))
        .unwrap_or(&s)
        .to_owned();
    s.strip_suffix("-1").unwrap_or(&s).to_owned()
}

/// The table's entry for `name` (`"ISO 606 16B-1"`, `"16B"`, `"ANSI 80"`,
/// `"80"`, any case or spacing).
pub fn find(name: &str) -> Option<&'static Designation> {
    let key = canonical(name);
    DESIGNATIONS.iter().find(|d| canonical(d.name) == key)
}

/// The `n` names nearest `name` by edit distance (on the canonical
/// spelling), nearest first.
pub fn nearest(name: &str, n: usize) -> Vec<&'static str> {
    let key = canonical(name);
    let mut scored: Vec<(usize, &'static str)> = DESIGNATIONS
        .iter()
        .map(|d| (edit_distance(&key, &canonical(d.name)), d.name))
        .collect();
    scored.sort_by_key(|&(dist, _)| dist);
    scored.into_iter().take(n).map(|(_, name)| name).collect()
}

/// Levenshtein distance between two strings (by characters).
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let above = row[j + 1];
            row[j + 1] = (above + 1)
                .min(row[j] + 1)
                .min(diagonal + usize::from(ca != *cb));
            diagonal = above;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spellings_find_the_same_entry() {
        for s in ["ISO 606 16B-1", "16B", "16b-1", "iso606 16B"] {
            assert_eq!(find(s).map(|d| d.name), Some("ISO 606 16B-1"), "{s}");
        }
        for s in ["ANSI 80", "80", "ansi 80-1"] {
            assert_eq!(find(s).map(|d| d.name), Some("ANSI 80"), "{s}");
        }
        assert!(find("16X").is_none());
    }

    #[test]
    fn edit_distance_counts_edits() {
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("16B", "16B"), 0);
    }

    #[test]
    fn a_typo_suggests_the_intended_name() {
        assert_eq!(nearest("ISO 606 16V-1", 1), vec!["ISO 606 16B-1"]);
        assert_eq!(nearest("ANSI 8O", 3)[0], "ANSI 80");
    }
}
