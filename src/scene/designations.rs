//! Chains by designation: `[chain] designation = "ISO 606 16B-1"` or
//! `"ANSI 80"` fills the chain's pitch, roller radius, mass per link, pin
//! radius, tensile strength and an axial link stiffness estimate, where the
//! row has them; a field written in the scene overrides the table's
//! (docs/model.md, “Chains by designation”).
//!
//! **Sources, value by value** (each row names its own in
//! [`Designation::sources`]; `chaindrive chains` prints them):
//!
//! - **ANSI** rows are typed in inches from the ASME B29.1 dimension table
//!   as printed by Engineers Edge ("Roller Chain Dimensions per ASME/ANSI
//!   B29.1M") and AmesWeb ("Roller Chain Dimensions Table"): pitch, roller
//!   diameter (bush diameter for the rollerless 25 and 35), width between
//!   the inner plates, pin diameter, link plate thickness and minimum
//!   ultimate tensile strength. B29.1 gives the roller-link plate height as
//!   at most 0.95 P; the table takes that maximum as the plate depth.
//!   Mass per metre is the weight per foot of the "Standard Roller Chain
//!   Dimensions" table (lb/ft × 1.48816 kg/m per lb/ft).
//! - **ISO 606 B-series** pitch, roller diameter, inner width and mass per
//!   metre of 05B to 48B are from the Ametric catalogue table "Standard
//!   Metric Roller Chain (DIN 8180/8187 and BS 228)"; its breaking strengths
//!   of 05B, 06B and 08B too. No printed copy of ISO 606's Table 1 could be
//!   read: pin diameter, inner plate depth, the other strengths (the
//!   standard's minimum tensile strengths as remembered), 56B to 72B's mass
//!   and inner width, and every B-series plate thickness are marked
//!   **estimate** in their row.
//! - **ANSI heavy** rows (60H to 240H: the standard chain's pitch, roller
//!   and pin with thicker link plates) are typed in millimetres from the
//!   Donghua "Drive Chains 2020" catalogue, heavy duty series simplex table
//!   (pp. 244–245): pitch, roller diameter, inner width, pin diameter, inner
//!   plate depth, plate thickness, minimum tensile strength and mass per
//!   metre. Its plate thicknesses are the next larger standard size's
//!   (B29.1's 80 has 0.125 in = 3.175 mm, the catalogue's 60H 3.25 mm; 240H
//!   0.500 in), to within 0.08 mm for 60H to 200H.
//! - **Motorcycle** rows 520, 525 and 530 (single strand only) hold what a
//!   source was read for: the 5/8 in pitch, the 10.16 mm roller (Wemoto's
//!   motorcycle chain table; the ANSI 50's 0.400 in), the inner widths
//!   6.35, 7.95 and 9.53 mm (Tsubaki, "The Complete Guide to Chain", Table
//!   1.9) and the 520's inner plate depth, 15.0 mm, of one maker's chain
//!   (D.I.D 520MXV, in a Suzuki service manual). Their pin diameters, plate
//!   thicknesses, masses and strengths are each maker's and grade's, and no
//!   table of them was readable (ISO 10190's Table 1 neither): those values
//!   are `None`, and a scene naming the chain gives the fields they would
//!   fill (`roller_mass_kg`, `stiffness_n_m`, `tensile_strength_n`,
//!   `pin_radius_m`); validation says which.
//!
//! **Stiffness estimate.** A link's two side plates in tension, through their
//! net section at the pin hole: K = η E A / P with A = 2 t (h₂ − d₂),
//! E = 206 GPa (steel) and a reduction η = 1/3 for what the plates' section
//! leaves out — the pin–bush and bush–plate contacts and the plates' waist.
//! η is calibrated on the paper's chain (pitch 88.9 mm, rollers 54 mm, the
//! size of a 56B: E A / P = 2.42 GN/m against the paper's 815 MN/m); it is
//! an estimate within a factor of about two, not a measurement. A measured
//! stiffness belongs in `chain.stiffness_n_m`, which overrides it. A row
//! without t, h₂ or d₂ (the motorcycle chains) has no estimate.

/// Young's modulus of chain steel, Pa.
pub(crate) const STEEL_E_PA: f64 = 206e9;
/// Reduction η of the plates' E A / P for the joints' compliance (module docs).
pub(crate) const STIFFNESS_REDUCTION: f64 = 1.0 / 3.0;

