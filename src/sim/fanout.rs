//! [`Fanout`]: one run fed to several observers.

use super::{Observer, Sample};

/// Several observers fed the same run, in the order they were added: a
/// recorder and a statistics collector, say. Each observer's
/// [`Observer::step`] is called from its own [`Observer::per_step_from_s`]
/// on.
///
/// ```
/// use chaindrive::prelude::*;
/// use chaindrive::sim::Fanout;
/// let (mut a, mut b) = ((), ());
/// let mut both = Fanout::new().with(&mut a).with(&mut b);
/// assert_eq!(both.len(), 2);
/// assert!(both.per_step_from_s().is_infinite());
/// ```
#[derive(Default)]
pub struct Fanout<'a> {
    observers: Vec<&'a mut dyn Observer>,
}

impl<'a> Fanout<'a> {
    /// No observers yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// `self` with `observer` added.
    pub fn with(mut self, observer: &'a mut dyn Observer) -> Self {
        self.observers.push(observer);
        self
    }

    /// Adds `observer`.
    pub fn push(&mut self, observer: &'a mut dyn Observer) {
        self.observers.push(observer);
    }

    /// How many observers it feeds.
    pub fn len(&self) -> usize {
        self.observers.len()
    }

    /// Whether it feeds none.
    pub fn is_empty(&self) -> bool {
        self.observers.is_empty()
    }
}

impl Observer for Fanout<'_> {
    fn sample(&mut self, s: &Sample<'_>) {
        for o in &mut self.observers {
            o.sample(s);
        }
    }

    fn step(&mut self, s: &Sample<'_>) {
        for o in &mut self.observers {
            if s.state.t_s >= o.per_step_from_s() {
                o.step(s);
            }
        }
    }

    fn per_step_from_s(&self) -> f64 {
        self.observers
            .iter()
            .map(|o| o.per_step_from_s())
            .fold(f64::INFINITY, f64::min)
    }
}
