//! A recording killed outright (SIGKILL) loses at most the recorder's flush
//! interval, and `chaindrive recover` makes it a complete, indexed file that
//! seeking readers open.

use crate::record::{Channels, FLUSH_INTERVAL_NS, RecordOptions, Recorder};
use crate::sim::{SampleRate, Simulation};
use crate::test_support::l60mc;
use std::io::{Cursor, Seek, SeekFrom, Write};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Messages a streaming reader finds in `bytes` before the first damage.
fn streamed(bytes: &[u8]) -> (u64, u64) {
    let Ok(stream) = mcap::MessageStream::new(bytes) else {
        return (0, 0);
    };
    let mut count = 0;
    let mut last_ns = 0;
    for m in stream {
        let Ok(m) = m else { break };
        count += 1;
        last_ns = last_ns.max(m.log_time);
    }
    (count, last_ns)
}

/// A file being written, readable while the recorder still holds it.
#[derive(Clone, Default)]
struct Shared(Arc<Mutex<Cursor<Vec<u8>>>>);

impl Write for Shared {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0.lock().expect("lock").write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl Seek for Shared {
    fn seek(&mut self, pos: SeekFrom) -> std::io::Result<u64> {
        self.0.lock().expect("lock").seek(pos)
    }
}

/// Regression: with small messages (here /sprockets only, ~150 bytes per
/// sample) a 1 MiB chunk held many seconds of the run, all lost to a kill.
/// Now the open chunk is written every FLUSH_INTERVAL_NS = 0.1 s of
/// simulated time, so while the recorder is still open (as when the process
/// is killed) a streaming reader already finds every sample up to within
/// 0.1 s of the run's end: at least up to t = 0.55 − 0.1 = 0.45 s.
#[test]
fn an_open_recording_streams_up_to_the_last_flush_interval() {
    assert_eq!(
        FLUSH_INTERVAL_NS, 100_000_000,
        "the bound below assumes 0.1 s"
    );
    let scene = l60mc(0.55);
    let mut sim = Simulation::new(&scene).expect("sim");
    let sampling = SampleRate::new(1000.0, scene.solver().dt_s).expect("rate");
    let options = RecordOptions {
        channels: Channels::SPROCKETS,
        scene_file: None,
        rate_hz: sampling.rate_hz,
    };
    let file = Shared::default();
    let mut recorder = Recorder::new(file.clone(), &scene, &options).expect("recorder");
    sim.run(0.55, sampling.every, &mut recorder, None)
        .expect("run");
    // The writer thread works behind the stepping loop: wait for it (bounded).
    let deadline = Instant::now() + Duration::from_secs(20);
    let (count, last_ns) = loop {
        let bytes = file.0.lock().expect("lock").get_ref().clone();
        let (count, last_ns) = streamed(&bytes);
        if last_ns >= 450_000_000 || Instant::now() > deadline {
            break (count, last_ns);
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    assert!(
        last_ns >= 450_000_000,
        "an open recording streams only up to t = {} s ({count} messages)",
        last_ns as f64 * 1e-9
    );
    drop(recorder);
    // Finished, it holds every sample: t = 0 … 0.55 s at 1 kHz.
    let bytes = file.0.lock().expect("lock").get_ref().clone();
    assert_eq!(streamed(&bytes).0, 551);
}