/// ASME B29.1 as printed by Engineers Edge and AmesWeb.
const B29: &str = "ASME B29.1 table (Engineers Edge; AmesWeb)";
/// ASME B29.1's plate height rule.
const B29_PLATE: &str = "ASME B29.1: roller-link plate height at most 0.95 P (the maximum)";
/// The weight-per-foot table of ANSI chains.
const ANSI_WEIGHT: &str = "\"Standard Roller Chain Dimensions\" table, weight lb/ft";
/// The Ametric metric chain catalogue.
const AMETRIC: &str = "Ametric catalogue, Standard Metric Roller Chain (DIN 8180/8187, BS 228)";
/// B-series values no source could be found for.
const ISO_ESTIMATE: &str = "estimate (ISO 606 Table 1 as remembered; no printed copy read)";
/// B-series plate thickness.
const PLATE_ESTIMATE: &str = "estimate (no catalogue found)";
/// The heavy series' maker's table.
const DONGHUA_HEAVY: &str =
    "Donghua Drive Chains 2020 catalogue, heavy duty series simplex table (pp. 244-245)";
/// The heavy series' plates, and how they compare with the standard series.
const DONGHUA_HEAVY_PLATE: &str = "Donghua Drive Chains 2020 catalogue, heavy duty series simplex table (pp. 244-245), T max: the next larger standard size's B29.1 thickness to within 0.08 mm";

/// Motorcycle chains' pitch, roller and inner width.
const MOTO_DIMENSIONS: &str = "pitch 5/8 in and roller 10.16 mm: Wemoto \"Motorcycle Chain Dimensions\" table (the ANSI 50's 0.400 in roller; Gearing Commander's table prints 10.30 mm); inner width: Tsubaki, The Complete Guide to Chain, Table 1.9 \"Motorcycle Chains\"";
/// The 520's plate depth, one maker's chain.
const MOTO_520_PLATE_DEPTH: &str = "h2 15.0 mm: the D.I.D 520MXV's inner plate height, standard value (Suzuki RMX450Z service manual, drive train service data); d2 none read (give chain.pin_radius_m)";
/// What no source gave for a motorcycle chain's pin and plate depth.
const MOTO_NO_PIN_PLATE: &str = "none read: ISO 10190 Table 1 and the makers' tables (D.I.D, RK, EK, Regina, Tsubaki) were not readable (give chain.pin_radius_m)";
/// A motorcycle chain's plate thickness.
const MOTO_NO_PLATE: &str = "none read: thicker than the ANSI chain's of the pitch (Tsubaki, Table 1.9: \"link plates are thicker (heavy)\"), by how much no table read said; the stiffness estimate needs it (give chain.stiffness_n_m)";
/// A motorcycle chain's mass.
const MOTO_NO_MASS: &str =
    "none read: each maker's and grade's own, no table readable (give chain.roller_mass_kg)";
/// A motorcycle chain's strength.
const MOTO_NO_STRENGTH: &str = "none read: each maker's and grade's own, ISO 10190's minimum not readable (give chain.tensile_strength_n)";

/// Where each of a row's values comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sources {
    /// Pitch, roller diameter and inner width.
    pub dimensions: &'static str,
    /// Pin diameter and inner plate depth.
    pub pin_and_plate_depth: &'static str,
    /// Plate thickness.
    pub plate_thickness: &'static str,
    /// Mass per metre.
    pub mass: &'static str,
    /// Tensile strength.
    pub strength: &'static str,
}

/// One chain of the table, single strand.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Designation {
    /// The designation as written in a scene (`"ISO 606 16B-1"`, `"ANSI 80"`).
    pub name: &'static str,
    /// Pitch P, m.
    pub pitch_m: f64,
    /// Roller diameter d₁ (bush diameter for a rollerless chain), m.
    pub roller_diameter_m: f64,
    /// Width between the inner plates b₁, m.
    pub inner_width_m: f64,
    /// Pin diameter d₂, m; `None` where no source was read
    /// ([`Sources::pin_and_plate_depth`] says so), as for every value below.
    pub pin_diameter_m: Option<f64>,
    /// Inner plate depth h₂, m.
    pub plate_depth_m: Option<f64>,
    /// Inner link plate thickness t, m.
    pub plate_thickness_m: Option<f64>,
    /// Mass per metre, kg/m.
    pub mass_per_m_kg: Option<f64>,
    /// Tensile strength, N (the standard's minimum, or a catalogue's
    /// breaking strength where [`Sources::strength`] says so).
    pub tensile_strength_n: Option<f64>,
    /// Where each value comes from.
    pub sources: Sources,
}

