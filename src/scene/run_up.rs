//! A driver's run-up read from a scene (`sprockets.run_up` on the driver):
//! after its ramp, the driver's speed (a governed driver's target) changes
//! linearly from `speed_rpm` to `to_rpm` over `duration_s`, starting at
//! `start_s`, and stays at `to_rpm` after (docs/model.md, “Run-up”).

use serde::{Deserialize, Serialize};

use super::checker::Checker;
use super::types::RunUp;

/// A run-up as written: `run_up = { to_rpm = 3000, duration_s = 60, start_s = 1 }`.
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RunUpFile {
    /// Speed at the end of the run-up, rpm, the sense of `speed_rpm`.
    pub to_rpm: f64,
    /// Length of the run-up, s (> 0).
    pub duration_s: f64,
    /// Start of the run-up, s (default: the end of the ramp; not before it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start_s: Option<f64>,
}

/// The validated run-up of driver `i` whose ramp lasts `ramp_s` to
/// `speed_rad_s`; errors name `sprockets[i].run_up.<field>`.
pub(super) fn check(
    c: &mut Checker,
    file: Option<&RunUpFile>,
    i: usize,
    ramp_s: f64,
    speed_rad_s: f64,
) -> Option<RunUp> {
    let f = file?;
    let p = |field: &str| format!("sprockets[{i}].run_up.{field}");
    let before = c.errors.len();
    let to_rpm = c.finite(&p("to_rpm"), f.to_rpm);
    let to_rad_s = to_rpm * std::f64::consts::TAU / 60.0;
    if to_rad_s.is_finite() && to_rad_s * speed_rad_s < 0.0 {
        c.fail(
            p("to_rpm"),
            format!(
                "must turn the sense of speed_rpm (a run-up does not reverse the driver), got {to_rpm}"
            ),
        );
    }
    let duration_s = c.positive(&p("duration_s"), f.duration_s);
    let start_s = match f.start_s {
        Some(v) => {
            let v = c.non_negative(&p("start_s"), v);
            if v.is_finite() && v < ramp_s {
                c.fail(
                    p("start_s"),
                    format!("must not be before the ramp's end ({ramp_s} s), got {v}"),
                );
            }
            v
        }
        None => ramp_s,
    };
    (c.errors.len() == before).then_some(RunUp {
        start_s,
        duration_s,
        to_rad_s,
    })
}
