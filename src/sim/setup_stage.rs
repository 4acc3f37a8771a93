//! What the drive being set up on each thread is solving, a phrase each
//! (the chain new at its pretension, a worn chain's wear step, a sprocket
//! let go): the setup notes it as it goes, and the command line's note of
//! a slow setup reads it from another thread. What this module does not
//! do: print anything.

use std::sync::Mutex;
use std::thread::ThreadId;

/// What the setup on each thread is solving, a phrase each (see [`stage`]).
static STAGES: Mutex<Vec<(ThreadId, String)>> = Mutex::new(Vec::new());

/// Notes that the setup on this thread now solves `what` (a phrase such as
/// "the chain new at its pretension"), until the next note or the setup's
/// end.
pub(crate) fn note_stage(what: impl FnOnce() -> String) {
    let thread = std::thread::current().id();
    // A poisoned lock only loses the note.
    if let Ok(mut stages) = STAGES.lock() {
        let text = what();
        match stages.iter_mut().find(|(t, _)| *t == thread) {
            Some(entry) => entry.1 = text,
            None => stages.push((thread, text)),
        }
    }
}

/// What the setup running on `thread` is solving ([`note_stage`]), if one is.
pub(crate) fn stage(thread: ThreadId) -> Option<String> {
    let stages = STAGES.lock().ok()?;
    stages
        .iter()
        .find(|(t, _)| *t == thread)
        .map(|(_, what)| what.clone())
}

/// Clears this thread's stage when the setup ends, however it ends.
pub(crate) struct Staged;

impl Drop for Staged {
    fn drop(&mut self) {
        let thread = std::thread::current().id();
        if let Ok(mut stages) = STAGES.lock() {
            stages.retain(|(t, _)| *t != thread);
        }
    }
}