impl Designation {
    /// Roller radius, m.
    pub(crate) fn roller_radius_m(&self) -> f64 {
        0.5 * self.roller_diameter_m
    }

    /// Pin radius, m (the joint friction's r_pin), where the row has it.
    pub(crate) fn pin_radius_m(&self) -> Option<f64> {
        self.pin_diameter_m.map(|d| 0.5 * d)
    }

    /// Length of the bushing the pin bears on, m: the bushing is pressed
    /// through the two inner plates, so it spans the width between them and
    /// their two thicknesses, b₁ + 2 t (the wear check's bearing length);
    /// `None` without the plate thickness.
    pub fn bushing_length_m(&self) -> Option<f64> {
        self.plate_thickness_m.map(|t| self.inner_width_m + 2.0 * t)
    }

    /// Mass lumped at each roller: mass per metre times the pitch, kg;
    /// `None` without the mass per metre.
    pub fn roller_mass_kg(&self) -> Option<f64> {
        self.mass_per_m_kg.map(|q| q * self.pitch_m)
    }

    /// Axial link stiffness estimate η E A / P, A = 2 t (h₂ − d₂), N/m
    /// (module docs); `None` without the plate thickness, plate depth and
    /// pin diameter it is made of.
    pub fn stiffness_n_m(&self) -> Option<f64> {
        let t = self.plate_thickness_m?;
        let area_m2 = 2.0 * t * (self.plate_depth_m? - self.pin_diameter_m?);
        Some(STIFFNESS_REDUCTION * STEEL_E_PA * area_m2 / self.pitch_m)
    }

    /// Whether the row is a motorcycle chain (520, 525, 530): single strand
    /// only, rated as the ANSI chain of its pitch.
    pub(crate) fn is_motorcycle(&self) -> bool {
        is_motorcycle_number(self.name)
    }

    /// How the stiffness estimate is derived, for listings.
    pub fn stiffness_source() -> &'static str {
        "estimate: (1/3) E A / P, A = 2 t (h2 - d2) net plate section, E = 206 GPa; 1/3 calibrated on the paper's 88.9 mm chain"
    }
}

/// The most strands a designation may name (`-2` to `-4`).
pub(crate) const MAX_STRANDS: u32 = 4;

/// How a multi-strand chain's values follow from its single strand's.
const MULTI_STRAND: &str = "n x the single strand's";

/// A chain of the table in `strands` strands side by side on common pins
/// (`"ANSI 80-2"`). Per strand count, as published and as derived:
///
/// - **tensile strength** n times the single strand's: the minimum ultimate
///   tensile strengths of multiple-strand chains in the U.S. Tsubaki RS
///   catalogue (RS50-2 to RS50-6: 9,760 to 29,280 lbs, n × 4,880) and the
///   ISO/ASA breaking loads of the Mecha catalogue (16A-2 113,400 N and
///   16A-3 170,100 N, n × 56,700 N) are exactly that;
/// - **mass per metre** n times (Tsubaki's RS50-2 1.39 lb/ft against 2 ×
///   0.70: the outer plates of the inner strands are shared, the pins
///   longer; within 1 %), **stiffness** n times (n strands' plates in
///   parallel on the same pins), the **bearing length** of the wear check n
///   times (the pin bears in n bushings);
/// - pitch, roller, pin and plate dimensions are the single strand's; the
///   **transverse pitch** (strand spacing) is published for the ANSI sizes
///   (`transverse_pitch_m`) and is listed only: the planar model has no
///   use for it;
/// - the **rating** multiplies the single strand's by the multiple-strand
///   factor (1.7, 2.5, 3.3), not by n, and so does the fatigue limit derived
///   from it (docs/design-checks.md, “Chain data”).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stranded {
    /// The single strand's row.
    pub single: &'static Designation,
    /// Strands, 1 to 4.
    pub strands: u32,
}

