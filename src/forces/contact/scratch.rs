//! The circular-seat pass's per-roller scratch ([`SeatScratch`]): sized once
//! with the chain, written by the geometry loop of `seats` and read by its
//! law loop; the contact pass only carries it.

use crate::scene::MAX_SPROCKETS;

/// No direction read for this roller yet (no sprocket index reaches it).
pub(super) const NO_DIRECTION: u64 = u64::MAX;

/// The geometry loop's outputs, one slot per roller (sized once: nothing is
/// allocated per evaluation).
#[derive(Clone, Debug)]
pub(super) struct SeatScratch {
    /// Each roller's hinted gap direction, as last read from its sprocket's
    /// table: kept between evaluations and read again only where
    /// `direction_of` no longer names the roller's sprocket and hint.
    pub(super) ux: Vec<f64>,
    pub(super) uy: Vec<f64>,
    /// (sprocket << 32) | gap hint of the direction in `ux`, `uy`;
    /// [`NO_DIRECTION`] before the first read.
    pub(super) direction_of: Vec<u64>,
    /// Address and length of each sprocket's table of gap directions when
    /// its directions were read: another table (another drive's model)
    /// forgets every kept direction.
    pub(super) tables: [(usize, usize); MAX_SPROCKETS],
    pub(super) rx: Vec<f64>,
    pub(super) ry: Vec<f64>,
    pub(super) depth: Vec<f64>,
    pub(super) nx: Vec<f64>,
    pub(super) ny: Vec<f64>,
    pub(super) rate: Vec<f64>,
    /// Bit 0: inside its hinted gap's cone; bit 1: touching its seat.
    pub(super) status: Vec<u8>,
}

impl SeatScratch {
    pub(super) fn new(rollers: usize) -> Self {
        let zeros = || vec![0.0; rollers];
        Self {
            ux: zeros(),
            uy: zeros(),
            direction_of: vec![NO_DIRECTION; rollers],
            tables: [(0, 0); MAX_SPROCKETS],
            rx: zeros(),
            ry: zeros(),
            depth: zeros(),
            nx: zeros(),
            ny: zeros(),
            rate: zeros(),
            status: vec![0; rollers],
        }
    }
}
