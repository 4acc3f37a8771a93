//! A torque-driven driver read from a scene: a drive torque (constant plus
//! a series or table in the driver's angle) and a PI speed governor to the
//! driver's speed law (`[sprockets.governor]`, docs/model.md, “A
//! torque-driven driver”).
//!
//! The validated form is data only; the gains from a bandwidth and the
//! governor's torque are the model's ([`crate::model::Governor`]).

use serde::{Deserialize, Serialize};

use super::checker::Checker;
use super::periodic::{
    Harmonic, LoadHarmonicFile, LoadTable, LoadTableFile, TableFiles, check_torque_harmonics,
    check_torque_table,
};

/// The governor's natural frequency when the scene gives neither gains nor
/// a bandwidth and the drive has no span frequency to derive one from
/// (`crate::model::default_bandwidth_hz`: a decade below the
/// lowest span frequency), Hz.
pub(crate) const DEFAULT_GOVERNOR_BANDWIDTH_HZ: f64 = 2.0;

/// A driver turned by a torque under a PI speed governor, as written
/// (`[sprockets.governor]` under a `role = "driver"` sprocket, whose
/// `speed_rpm` and `ramp_s` become the governor's target).
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct GovernorFile {
    /// Constant drive torque, N·m, counter-clockwise positive (default 0).
    #[serde(default)]
    pub drive_torque_n_m: f64,
    /// A drive torque in the driver's angle, as a harmonic series
    /// (`[[sprockets.governor.drive_harmonics]]`), added to the constant one.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub drive_harmonics: Vec<LoadHarmonicFile>,
    /// A drive torque in the driver's angle, tabled over one revolution in a
    /// CSV file (`sprockets.governor.drive_table`, the format of a
    /// `load_table`), added to the constant one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drive_table: Option<LoadTableFile>,
    /// Proportional gain K_p, N·m per rad/s (with `ki_n_m_rad`, instead of
    /// `bandwidth_hz`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kp_n_m_s_rad: Option<f64>,
    /// Integral gain K_i, N·m per rad (with `kp_n_m_s_rad`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ki_n_m_rad: Option<f64>,
    /// The closed loop's natural frequency f_n, Hz, critically damped: K_p =
    /// 2 ω_n J, K_i = ω_n² J with ω_n = 2π f_n and J the drive's inertia
    /// referred to the driver (default: a decade below the drive's lowest
    /// span frequency, docs/model.md, “A torque-driven driver”).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bandwidth_hz: Option<f64>,
}

/// How a governor's gains are set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum GovernorGains {
    /// Given: K_p, N·m·s/rad, and K_i, N·m/rad.
    Given {
        /// K_p, N·m per rad/s.
        kp_n_m_s_rad: f64,
        /// K_i, N·m per rad.
        ki_n_m_rad: f64,
    },
    /// From the closed loop's natural frequency, Hz (critical damping).
    Bandwidth {
        /// f_n, Hz.
        hz: f64,
    },
    /// Neither given: the bandwidth a decade below the drive's lowest span
    /// frequency (the model derives it from the drive's geometry).
    FromSpans,
}

/// A validated governor: the drive torque and the gains.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct GovernorSpec {
    /// Constant drive torque, N·m.
    pub drive_torque_n_m: f64,
    /// Drive torque in the driver's angle: a harmonic series, N·m.
    pub drive_harmonics: Vec<Harmonic>,
    /// Drive torque in the driver's angle: a table.
    pub drive_table: Option<LoadTable>,
    /// The gains.
    pub gains: GovernorGains,
}

/// Validates sprocket `i`'s governor `g` (whether the sprocket may have
/// one is the excitation's check); a table is read from `tables`.
pub(super) fn check_governor(
    c: &mut Checker,
    g: &GovernorFile,
    i: usize,
    tables: TableFiles<'_>,
) -> GovernorSpec {
    let p = |field: &str| format!("sprockets[{i}].governor.{field}");
    let drive_torque_n_m = c.finite(&p("drive_torque_n_m"), g.drive_torque_n_m);
    let drive_harmonics = check_torque_harmonics(c, &p("drive_harmonics"), &g.drive_harmonics);
    let drive_table = check_torque_table(c, &p("drive_table"), g.drive_table.as_ref(), tables);
    let gains = match (g.kp_n_m_s_rad, g.ki_n_m_rad, g.bandwidth_hz) {
        (None, None, None) => GovernorGains::FromSpans,
        (None, None, Some(hz)) => GovernorGains::Bandwidth {
            hz: c.positive(&p("bandwidth_hz"), hz),
        },
        (Some(kp), Some(ki), None) => GovernorGains::Given {
            kp_n_m_s_rad: c.positive(&p("kp_n_m_s_rad"), kp),
            ki_n_m_rad: c.non_negative(&p("ki_n_m_rad"), ki),
        },
        (kp, _, hz) => {
            let (field, why) = if hz.is_some() {
                (
                    if kp.is_some() {
                        "kp_n_m_s_rad"
                    } else {
                        "ki_n_m_rad"
                    },
                    "cannot be given with bandwidth_hz: give either both gains (kp_n_m_s_rad, ki_n_m_rad) or a bandwidth",
                )
            } else if kp.is_some() {
                ("ki_n_m_rad", "is required with kp_n_m_s_rad")
            } else {
                ("kp_n_m_s_rad", "is required with ki_n_m_rad")
            };
            c.fail(p(field), why);
            GovernorGains::Bandwidth {
                hz: DEFAULT_GOVERNOR_BANDWIDTH_HZ,
            }
        }
    };
    GovernorSpec {
        drive_torque_n_m,
        drive_harmonics,
        drive_table,
        gains,
    }
}