impl Stranded {
    /// The designation as a scene names it: the table's name, with `-n`
    /// for more than one strand (`"ANSI 80-2"`, `"ISO 606 16B-2"`).
    pub fn name(&self) -> String {
        if self.strands == 1 {
            self.single.name.to_owned()
        } else {
            format!(
                "{}-{}",
                self.single.name.trim_end_matches("-1"),
                self.strands
            )
        }
    }

    /// n as a number.
    fn n(&self) -> f64 {
        f64::from(self.strands)
    }

    /// Minimum tensile strength of all strands, n F₁, N (`None` where the
    /// row has none, as for every value below).
    pub fn tensile_strength_n(&self) -> Option<f64> {
        self.single.tensile_strength_n.map(|f| self.n() * f)
    }

    /// Mass per metre of all strands, n q₁, kg/m.
    pub fn mass_per_m_kg(&self) -> Option<f64> {
        self.single.mass_per_m_kg.map(|q| self.n() * q)
    }

    /// Mass lumped at each roller (all strands), kg.
    pub fn roller_mass_kg(&self) -> Option<f64> {
        self.single.roller_mass_kg().map(|m| self.n() * m)
    }

    /// Axial link stiffness estimate of all strands, n K₁, N/m.
    pub fn stiffness_n_m(&self) -> Option<f64> {
        self.single.stiffness_n_m().map(|k| self.n() * k)
    }

    /// Bushing length the pin bears on, all strands, n (b₁ + 2 t), m.
    pub(crate) fn bushing_length_m(&self) -> Option<f64> {
        self.single.bushing_length_m().map(|l| self.n() * l)
    }

    /// Where a value of this chain comes from: the single strand's source,
    /// or for several strands how it is derived from it.
    pub fn derived(&self, single_source: &'static str) -> String {
        if self.strands == 1 {
            single_source.to_owned()
        } else {
            format!("{MULTI_STRAND} ({single_source})")
        }
    }
}

/// The transverse pitch (strand spacing) of an ANSI multiple-strand chain,
/// m: the "Transverse Pitch K" column of the PEER "ANSI Standard Roller
/// Chains, Single & Double Strand" catalogue table (35-2 to 240-2), in
/// inches; U.S. Tsubaki prints the same .713 in for RS50. `None` for the
/// ISO 606 B series (no table read) and ANSI 25 and 41.
pub(crate) fn transverse_pitch_m(d: &Designation) -> Option<f64> {
    let inches = match d.name {
        "ANSI 35" => 0.399,
        "ANSI 40" => 0.566,
        "ANSI 50" => 0.713,
        "ANSI 60" => 0.897,
        "ANSI 80" => 1.153,
        "ANSI 100" => 1.408,
        "ANSI 120" => 1.789,
        "ANSI 140" => 1.924,
        "ANSI 160" => 2.305,
        "ANSI 180" => 2.592,
        "ANSI 200" => 2.817,
        "ANSI 240" => 3.458,
        _ => return None,
    };
    Some(inches * INCH_M)
}

/// Metres per inch.
const INCH_M: f64 = 0.0254;
/// Newtons per pound-force.
const LBF_N: f64 = 4.448_221_615_260_5;
/// kg/m per lb/ft.
const LB_FT_KG_M: f64 = 0.453_592_37 / 0.3048;

/// An ANSI row as printed in ASME B29.1, in inches and pounds: pitch,
/// roller diameter, width, pin diameter, plate thickness, minimum ultimate
/// tensile strength (lbf) and weight (lb/ft).
#[allow(clippy::too_many_arguments)]
const fn ansi(
    name: &'static str,
    p_in: f64,
    dr_in: f64,
    w_in: f64,
    dp_in: f64,
    lpt_in: f64,
    muts_lbf: f64,
    weight_lb_ft: f64,
) -> Designation {
    Designation {
        name,
        pitch_m: p_in * INCH_M,
        roller_diameter_m: dr_in * INCH_M,
        inner_width_m: w_in * INCH_M,
        pin_diameter_m: Some(dp_in * INCH_M),
        plate_depth_m: Some(0.95 * p_in * INCH_M),
        plate_thickness_m: Some(lpt_in * INCH_M),
        mass_per_m_kg: Some(weight_lb_ft * LB_FT_KG_M),
        tensile_strength_n: Some(muts_lbf * LBF_N),
        sources: Sources {
            dimensions: B29,
            pin_and_plate_depth: B29_PLATE,
            plate_thickness: B29,
            mass: ANSI_WEIGHT,
            strength: B29,
        },
    }
}

