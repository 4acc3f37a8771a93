//! Excitation read from a scene: a driver's speed harmonics in its angle, a
//! load torque that depends on a sprocket's angle (a harmonic series or a
//! periodic table read from a CSV file) and a torque-driven driver's speed
//! governor (docs/model.md, “Excitation”).
//!
//! The check here takes what a user writes under a `[[sprockets]]` table
//! (the series and tables themselves are [`super::periodic`]'s, the
//! governor [`super::governor`]'s); the validated forms are data only (SI
//! units, radians). Evaluating them (the periodic spline through a table,
//! the governor's torque) is the model's ([`crate::model`]).

use super::RoleKind;
use super::checker::Checker;
use super::governor::{GovernorFile, GovernorSpec, check_governor};
use super::periodic::{
    Harmonic, LoadHarmonicFile, LoadTable, LoadTableFile, SpeedHarmonicFile, TableFiles,
    check_order, check_torque_harmonics, check_torque_table,
};

/// What a sprocket is excited by beyond a constant speed or load.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Excitation {
    /// The driver's speed harmonics (relative amplitudes); empty: the speed
    /// law alone.
    pub speed_harmonics: Vec<Harmonic>,
    /// A load torque in the sprocket's angle, N·m (summed with the table).
    pub load_harmonics: Vec<Harmonic>,
    /// A tabled load torque in the sprocket's angle.
    pub load_table: Option<LoadTable>,
    /// A driver turned by a torque under a speed governor; `None`: a
    /// driver's speed is prescribed.
    pub governor: Option<GovernorSpec>,
}

/// A sprocket's excitation as written: its fields of a `[[sprockets]]`
/// table that [`check_excitation`] reads.
#[derive(Clone, Copy)]
pub(super) struct ExcitationFile<'a> {
    pub(super) speed_harmonics: &'a [SpeedHarmonicFile],
    pub(super) load_harmonics: &'a [LoadHarmonicFile],
    pub(super) load_table: Option<&'a LoadTableFile>,
    pub(super) governor: Option<&'a GovernorFile>,
}

/// Validates the excitation fields `f` of sprocket `i` (role `kind`),
/// reading a load table from `tables`.
pub(super) fn check_excitation(
    c: &mut Checker,
    f: ExcitationFile<'_>,
    i: usize,
    kind: Option<RoleKind>,
    tables: TableFiles<'_>,
) -> Excitation {
    let p = |field: &str| format!("sprockets[{i}].{field}");
    let driver = kind == Some(RoleKind::Driver);
    if !driver && !f.speed_harmonics.is_empty() {
        c.fail(
            p("speed_harmonics"),
            "is allowed only for role = \"driver\"",
        );
    }
    if driver && !f.load_harmonics.is_empty() {
        c.fail(
            p("load_harmonics"),
            "is not allowed for role = \"driver\" (its speed is prescribed)",
        );
    }
    if driver && f.load_table.is_some() {
        c.fail(
            p("load_table"),
            "is not allowed for role = \"driver\" (its speed is prescribed)",
        );
    }
    let speed_harmonics: Vec<Harmonic> = f
        .speed_harmonics
        .iter()
        .enumerate()
        .map(|(k, h)| {
            let at = |field: &str| p(&format!("speed_harmonics[{k}].{field}"));
            Harmonic {
                order: check_order(c, &at("order"), h.order),
                amplitude: c.finite(&at("amplitude"), h.amplitude),
                phase_rad: c.finite(&at("phase_deg"), h.phase_deg).to_radians(),
            }
        })
        .collect();
    let sum: f64 = speed_harmonics.iter().map(|h| h.amplitude.abs()).sum();
    if sum.is_finite() && sum >= 1.0 {
        c.fail(
            p("speed_harmonics"),
            format!(
                "the relative amplitudes' magnitudes sum to {sum}; they must sum to < 1 so that the speed keeps its sign"
            ),
        );
    }
    let load_harmonics = check_torque_harmonics(c, &p("load_harmonics"), f.load_harmonics);
    let load_table = check_torque_table(c, &p("load_table"), f.load_table, tables);
    let governor = f.governor.map(|g| {
        if !driver {
            c.fail(
                p("governor"),
                "is allowed only for role = \"driver\" (it turns the driver by a torque)",
            );
        }
        if !f.speed_harmonics.is_empty() {
            c.fail(
                p("speed_harmonics"),
                "is not allowed on a driver with a governor (its speed is not prescribed; give a drive torque in its angle with governor.drive_harmonics)",
            );
        }
        check_governor(c, g, i, tables)
    });
    Excitation {
        speed_harmonics,
        load_harmonics,
        load_table,
        governor,
    }
}
