//! The circular-seat pass's per-roller scratch ([`SeatScratch`]): sized once
//! with the chain, written by the geometry loop of `seats` and read by its
//! law loop; the contact pass only carries it.

/// The geometry loop's outputs, one slot per roller (sized once: nothing is
/// allocated per evaluation).
#[derive(Clone, Debug, Default)]
pub(super) struct SeatScratch {
    pub(super) ux: Vec<f64>,
    pub(super) uy: Vec<f64>,
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