/// A B-series row in millimetres, kg/m and kN: pitch, roller diameter,
/// inner width, pin diameter, inner plate depth, plate thickness, mass per
/// metre, tensile strength; `checked` is how far the row was found in the
/// Ametric catalogue (0: nothing, 1: P, d₁, b₁, 2: and the mass, 3: and the
/// strength).
const fn iso(name: &'static str, mm: [f64; 8], checked: u8) -> Designation {
    from_mm(
        name,
        mm,
        Sources {
            dimensions: if checked >= 1 { AMETRIC } else { ISO_ESTIMATE },
            pin_and_plate_depth: ISO_ESTIMATE,
            plate_thickness: PLATE_ESTIMATE,
            mass: if checked >= 2 { AMETRIC } else { ISO_ESTIMATE },
            strength: if checked >= 3 { AMETRIC } else { ISO_ESTIMATE },
        },
    )
}

/// An ANSI heavy row as the Donghua catalogue prints it, in millimetres,
/// kg/m and kN: pitch, roller diameter, inner width, pin diameter, inner
/// plate depth, plate thickness, mass per metre, minimum tensile strength.
const fn heavy(name: &'static str, mm: [f64; 8]) -> Designation {
    from_mm(
        name,
        mm,
        Sources {
            dimensions: DONGHUA_HEAVY,
            pin_and_plate_depth: DONGHUA_HEAVY,
            plate_thickness: DONGHUA_HEAVY_PLATE,
            mass: DONGHUA_HEAVY,
            strength: DONGHUA_HEAVY,
        },
    )
}

/// A motorcycle chain of 5/8 in pitch (`"520"`: the pitch in eighths of
/// an inch, then the inner width's code) with its inner width b₁ and, where
/// a source gives it, its inner plate depth h₂, both in millimetres; every
/// other value unknown (module docs).
const fn moto(
    name: &'static str,
    b1_mm: f64,
    h2_mm: Option<f64>,
    pin_and_plate_depth: &'static str,
) -> Designation {
    Designation {
        name,
        pitch_m: 0.625 * INCH_M,
        roller_diameter_m: 10.16e-3,
        inner_width_m: b1_mm * 1e-3,
        pin_diameter_m: None,
        plate_depth_m: match h2_mm {
            Some(h) => Some(h * 1e-3),
            None => None,
        },
        plate_thickness_m: None,
        mass_per_m_kg: None,
        tensile_strength_n: None,
        sources: Sources {
            dimensions: MOTO_DIMENSIONS,
            pin_and_plate_depth,
            plate_thickness: MOTO_NO_PLATE,
            mass: MOTO_NO_MASS,
            strength: MOTO_NO_STRENGTH,
        },
    }
}

/// A row in a catalogue's units, `[P, d₁, b₁, d₂, h₂, t]` in millimetres,
/// then kg/m and kN, with where its values come from.
const fn from_mm(name: &'static str, mm: [f64; 8], sources: Sources) -> Designation {
    let [p_mm, d1_mm, b1_mm, d2_mm, h2_mm, t_mm, q_kg_m, f_kn] = mm;
    Designation {
        name,
        pitch_m: p_mm * 1e-3,
        roller_diameter_m: d1_mm * 1e-3,
        inner_width_m: b1_mm * 1e-3,
        pin_diameter_m: Some(d2_mm * 1e-3),
        plate_depth_m: Some(h2_mm * 1e-3),
        plate_thickness_m: Some(t_mm * 1e-3),
        mass_per_m_kg: Some(q_kg_m),
        tensile_strength_n: Some(f_kn * 1e3),
        sources,
    }
}

/// Every designation known, ISO 606 B series, ANSI, ANSI heavy, then the
/// motorcycle chains, by pitch.
#[rustfmt::skip]
pub const DESIGNATIONS: &[Designation] = &[
    //   name                     P      d1      b1      d2      h2       t    kg/m      kN   checked
    iso("ISO 606 05B-1",    [   8.00,   5.00,   3.00,   2.31,   7.11,   0.75,   0.18,     5.0], 3),
    iso("ISO 606 06B-1",    [  9.525,   6.35,   5.72,   3.28,   8.26,   1.00,   0.41,     9.0], 3),
    iso("ISO 606 08B-1",    [  12.70,   8.51,   7.75,   4.45,  11.81,   1.60,   0.70,    18.0], 3),
    iso("ISO 606 10B-1",    [ 15.875,  10.16,   9.65,   5.08,  14.73,   1.50,   0.91,    22.2], 2),
    iso("ISO 606 12B-1",    [  19.05,  12.07,  11.68,   5.72,  16.13,   1.80,   1.18,    28.9], 2),
    iso("ISO 606 16B-1",    [  25.40,  15.88,  17.02,   8.28,  21.08,   3.10,   2.68,    60.0], 2),
    iso("ISO 606 20B-1",    [  31.75,  19.05,  19.56,  10.19,  26.42,   3.50,   3.50,    95.0], 2),
    iso("ISO 606 24B-1",    [  38.10,  25.40,  25.40,  14.63,  33.40,   4.80,   6.80,   160.0], 2),
    iso("ISO 606 28B-1",    [  44.45,  27.94,  30.99,  15.90,  37.08,   6.00,   8.50,   200.0], 2),
    iso("ISO 606 32B-1",    [  50.80,  29.21,  30.99,  17.81,  42.29,   6.00,   10.5,   250.0], 2),
    iso("ISO 606 40B-1",    [  63.50,  39.37,  38.10,  22.89,  52.96,   8.00,   16.4,   355.0], 2),
    iso("ISO 606 48B-1",    [  76.20,  48.26,  45.72,  29.24,  63.88,  10.00,   25.0,   560.0], 2),
    iso("ISO 606 56B-1",    [  88.90,  53.98,  53.34,  34.32,  77.85,  12.00,   35.0,   850.0], 0),
    iso("ISO 606 64B-1",    [ 101.60,  63.50,  60.96,  39.40,  90.17,  13.00,   46.0,  1120.0], 0),
    iso("ISO 606 72B-1",    [ 114.30,  72.39,  68.58,  44.48, 103.63,  15.00,   60.0,  1400.0], 0),
    //    name        P      Dr     W      Dp      LPT    MUTS lbf  lb/ft
    ansi("ANSI 25",  0.250, 0.130, 0.125, 0.0905, 0.030,    780.0, 0.084),
    ansi("ANSI 35",  0.375, 0.200, 0.188, 0.141,  0.050,   1760.0, 0.21),
    ansi("ANSI 40",  0.500, 0.312, 0.312, 0.156,  0.060,   3125.0, 0.41),
    ansi("ANSI 41",  0.500, 0.306, 0.250, 0.141,  0.050,   1500.0, 0.28),
    ansi("ANSI 50",  0.625, 0.400, 0.375, 0.200,  0.080,   4880.0, 0.68),
    ansi("ANSI 60",  0.750, 0.469, 0.500, 0.234,  0.094,   7030.0, 1.00),
    ansi("ANSI 80",  1.000, 0.625, 0.625, 0.312,  0.125,  12500.0, 1.69),
    ansi("ANSI 100", 1.250, 0.750, 0.750, 0.375,  0.156,  19530.0, 2.49),
    ansi("ANSI 120", 1.500, 0.875, 1.000, 0.437,  0.187,  28125.0, 3.67),
    ansi("ANSI 140", 1.750, 1.000, 1.000, 0.500,  0.219,  38280.0, 4.93),
    ansi("ANSI 160", 2.000, 1.125, 1.250, 0.562,  0.250,  50000.0, 6.43),
    ansi("ANSI 180", 2.250, 1.406, 1.406, 0.687,  0.281,  63280.0, 8.70),
    ansi("ANSI 200", 2.500, 1.562, 1.500, 0.781,  0.312,  78125.0, 10.51),
    ansi("ANSI 240", 3.000, 1.875, 1.875, 0.937,  0.375, 112500.0, 16.90),
    //     name                P      d1      b1      d2      h2       T    kg/m      kN
    heavy("ANSI 60H",   [ 19.050,  11.91,  12.57,   5.94,  18.00,   3.25,   1.87,   31.80]),
    heavy("ANSI 80H",   [ 25.400,  15.88,  15.75,   7.92,  24.00,   4.00,   3.10,   56.70]),
    heavy("ANSI 100H",  [ 31.750,  19.05,  18.90,   9.53,  30.00,   4.80,   4.52,   88.50]),
    heavy("ANSI 120H",  [ 38.100,  22.23,  25.22,  11.10,  35.70,   5.60,   6.60,  127.00]),
    heavy("ANSI 140H",  [ 44.450,  25.40,  25.22,  12.70,  41.00,   6.40,   8.30,  172.40]),
    heavy("ANSI 160H",  [ 50.800,  28.58,  31.55,  14.27,  47.80,   7.20,  10.30,  226.80]),
    heavy("ANSI 180H",  [ 57.150,  35.71,  35.48,  17.46,  53.60,   8.00,  14.83,  281.00]),
    heavy("ANSI 200H",  [ 63.500,  39.68,  37.85,  19.85,  60.00,   9.50,  19.16,  353.80]),
    heavy("ANSI 240H",  [ 76.200,  47.63,  47.35,  23.81,  72.39,  12.70,  30.40,  510.30]),
    //    name    b1 mm  h2 mm        source of h2 (and of d2: none)
    moto("520",  6.35,  Some(15.0),  MOTO_520_PLATE_DEPTH),
    moto("525",  7.95,  None,        MOTO_NO_PIN_PLATE),
    moto("530",  9.53,  None,        MOTO_NO_PIN_PLATE),
];

/// A designation's canonical spelling for comparison: upper case, no
/// blanks, an optional "ISO606"/"ANSI" prefix and a single-strand "-1"
/// suffix dropped.
fn canonical(name: &str) -> String {
    let (base, _) = split_strands(name);
    if let Some(number) = base
        .strip_prefix("ISO606")
        .or_else(|| base.strip_prefix("ANSI"))
    {
        return ansi_of_iso_a(number).unwrap_or_else(|| number.to_owned());
    }
    // A motorcycle number takes no prefix: "ANSI 530" is no chain.
    if is_motorcycle_number(&base) {
        return format!("{MOTORCYCLE_KEY}{base}");
    }
    ansi_of_iso_a(&base).unwrap_or(base)
}

/// The canonical spelling's mark of a motorcycle number (`"MOTO520"`).
const MOTORCYCLE_KEY: &str = "MOTO";

/// Whether a name (upper case, no blanks) is a motorcycle chain number:
/// three digits from 4xx to 6xx (420, 520, 530, 630), an optional heavy
/// grade's H. No ANSI number has them (100 to 240 are the three-digit ones).
fn is_motorcycle_number(s: &str) -> bool {
    let digits = s.strip_suffix('H').unwrap_or(s);
    digits.len() == 3
        && digits.chars().all(|c| c.is_ascii_digit())
        && matches!(digits.as_bytes()[0], b'4' | b'5' | b'6')
}

/// A name in upper case without blanks, split at a trailing strand count
/// `-N` (N one or two digits): ("80", 2) for "ANSI 80-2"; a name without
/// one is a single strand.
fn split_strands(name: &str) -> (String, u32) {
    let s: String = name
        .chars()
        .filter(|c| !c.is_whitespace())
        .flat_map(char::to_uppercase)
        .collect();
    if let Some((base, n)) = s.rsplit_once('-')
        && !n.is_empty()
        && n.len() <= 2
        && n.chars().all(|c| c.is_ascii_digit())
        && let Ok(strands) = n.parse::<u32>()
    {
        return (base.to_owned(), strands);
    }
    (s, 1)
}

/// The ANSI number of an ISO 606 A-series or bush-chain name, canonical
/// spelling: ISO 606's A series is ASME B29.1's chains in metric names, its
/// two digits the pitch in sixteenths of an inch (08A = ANSI 40, 16A =
/// ANSI 80), 04C and 06C the bush chains ANSI 25 and 35.
fn ansi_of_iso_a(s: &str) -> Option<String> {
    match s {
        "04C" => return Some("25".to_owned()),
        "06C" => return Some("35".to_owned()),
        _ => {}
    }
    let digits = s.strip_suffix('A')?;
    if digits.len() != 2 || !digits.chars().all(|c| c.is_ascii_digit()) {
        return None;
    }
    let sixteenths: u32 = digits.parse().ok()?;
    // ANSI's leading digits: the pitch in eighths of an inch.
    (sixteenths % 2 == 0 && sixteenths >= 8).then(|| format!("{}0", sixteenths / 2))
}

/// The table's entry for `name` (`"ISO 606 16B-1"`, `"16B"`, `"ANSI 80"`,
/// `"80"`, any case or spacing), a single strand.
pub fn find(name: &str) -> Option<&'static Designation> {
    match lookup(name) {
        Ok(chain) if chain.strands == 1 => Some(chain.single),
        _ => None,
    }
}

/// The chain `name` designates, with its strand count: `"ANSI 80-2"`,
/// `"16B-3"`, `"08A-2"` (a name without a count is one strand); `Err` says
/// what is wrong and what is allowed.
pub fn lookup(name: &str) -> Result<Stranded, String> {
    let (_, strands) = split_strands(name);
    let key = canonical(name);
    let Some(single) = DESIGNATIONS.iter().find(|d| canonical(d.name) == key) else {
        return Err(format!(
            "unknown designation \"{name}\"{}; nearest: {} (`chaindrive chains` lists all; a multi-strand chain adds -2 to -{MAX_STRANDS})",
            not_tabled(&key),
            nearest(name, 3)
                .iter()
                .map(|n| format!("\"{n}\""))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    };
    let most = max_strands(single);
    if most == 1 && strands != 1 {
        let kind = if single.is_motorcycle() {
            " is a motorcycle chain: motorcycle chains are made as a single strand only"
        } else {
            " is made as a single strand only"
        };
        return Err(format!(
            "\"{name}\": {}{kind}, not in {strands} strands (write \"{}\")",
            single.name, single.name
        ));
    }
    if !(1..=most).contains(&strands) {
        return Err(format!(
            "\"{name}\": {} comes in 1 to {most} strands here (\"{}\" to \"{}-{most}\": the rating's multiple-strand factors stop at {most}), not {strands}",
            single.name,
            single.name,
            single.name.trim_end_matches("-1")
        ));
    }
    Ok(Stranded { single, strands })
}

/// Why a name of a known family is not in the table: the table's
/// motorcycle chains are 520, 525 and 530 (not their heavy grades, not the
/// other sizes), a motorcycle number takes no ANSI or ISO 606 prefix, and
/// the heavy series has rows from 60H to 240H only (docs/design-checks.md,
/// “Chain data”); empty for any other name.
fn not_tabled(key: &str) -> &'static str {
    if key.starts_with(MOTORCYCLE_KEY) {
        " (the table's motorcycle chains are 520, 525 and 530; other sizes and the makers' heavy grades (520H, 530H) have no row: give chain.pitch_m, roller_radius_m, roller_mass_kg and stiffness_n_m)"
    } else if is_motorcycle_number(key) {
        // "ANSI 530": the prefix was stripped, the number is a motorcycle's.
        " (a motorcycle chain number takes no ANSI or ISO 606 prefix: write \"520\", \"525\" or \"530\")"
    } else if key.ends_with('H')
        && key.len() > 1
        && key[..key.len() - 1].chars().all(|c| c.is_ascii_digit())
    {
        " (the table's ANSI heavy chains are 60H to 240H: give chain.pitch_m, roller_radius_m, roller_mass_kg and stiffness_n_m, or the standard chain of the same size)"
    } else {
        ""
    }
}

/// The most strands a designation may have: the rating's strand factors
/// (1.7, 2.5, 3.3 for 2 to 4 strands) stop at four; ANSI 41 and the
/// motorcycle chains are single strands only.
fn max_strands(d: &Designation) -> u32 {
    if d.name == "ANSI 41" || d.is_motorcycle() {
        1
    } else {
        MAX_STRANDS
    }
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
    fn iso_a_series_names_find_their_ansi_chain() {
        for (iso, ansi) in [
            ("ISO 606 08A-1", "ANSI 40"),
            ("10A", "ANSI 50"),
            ("16A-1", "ANSI 80"),
            ("iso 606 48a-1", "ANSI 240"),
            ("06C", "ANSI 35"),
        ] {
            assert_eq!(find(iso).map(|d| d.name), Some(ansi), "{iso}");
        }
        for unknown in ["09A", "08A-2", "ANSI 530", "6A"] {
            assert!(find(unknown).is_none(), "{unknown}");
        }
    }

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
